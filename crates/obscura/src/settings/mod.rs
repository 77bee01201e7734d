//! Settings. [`AoOptions`] fixes what can run and is compiled into pipelines at creation;
//! [`AoParams`] is cheap to change every frame. Both validate before any GPU work.

mod params;

pub use params::{AoParams, CameraMotion, DepthNoise, DEFAULT_THICKNESS, MIN_SCALE};

use crate::{Error, Result};

/// The one of `all` whose `name` is `s` (the names the CLI and the Python package take),
/// or a message listing the names.
pub fn by_name<T: Copy>(
    all: &[T],
    name: impl Fn(T) -> &'static str,
    s: &str,
) -> std::result::Result<T, String> {
    all.iter().copied().find(|&t| name(t) == s).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&t| name(t)).collect();
        format!("expected one of {}", names.join(", "))
    })
}

/// The AO estimator: the integral each pixel evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Estimator {
    /// Horizon-based AO (Bavoil, Sainz & Dimitrov 2008): `directions` directions,
    /// tangent bias, falloff 1 − r²/R². Samples/pixel = directions × steps.
    Hbao,
    /// Ground-Truth AO (Jimenez et al. 2016): `directions` slices marched both ways,
    /// cosine-weighted horizon integration, visibility within R (the reference's
    /// definition; the bias angle is not used). Samples/pixel = 2 × directions × steps.
    /// The default: at equal samples it has 17–58% less error against ray-traced AO than
    /// HBAO on every shared scene (docs/quality.md).
    #[default]
    Gtao,
    /// Volumetric Obscurance (Loos & Sloan 2010): occupied fraction of a sphere of radius R
    /// centred on the surface, by line integrals; no normal needed.
    /// Samples/pixel = directions × steps.
    Vo,
    /// Volumetric AO (Szirmay-Kalos et al. 2009): occupied fraction of a sphere of radius
    /// R/2 centred R/2 along the normal. Samples/pixel = directions × steps. VO and VAO
    /// take surfaces as 2R thick (`shader::SPHERE_THICKNESS`), so foreground objects do not
    /// darken what lies far behind them.
    Vao,
    /// Scalable Ambient Obscurance (McGuire, Mara & Luebke, HPG 2012): `directions × steps`
    /// samples on a golden-angle spiral, each read from the level of the depth pyramid its
    /// distance calls for (level ⌊log2(r_px / 8)⌋), Alchemy AO's obscurance sum with
    /// σ = R (see passes/estimators/sao.wgsl). Samples/pixel = directions × steps.
    Sao,
    /// Volumetric Obscurance's area integral (Loos & Sloan 2010): VO's sphere and samples,
    /// but each sample stands for its share of the sphere's screen disk and reads the mean
    /// and variance of depth over a texel of that area (a moments pyramid, built by extra
    /// passes); the chord's occupied length is its expectation over that texel's depths,
    /// taken as uniform with that mean and variance (passes/estimators/sphere_area.wgsl).
    /// Samples/pixel = directions × steps.
    VoArea,
    /// Visibility-bitmask AO (Therrien, Levesque & Gilet 2023, "Screen Space Indirect
    /// Lighting with Visibility Bitmask"): GTAO's slices and samples, but each slice keeps
    /// a 32-bit field of occluded sectors instead of two horizons. A sample occludes the
    /// sectors between its front (the depth seen) and its back (the front pushed away
    /// from the camera by [`AoParams::thickness`]), so thin objects no longer cast the
    /// shadow of an infinitely deep wall. Sectors are equal steps of a pseudo-angle (a
    /// division instead of an arc cosine) and a slice's visibility is the cosine-weighted
    /// integral between the edges of its clear runs, so with infinite thickness it is GTAO
    /// with each horizon rounded to a sector edge (passes/estimators/bitmask.wgsl).
    /// Samples/pixel = 2 × directions × steps.
    Bitmask,
}

impl Estimator {
    /// Every estimator.
    pub const ALL: [Estimator; 7] = [
        Estimator::Hbao,
        Estimator::Gtao,
        Estimator::Vo,
        Estimator::Vao,
        Estimator::Sao,
        Estimator::VoArea,
        Estimator::Bitmask,
    ];

    /// Short name used by the CLI, labels and reports.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::Hbao => "hbao",
            Estimator::Gtao => "gtao",
            Estimator::Vo => "vo",
            Estimator::Vao => "vao",
            Estimator::Sao => "sao",
            Estimator::VoArea => "vo-area",
            Estimator::Bitmask => "bitmask",
        }
    }

    /// Whether the estimator reads the depth pyramid (built by extra passes).
    pub fn uses_pyramid(self) -> bool {
        self == Estimator::Sao
    }

    /// Whether the estimator reads the depth moments pyramid (built by extra passes).
    pub fn uses_moments(self) -> bool {
        self == Estimator::VoArea
    }

    /// Whether the estimator can output bent normals ([`AoOptions::bent_normals`]): GTAO
    /// and HBAO, whose horizons bound the unoccluded arc of every slice or direction, and
    /// the bitmask, whose clear sectors are that arc.
    pub fn has_bent_normals(self) -> bool {
        matches!(self, Estimator::Gtao | Estimator::Hbao | Estimator::Bitmask)
    }
}

/// Quality presets. Each estimator's directions (slices for GTAO) and steps are chosen so
/// that a preset costs about the same number of samples per pixel with every estimator:
///
/// | preset | samples/pixel | GTAO, bitmask: slices × steps (each way) | HBAO, VO, VAO, SAO, VO-area directions × steps |
/// |---|---|---|---|
/// | `Low` | 8 | 2 × 2 | 4 × 2 |
/// | `Medium` | 16 | 2 × 4 | 4 × 4 |
/// | `High` (default) | 30 or 32 | 3 × 5 at march exponent 1.3 where the samples' lattice is at most 2 pixels, else 4 × 4 evenly | 8 × 4 |
/// | `Ultra` | 96 | 8 × 6 | 16 × 6 |
///
/// `High` for GTAO and the bitmask depends on the layout and resolution
/// ([`AoOptions::with_preset`], [`AoOptions::lattice_px`]): where the samples' lattice is
/// fine (2×2 layers at full resolution, the randomized layout at full and half
/// resolution) three slices of five steps crowded toward the centre
/// ([`HIGH_MARCH_EXPONENT`]) find the contact shadows a few pixels wide that four even
/// steps step over; with fewer samples they were better than 4 × 4 there on the mean of
/// the shared views, and at full resolution on every view (docs/thickness.md, "The default
/// changed"). Where the lattice is coarser (4×4 layers, 2×2 layers below full resolution,
/// the randomized layout at quarter or scaled resolution) the crowded steps land on a few
/// lattice points, the far field thins and the AO brightens, so `High` keeps 4 × 4 evenly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Preset {
    Low,
    Medium,
    #[default]
    High,
    Ultra,
}

impl Preset {
    /// Every preset, cheapest first.
    pub const ALL: [Preset; 4] = [Preset::Low, Preset::Medium, Preset::High, Preset::Ultra];
}

/// How the AO pass is laid out over the image (seed 000, "Deinterleaved Texturing").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum AoMode {
    /// One full-resolution pass; each pixel takes its pattern from the 4×4 table.
    Randomized,
    /// The image is split into 2×2 layers (half resolution each); each layer runs with one
    /// pattern and samples on its own lattice; the results are re-interleaved.
    #[default]
    Deinterleaved2,
    /// As `Deinterleaved2` with 4×4 layers (quarter resolution each, 16 patterns).
    Deinterleaved4,
}

impl AoMode {
    /// Every mode.
    pub const ALL: [AoMode; 3] = [
        AoMode::Randomized,
        AoMode::Deinterleaved2,
        AoMode::Deinterleaved4,
    ];

    /// The split factor N (layers are N×N); 1 for the single pass.
    pub fn split(self) -> u32 {
        match self {
            AoMode::Randomized => 1,
            AoMode::Deinterleaved2 => 2,
            AoMode::Deinterleaved4 => 4,
        }
    }

    /// Short name used by the CLI and benchmark output.
    pub fn name(self) -> &'static str {
        match self {
            AoMode::Randomized => "randomized",
            AoMode::Deinterleaved2 => "deinterleaved2",
            AoMode::Deinterleaved4 => "deinterleaved4",
        }
    }
}

/// The resolution the AO is computed at (seeds 002 and 004: low-resolution shading with
/// depth-aware upsampling). Sizes round up (`ceil(size / factor)`), and a low-resolution
/// pixel's centre sits at the centre of the full-resolution block it stands for, so odd
/// sizes neither shift nor crop the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Resolution {
    #[default]
    Full,
    Half,
    Quarter,
    /// Any scale in [1/4, 1], chosen per frame ([`AoParams::scale`]; a frame-budget
    /// controller sets it, [`crate::budget::ScaleController`]): the AO grid is
    /// `ceil(full × scale)`. Textures are created once for scale 1. Each working texel takes
    /// the prepared value of one of the full-resolution pixels it covers, chosen by
    /// [`AoOptions::downsample`]'s rule among the 2 × 2 nearest its centre (at scale 1/2
    /// half resolution's picks), recentred along its tangent plane (passes/pyramid/rescale.wgsl);
    /// the AO comes back through
    /// the joint bilateral upsampler at that scale (passes/upsample/upsample_scaled.wgsl). Temporal
    /// accumulation (with [`AoOptions::history`]) runs on the working grid, reprojecting
    /// into the previous frame's grid whatever its scale. At scale 1 it is the
    /// full-resolution pipeline.
    /// Needs the bilateral upsampler, the spatial or no denoiser, an estimator without
    /// depth mips (not SAO or VO's area integral) and no bent normals.
    Scaled,
}

impl Resolution {
    /// The fixed resolutions ([`Resolution::Scaled`] takes its scale per frame).
    pub const ALL: [Resolution; 3] = [Resolution::Full, Resolution::Half, Resolution::Quarter];

    /// Full-resolution pixels per AO pixel along each axis: 1, 2 or 4 (1 for `Scaled`,
    /// whose textures are sized for scale 1).
    pub fn factor(self) -> u32 {
        match self {
            Resolution::Full | Resolution::Scaled => 1,
            Resolution::Half => 2,
            Resolution::Quarter => 4,
        }
    }

    /// Short name used by the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            Resolution::Full => "full",
            Resolution::Half => "half",
            Resolution::Quarter => "quarter",
            Resolution::Scaled => "scaled",
        }
    }
}

/// How a 2×2 block of depths becomes one low-resolution depth (seed 004). Every rule picks
/// one of the four samples (depths are never averaged: an average is a surface that is not
/// there), and the low-resolution normal is that sample's normal. Sky samples are skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DepthDownsample {
    /// The farthest depth (NVIDIA's rule in seed 004): thin foreground features vanish.
    Max,
    /// The nearest depth: foreground wins, background detail vanishes.
    Min,
    /// Min and max alternating in a checkerboard over low-resolution pixels (Call of Duty:
    /// Black Ops 3, in seed 004): both sides of an edge survive somewhere. The default: with
    /// the bilateral upsampler, the lowest error against ray-traced AO at half resolution
    /// over every shared view (docs/mixed-resolution.md); all four rules are within 5%.
    #[default]
    Checkerboard,
    /// Reject the sample farthest from the centroid of the remaining ones until two remain,
    /// then keep the one closer to the last centroid (seed 004 leaves the last pair's choice
    /// open): the depth most like its neighbours.
    Representative,
}

impl DepthDownsample {
    /// Every rule.
    pub const ALL: [DepthDownsample; 4] = [
        DepthDownsample::Max,
        DepthDownsample::Min,
        DepthDownsample::Checkerboard,
        DepthDownsample::Representative,
    ];

    /// Short name used by the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            DepthDownsample::Max => "max",
            DepthDownsample::Min => "min",
            DepthDownsample::Checkerboard => "checkerboard",
            DepthDownsample::Representative => "representative",
        }
    }
}

/// How low-resolution AO returns to full resolution. Each reads the 2×2 low-resolution
/// pixels around the full-resolution pixel (the bilinear footprint).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Upsampler {
    /// Bilinear weights only: cheapest, bleeds across depth edges.
    Bilinear,
    /// The sample whose depth is closest to the full-resolution depth (seed 004).
    NearestDepth,
    /// Bilinear where the 2×2 neighbourhood is one surface, nearest-depth where it holds a
    /// discontinuity (seed 004). A surface: every low-resolution normal within 25° of their
    /// mean, every sample within 2% of the depth from the full-resolution pixel's tangent
    /// plane, and no sample whose own footprint (depth pyramid min/max) spans more than 5% of
    /// its depth. See passes/upsample/upsample_classified.wgsl.
    Classified,
    /// Joint bilateral (Yang et al., "Geometry-Aware Framebuffer Level of Detail", 2008;
    /// seed 002): bilinear weights × depth weight (distance from the tangent plane relative
    /// to depth) × normal agreement. The default: the lowest error against ray-traced AO,
    /// over the image and in the discontinuity band, with every rule at half resolution and
    /// in the single pass at quarter resolution (docs/mixed-resolution.md; deinterleaved at
    /// quarter resolution bilinear is within 0.001 of it). Costs the most after classified:
    /// it needs every full-resolution pixel's normal (BENCHMARKS.md). Nearest-depth and
    /// classified keep edges as well but pass the low-resolution noise through unaveraged.
    #[default]
    Bilateral,
}

impl Upsampler {
    /// Every upsampler.
    pub const ALL: [Upsampler; 4] = [
        Upsampler::Bilinear,
        Upsampler::NearestDepth,
        Upsampler::Classified,
        Upsampler::Bilateral,
    ];

    /// Short name used by the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            Upsampler::Bilinear => "bilinear",
            Upsampler::NearestDepth => "nearest-depth",
            Upsampler::Classified => "classified",
            Upsampler::Bilateral => "bilateral",
        }
    }
}

/// Optional filtering of the AO at its working resolution, before upsampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Denoise {
    None,
    /// Edge-aware spatial denoiser (passes/denoise/denoise.wgsl): one pass of a joint bilateral
    /// filter (Tomasi & Manduchi 1998; Kopf et al. 2007) over exactly one jitter period,
    /// 3×3 for 2×2 deinterleaving, 5×5 for 4×4 patterns, whose spatial weights (1-2-1,
    /// 1-2-2-2-1) give every sampling pattern the same total weight, so the dither pattern
    /// cancels on a flat surface. Each tap is weighted by its distance from the centre's
    /// tangent plane and the centre's from its own, and by the angle between normals, so
    /// nothing crosses a depth edge or a crease. The output is the weighted least-squares
    /// plane's value at the centre (local linear regression, Buades, Coll & Morel 2006), not
    /// the weighted mean, so a kernel cut off on one side by a crease is not biased by the
    /// AO's gradient there. The default: on the nine shared views (640×400, lavapipe, mean
    /// RMSE against ray-traced AO) it lowers every GTAO preset in both layouts on every view
    /// but one (2×2 high 0.0658 → 0.0605, randomized high 0.0622 → 0.0578; house5 at
    /// randomized ultra +0.0005), for about 13 ms. docs/sample-reuse.md.
    #[default]
    Spatial,
    /// Seed 003's 2×2 box downsample of the AO (4 taps), then upsampling from that half
    /// size: averages the 2×2 pattern tile. Not depth-aware.
    Box,
    /// Seed 003's 6×6 tent downsample (9 taps on a 2-pixel grid, weights 1-2-1 × 1-2-1,
    /// each tap the mean of 2×2 texels), then upsampling. Not depth-aware.
    Tent,
}

impl Denoise {
    /// Every denoise choice.
    pub const ALL: [Denoise; 4] = [Denoise::None, Denoise::Spatial, Denoise::Box, Denoise::Tent];

    /// Short name used by the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            Denoise::None => "none",
            Denoise::Spatial => "spatial",
            Denoise::Box => "box",
            Denoise::Tent => "tent",
        }
    }

    /// Whether it halves the AO once more before upsampling.
    pub fn downsamples(self) -> bool {
        matches!(self, Denoise::Box | Denoise::Tent)
    }
}

/// How the depth pyramid's levels after the first are built (SAO and the classified
/// upsampler read it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PyramidBuild {
    /// Four levels per pass on GPUs, one per pass on CPU adapters (the default).
    #[default]
    Auto,
    /// One pass per level, each reading the level above: the fastest on CPU drivers,
    /// where workgroup barriers are expensive (lavapipe, 1920×1080 at half resolution:
    /// 9 ms for the 9 levels after the first, against 55 ms in three passes, BENCHMARKS.md).
    OneLevelPerPass,
    /// Four levels per pass (WebGPU's default limit of storage textures per stage),
    /// through workgroup memory: a quarter of the passes and barriers, as GPUs prefer.
    FourLevelsPerPass,
}

impl PyramidBuild {
    /// Every choice.
    pub const ALL: [PyramidBuild; 3] = [
        PyramidBuild::Auto,
        PyramidBuild::OneLevelPerPass,
        PyramidBuild::FourLevelsPerPass,
    ];

    /// Levels per pass on an adapter of `device_type`.
    pub fn levels_per_pass(self, device_type: wgpu::DeviceType) -> u32 {
        match self {
            PyramidBuild::Auto if device_type == wgpu::DeviceType::Cpu => 1,
            PyramidBuild::Auto | PyramidBuild::FourLevelsPerPass => 4,
            PyramidBuild::OneLevelPerPass => 1,
        }
    }
}

/// Creation-time choices: compiled into the shaders as WGSL `override` constants, because
/// constant loop bounds are markedly faster than uniforms on CPU drivers (see docs/design.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoOptions {
    /// The estimator. Default: GTAO.
    pub estimator: Estimator,
    /// Directions (HBAO, VO, VAO, SAO) or slices (GTAO) per pixel. Unit: count. Range 1..=64
    /// (64 × 64 is the screen-space reference's brute force).
    /// Default 3 (GTAO's `Preset::High` in the default layout; [`AoOptions::with_preset`]
    /// gives every estimator's, for any layout and resolution).
    pub directions: u32,
    /// Ray-march steps per direction. Unit: count. Range 1..=64. Default 5.
    /// Samples per pixel = `directions * steps`.
    pub steps: u32,
    /// Where GTAO's and the bitmask estimator's steps land along a direction (other
    /// estimators ignore it). 1: evenly, step k of S (jittered by j) at `1 + (k + j) · R_px/(S+1)`
    /// pixels, GTAO's march. e > 1: at `c + (1 + R_px · S/(S+1) − c) · ((k + j)/S)^e` pixels,
    /// `c` the sampling lattice's cell (1, or N in the N×N layouts), so closer together
    /// near the centre, where contact shadows a few pixels wide are (XeGTAO's sample
    /// distribution power). An `override` constant like `steps`: the even march compiles
    /// to exactly the code it was before the exponent existed. Range [1, 4].
    /// Default [`HIGH_MARCH_EXPONENT`], `Preset::High`'s in the default layout; counts
    /// picked by hand march evenly unless chosen otherwise: set [`EVEN_MARCH_EXPONENT`]
    /// with them, or use [`AoOptions::with_preset`].
    pub march_exponent: f32,
    /// Single randomized pass or N×N deinterleaving. Default: `Deinterleaved2`, the best
    /// quality per millisecond measured at full resolution (BENCHMARKS.md,
    /// docs/quality.md): never slower than the single pass, 1.4–2× faster at large radii,
    /// error within 1–2% of it (on an NVIDIA H100: 1.12–1.89×). `Deinterleaved4` is faster
    /// still on lavapipe at large on-screen radii (2–2.9×) but loses detail when the radius
    /// spans few pixels; on the H100 it is slower than the single pass at small radii and
    /// at best 1.34× (unfused), as its 16-layer split and denoise cost more than they save
    /// (BENCHMARKS.md, "On a hardware GPU"). Below full resolution
    /// prefer `Randomized`: a layer's samples are then N low-resolution texels (2N pixels)
    /// apart and the error rises (half resolution, bilateral: mean RMSE 0.095 against
    /// 0.079, docs/mixed-resolution.md) for 7% less time.
    pub mode: AoMode,
    /// Fuse the passes around the AO pass (true, default): in deinterleaved modes the
    /// prepare pass writes the layers and the AO pass writes full resolution directly;
    /// below full resolution the prepare pass writes the first downsampled level (and
    /// full-resolution linear depth) itself. False: separate split, merge and downsample
    /// passes over full-resolution intermediates, with the same results up to rounding
    /// (kept to measure the difference; tests compare the two). On an NVIDIA H100 unfused
    /// is 1.09–1.27× faster with `Deinterleaved4` and fused 1.05–1.09× faster with
    /// `Deinterleaved2` (BENCHMARKS.md, "On a hardware GPU").
    pub fused: bool,
    /// Per-pixel (or per-layer) rotation and offset of the samples (true, default). False:
    /// every pixel samples the same fixed pattern (rotation half a sector, offset ½) — the
    /// screen-space reference evaluates the estimator's integral this way, with no noise.
    pub jitter: bool,
    /// AO resolution. Default `Full`.
    pub resolution: Resolution,
    /// Depth downsampling rule below full resolution. Default `Checkerboard`.
    pub downsample: DepthDownsample,
    /// Below full resolution: move each picked sample along its own tangent plane to the
    /// centre of its low-resolution texel (true, default), so positions rebuilt at texel
    /// centres lie on the surface; the rule still picks one real sample (depth and normal
    /// of one surface, never an average). False: the picked depth as is, placed at the
    /// texel centre, which bends tilted surfaces by up to a pixel's slope, so flat surfaces
    /// read as bumpy and occlude themselves (test `recentred_levels_lie_on_the_surface`:
    /// relative depth error below 1e-4 recentred, above 1e-3 not).
    pub recentre: bool,
    /// Upsampler below full resolution (and after box/tent denoising). Default `Bilateral`.
    pub upsample: Upsampler,
    /// Filtering at the working resolution. Default `Spatial`.
    pub denoise: Denoise,
    /// How the depth pyramid is built. Default `Auto`.
    pub pyramid: PyramidBuild,
    /// Temporal accumulation (passes/temporal/temporal.wgsl): keep a history of the AO, reproject
    /// it with the camera motion of [`AoParams::motion`], reject it where the surface was
    /// not visible (disocclusion), clamp it to the current 3×3 neighbourhood and blend it
    /// with this frame's AO; the sampling patterns rotate every frame so frames stratify
    /// together. 0 = off (default); N ≥ 2: at most N frames of history (the blend weight
    /// of the current frame never drops below 1/N). Range 0 or 2..=256.
    pub history: u32,
    /// Bent normals beside the AO ([`crate::Ao::bent_normals`]): per pixel the unit,
    /// view-space, cosine-weighted mean of the unoccluded directions (Jimenez et al. 2016,
    /// sec. 5), integrated from the same horizons as the AO, for diffuse environment
    /// lighting and specular occlusion. Through the temporal pass, the spatial denoiser and
    /// the upsampler with the AO's texels and weights, so at full resolution; not through
    /// the box/tent filters (with them, at the working resolution). GTAO, HBAO and the bitmask
    /// ([`Estimator::has_bent_normals`]). Default `false`.
    pub bent_normals: bool,
    /// A second depth layer from the renderer ([`crate::AoInput::second_layer`]): the
    /// nearest surface behind each pixel's first one, peeled at the thickness prior behind
    /// it (depth peeling with a minimum separation, Mara, McGuire, Nowrouzezahrai & Luebke
    /// 2016, "Deep G-Buffers"). The bitmask estimator reads it where the first layer hides
    /// it, each layer a solid [`AoParams::thickness`] deep, so what stands behind a thin
    /// foreground object occludes too (docs/thickness.md). With a second layer a thinner
    /// prior than the one-layer default measured better: 0.75 (the layer behind now stands
    /// for what the prior stood for alone). Every frame must then give one.
    /// [`Estimator::Bitmask`] at [`Resolution::Full`] only (any layout, denoiser, history,
    /// bent normals). Default `false`.
    pub second_layer: bool,
}

/// The even march, [`AoOptions::march_exponent`] 1: GTAO's steps evenly spaced.
pub const EVEN_MARCH_EXPONENT: f32 = 1.0;

/// [`Preset::High`]'s march exponent for GTAO and the bitmask where the samples' lattice is
/// at most [`FINE_LATTICE_PX`] pixels, chosen over all shared views (docs/thickness.md).
pub const HIGH_MARCH_EXPONENT: f32 = 1.3;

/// The coarsest sampling lattice, in full-resolution pixels, at which `Preset::High`
/// crowds its steps toward the centre ([`AoOptions::lattice_px`]).
pub const FINE_LATTICE_PX: f32 = 2.0;

impl Default for AoOptions {
    fn default() -> Self {
        Self {
            estimator: Estimator::default(),
            // Preset::High for GTAO in the default layout (a test checks they agree).
            directions: 3,
            steps: 5,
            march_exponent: HIGH_MARCH_EXPONENT,
            mode: AoMode::default(),
            fused: true,
            jitter: true,
            resolution: Resolution::Full,
            downsample: DepthDownsample::Checkerboard,
            recentre: true,
            upsample: Upsampler::Bilateral,
            denoise: Denoise::Spatial,
            pyramid: PyramidBuild::Auto,
            history: 0,
            bent_normals: false,
            second_layer: false,
        }
    }
}

/// `Ok` when `ok`, else the invalid-setting error naming `field`, `value` and `expected`.
fn check<T: std::fmt::Display>(
    ok: bool,
    field: &'static str,
    value: T,
    expected: &'static str,
) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(Error::InvalidSetting {
            field,
            value: value.to_string(),
            expected,
        })
    }
}

impl AoOptions {
    /// The options of `preset` for `estimator` in the default layout and resolution (2×2
    /// layers, full resolution, fused); see [`Preset`]. For another layout or resolution,
    /// set them and then [`AoOptions::with_preset`].
    pub fn preset(estimator: Estimator, preset: Preset) -> Self {
        Self {
            estimator,
            ..Self::default()
        }
        .with_preset(preset)
    }

    /// These options with `preset`'s directions, steps and march exponent for their
    /// estimator, layout and resolution (see [`Preset`]); everything else is kept.
    pub fn with_preset(self, preset: Preset) -> Self {
        let marches = matches!(self.estimator, Estimator::Gtao | Estimator::Bitmask);
        let fine = self.lattice_px() <= FINE_LATTICE_PX;
        let (directions, steps, march_exponent) = match (marches, preset) {
            (true, Preset::Low) => (2, 2, EVEN_MARCH_EXPONENT),
            (true, Preset::Medium) => (2, 4, EVEN_MARCH_EXPONENT),
            (true, Preset::High) if fine => (3, 5, HIGH_MARCH_EXPONENT),
            (true, Preset::High) => (4, 4, EVEN_MARCH_EXPONENT),
            (true, Preset::Ultra) => (8, 6, EVEN_MARCH_EXPONENT),
            (false, Preset::Low) => (4, 2, EVEN_MARCH_EXPONENT),
            (false, Preset::Medium) => (4, 4, EVEN_MARCH_EXPONENT),
            (false, Preset::High) => (8, 4, EVEN_MARCH_EXPONENT),
            (false, Preset::Ultra) => (16, 6, EVEN_MARCH_EXPONENT),
        };
        Self {
            directions,
            steps,
            march_exponent,
            ..self
        }
    }

    /// The spacing of the lattice the AO pass samples on, in full-resolution pixels: the
    /// layout's split (1, 2 or 4) times the resolution's factor. `Scaled` counts at its
    /// smallest scale ([`MIN_SCALE`]), since its scale changes per frame.
    pub fn lattice_px(&self) -> f32 {
        let factor = match self.resolution {
            Resolution::Scaled => 1.0 / MIN_SCALE,
            r => r.factor() as f32,
        };
        self.mode.split() as f32 * factor
    }

    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        check(
            (1..=64).contains(&self.directions),
            "directions",
            self.directions,
            "an integer in 1..=64",
        )?;
        check(
            (1..=64).contains(&self.steps),
            "steps",
            self.steps,
            "an integer in 1..=64",
        )?;
        check(
            (1.0..=4.0).contains(&self.march_exponent),
            "march_exponent",
            self.march_exponent,
            "a number in [1, 4]",
        )?;
        check(
            self.history == 0 || (2..=256).contains(&self.history),
            "history",
            self.history,
            "0 (off) or a frame count in 2..=256",
        )?;
        check(
            !self.bent_normals || self.estimator.has_bent_normals(),
            "bent_normals",
            format!("true with estimator {}", self.estimator.name()),
            "false unless the estimator is gtao",
        )?;
        check(
            !self.second_layer
                || (self.estimator == Estimator::Bitmask && self.resolution == Resolution::Full),
            "second_layer",
            format!(
                "true with estimator {} at resolution {}",
                self.estimator.name(),
                self.resolution.name()
            ),
            "false unless the estimator is bitmask at full resolution",
        )?;
        if self.resolution == Resolution::Scaled {
            let e = self.estimator;
            check(
                !e.uses_pyramid() && !e.uses_moments(),
                "estimator",
                e.name(),
                "an estimator without depth mips (gtao, hbao, vo, vao) with resolution scaled",
            )?;
            check(
                self.upsample == Upsampler::Bilateral,
                "upsample",
                self.upsample.name(),
                "bilateral with resolution scaled",
            )?;
            check(
                matches!(self.denoise, Denoise::None | Denoise::Spatial),
                "denoise",
                self.denoise.name(),
                "none or spatial with resolution scaled",
            )?;
            check(
                !self.bent_normals,
                "bent_normals",
                "true",
                "false with resolution scaled",
            )?;
        }
        Ok(())
    }

    /// Side of the tile of sampling patterns on the AO's working grid: 2 in 2×2
    /// deinterleaving, 4 otherwise (the randomized pass's 4×4 table, 4×4 layers).
    pub fn pattern_period(&self) -> u32 {
        match self.mode {
            AoMode::Deinterleaved2 => 2,
            AoMode::Randomized | AoMode::Deinterleaved4 => 4,
        }
    }

    /// The screen-space reference of `estimator`: its integral brute-forced in one
    /// full-resolution pass with no jitter, 64 directions (slices) × 64 steps — what the
    /// estimator converges to as samples increase, given one depth layer. Comparing it with
    /// ray-traced AO measures the limits of the depth buffer; comparing an estimate with it
    /// measures the estimate's sampling error.
    pub fn screen_reference(estimator: Estimator) -> Self {
        Self {
            estimator,
            directions: 64,
            steps: 64,
            march_exponent: EVEN_MARCH_EXPONENT,
            mode: AoMode::Randomized,
            jitter: false,
            // The integral itself: no denoiser smoothing it (the default has one).
            denoise: Denoise::None,
            ..Self::default()
        }
    }

    /// Full-resolution pixels per pixel of the AO the upsampler reads (1: no upsampling).
    pub fn upsample_factor(&self) -> u32 {
        self.resolution.factor() * if self.denoise.downsamples() { 2 } else { 1 }
    }

    /// Whether the AO is written straight to the output by the AO pass (no post-processing).
    pub fn direct(&self) -> bool {
        self.resolution == Resolution::Full && self.denoise == Denoise::None && self.history == 0
    }

    /// Samples per pixel of the AO pass.
    pub fn samples_per_pixel(&self) -> u32 {
        match self.estimator {
            Estimator::Gtao | Estimator::Bitmask => 2 * self.directions * self.steps,
            Estimator::Hbao
            | Estimator::Vo
            | Estimator::Vao
            | Estimator::Sao
            | Estimator::VoArea => self.directions * self.steps,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        AoOptions::default().validate().unwrap();
        AoParams::default().validate().unwrap();
        assert_eq!(
            AoOptions::default(),
            AoOptions::preset(Estimator::Gtao, Preset::High)
        );
    }

    #[test]
    fn presets_cost_the_documented_samples_with_every_estimator() {
        for (preset, spp) in Preset::ALL.into_iter().zip([8, 16, 32, 96]) {
            for e in Estimator::ALL {
                AoOptions::preset(e, preset).validate().unwrap();
                for mode in AoMode::ALL {
                    for resolution in [
                        Resolution::Full,
                        Resolution::Half,
                        Resolution::Quarter,
                        Resolution::Scaled,
                    ] {
                        let o = AoOptions {
                            estimator: e,
                            mode,
                            resolution,
                            ..AoOptions::default()
                        }
                        .with_preset(preset);
                        // GTAO's and the bitmask's High on a fine lattice: 3 × 5 crowded.
                        let crowded = o.march_exponent != EVEN_MARCH_EXPONENT;
                        let expected = if crowded { 30 } else { spp };
                        assert_eq!(o.samples_per_pixel(), expected, "{e:?} {preset:?}");
                        assert_eq!(
                            crowded,
                            preset == Preset::High
                                && matches!(e, Estimator::Gtao | Estimator::Bitmask)
                                && (mode == AoMode::Randomized
                                    && resolution != Resolution::Quarter
                                    && resolution != Resolution::Scaled
                                    || mode == AoMode::Deinterleaved2
                                        && resolution == Resolution::Full),
                            "{e:?} {preset:?} {mode:?} {resolution:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn out_of_range_values_name_the_field() {
        let cases: [(AoParams, &str); 6] = [
            (
                AoParams {
                    radius: f32::NAN,
                    ..Default::default()
                },
                "radius",
            ),
            (
                AoParams {
                    bias_angle_deg: 75.0,
                    ..Default::default()
                },
                "bias_angle_deg",
            ),
            (
                AoParams {
                    strength: -1.0,
                    ..Default::default()
                },
                "strength",
            ),
            (
                AoParams {
                    max_radius_px: 0.0,
                    ..Default::default()
                },
                "max_radius_px",
            ),
            (
                AoParams {
                    scale: 0.2,
                    ..Default::default()
                },
                "scale",
            ),
            (
                AoParams {
                    scale: f32::NAN,
                    ..Default::default()
                },
                "scale",
            ),
        ];
        for (p, name) in cases {
            match p.validate() {
                Err(Error::InvalidSetting { field, .. }) => assert_eq!(field, name),
                other => panic!("{name}: expected InvalidSetting, got {other:?}"),
            }
        }
        let o = AoOptions {
            directions: 0,
            ..Default::default()
        };
        assert!(matches!(
            o.validate(),
            Err(Error::InvalidSetting {
                field: "directions",
                ..
            })
        ));
        // The scaled resolution names the option it cannot work with.
        let scaled = AoOptions {
            resolution: Resolution::Scaled,
            ..Default::default()
        };
        assert!(scaled.validate().is_ok());
        for (o, name) in [
            (
                AoOptions {
                    estimator: Estimator::Sao,
                    ..scaled
                },
                "estimator",
            ),
            (
                AoOptions {
                    upsample: Upsampler::Classified,
                    ..scaled
                },
                "upsample",
            ),
            (
                AoOptions {
                    denoise: Denoise::Box,
                    ..scaled
                },
                "denoise",
            ),
            (
                AoOptions {
                    bent_normals: true,
                    ..scaled
                },
                "bent_normals",
            ),
        ] {
            match o.validate() {
                Err(Error::InvalidSetting { field, .. }) => assert_eq!(field, name),
                other => panic!("{name}: expected InvalidSetting, got {other:?}"),
            }
        }
    }
}

//! The option types: which estimator, layout, resolution, denoiser and pyramid build an
//! [`AoOptions`](super::AoOptions) compiles, with the names the CLI and Python take.

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
    /// from the camera by [`AoParams::thickness`](crate::AoParams::thickness)), so thin objects no longer cast the
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

    /// Whether the estimator can output bent normals ([`AoOptions::bent_normals`](crate::AoOptions::bent_normals)): GTAO
    /// and HBAO, whose horizons bound the unoccluded arc of every slice or direction, and
    /// the bitmask, whose clear sectors are that arc.
    pub fn has_bent_normals(self) -> bool {
        matches!(self, Estimator::Gtao | Estimator::Hbao | Estimator::Bitmask)
    }
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
    /// Any scale in [1/4, 1], chosen per frame ([`AoParams::scale`](crate::AoParams::scale); a frame-budget
    /// controller sets it, [`crate::budget::ScaleController`]): the AO grid is
    /// `ceil(full × scale)`. Textures are created once for scale 1. Each working texel takes
    /// the prepared value of one of the full-resolution pixels it covers, chosen by
    /// [`AoOptions::downsample`](crate::AoOptions::downsample)'s rule among the 2 × 2 nearest its centre (at scale 1/2
    /// half resolution's picks), recentred along its tangent plane (passes/pyramid/rescale.wgsl);
    /// the AO comes back through
    /// the joint bilateral upsampler at that scale (passes/upsample/upsample_scaled.wgsl). Temporal
    /// accumulation (with [`AoOptions::history`](crate::AoOptions::history)) runs on the working grid, reprojecting
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

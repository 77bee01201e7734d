//! Settings. [`AoOptions`] fixes what can run and is compiled into pipelines at creation;
//! [`AoParams`] is cheap to change every frame. Both validate before any GPU work.

mod choices;
mod params;
mod presets;

pub use choices::{
    by_name, AoMode, Denoise, DepthDownsample, Estimator, PyramidBuild, Resolution, Upsampler,
};
pub use params::{AoParams, CameraMotion, DepthNoise, DEFAULT_THICKNESS, MIN_SCALE};
pub use presets::{
    Preset, EVEN_MARCH_EXPONENT, FINE_LATTICE_PX, HIGH_MARCH_EXPONENT, LAYERED_GUARD_BAND,
    LAYERED_THICKNESS,
};

use crate::{Error, Result};

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
    /// Ray-march steps per direction. Unit: count. Range 1..=64. Default 6.
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

impl Default for AoOptions {
    fn default() -> Self {
        Self {
            estimator: Estimator::default(),
            // Preset::High for GTAO in the default layout (a test checks they agree).
            directions: 3,
            steps: 6,
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

/// The estimator for a depth map given alone (`obscura render --depth`, Python), where
/// normals come from the depth and accuracy counts for more than a millisecond: the
/// visibility bitmask, at the same preset. On the nine shared views from depth alone it
/// scores 0.0638 RMSE against 0.0643 for GTAO on clean depth and 0.0941 against 0.0947 on
/// Kinect-like depth (higher on two views and one), at 1.3–1.4× GTAO's time on lavapipe
/// (docs/guide/depth-maps.md). A renderer's frame keeps [`Estimator::default`].
pub const DEPTH_MAP_ESTIMATOR: Estimator = Estimator::Bitmask;

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

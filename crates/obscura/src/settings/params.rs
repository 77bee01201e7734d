//! Per-frame parameters ([`AoParams`]): the radius and strength, the camera's motion for
//! temporal accumulation, the working scale, and the depth noise model ([`DepthNoise`]).

use super::check;
use crate::Result;

/// Per-pixel depth uncertainty of the input, σ(d) = `constant` + `linear` · d +
/// `quadratic` · d² (clamped at 0), in view-space units at linear view depth d. A
/// structured-light sensor in metres: σ ≈ 0.0015 · d² (Khoshelham & Elberink 2012); a
/// stereo rig: σ ≈ δ / (f · B) · d² for disparity error δ pixels, focal length f pixels and
/// baseline B; integer encodings add their quantisation step / √12. Integer maps also
/// store depth in terraces of `step(d)` = max(`step_constant`, `step_quadratic` · d²)
/// (the encoding's unit; a sensor quantising disparity, Smisek et al. 2011): a fitting
/// window narrower than a terrace sees a flat surface, and the next terrace sits a whole
/// step away, however small σ is. When σ is non-zero: normals and depth come from planes
/// fitted over a window wide enough for σ and for the terraces, taking taps within the
/// noise and one step of the plane (passes/prepare/normals_fit.wgsl), and the estimators measure
/// occluders from the surface
/// raised [`crate::passes::constants::NOISE_OFFSET_SIGMAS`] σ along its normal, so noise near the
/// tangent plane does not read as occlusion. Zero (the default): rendered depth, the
/// passes are those without a noise model. The plane-fitting prepare pass is compiled on
/// the first frame that gives a noise model.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct DepthNoise {
    /// σ at depth 0, view-space units. Range: finite, ≥ 0.
    pub constant: f32,
    /// dσ/dd at depth 0 (unitless). Range: finite (negative allowed: a square in d).
    pub linear: f32,
    /// The d² coefficient, 1 / view-space units. Range: finite, ≥ 0.
    pub quadratic: f32,
    /// The terraces' smallest step, view-space units (an integer map's unit). Range:
    /// finite, ≥ 0. Used only where σ is non-zero.
    pub step_constant: f32,
    /// The terraces' step over d², 1 / view-space units. Range: finite, ≥ 0.
    pub step_quadratic: f32,
}

impl DepthNoise {
    /// No noise: clean rendered depth.
    pub const NONE: DepthNoise = DepthNoise {
        constant: 0.0,
        linear: 0.0,
        quadratic: 0.0,
        step_constant: 0.0,
        step_quadratic: 0.0,
    };

    /// Whether σ is zero everywhere (the steps matter only with noise).
    pub fn is_none(&self) -> bool {
        self.constant == 0.0 && self.linear == 0.0 && self.quadratic == 0.0
    }

    /// σ at linear depth `d` (common.wgsl, `depth_sigma`).
    pub fn sigma(&self, d: f32) -> f32 {
        (self.constant + (self.linear + self.quadratic * d) * d).max(0.0)
    }

    /// The terraces' step at linear depth `d` (common.wgsl, `depth_step`).
    pub fn step(&self, d: f32) -> f32 {
        self.step_constant.max(self.step_quadratic * d * d)
    }
}

/// Per-frame parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoParams {
    /// Radius of the sampled disk, in view-space units (metres for a metre-scaled scene).
    /// Range: finite, > 0. Default 1.0.
    pub radius: f32,
    /// Tangent bias angle in degrees: horizons less than this above the tangent plane do not
    /// occlude (hides tessellation and depth-precision noise). HBAO and SAO only; the other
    /// estimators take none. Range 0..60. Default 10.
    pub bias_angle_deg: f32,
    /// Multiplier on the occlusion (1 = the estimator's own value). Range 0..=4. Default 1.
    pub strength: f32,
    /// The on-screen radius is clamped to this many pixels (keeps near-camera cost bounded).
    /// Range 1..=4096. Default 256.
    pub max_radius_px: f32,
    /// How the camera moved since the previous frame (used with [`AoOptions::history`]).
    /// Default [`CameraMotion::Still`].
    pub motion: CameraMotion,
    /// The depth input's noise σ(d) (see [`DepthNoise`]). Default none (rendered depth).
    pub depth_noise: DepthNoise,
    /// Working pixels per full-resolution pixel along each axis with
    /// [`Resolution::Scaled`]; must be 1 otherwise. Range [0.25, 1]. Default 1.
    pub scale: f32,
    /// How deep a surface is behind the depth seen, as a multiple of [`AoParams::radius`]:
    /// the thickness prior of [`crate::Estimator::Bitmask`] (other estimators ignore it).
    /// One depth layer cannot show how far an object extends away from the camera; this
    /// assumes every object is this deep there (docs/thickness.md); the part of such a
    /// solid within the radius occludes, even where its front lies beyond it.
    /// `f32::INFINITY`: infinitely thick, GTAO's assumption (a sample's front counts in full
    /// within the radius, in part up to `GTAO_FALLOFF_END` radii, passes/constants.rs).
    /// Range > 0. Default [`DEFAULT_THICKNESS`].
    pub thickness: f32,
}

/// The default [`AoParams::thickness`], chosen over all shared views (docs/thickness.md).
pub const DEFAULT_THICKNESS: f32 = 1.0;

/// The camera's motion since the previous recorded frame, for temporal accumulation.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum CameraMotion {
    /// The same camera as last frame (the history is reused as is).
    #[default]
    Still,
    /// The camera moved: `previous_from_current` (column-major, `m[column][row]`) takes
    /// this frame's view-space points to the previous frame's view space, i.e.
    /// `previous_view * inverse(current_view)` for world-to-view matrices. Must be a rigid
    /// motion (rotation and translation). The projection may change too; the previous one
    /// is remembered.
    Moved {
        previous_from_current: [[f32; 4]; 4],
    },
    /// A camera cut: the history is discarded.
    Cut,
}

impl Default for AoParams {
    fn default() -> Self {
        Self {
            radius: 1.0,
            bias_angle_deg: 10.0,
            strength: 1.0,
            max_radius_px: 256.0,
            motion: CameraMotion::Still,
            depth_noise: DepthNoise::NONE,
            scale: 1.0,
            thickness: DEFAULT_THICKNESS,
        }
    }
}

/// The smallest [`AoParams::scale`].
pub const MIN_SCALE: f32 = 0.25;

impl AoParams {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        check(
            self.radius.is_finite() && self.radius > 0.0,
            "radius",
            self.radius,
            "a finite number > 0 (view-space units)",
        )?;
        check(
            (0.0..60.0).contains(&self.bias_angle_deg),
            "bias_angle_deg",
            self.bias_angle_deg,
            "degrees in [0, 60)",
        )?;
        check(
            (0.0..=4.0).contains(&self.strength),
            "strength",
            self.strength,
            "a number in [0, 4]",
        )?;
        check(
            (1.0..=4096.0).contains(&self.max_radius_px),
            "max_radius_px",
            self.max_radius_px,
            "pixels in [1, 4096]",
        )?;
        check(
            self.thickness > 0.0 && !self.thickness.is_nan(),
            "thickness",
            self.thickness,
            "a number > 0 (times the radius), or infinity",
        )?;
        check(
            (MIN_SCALE..=1.0).contains(&self.scale),
            "scale",
            self.scale,
            "a number in [0.25, 1]",
        )?;
        if let CameraMotion::Moved {
            previous_from_current: m,
        } = self.motion
        {
            let rigid = crate::depth::input::is_rigid(&m);
            check(
                rigid,
                "motion",
                format!("{m:?}"),
                "a finite rigid transform (orthonormal rotation, translation, last row 0 0 0 1)",
            )?;
        }
        let n = self.depth_noise;
        check(
            n.constant.is_finite() && n.constant >= 0.0,
            "depth_noise.constant",
            n.constant,
            "a finite number >= 0 (view-space units)",
        )?;
        check(
            n.linear.is_finite(),
            "depth_noise.linear",
            n.linear,
            "a finite number",
        )?;
        check(
            n.quadratic.is_finite() && n.quadratic >= 0.0,
            "depth_noise.quadratic",
            n.quadratic,
            "a finite number >= 0 (1 / view-space units)",
        )?;
        check(
            n.step_constant.is_finite() && n.step_constant >= 0.0,
            "depth_noise.step_constant",
            n.step_constant,
            "a finite number >= 0 (view-space units)",
        )?;
        check(
            n.step_quadratic.is_finite() && n.step_quadratic >= 0.0,
            "depth_noise.step_quadratic",
            n.step_quadratic,
            "a finite number >= 0 (1 / view-space units)",
        )
    }
}

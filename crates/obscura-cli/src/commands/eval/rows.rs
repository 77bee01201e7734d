//! One evaluated variant on one view (`Row`), with the bent-normal and temporal figures it
//! may carry, and the bent normals' error against the ray tracer's.

pub(super) struct Row {
    pub(super) view: String,
    pub(super) variant: String,
    /// Estimator name ("none" for the white baseline) and mode ("" for the baseline,
    /// "screen-reference" for the screen-space reference).
    pub(super) estimator: String,
    pub(super) mode: String,
    pub(super) rmse: f32,
    pub(super) bias: f32,
    pub(super) ssim: f32,
    /// Mean ꟻLIP against the truth (obscura_eval::flip).
    pub(super) flip: f32,
    /// Whether this is the library's default frame (`EvalArgs::default_frame`, no guard band,
    /// the default thickness, full scale, one frame).
    pub(super) default: bool,
    pub(super) band_rmse: f32,
    /// RMSE against the estimator's own screen-space reference: its sampling error.
    pub(super) screen_rmse: Option<f32>,
    /// Mean difference from the estimator's own screen-space reference: the sampling's
    /// bias (a maximum over a few steps reads horizons low, so GTAO's is positive).
    pub(super) screen_bias: Option<f32>,
    /// Mean ꟻLIP against the estimator's own screen-space reference: how visible the
    /// sampling pattern is (streaks, noise).
    pub(super) screen_flip: Option<f32>,
    /// Below full resolution (or with denoising): RMSE over the image and over the band
    /// against the same estimator and mode at full resolution.
    pub(super) full_rmse: Option<(f32, f32)>,
    pub(super) ms: Option<f64>,
    /// With --frames: the temporal figures.
    pub(super) temporal: Option<TemporalFigures>,
    /// With --frames, for every variant: the flicker of the orbit's last two frames
    /// (eval/flicker.rs).
    pub(super) orbit_flicker: Option<f32>,
    /// With --bent-normals: the bent normals' angles to the traced ones.
    pub(super) bent: Option<BentError>,
}

/// Mean angles (degrees) to the ray-traced bent normal, over the compared pixels and over
/// the occluded ones (traced AO < [`OCCLUDED`]): of the estimate's bent normal, and of the
/// surface normal the estimate used.
#[derive(Clone, Copy, Debug)]
pub(super) struct BentError {
    pub(super) bent: f32,
    pub(super) bent_occluded: f32,
    pub(super) normal: f32,
    pub(super) normal_occluded: f32,
}

/// Traced AO below which a pixel counts as occluded for [`BentError`].
pub(super) const OCCLUDED: f32 = 0.9;

/// [`BentError`] of `bent` (rgba per pixel) and the prepared normals (`vec4(d, n)` per
/// pixel) against `truth`'s bent normals, where `mask` holds and both are defined.
pub(super) fn bent_error(
    bent: &[f32],
    prepared: &[f32],
    truth: &obscura_eval::ReferenceAo,
    mask: &[bool],
) -> BentError {
    use glam::Vec3;
    let angle = |a: Vec3, b: Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees() as f64;
    // Sums of (bent angle, normal angle, count), all pixels and occluded ones.
    let (mut all, mut occ) = ([0.0f64; 3], [0.0f64; 3]);
    for (i, m) in mask.iter().enumerate() {
        let t = Vec3::from(truth.bent[i]);
        let g = Vec3::from_slice(&bent[4 * i..4 * i + 3]);
        let n = Vec3::from_slice(&prepared[4 * i + 1..4 * i + 4]);
        if !m || t.length_squared() < 0.25 || g.length_squared() < 0.25 {
            continue;
        }
        let (b, nn) = (angle(g, t), angle(n.normalize_or_zero(), t));
        for (acc, on) in [(&mut all, true), (&mut occ, truth.ao[i] < OCCLUDED)] {
            if on {
                acc[0] += b;
                acc[1] += nn;
                acc[2] += 1.0;
            }
        }
    }
    let mean = |acc: [f64; 3], k: usize| (acc[k] / acc[2].max(1.0)) as f32;
    BentError {
        bent: mean(all, 0),
        bent_occluded: mean(occ, 0),
        normal: mean(all, 1),
        normal_occluded: mean(occ, 1),
    }
}

/// How temporal accumulation behaves on one view (`eval --frames N`).
#[derive(Clone, Copy, Debug)]
pub(super) struct TemporalFigures {
    /// N: frames of the still camera and of the orbit.
    pub(super) frames: u32,
    /// Mean |AO(frame N+1) − AO(frame N)| of a still camera.
    pub(super) flicker: f32,
    /// RMSE of the last frame of the orbit.
    pub(super) orbit_rmse: f32,
    /// Pixels of the orbit's last frame that became visible 4 frames before it (history of
    /// 5 frames): their RMSE after the orbit, their RMSE in the still camera's converged
    /// image, and how many there are.
    pub(super) disoccluded: Option<(f32, f32, usize)>,
}

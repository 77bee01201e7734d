//! Estimating a depth map's noise σ(d) from the data itself, for [`crate::DepthNoise`].
//!
//! Every 3×3 window whose nine depths are valid gets a least-squares plane (in 1/d for a
//! perspective camera, where planes are exactly linear in pixel position; in d for an
//! orthographic one). With independent noise of deviation σ on each tap, the residual sum
//! of squares over σ² follows χ² with 9 − 3 = 6 degrees of freedom (the standard
//! regression result; noise-level estimation from local-fit residuals as in Immerkær 1996,
//! "Fast noise variance estimation", and Förstner 2000). The windows are sorted by depth
//! into bins of equal count; in each bin the 5th-percentile window estimates σ, so windows
//! across depth edges and creases (whose residual is geometry, not noise) do not count
//! unless they are nearly all of it (the median overestimated σ up to 2× on the shared
//! city and voxel views; docs/depth-noise.md).
//!
//! Integer-encoded maps are also quantised: at least their unit step, and coarser where the
//! sensor quantises disparity (structured light and stereo store depth in terraces whose
//! step grows as d²; Khoshelham & Elberink 2012, Smisek et al. 2011). Where at least half
//! of a bin's windows (taken with its two neighbour bins) read exactly the same depth as
//! the next pixel along the plane's steeper axis, the map resolves less than
//! the surfaces' change per pixel, and its typical non-zero step between neighbours (the
//! lower quartile, steps under 5% of the depth so edges do not count) is its resolution.
//! Terraces leave the 3×3 residuals at zero, so a bin's σ is the larger of the residuals'
//! and the step's / √12 (uniform quantisation error).
//!
//! σ(d) = C + L·d + Q·d² is then fitted to a running median (3 bins) of the bins' σ by
//! least squares in relative error, with C ≥ 0 and Q ≥ 0.
//!
//! Where some bin shows terraces, the model also carries their step (the fit of the
//! prepare pass spans them, [`DepthNoise::step`]): the encoding's unit, and the median of
//! step / d² over bins whose terraces are coarser than the unit. Noise of half a step or
//! more dithers terraces away (Widrow & Kollár 2008), leaving no ties: then no step.

use crate::passes::constants::DEPTH_RANGE_TOLERANCE;
use crate::{DepthNoise, Error, Projection, Result};

/// The quantile of the windows' residuals that estimates σ in a bin, and that quantile of
/// χ² with 6 degrees of freedom (the 3×3 window's residual dof).
const QUANTILE: f64 = 0.05;
const CHI2_6_QUANTILE: f64 = 1.635_382_894;
/// Most depth bins the model is fitted to.
const BINS: usize = 16;
/// Fewest windows per bin.
const MIN_PER_BIN: usize = 256;
/// Most windows examined (larger maps are sampled on a regular grid).
const MAX_WINDOWS: usize = 1 << 20;
/// Noise whose σ is below this fraction of a pixel's footprint everywhere tilts the
/// three-pixel normals by under ~1° and moves the surface by under 2% of a pixel: it is
/// dropped, so clean (rendered) depth keeps the passes without a noise model.
pub const NEGLIGIBLE_SIGMA_PX: f32 = 0.02;

/// One depth bin of an estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseBin {
    /// The bin's median depth.
    pub depth: f32,
    /// σ measured in the bin (view-space units).
    pub sigma: f32,
    /// 3×3 windows in the bin.
    pub windows: usize,
    /// The terraces' step measured in the bin: 0 for float maps and where at most half of
    /// the windows tie with a neighbour (no terraces, or noise dithers them away).
    pub step: f32,
}

/// What [`DepthNoise::estimate`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseEstimate {
    /// The fitted model; [`DepthNoise::NONE`] when the noise is negligible
    /// ([`NEGLIGIBLE_SIGMA_PX`]) or there is too little valid depth to measure it.
    pub model: DepthNoise,
    /// The measured bins, nearest first (empty with too little valid depth).
    pub bins: Vec<NoiseBin>,
    /// The largest σ of the fitted model over the bins, in pixel footprints.
    pub sigma_px: f32,
}

impl DepthNoise {
    /// Estimates σ(d) of a linear-depth map (`width` × `height`, row-major, view-space
    /// units; values ≤ 0 or not finite are holes) seen through `projection`. `quantum`: the
    /// step of an integer encoding in view units (a millimetre PNG read in metres: 0.001),
    /// `None` for float data. See the module documentation for the method. Errors only on a
    /// `depth` of the wrong length.
    pub fn estimate(
        depth: &[f32],
        width: u32,
        height: u32,
        projection: &Projection,
        quantum: Option<f32>,
    ) -> Result<NoiseEstimate> {
        let (w, h) = (width as usize, height as usize);
        if depth.len() != w * h {
            return Err(Error::InvalidTexture {
                what: "depth map",
                reason: format!("{} values for {width}x{height}", depth.len()),
            });
        }
        let persp = projection.is_perspective();
        // A pixel's footprint: `footprint * d` (perspective) or `footprint` (orthographic).
        let footprint = 2.0 * projection.ndc_to_view_scale()[1] / height.max(1) as f32;
        let windows = residuals(depth, w, h, persp);
        let none = NoiseEstimate {
            model: DepthNoise::NONE,
            bins: Vec::new(),
            sigma_px: 0.0,
        };
        let count = (windows.len() / MIN_PER_BIN).min(BINS);
        if count < 1 {
            return Ok(none);
        }
        let mut windows = windows;
        windows.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let bins: Vec<NoiseBin> = (0..count)
            .map(|i| {
                let slice = &windows[i * windows.len() / count..(i + 1) * windows.len() / count];
                let depth = slice[slice.len() / 2].0;
                let mut s2: Vec<f64> = slice.iter().map(|w| w.1).collect();
                let k = (QUANTILE * s2.len() as f64) as usize;
                let q = *s2.select_nth_unstable_by(k, f64::total_cmp).1;
                let sigma = (6.0 * q / CHI2_6_QUANTILE).sqrt() as f32;
                // Terraces from this bin and its neighbours: one bin may hold a single
                // terrace, whose steps are at its edges.
                let around = &windows[i.saturating_sub(1) * windows.len() / count
                    ..(i + 2).min(count) * windows.len() / count];
                let terrace = quantum.map_or(0.0, |_| terrace_step(around, depth));
                let step = if terrace > 0.0 {
                    quantum.unwrap_or(0.0).max(terrace)
                } else {
                    0.0
                };
                NoiseBin {
                    depth,
                    sigma: sigma.max(quantum.unwrap_or(0.0).max(step) / 12f32.sqrt()),
                    windows: slice.len(),
                    step,
                }
            })
            .collect();
        // Terraces where some bin shows them; none where the noise dithers them away
        // (noise of half a step or more, Widrow & Kollár 2008: no ties to see).
        let unit = quantum.unwrap_or(0.0);
        let terraced = bins.iter().any(|b| b.step > 0.0);
        let model = DepthNoise {
            step_constant: if terraced { unit } else { 0.0 },
            step_quadratic: step_quadratic(&bins, unit),
            ..fit_model(&bins)
        };
        let px = |d: f32| if persp { footprint * d } else { footprint };
        let sigma_px = bins
            .iter()
            .map(|b| model.sigma(b.depth) / px(b.depth))
            .fold(0.0f32, f32::max);
        // Noise is negligible when the fitted model is, or when most bins measure none
        // (the rest are geometry: curvature at the pixel scale, edges).
        let mut measured: Vec<f32> = bins.iter().map(|b| b.sigma / px(b.depth)).collect();
        let mid = measured.len() / 2;
        let median_px = *measured.select_nth_unstable_by(mid, f32::total_cmp).1;
        Ok(NoiseEstimate {
            model: if sigma_px < NEGLIGIBLE_SIGMA_PX || median_px < NEGLIGIBLE_SIGMA_PX {
                DepthNoise::NONE
            } else {
                model
            },
            bins,
            sigma_px,
        })
    }
}

/// The d² law of a sensor that quantises disparity: the median of step / d² over the bins
/// whose terraces are coarser than the encoding's `unit` (by half again, so a map that is
/// only quantised by its encoding gets 0).
fn step_quadratic(bins: &[NoiseBin], unit: f32) -> f32 {
    let mut k: Vec<f32> = bins
        .iter()
        .filter(|b| b.step > 1.5 * unit && b.depth > 0.0)
        .map(|b| b.step / (b.depth * b.depth))
        .collect();
    if k.is_empty() {
        return 0.0;
    }
    let mid = k.len() / 2;
    *k.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// A bin's terrace step: with at least half of its windows' differences along the
/// gradient exactly zero, the lower quartile of the others below 5% of `depth` (larger
/// ones are edges); else 0.
fn terrace_step(windows: &[Window], depth: f32) -> f32 {
    let diffs = || windows.iter().map(|w| w.2);
    let ties = diffs().filter(|&d| d == 0.0).count();
    if 2 * ties < windows.len() {
        return 0.0;
    }
    let mut steps: Vec<f32> = diffs()
        .filter(|&d| d > 0.0 && d < DEPTH_RANGE_TOLERANCE * depth)
        .collect();
    if steps.is_empty() {
        return 0.0;
    }
    let k = steps.len() / 4;
    *steps.select_nth_unstable_by(k, f32::total_cmp).1
}

/// A 3×3 window: centre depth, residual variance (depth units²) and the centre's absolute
/// difference to its neighbour along the fitted plane's steeper axis (right or below): a
/// floor seen straight has equal depths along each row whatever its quantisation.
type Window = (f32, f64, f32);

/// Every fully valid 3×3 window (on a grid of stride ≥ 1 keeping at most [`MAX_WINDOWS`]).
fn residuals(depth: &[f32], w: usize, h: usize, persp: bool) -> Vec<Window> {
    if w < 3 || h < 3 {
        return Vec::new();
    }
    let stride = (((w - 2) * (h - 2)) as f64 / MAX_WINDOWS as f64)
        .sqrt()
        .ceil()
        .max(1.0) as usize;
    let mut out = Vec::with_capacity(((w - 2) / stride + 1) * ((h - 2) / stride + 1));
    let mut f = [0.0f64; 9];
    for y in (1..h - 1).step_by(stride) {
        'pixel: for x in (1..w - 1).step_by(stride) {
            for (k, v) in f.iter_mut().enumerate() {
                let d = depth[(y + k / 3 - 1) * w + x + k % 3 - 1];
                if !(d > 0.0 && d.is_finite()) {
                    continue 'pixel;
                }
                *v = if persp { 1.0 / d as f64 } else { d as f64 };
            }
            // On the full 3×3 grid the plane's three columns are orthogonal: the mean, and
            // Σu·f / 6, Σv·f / 6 for offsets u, v ∈ {−1, 0, 1}.
            let mean = f.iter().sum::<f64>() / 9.0;
            let (mut gu, mut gv) = (0.0, 0.0);
            for (k, v) in f.iter().enumerate() {
                gu += ((k % 3) as f64 - 1.0) * v;
                gv += ((k / 3) as f64 - 1.0) * v;
            }
            let (gu, gv) = (gu / 6.0, gv / 6.0);
            let rss: f64 = f
                .iter()
                .enumerate()
                .map(|(k, v)| {
                    let r = v - mean - gu * ((k % 3) as f64 - 1.0) - gv * ((k / 3) as f64 - 1.0);
                    r * r
                })
                .sum();
            let d = depth[y * w + x];
            // δd = d² δ(1/d) in perspective.
            let to_depth = if persp { (d as f64).powi(4) } else { 1.0 };
            let next = if gu.abs() >= gv.abs() {
                y * w + x + 1
            } else {
                (y + 1) * w + x
            };
            out.push((d, rss / 6.0 * to_depth, (depth[next] - d).abs()));
        }
    }
    out
}

/// σ(d) fitted to the bins after a running median over 3 bins in depth order: a lone bin
/// can be all edges, or all one terrace of a quantised map.
fn fit_model(bins: &[NoiseBin]) -> DepthNoise {
    let smoothed: Vec<NoiseBin> = (0..bins.len())
        .map(|i| {
            let mut s: Vec<f32> = bins[i.saturating_sub(1)..(i + 2).min(bins.len())]
                .iter()
                .map(|b| b.sigma)
                .collect();
            s.sort_by(f32::total_cmp);
            NoiseBin {
                sigma: s[s.len() / 2],
                ..bins[i]
            }
        })
        .collect();
    fit_bins(&smoothed)
}

/// σ(d) = C + L·d + Q·d² fitted to the bins in relative error (each bin weighted by
/// 1 / σ², σ at least a quarter of the median bin's), with C ≥ 0 and Q ≥ 0: the best of
/// the unconstrained fit and those with C, Q or both held at 0 that respect the bounds.
fn fit_bins(bins: &[NoiseBin]) -> DepthNoise {
    let mut sigmas: Vec<f32> = bins.iter().map(|b| b.sigma).collect();
    let mid = sigmas.len() / 2;
    let median = *sigmas.select_nth_unstable_by(mid, f32::total_cmp).1 as f64;
    // Depth and σ in units of the farthest bin's depth and the median σ, so the normal
    // equations are well conditioned.
    let unit_d = bins
        .iter()
        .map(|b| b.depth as f64)
        .fold(f64::MIN_POSITIVE, f64::max);
    let unit_s = median.max(1e-7 * unit_d);
    let rows: Vec<([f64; 3], f64, f64)> = bins
        .iter()
        .map(|b| {
            let d = b.depth as f64 / unit_d;
            let s = b.sigma as f64 / unit_s;
            // The floors keep a clean bin (σ ≈ 0) from taking all the weight.
            let weight = 1.0 / s.max(0.25).max(1e-7 * d * unit_d / unit_s).powi(2);
            ([1.0, d, d * d], s, weight)
        })
        .collect();
    let mut best: Option<(f64, [f64; 3])> = None;
    for free in [
        [true, true, true],
        [false, true, true],
        [true, true, false],
        [false, true, false],
    ] {
        // Normal equations over the free coefficients; a held one gets the row c_k = 0.
        let mut a = glam::DMat3::ZERO;
        let mut r = glam::DVec3::ZERO;
        for (x, s, wt) in &rows {
            let x = glam::DVec3::from_array(*x)
                * glam::DVec3::select(free.into(), glam::DVec3::ONE, glam::DVec3::ZERO);
            a += glam::DMat3::from_cols(x * x.x, x * x.y, x * x.z) * *wt;
            r += x * (wt * s);
        }
        for (k, &f) in free.iter().enumerate() {
            if !f {
                a.col_mut(k)[k] = 1.0;
            }
        }
        // Singular relative to the columns' own scales (1, d, d²).
        let scale = a.x_axis.x * a.y_axis.y * a.z_axis.z;
        let det = a.determinant();
        if det.abs().partial_cmp(&(1e-12 * scale.abs())) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let c = (a.inverse() * r).to_array();
        if c[0] < 0.0 || c[2] < 0.0 {
            continue;
        }
        let cost: f64 = rows
            .iter()
            .map(|(x, s, wt)| {
                let m = (c[0] + c[1] * x[1] + c[2] * x[2]).max(0.0);
                wt * (m - s).powi(2)
            })
            .sum();
        if best.is_none_or(|(b, _)| cost < b) {
            best = Some((cost, c));
        }
    }
    match best {
        Some((_, c)) => DepthNoise {
            constant: (c[0] * unit_s) as f32,
            linear: (c[1] * unit_s / unit_d) as f32,
            quadratic: (c[2] * unit_s / (unit_d * unit_d)) as f32,
            ..DepthNoise::NONE
        },
        None => DepthNoise::NONE,
    }
}

/// A small deterministic generator (SplitMix64, Steele et al. 2014) with Gaussian draws
/// (Box–Muller), so simulated noise (sensor depth in `obscura eval`, the tests) is the same
/// on every run and every machine.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1].
    pub fn unit(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }

    /// A standard normal draw.
    pub fn gaussian(&mut self) -> f32 {
        let (u, v) = (self.unit(), self.unit());
        ((-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 320;
    const H: u32 = 240;

    fn camera() -> Projection {
        Projection::Perspective {
            fov_y: 1.0,
            aspect: W as f32 / H as f32,
            near: 0.1,
            far: 100.0,
        }
    }

    /// Linear depth of a floor tilted away from the camera: every row at its own depth,
    /// from about 1 to 4 view units, and sky (0) above the horizon.
    fn floor() -> Vec<f32> {
        let t = (0.5f32).tan();
        (0..W * H)
            .map(|i| {
                let y = 1.0 - 2.0 * ((i / W) as f32 + 0.5) / H as f32;
                // The plane y = −1 seen by rays (…, y·t, −1): d = 1 / (−y t) for y < 0.
                let dy = -y * t;
                if dy > 1.0 / 4.0 {
                    1.0 / dy
                } else {
                    0.0
                }
            })
            .collect()
    }

    fn add_noise(depth: &[f32], model: &DepthNoise, seed: u64) -> Vec<f32> {
        let mut rng = Rng(seed);
        depth
            .iter()
            .map(|&d| {
                let g = rng.gaussian();
                if d > 0.0 {
                    d + model.sigma(d) * g
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// On a noisy plane every bin measures the σ the noise was drawn with (within 10%:
    /// each bin holds ≥ 256 windows of 6 dof, a relative standard error of a few %), and
    /// the fitted model follows it.
    #[test]
    fn recovers_the_sigma_of_a_noisy_plane() {
        for model in [
            DepthNoise {
                constant: 0.0,
                linear: 0.0,
                quadratic: 0.002,
                ..DepthNoise::NONE
            },
            DepthNoise {
                constant: 0.003,
                ..DepthNoise::NONE
            },
            DepthNoise {
                constant: 0.001,
                linear: 0.002,
                quadratic: 0.0005,
                ..DepthNoise::NONE
            },
        ] {
            let depth = add_noise(&floor(), &model, 7);
            let e = DepthNoise::estimate(&depth, W, H, &camera(), None).unwrap();
            assert!(e.bins.len() >= 8, "{e:?}");
            for b in &e.bins {
                let truth = model.sigma(b.depth);
                assert!(
                    (b.sigma / truth - 1.0).abs() < 0.1,
                    "{model:?}: bin {b:?}, truth {truth}"
                );
                let fitted = e.model.sigma(b.depth);
                assert!(
                    (fitted / truth - 1.0).abs() < 0.1,
                    "{model:?}: fitted {fitted} at {b:?}"
                );
            }
        }
    }

    /// Clean depth with creases and depth edges (a staircase of boxes on the floor) has no
    /// noise to find: the estimate is none, so rendered depth keeps its passes.
    #[test]
    fn clean_depth_with_edges_reads_as_clean() {
        let mut depth = floor();
        for (i, d) in depth.iter_mut().enumerate() {
            let (x, y) = (i as u32 % W, i as u32 / W);
            // Every other 6-pixel column band is a box 0.5 nearer: edges in 1 window in 3.
            if *d > 0.0 && (x / 6) % 2 == 0 && y % 9 < 6 {
                *d -= 0.5;
            }
        }
        let e = DepthNoise::estimate(&depth, W, H, &camera(), None).unwrap();
        assert!(e.model.is_none() && e.sigma_px < 1e-3, "{e:?}");
        // The same map with noise of 0.1 px is not clean.
        let noisy = add_noise(
            &depth,
            &DepthNoise {
                linear: 0.004,
                ..DepthNoise::NONE
            },
            3,
        );
        let e = DepthNoise::estimate(&noisy, W, H, &camera(), None).unwrap();
        assert!(!e.model.is_none(), "{e:?}");
    }

    /// Disparity-quantised depth (terraces whose step grows as d², as a structured-light
    /// sensor stores it): the 3×3 residuals are zero on the terraces, and the estimate is
    /// the step / √12 (within 25%) when the map says it is integer-encoded, and the step
    /// model follows the d² law (within 25%) above the encoding's unit; noise dithers the
    /// terraces away; a finely quantised map is clean.
    #[test]
    fn terraces_of_an_integer_map_are_its_resolution() {
        // Depth from a disparity rounded to 1/8: step ≈ d² / (fb) / 8 with fb = 10, 2.7
        // times the floor's change per row (terraces ~3 rows deep) and under 5% of d.
        let fb = 10.0f32;
        let terraces: Vec<f32> = floor()
            .iter()
            .map(|&d| {
                if d > 0.0 {
                    fb / ((fb / d * 8.0).round() / 8.0)
                } else {
                    0.0
                }
            })
            .collect();
        let e = DepthNoise::estimate(&terraces, W, H, &camera(), Some(1e-4)).unwrap();
        assert!(!e.model.is_none() && e.bins.len() >= 8, "{e:?}");
        // Bins are cut by depth, so one may hold a single terrace (no step to see): the
        // fitted model, which takes a running median over the bins, is what must be right.
        for b in &e.bins {
            let truth = b.depth * b.depth / fb / 8.0 / 12f32.sqrt();
            let model = e.model.sigma(b.depth);
            assert!(
                (model / truth - 1.0).abs() < 0.25,
                "{e:?}: at {b:?}, step/√12 {truth}"
            );
            let step = e.model.step(b.depth);
            assert!(
                (step / (truth * 12f32.sqrt()) - 1.0).abs() < 0.25,
                "{e:?}: at {b:?}, step {step}"
            );
        }
        assert_eq!(e.model.step_constant, 1e-4);
        // Noise of many units before the rounding dithers the terraces away: no ties, no
        // steps in the model (its σ is the noise's).
        let noise = DepthNoise {
            quadratic: 0.002,
            ..DepthNoise::NONE
        };
        let dithered: Vec<f32> = add_noise(&floor(), &noise, 5)
            .iter()
            .map(|&d| (d * 1e4).round() / 1e4)
            .collect();
        let e = DepthNoise::estimate(&dithered, W, H, &camera(), Some(1e-4)).unwrap();
        assert!(
            e.model.step_constant == 0.0 && e.model.step_quadratic == 0.0 && !e.model.is_none(),
            "{e:?}"
        );
        // A fine integer map (1e-5 units, far below the surface's change per pixel) has
        // few ties: only its unit, which is negligible.
        let fine: Vec<f32> = floor().iter().map(|&d| (d * 1e5).round() / 1e5).collect();
        let e = DepthNoise::estimate(&fine, W, H, &camera(), Some(1e-5)).unwrap();
        assert!(e.model.is_none(), "{e:?}");
    }

    /// A map too small or too empty to measure gives none; a wrong length is an error.
    #[test]
    fn too_little_depth_and_bad_lengths() {
        let e = DepthNoise::estimate(&[1.0; 4], 2, 2, &camera(), None).unwrap();
        assert!(e.model.is_none() && e.bins.is_empty());
        let e = DepthNoise::estimate(&vec![0.0; (W * H) as usize], W, H, &camera(), None).unwrap();
        assert!(e.model.is_none() && e.bins.is_empty());
        assert!(DepthNoise::estimate(&[1.0; 5], 2, 2, &camera(), None).is_err());
    }
}

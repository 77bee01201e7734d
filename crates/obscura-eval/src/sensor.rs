//! Sensor-like depth made from clean rendered depth, to judge AO on noisy depth against the
//! same ray-traced truth as the clean depth (`obscura eval --sensor`).
//!
//! Each view's depth range is mapped onto a consumer depth camera's, [`NEAR_M`]–[`FAR_M`]
//! metres (z = NEAR_M + (FAR_M − NEAR_M)(d − d_min)/(d_max − d_min)); the sensor's noise and
//! quantisation are applied to z, and the result mapped back. So every view sees the
//! sensor's whole range of noise, from its nearest surface (σ 0.4 mm for the Kinect model)
//! to its farthest (σ 37.5 mm).

/// The depth range a view is mapped onto, metres.
pub const NEAR_M: f32 = 0.5;
pub const FAR_M: f32 = 5.0;

/// A simulated depth sensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sensor {
    /// Structured light / time of flight (Kinect-like): axial Gaussian noise with
    /// σ = 1.5 mm · z² (z in metres; Khoshelham & Elberink 2012 report σ from 1.5 mm at
    /// 1 m to 4 cm at 5 m for the Kinect v1), stored as 16-bit millimetres.
    Kinect,
    /// Stereo matching: disparity f·B/z with baseline [`STEREO_BASELINE_M`], Gaussian
    /// matching noise of [`STEREO_NOISE_PX`] and rounded to [`STEREO_STEP_PX`] (sub-pixel
    /// disparity as semi-global matchers store it), so the depth error grows as z².
    Stereo,
}

/// The stereo rig's baseline, metres.
pub const STEREO_BASELINE_M: f32 = 0.12;
/// Disparity matching noise, pixels (standard deviation).
pub const STEREO_NOISE_PX: f32 = 0.05;
/// Disparity quantisation step, pixels.
pub const STEREO_STEP_PX: f32 = 0.125;

impl Sensor {
    pub fn name(self) -> &'static str {
        match self {
            Sensor::Kinect => "kinect",
            Sensor::Stereo => "stereo",
        }
    }

    /// The sensor's depth noise as σ(z) = constant + quadratic · z² in metres, for a camera
    /// of focal length `focal_px`: the axial noise plus the quantisation (step / √12).
    pub fn sigma_m(self, focal_px: f32) -> (f32, f32) {
        match self {
            Sensor::Kinect => (0.001 / 12f32.sqrt(), 0.0015),
            Sensor::Stereo => {
                let px = (STEREO_NOISE_PX.powi(2) + STEREO_STEP_PX.powi(2) / 12.0).sqrt();
                (0.0, px / (focal_px * STEREO_BASELINE_M))
            }
        }
    }
}

/// The affine map of a view's depth onto the sensor's range: z = offset + scale · d.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeMap {
    pub offset: f32,
    pub scale: f32,
}

impl RangeMap {
    /// The map of depths `d_min..=d_max` onto NEAR_M..=FAR_M (a unit scale when the range
    /// is empty).
    pub fn new(d_min: f32, d_max: f32) -> Self {
        let scale = if d_max > d_min {
            (FAR_M - NEAR_M) / (d_max - d_min)
        } else {
            1.0
        };
        Self {
            offset: NEAR_M - scale * d_min,
            scale,
        }
    }

    /// A sensor noise σ(z) = c + k z² (metres) as σ of the depth before the map:
    /// (c + k (offset + scale d)²) / scale, returned as (constant, linear, quadratic).
    pub fn sigma_in_depth(&self, (c, k): (f32, f32)) -> (f32, f32, f32) {
        let (o, s) = (self.offset, self.scale);
        ((c + k * o * o) / s, 2.0 * k * o, k * s)
    }
}

/// Sensor-like linear depth from clean linear depth `depth` (scene units, 0 = no surface),
/// for a pinhole camera of focal length `focal_px` pixels, with the sensor's random noise
/// times `noise_scale` (1: the sensor; 0: its quantisation alone). Returns the noisy depth
/// and the map of the view's depth range onto the sensor's.
pub fn simulate(
    depth: &[f32],
    focal_px: f32,
    sensor: Sensor,
    noise_scale: f32,
    seed: u64,
) -> (Vec<f32>, RangeMap) {
    let valid = || depth.iter().copied().filter(|d| d.is_finite() && *d > 0.0);
    let map = RangeMap::new(
        valid().fold(f32::MAX, f32::min),
        valid().fold(0.0f32, f32::max),
    );
    let mut rng = obscura::noise::Rng(seed);
    let noisy = depth
        .iter()
        .map(|&d| {
            if !(d.is_finite() && d > 0.0) {
                return 0.0;
            }
            let z = map.offset + map.scale * d;
            let zm = match sensor {
                Sensor::Kinect => {
                    let z = z + noise_scale * 0.0015 * z * z * rng.gaussian();
                    (z * 1000.0).round() / 1000.0
                }
                Sensor::Stereo => {
                    let fb = focal_px * STEREO_BASELINE_M;
                    let disparity = fb / z + noise_scale * STEREO_NOISE_PX * rng.gaussian();
                    let q = (disparity / STEREO_STEP_PX).round() * STEREO_STEP_PX;
                    if q > 0.0 {
                        fb / q
                    } else {
                        0.0
                    }
                }
            };
            let back = (zm - map.offset) / map.scale;
            if zm > 0.0 && back > 0.0 {
                back
            } else {
                0.0
            }
        })
        .collect();
    (noisy, map)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Kinect model's noise, measured on a constant depth, has the stated σ within 5%,
    /// no mean shift beyond the quantisation, and values on the millimetre grid; the map
    /// puts the nearest and farthest depths at 0.5 and 5 m, and σ in depth units agrees.
    #[test]
    fn kinect_noise_has_the_stated_sigma() {
        // One pixel at the near end, one at the far end, the rest half way (2.75 m).
        let mut depth = vec![3.0f32; 200_000];
        depth[0] = 1.0;
        depth[1] = 5.0;
        let (noisy, map) = simulate(&depth, 500.0, Sensor::Kinect, 1.0, 7);
        assert!((map.offset + map.scale - NEAR_M).abs() < 1e-6);
        assert!((map.offset + 5.0 * map.scale - FAR_M).abs() < 1e-5);
        let z: Vec<f64> = noisy[2..]
            .iter()
            .map(|d| (map.offset + map.scale * d) as f64)
            .collect();
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let sd = (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / z.len() as f64).sqrt();
        let want = 0.0015 * 2.75f64 * 2.75;
        assert!((mean - 2.75).abs() < 1e-3, "mean {mean}");
        assert!((sd / want - 1.0).abs() < 0.05, "σ {sd}, want {want}");
        assert!(z
            .iter()
            .all(|v| ((v * 1000.0).round() - v * 1000.0).abs() < 1e-2));
        // σ in depth units at d = 3: σ(z) / scale.
        let (c, l, q) = map.sigma_in_depth((0.0, 0.0015));
        let sd_depth = c + l * 3.0 + q * 9.0;
        assert!((sd_depth - (want as f32) / map.scale).abs() < 1e-5);
        // Half the noise scale: half the σ; none: the millimetre grid alone.
        let sd_of = |scale: f32| {
            let (n, _) = simulate(&depth, 500.0, Sensor::Kinect, scale, 7);
            let z: Vec<f64> = n[2..]
                .iter()
                .map(|d| (map.offset + map.scale * d) as f64)
                .collect();
            (z.iter().map(|v| (v - 2.75).powi(2)).sum::<f64>() / z.len() as f64).sqrt()
        };
        assert!((sd_of(0.5) / (0.5 * want) - 1.0).abs() < 0.05);
        assert!(sd_of(0.0) <= 0.0005, "{}", sd_of(0.0));
    }

    /// Stereo depth lies on the disparity grid: f·B / z is a multiple of the step.
    #[test]
    fn stereo_depth_is_disparity_quantised() {
        let depth: Vec<f32> = (1..1000).map(|i| i as f32 * 0.01).collect();
        let (noisy, map) = simulate(&depth, 600.0, Sensor::Stereo, 1.0, 3);
        for (d, n) in depth.iter().zip(&noisy) {
            let z = map.offset + map.scale * n;
            let k = 600.0 * STEREO_BASELINE_M / z / STEREO_STEP_PX;
            assert!((k - k.round()).abs() < 1e-2, "{d} -> {z}: {k}");
        }
        // Missing depth stays missing.
        let (n, _) = simulate(&[0.0, f32::NAN, 1.0], 600.0, Sensor::Stereo, 1.0, 3);
        assert_eq!(&n[..2], &[0.0, 0.0]);
    }
}

//! Captured depth maps as a source of [`crate::AoInput`]: the one depth-map path that the
//! CLI's `render --depth` uses, and that any other front end (a Python binding, a batch
//! tool) uses the same way. A rasterised scene is the other source.
//!
//! The rules, in one place:
//! - Depth 0, NaN and ±inf are missing data: sky, never a near occluder.
//! - An integer encoding (16-bit PNG, uint16 arrays) is in stored units and is multiplied
//!   by a depth scale; float data is in scene units already (Open3D's convention), so one
//!   intrinsics file serves both encodings of the same data ([`DepthMap::from_integer`],
//!   [`DepthMap::from_float`]).
//! - obscura's projections are centred, and a camera's principal point rarely is: the map
//!   is padded with missing pixels until (cx, cy) sits at the centre (sky never occludes,
//!   so the padding changes nothing), and the AO is cropped back ([`Framed::crop`]).
//! - The default radius is 3% of the diagonal of the valid points' bounds (the rule used
//!   for meshes), the bounds taken between the 1st and 99th percentiles per axis so a few
//!   outliers (sensor spikes, 1e30 fill values) do not set it.

mod front_end;
#[cfg(not(target_arch = "wasm32"))]
mod renderer;

pub use front_end::{
    describe_noise, noise_model, normals_warning, npy_f32, view_normals, NoiseSpec, NormalsFrame,
};
#[cfg(not(target_arch = "wasm32"))]
pub use renderer::Renderer;

use crate::{Error, NoiseEstimate, Projection, Result};

/// Largest depth map accepted, per side (the AO still checks the adapter's limit).
pub const MAX_SIDE: u32 = 16384;

/// The narrowest and widest field of view, degrees, that a pinhole's focal length may give
/// across its image side ([`Intrinsics::validate`]): below 0.01° the projection's entries
/// overflow what f32 holds once squared, above 179° no pinhole camera images it (a wider
/// lens is a fisheye, which these intrinsics cannot describe).
pub const FOV_RANGE_DEG: (f32, f32) = (0.01, 179.0);

/// The default AO radius as a fraction of the diagonal of the scene's bounds.
pub const DEFAULT_RADIUS_FRACTION: f32 = 0.03;

fn invalid(message: String) -> Error {
    Error::InvalidDepthMap(message)
}

fn check_size(width: u32, height: u32) -> Result<()> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(invalid(format!(
            "depth map is {width}x{height}; each side must be in 1..={MAX_SIDE}"
        )));
    }
    Ok(())
}

/// Pinhole intrinsics (OpenCV convention: x right, y down, integer pixel coordinates at
/// pixel centres), in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    pub fx: f32,
    pub fy: f32,
    pub cx: f32,
    pub cy: f32,
    pub width: u32,
    pub height: u32,
}

impl Intrinsics {
    /// The checks that need no image size: finite focal lengths > 0 and a finite principal
    /// point. A batch whose maps' sizes are not known yet runs these before it starts;
    /// [`Intrinsics::validate`] checks the rest per map.
    pub fn validate_unsized(&self) -> Result<()> {
        for (k, x) in [("fx", self.fx), ("fy", self.fy)] {
            if !(x.is_finite() && x > 0.0) {
                return Err(invalid(format!(
                    "intrinsics `{k}` = {x} must be finite and > 0"
                )));
            }
        }
        for (k, x) in [("cx", self.cx), ("cy", self.cy)] {
            if !x.is_finite() {
                return Err(invalid(format!("intrinsics `{k}` = {x} must be finite")));
            }
        }
        Ok(())
    }

    /// Checks the focal lengths (finite, > 0, and a field of view across the image within
    /// [`FOV_RANGE_DEG`]), the size (1..=[`MAX_SIDE`]) and that the principal point lies in
    /// the image (with a pixel of slack).
    pub fn validate(&self) -> Result<()> {
        check_size(self.width, self.height)?;
        self.validate_unsized()?;
        for (k, x, side) in [("fx", self.fx, self.width), ("fy", self.fy, self.height)] {
            // Field of view 2 atan(side / 2f), so f = side / (2 tan(fov / 2)).
            let focal = |fov: f32| side as f32 / (2.0 * (fov.to_radians() / 2.0).tan());
            let (lo, hi) = (focal(FOV_RANGE_DEG.1), focal(FOV_RANGE_DEG.0));
            if !(lo..=hi).contains(&x) {
                return Err(invalid(format!(
                    "intrinsics `{k}` = {x} px gives a {:.3}° field of view across {side} px; \
                     a pinhole camera's is {}° to {}° (`{k}` from {lo:.3} to {hi:.0} px)",
                    2.0 * (side as f32 / (2.0 * x)).atan().to_degrees(),
                    FOV_RANGE_DEG.0,
                    FOV_RANGE_DEG.1,
                )));
            }
        }
        let inside = |c: f32, size: u32| c.is_finite() && c >= -1.0 && c <= size as f32;
        if !(inside(self.cx, self.width) && inside(self.cy, self.height)) {
            return Err(invalid(format!(
                "intrinsics principal point ({}, {}) lies outside the {}x{} image",
                self.cx, self.cy, self.width, self.height
            )));
        }
        Ok(())
    }

    /// Padding (left, top, right, bottom) that centres the principal point, and the
    /// centred projection of the padded image with these clip planes.
    pub fn centred(&self, near: f32, far: f32) -> ([u32; 4], Projection) {
        // Pixel centre u has continuous coordinate u + 0.5; the principal point is at
        // cx + 0.5. Padding l left and r right centres it when cx + 0.5 + l = (w + l + r) / 2.
        let pad = |c: f32, n: u32| -> (u32, u32) {
            let twice = 2.0 * (c + 0.5) - n as f32; // = r - l
            if twice >= 0.0 {
                (0, twice.round() as u32)
            } else {
                ((-twice).round() as u32, 0)
            }
        };
        let (l, r) = pad(self.cx, self.width);
        let (t, b) = pad(self.cy, self.height);
        let (w, h) = ((self.width + l + r) as f32, (self.height + t + b) as f32);
        let projection = Projection::Perspective {
            fov_y: 2.0 * (h / (2.0 * self.fy)).atan(),
            aspect: (w / (2.0 * self.fx)) / (h / (2.0 * self.fy)),
            near,
            far,
        };
        ([l, t, r, b], projection)
    }
}

/// A depth map in scene units, row-major; 0 = missing.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthMap {
    pub width: u32,
    pub height: u32,
    pub depth: Vec<f32>,
    /// The step of an integer encoding in scene units (its depth scale), `None` for float
    /// data: what [`crate::DepthNoise::estimate`] takes as `quantum`.
    pub quantum: Option<f32>,
}

impl DepthMap {
    fn new(
        width: u32,
        height: u32,
        values: Vec<f32>,
        scale: f32,
        quantum: Option<f32>,
    ) -> Result<Self> {
        check_size(width, height)?;
        if values.len() != width as usize * height as usize {
            return Err(invalid(format!(
                "depth map has {} values for {width}x{height}",
                values.len()
            )));
        }
        let depth = values
            .into_iter()
            .map(|d| {
                let d = d * scale;
                if d.is_finite() && d > 0.0 {
                    d
                } else {
                    0.0
                }
            })
            .collect();
        Ok(DepthMap {
            width,
            height,
            depth,
            quantum,
        })
    }

    /// Float depth in scene units (row-major, `width` × `height` values).
    pub fn from_float(width: u32, height: u32, values: Vec<f32>) -> Result<Self> {
        Self::new(width, height, values, 1.0, None)
    }

    /// Integer depth (stored units, row-major) times `scale` scene units per unit (0.001
    /// for millimetres read in metres).
    pub fn from_integer(width: u32, height: u32, values: Vec<f32>, scale: f32) -> Result<Self> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(invalid(format!(
                "depth scale {scale} must be finite and > 0"
            )));
        }
        Self::new(width, height, values, scale, Some(scale))
    }

    /// Whether the map was stored as integers.
    pub fn is_integer(&self) -> bool {
        self.quantum.is_some()
    }

    /// The map seen through `k`: padded so the principal point is centred, with its
    /// projection, depth range and default radius. Errors if the sizes differ or no pixel
    /// has valid depth.
    pub fn frame(&self, k: &Intrinsics) -> Result<Framed> {
        k.validate()?;
        // The fields are public: check them again.
        check_size(self.width, self.height)?;
        if self.depth.len() != self.width as usize * self.height as usize {
            return Err(invalid(format!(
                "depth map has {} values for {}x{}",
                self.depth.len(),
                self.width,
                self.height
            )));
        }
        if (self.width, self.height) != (k.width, k.height) {
            return Err(invalid(format!(
                "the depth map is {}x{} but the intrinsics say {}x{}",
                self.width, self.height, k.width, k.height
            )));
        }
        let points = back_project(self, k);
        if points.is_empty() {
            return Err(invalid(
                "the depth map has no valid depth (every value is 0, NaN or infinite)".into(),
            ));
        }
        let (lo, hi) = percentile_bounds(&points, 0.01, 0.99);
        let default_radius = DEFAULT_RADIUS_FRACTION * (hi - lo).length();
        let (zmin, zmax) = points
            .iter()
            .fold((f32::MAX, 0.0f32), |(a, b), p| (a.min(p.z), b.max(p.z)));
        let (pad, projection) = k.centred(0.5 * zmin, (2.0 * zmax).min(f32::MAX));
        let padded_width = self.width + pad[0] + pad[2];
        Ok(Framed {
            width: self.width,
            height: self.height,
            pad,
            padded_size: [padded_width, self.height + pad[1] + pad[3]],
            depth: pad_rows(&self.depth, self.width, pad),
            projection,
            default_radius,
            depth_range: [zmin, zmax],
            valid: points.len(),
            quantum: self.quantum,
        })
    }
}

/// A depth map ready for the AO passes ([`DepthMap::frame`]): linear depth padded to
/// `padded_size` so that `projection` is centred.
#[derive(Clone, Debug)]
pub struct Framed {
    /// The map's own size (what [`Framed::crop`] returns).
    pub width: u32,
    pub height: u32,
    /// Missing pixels added (left, top, right, bottom).
    pub pad: [u32; 4],
    pub padded_size: [u32; 2],
    /// Padded linear depth, row-major, 0 = missing: upload as `R32Float` with
    /// [`crate::DepthConvention::LinearView`].
    pub depth: Vec<f32>,
    pub projection: Projection,
    /// 3% of the diagonal of the valid points' percentile bounds, scene units (0 when
    /// they span nothing: see [`Framed::radius`]).
    pub default_radius: f32,
    /// Nearest and farthest valid depth.
    pub depth_range: [f32; 2],
    /// Pixels with valid depth.
    pub valid: usize,
    /// The map's [`DepthMap::quantum`].
    pub quantum: Option<f32>,
}

impl Framed {
    /// Per-pixel `values` of the map's size (rows of `width`), padded like the depth with
    /// `T::default()` (for example normals given with the map).
    pub fn pad<T: Copy + Default>(&self, values: &[T]) -> Result<Vec<T>> {
        if values.len() != self.width as usize * self.height as usize {
            return Err(invalid(format!(
                "{} values given for a {}x{} depth map",
                values.len(),
                self.width,
                self.height
            )));
        }
        Ok(pad_rows(values, self.width, self.pad))
    }

    /// A padded-size image (the AO) cropped back to the map's size.
    pub fn crop(&self, padded: &[f32]) -> Result<Vec<f32>> {
        let [pw, ph] = self.padded_size;
        if padded.len() != pw as usize * ph as usize {
            return Err(invalid(format!(
                "{} values to crop from a {pw}x{ph} padded map",
                padded.len()
            )));
        }
        Ok((0..self.height)
            .flat_map(|y| {
                let row = ((y + self.pad[1]) * pw + self.pad[0]) as usize;
                padded[row..row + self.width as usize].iter().copied()
            })
            .collect())
    }

    /// The AO radius: `given`, or the default radius when it can be derived; otherwise an
    /// error that names the cause (a map whose valid points span no extent, such as a
    /// single valid pixel), never an invalid radius the caller did not give.
    pub fn radius(&self, given: Option<f32>) -> Result<f32> {
        match given {
            Some(r) => Ok(r),
            None if self.default_radius.is_finite() && self.default_radius > 0.0 => {
                Ok(self.default_radius)
            }
            None => Err(invalid(format!(
                "cannot derive a default radius (3% of the extent of the valid depth): the \
                 {} valid pixels span no extent; give the radius",
                self.valid
            ))),
        }
    }

    /// The depth noise estimated from the map ([`crate::DepthNoise::estimate`]).
    pub fn estimate_noise(&self) -> Result<NoiseEstimate> {
        let [w, h] = self.padded_size;
        crate::DepthNoise::estimate(&self.depth, w, h, &self.projection, self.quantum)
    }
}

/// `values` (rows of `width`) inside an image of `T::default()` with `pad` = [left, top,
/// right, bottom] pixels around them.
fn pad_rows<T: Copy + Default>(values: &[T], width: u32, pad: [u32; 4]) -> Vec<T> {
    let height = (values.len() / width as usize) as u32;
    let pw = width + pad[0] + pad[2];
    let mut padded = vec![T::default(); (pw * (height + pad[1] + pad[3])) as usize];
    for (y, row) in values.chunks_exact(width as usize).enumerate() {
        let start = ((y as u32 + pad[1]) * pw + pad[0]) as usize;
        padded[start..start + row.len()].copy_from_slice(row);
    }
    padded
}

/// The valid pixels' view-space points (x right, y down, z the depth: the camera's frame).
fn back_project(map: &DepthMap, k: &Intrinsics) -> Vec<glam::Vec3> {
    map.depth
        .iter()
        .enumerate()
        .filter(|(_, d)| **d > 0.0)
        .map(|(i, &d)| {
            let (u, v) = ((i as u32 % map.width) as f32, (i as u32 / map.width) as f32);
            glam::Vec3::new((u - k.cx) / k.fx * d, (v - k.cy) / k.fy * d, d)
        })
        .collect()
}

/// Per axis, the values below which fractions `lo` and `hi` of the points lie (nearest
/// rank), as two corners.
fn percentile_bounds(points: &[glam::Vec3], lo: f32, hi: f32) -> (glam::Vec3, glam::Vec3) {
    let (mut a, mut b) = ([0.0f32; 3], [0.0f32; 3]);
    let mut axis: Vec<f32> = Vec::with_capacity(points.len());
    let rank = |q: f32, n: usize| ((q * (n - 1) as f32).round() as usize).min(n - 1);
    for k in 0..3 {
        axis.clear();
        axis.extend(points.iter().map(|p| p[k]));
        let (i, j) = (rank(lo, axis.len()), rank(hi, axis.len()));
        a[k] = *axis.select_nth_unstable_by(i, f32::total_cmp).1;
        // After the first selection everything from i on is >= a[k]: select j within it.
        b[k] = *axis[i..].select_nth_unstable_by(j - i, f32::total_cmp).1;
    }
    (glam::Vec3::from(a), glam::Vec3::from(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn intrinsics(cx: f32, cy: f32) -> Intrinsics {
        Intrinsics {
            fx: 100.0,
            fy: 100.0,
            cx,
            cy,
            width: 8,
            height: 6,
        }
    }

    #[test]
    fn focal_lengths_beyond_a_pinholes_field_of_view_are_refused() {
        intrinsics(4.0, 3.0).validate().unwrap();
        // 8 px wide: 0.01° of view is fx = 4 / tan(0.005°) = 45,837 px; 179° is
        // 4 / tan(89.5°) = 0.0349 px. Just inside each bound passes, just outside fails.
        let with = |fx: f32, fy: f32| Intrinsics {
            fx,
            fy,
            ..intrinsics(4.0, 3.0)
        };
        for (fx, fy) in [(4.5e4, 100.0), (0.04, 100.0), (100.0, 3.4e4), (100.0, 0.03)] {
            with(fx, fy).validate().unwrap();
        }
        for (fx, fy, field) in [
            (1e30, 100.0, "`fx` = 1000000000000000000000000000000 px"),
            (4.7e4, 100.0, "`fx` = 47000 px"),
            (0.03, 100.0, "`fx` = 0.03 px"),
            (100.0, 1e-4, "`fy` = 0.0001 px"),
        ] {
            let e = with(fx, fy).validate().unwrap_err().to_string();
            assert!(e.contains(field) && e.contains("field of view"), "{e}");
        }
    }

    #[test]
    fn normals_none_of_which_is_a_vector_are_refused() {
        let frame = NormalsFrame::OpenCv;
        for bad in [[f32::NAN; 3], [0.0; 3], [f32::INFINITY, 0.0, -1.0]] {
            let values: Vec<f32> = bad.iter().copied().cycle().take(12).collect();
            let e = view_normals(&values, 3, frame).unwrap_err().to_string();
            assert!(e.contains("not one is a finite, non-zero vector"), "{e}");
        }
        // One good normal among missing ones is accepted; the rest stay missing (zero).
        let mut values = vec![f32::NAN; 12];
        values[3..6].copy_from_slice(&[0.0, 0.0, -1.0]);
        let (n, away) = view_normals(&values, 3, frame).unwrap();
        assert_eq!(n[1], [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(n[0], [0.0; 4]);
        assert_eq!(away, 0.0);
        // Facing away: the OpenGL reading of OpenCV normals; warned above one half.
        let (_, away) = view_normals(&values, 3, NormalsFrame::OpenGl).unwrap();
        assert_eq!(away, 1.0);
        assert!(normals_warning(away).is_some() && normals_warning(0.5).is_none());
    }

    #[test]
    fn padding_centres_the_principal_point_and_crop_undoes_it() {
        // cx = 2.5: pixel centres 0.5..7.5 around 3.0, so 2 pixels go on the left.
        let k = intrinsics(2.5, 3.5);
        let values: Vec<f32> = (1..=48).map(|i| i as f32).collect();
        let map = DepthMap::from_float(8, 6, values.clone()).unwrap();
        let f = map.frame(&k).unwrap();
        let [l, t, r, b] = f.pad;
        assert_eq!([l, t, r, b], [2, 0, 0, 2]);
        let [pw, ph] = f.padded_size;
        // The principal point's continuous coordinate sits at the padded centre.
        assert_eq!(2.0 * (k.cx + 0.5 + l as f32), pw as f32);
        assert_eq!(2.0 * (k.cy + 0.5 + t as f32), ph as f32);
        assert_eq!(f.crop(&f.depth).unwrap(), values);
        assert!(
            f.crop(&values).is_err(),
            "an unpadded image is not the padded size"
        );
        // The projection's focal length in pixels is fy: tan(fov/2) = (h/2) / fy.
        let Projection::Perspective { fov_y, aspect, .. } = f.projection else {
            panic!("a pinhole map gives a perspective projection");
        };
        assert!(((fov_y / 2.0).tan() - ph as f32 / 2.0 / k.fy).abs() < 1e-6);
        assert!((aspect - pw as f32 / ph as f32).abs() < 1e-6);
    }

    #[test]
    fn the_scale_applies_to_integer_maps_only_and_bad_values_are_missing() {
        let raw = vec![1500.0, 0.0, f32::NAN, -3.0, f32::INFINITY, 2000.0];
        let int = DepthMap::from_integer(3, 2, raw.clone(), 0.001).unwrap();
        for (got, want) in int.depth.iter().zip([1.5, 0.0, 0.0, 0.0, 0.0, 2.0]) {
            assert!((got - want).abs() <= 1e-6, "{:?}", int.depth);
        }
        assert_eq!(int.quantum, Some(0.001));
        let float = DepthMap::from_float(3, 2, raw).unwrap();
        assert_eq!(float.depth, vec![1500.0, 0.0, 0.0, 0.0, 0.0, 2000.0]);
        assert!(!float.is_integer());
    }

    #[test]
    fn outliers_do_not_set_the_default_radius() {
        // A 100×100 wall at depth 2 (1 m wide at fx = 200), three pixels at 1e30.
        let k = Intrinsics {
            fx: 200.0,
            fy: 200.0,
            cx: 49.5,
            cy: 49.5,
            width: 100,
            height: 100,
        };
        let mut values = vec![2.0f32; 100 * 100];
        for i in [5, 500, 9000] {
            values[i] = 1e30;
        }
        let f = DepthMap::from_float(100, 100, values)
            .unwrap()
            .frame(&k)
            .unwrap();
        // Between its 1st and 99th percentiles the wall spans 0.98–0.99 m per axis (pixel
        // centres 1 cm apart), and no depth: a diagonal of 0.98·√2 within 1%.
        let expected = 0.03 * 0.98 * 2f32.sqrt();
        assert!(
            (f.default_radius - expected).abs() < 0.01 * expected,
            "radius {} against {expected}",
            f.default_radius
        );
        assert_eq!(f.valid, 100 * 100);
        assert_eq!(f.pad, [0; 4]);
    }

    #[test]
    fn bad_maps_and_intrinsics_are_clear_errors() {
        let map = DepthMap::from_float(8, 6, vec![1.0; 48]).unwrap();
        let cases = [
            (map.frame(&intrinsics(20.0, 3.0)), "outside"),
            (
                map.frame(&Intrinsics {
                    fx: f32::NAN,
                    ..intrinsics(3.5, 2.5)
                }),
                "fx",
            ),
            (
                map.frame(&Intrinsics {
                    width: 9,
                    ..intrinsics(3.5, 2.5)
                }),
                "intrinsics say",
            ),
            (
                DepthMap::from_float(8, 6, vec![0.0; 48])
                    .unwrap()
                    .frame(&intrinsics(3.5, 2.5)),
                "no valid depth",
            ),
        ];
        for (result, needle) in cases {
            let e = result.expect_err(needle).to_string();
            assert!(e.contains(needle), "`{e}` lacks `{needle}`");
        }
        for e in [
            DepthMap::from_float(0, 6, vec![]).unwrap_err(),
            DepthMap::from_float(8, 6, vec![1.0; 47]).unwrap_err(),
            DepthMap::from_integer(8, 6, vec![1.0; 48], 0.0).unwrap_err(),
        ] {
            assert!(matches!(e, Error::InvalidDepthMap(_)), "{e}");
        }
        let f = map.frame(&intrinsics(3.5, 2.5)).unwrap();
        assert!(f.pad(&[0u8; 47]).is_err());
        // A single valid pixel spans no extent: the radius must be given, and the error
        // says so instead of rejecting a radius of 0 that nobody gave.
        let mut one = vec![0.0; 48];
        one[9] = 2.0;
        let lone = DepthMap::from_float(8, 6, one)
            .unwrap()
            .frame(&intrinsics(3.5, 2.5))
            .unwrap();
        let e = lone.radius(None).unwrap_err().to_string();
        assert!(e.contains("1 valid pixels span no extent"), "{e}");
        assert_eq!(lone.radius(Some(0.5)).unwrap(), 0.5);
        assert_eq!(f.radius(None).unwrap(), f.default_radius);
        assert_eq!(f.pad(&[7u8; 48]).unwrap(), vec![7u8; 48]);
    }
}

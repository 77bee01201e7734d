//! A look-at camera with perspective or orthographic projection. Depth is written
//! reversed (near → 1, far → 0), matching [`obscura::DepthConvention::ReversedZ`]
//! ([`DEPTH_CONVENTION`]): a float's exponent then spends its precision where the
//! projection's 1/z loses it, so the depth keeps about 2⁻²⁴ of the view depth everywhere
//! (Reed 2015, "Depth Precision Visualized"; docs/thickness.md, "The depth buffer: reversed-Z").

use crate::{Aabb, SceneError};
use glam::{Mat4, Vec3, Vec4};

/// The depth convention of [`Camera::projection_matrix`] and of everything obscura-scene
/// rasterizes: reversed-Z, the sky cleared to 0.
pub const DEPTH_CONVENTION: obscura::DepthConvention = obscura::DepthConvention::ReversedZ;

/// The depth that obscura-scene clears to where no surface is (the far plane, reversed):
/// a surface's depth is above it.
pub const SKY_DEPTH: f32 = 0.0;

/// The camera's projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraProjection {
    /// Vertical field of view in degrees.
    Perspective { fov_y_deg: f32 },
    /// Height of the view volume in world units.
    Orthographic { height: f32 },
}

/// A look-at camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub projection: CameraProjection,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// Checks for NaN/inf, eye == target, `up` parallel to the view direction, and bad
    /// near/far or projection extents.
    pub fn validate(&self) -> Result<(), SceneError> {
        let bad = |m: String| Err(SceneError::Camera(m));
        if !(self.eye.is_finite() && self.target.is_finite() && self.up.is_finite()) {
            return bad(format!(
                "eye {} / target {} / up {} must be finite",
                self.eye, self.target, self.up
            ));
        }
        let dir = self.target - self.eye;
        if dir.length() <= 1e-6 * self.eye.length().max(1.0) {
            return bad("eye and target are the same point".into());
        }
        if dir.normalize().cross(self.up.normalize_or_zero()).length() < 1e-4 {
            return bad("the up vector is parallel to the view direction".into());
        }
        if !(self.near.is_finite()
            && self.far.is_finite()
            && self.near > 0.0
            && self.far > self.near)
        {
            return bad(format!(
                "near {} and far {} must be finite with 0 < near < far",
                self.near, self.far
            ));
        }
        match self.projection {
            CameraProjection::Perspective { fov_y_deg }
                if !(fov_y_deg > 0.1 && fov_y_deg < 179.0) =>
            {
                bad(format!("field of view {fov_y_deg}° must be in (0.1, 179)"))
            }
            CameraProjection::Orthographic { height } if !(height.is_finite() && height > 0.0) => {
                bad(format!(
                    "orthographic height {height} must be finite and > 0"
                ))
            }
            _ => Ok(()),
        }
    }

    /// World → view: right-handed, x right, y up, looking down −z.
    pub fn view_matrix(&self) -> Mat4 {
        let f = (self.target - self.eye).normalize();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        Mat4::from_cols(
            Vec4::new(s.x, u.x, -f.x, 0.0),
            Vec4::new(s.y, u.y, -f.y, 0.0),
            Vec4::new(s.z, u.z, -f.z, 0.0),
            Vec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        )
    }

    /// The camera with its eye turned `degrees` about the vertical (`up`) axis through the
    /// target, at the same distance and with the same projection.
    pub fn orbit(&self, degrees: f32) -> Camera {
        let turn = glam::Quat::from_axis_angle(self.up.normalize(), degrees.to_radians());
        Camera {
            eye: self.target + turn * (self.eye - self.target),
            ..*self
        }
    }

    /// The motion from `previous` to this camera, as obscura's temporal accumulation wants
    /// it: `previous_view * inverse(view)`, taking this view space to the previous one.
    pub fn motion_since(&self, previous: &Camera) -> obscura::CameraMotion {
        let m = previous.view_matrix() * self.view_matrix().inverse();
        obscura::CameraMotion::Moved {
            previous_from_current: m.to_cols_array_2d(),
        }
    }

    /// View → clip, depth in [0, 1] reversed ([`DEPTH_CONVENTION`]): 1 at near, 0 at far.
    pub fn projection_matrix(&self, aspect: f32) -> Mat4 {
        let (n, f) = (self.near, self.far);
        match self.projection {
            // z_ndc = n/(f−n)·(f/d − 1) for view depth d = −z.
            CameraProjection::Perspective { fov_y_deg } => {
                let h = 1.0 / (0.5 * fov_y_deg.to_radians()).tan();
                let r = n / (f - n);
                Mat4::from_cols(
                    Vec4::new(h / aspect, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, h, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, r, -1.0),
                    Vec4::new(0.0, 0.0, r * f, 0.0),
                )
            }
            // z_ndc = (f − d)/(f − n).
            CameraProjection::Orthographic { height } => {
                let (hw, hh) = (0.5 * height * aspect, 0.5 * height);
                let inv = 1.0 / (f - n);
                Mat4::from_cols(
                    Vec4::new(1.0 / hw, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, 1.0 / hh, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, inv, 0.0),
                    Vec4::new(0.0, 0.0, f * inv, 1.0),
                )
            }
        }
    }

    /// This camera's view, `height` pixels tall, widened by `guard` pixels on each side: the
    /// camera a renderer draws a guard band with, at `width + 2·guard` × `height + 2·guard`
    /// (the same eye and pixel size; a wider field of view, or a taller orthographic
    /// volume). obscura takes the band with this camera's own projection
    /// ([`obscura::AoInput::guard_band`]).
    pub fn widened(&self, height: u32, guard: u32) -> Camera {
        if guard == 0 {
            return *self;
        }
        let grow = (height as f64 + 2.0 * guard as f64) / height.max(1) as f64;
        let projection = match self.projection {
            CameraProjection::Perspective { fov_y_deg } => {
                let half = (0.5 * (fov_y_deg as f64).to_radians()).tan() * grow;
                CameraProjection::Perspective {
                    fov_y_deg: (2.0 * half.atan()).to_degrees() as f32,
                }
            }
            CameraProjection::Orthographic { height: h } => CameraProjection::Orthographic {
                height: (h as f64 * grow) as f32,
            },
        };
        Camera {
            projection,
            ..*self
        }
    }

    /// The same projection in obscura's typed form.
    pub fn obscura_projection(&self, aspect: f32) -> obscura::Projection {
        match self.projection {
            CameraProjection::Perspective { fov_y_deg } => obscura::Projection::Perspective {
                fov_y: fov_y_deg.to_radians(),
                aspect,
                near: self.near,
                far: self.far,
            },
            CameraProjection::Orthographic { height } => obscura::Projection::Orthographic {
                half_width: 0.5 * height * aspect,
                half_height: 0.5 * height,
                near: self.near,
                far: self.far,
            },
        }
    }

    /// Near and far planes that enclose `bounds` as seen from `eye`: far reaches the
    /// farthest corner, near is 1/10000 of it. Reversed-Z keeps Depth32Float's step near
    /// 2⁻²⁴ of the view depth at every depth; in the standard convention it was about
    /// 2⁻²⁴ z² / near, 1.1–2.2% of the AO radius on the shared views (docs/thickness.md,
    /// "The depth buffer: reversed-Z").
    pub fn fit_clip_planes(&mut self, bounds: &Aabb) {
        let far = corners(bounds)
            .iter()
            .map(|c| (*c - self.eye).length())
            .fold(0.0f32, f32::max)
            * 1.01;
        self.far = far.max(1e-3);
        self.near = self.far * 1e-4;
    }

    /// A camera that frames `bounds`: looking at its centre from the front-right and
    /// above, far enough for the bounding sphere to fit the field of view.
    pub fn framing(bounds: &Aabb, projection: CameraProjection) -> Camera {
        let center = bounds.center();
        let radius = (bounds.diagonal() * 0.5).max(1e-3);
        let dir = Vec3::new(0.55, 0.45, 1.0).normalize();
        let dist = match projection {
            CameraProjection::Perspective { fov_y_deg } => {
                radius / (0.5 * fov_y_deg.to_radians()).sin()
            }
            CameraProjection::Orthographic { .. } => radius * 2.0,
        };
        let mut cam = Camera {
            eye: center + dir * dist,
            target: center,
            up: Vec3::Y,
            projection,
            near: 0.01,
            far: 100.0,
        };
        cam.fit_clip_planes(bounds);
        cam
    }
}

fn corners(b: &Aabb) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera {
            eye: Vec3::new(0.0, 1.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
            near: 0.1,
            far: 50.0,
        }
    }

    #[test]
    fn rejects_degenerate_cameras() {
        cam().validate().unwrap();
        let mut c = cam();
        c.eye.x = f32::NAN;
        assert!(c.validate().is_err());
        let mut c = cam();
        c.target = c.eye;
        assert!(c.validate().is_err());
        let mut c = cam();
        c.up = c.target - c.eye;
        assert!(c.validate().is_err());
        let mut c = cam();
        c.far = c.near;
        assert!(c.validate().is_err());
    }

    /// Depth32Float's rounding of the reversed depth, linearized back, keeps every view
    /// depth from 2·near to far/2 within 1e-6 of itself at `fit_clip_planes`' ratio (far =
    /// 10⁴ near; analytic bound 2⁻²⁴·f/(f−d) plus a few ulps of the linearization). The
    /// standard convention, whose step is 2⁻²⁴·d²/near, loses more than 1e-5 of some
    /// depth in the same range: that is why the G-buffer is reversed.
    #[test]
    fn reversed_depth_keeps_precision_where_the_standard_one_loses_it() {
        let c = Camera {
            near: 0.01,
            far: 100.0,
            ..cam()
        };
        let aspect = 1.5;
        let m = c.projection_matrix(aspect).as_dmat4();
        let linearize = |convention| c.obscura_projection(aspect).linearize(convention).unwrap();
        let (reversed, standard) = (
            linearize(DEPTH_CONVENTION),
            linearize(obscura::DepthConvention::Standard),
        );
        let (n, f) = (c.near as f64, c.far as f64);
        let relative = |z: f64, lin: &obscura::Linearize, d: f64| {
            // The rasterizer stores the exact NDC depth rounded to f32.
            let back = lin.apply(z as f32).map_or(f64::INFINITY, f64::from);
            (back - d).abs() / d
        };
        let (mut worst_reversed, mut worst_standard) = (0f64, 0f64);
        let mut d = 2.0 * n;
        while d <= 0.5 * f {
            let clip = m * glam::DVec4::new(0.0, 0.0, -d, 1.0);
            worst_reversed = worst_reversed.max(relative(clip.z / clip.w, &reversed, d));
            let z_standard = f / (f - n) * (1.0 - n / d);
            worst_standard = worst_standard.max(relative(z_standard, &standard, d));
            d *= 1.037;
        }
        assert!(worst_reversed <= 1e-6, "reversed: {worst_reversed}");
        assert!(worst_standard > 1e-5, "standard: {worst_standard}");
    }

    #[test]
    fn matrix_depth_matches_obscura_linearization() {
        // The rasterizer's matrix and obscura's typed projection must agree, or AO would be
        // computed on the wrong geometry.
        for projection in [
            CameraProjection::Perspective { fov_y_deg: 50.0 },
            CameraProjection::Orthographic { height: 4.0 },
        ] {
            let c = Camera {
                projection,
                ..cam()
            };
            let aspect = 1.6;
            let m = c.projection_matrix(aspect);
            let lin = c
                .obscura_projection(aspect)
                .linearize(DEPTH_CONVENTION)
                .unwrap();
            for d in [0.5f32, 2.0, 17.0, 45.0] {
                let clip = m * glam::Vec4::new(0.3, -0.2, -d, 1.0);
                let z = clip.z / clip.w;
                let back = lin.apply(z).unwrap();
                assert!(
                    (back - d).abs() < 1e-3 * d,
                    "{projection:?} d={d} got {back}"
                );
            }
        }
    }
}

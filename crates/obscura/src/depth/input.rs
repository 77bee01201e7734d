//! The input contract: how depth is encoded, how the camera projects, which part of the
//! texture to process. All conversions here are pure functions, mirrored by the WGSL in
//! `passes/common.wgsl` through the uniform values they produce.
//!
//! View space follows the usual right-handed convention: x right, y up, the camera looks
//! along −z. "Linear depth" `d` is the positive distance along the view axis, `d = −z_view`.

use crate::{Error, Result};

/// How values in the depth texture map to view distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum DepthConvention {
    /// Standard [0, 1] depth as wgpu/D3D/Vulkan write it: near plane → 0, far plane → 1.
    #[default]
    Standard,
    /// Reversed-Z: near plane → 1, far plane → 0.
    ReversedZ,
    /// Reversed-Z with the far plane at infinity: `depth = near / d` (perspective only).
    ReversedZInfinite,
    /// The texture already holds linear view depth `d` (positive, in view-space units).
    LinearView,
}

impl DepthConvention {
    /// Every convention.
    pub const ALL: [DepthConvention; 4] = [
        DepthConvention::Standard,
        DepthConvention::ReversedZ,
        DepthConvention::ReversedZInfinite,
        DepthConvention::LinearView,
    ];
}

/// A camera projection, described by parameters (or read from a matrix with
/// [`Projection::from_matrix`], whose layout is stated there).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Projection {
    /// Symmetric perspective. `fov_y` is the full vertical field of view in radians,
    /// `aspect` = width / height of the viewport. `far` may be `f32::INFINITY` with
    /// [`DepthConvention::ReversedZInfinite`]; it is otherwise ignored by `LinearView`.
    Perspective {
        fov_y: f32,
        aspect: f32,
        near: f32,
        far: f32,
    },
    /// Orthographic with a view volume `2*half_width` × `2*half_height` (view-space units),
    /// centred on the view axis, from `near` to `far`.
    Orthographic {
        half_width: f32,
        half_height: f32,
        near: f32,
        far: f32,
    },
}

/// The sub-rectangle of the input textures to process, in pixels. The output has the
/// viewport's size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Viewport {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Viewport {
    /// A viewport covering a whole `width` × `height` texture.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x: 0,
            y: 0,
            width,
            height,
        }
    }
}

/// How an optional caller-provided normal texture encodes normals. Normals need not be
/// unit length (they are normalized after decoding); zero or non-finite ones fall back to
/// view-space +z (towards the camera).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum NormalEncoding {
    /// A float texture (e.g. `Rgba16Float`) with view-space xyz in [−1, 1].
    ViewSigned,
    /// A unorm texture (e.g. `Rgba8Unorm`) with view-space `xyz * 0.5 + 0.5`.
    ViewUnorm,
    /// A float texture with world-space xyz in [−1, 1]. `view_from_world` rotates world
    /// directions into view space: the upper-left 3×3 of the view matrix, column-major
    /// (`m[column][row]`, glam's `Mat3::to_cols_array_2d` of `Mat3::from_mat4(view)`).
    WorldSigned { view_from_world: [[f32; 3]; 3] },
    /// A unorm texture with world-space `xyz * 0.5 + 0.5`, rotated as for `WorldSigned`.
    WorldUnorm { view_from_world: [[f32; 3]; 3] },
}

/// The 3×3 identity, as columns.
pub(crate) const IDENTITY3: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Whether the column-major 4×4 matrix `m` is a finite rigid motion: an orthonormal
/// rotation (tolerance 1e-3, determinant +1), any translation, last row (0, 0, 0, 1).
pub(crate) fn is_rigid(m: &[[f32; 4]; 4]) -> bool {
    if !m.iter().flatten().all(|v| v.is_finite()) {
        return false;
    }
    let mat = glam::Mat4::from_cols_array_2d(m);
    let r = glam::Mat3::from_mat4(mat);
    let ortho = (r.transpose() * r - glam::Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|v| v.abs() < 1e-3);
    ortho && r.determinant() > 0.0 && mat.row(3).abs_diff_eq(glam::Vec4::W, 1e-6)
}

impl NormalEncoding {
    /// Whether texel values are `xyz * 0.5 + 0.5`.
    pub fn is_unorm(self) -> bool {
        matches!(
            self,
            NormalEncoding::ViewUnorm | NormalEncoding::WorldUnorm { .. }
        )
    }

    /// The rotation from the texture's space into view space, as three columns (identity
    /// for view-space normals). A typed error when the matrix is not finite, degenerate or
    /// mirrored (determinant ≤ 0.01): normals would point the wrong way.
    pub fn to_view(self) -> Result<[[f32; 3]; 3]> {
        let m = match self {
            NormalEncoding::ViewSigned | NormalEncoding::ViewUnorm => return Ok(IDENTITY3),
            NormalEncoding::WorldSigned { view_from_world }
            | NormalEncoding::WorldUnorm { view_from_world } => view_from_world,
        };
        let det = glam::Mat3::from_cols_array_2d(&m).determinant();
        if m.iter().flatten().all(|v| v.is_finite()) && det > 0.01 {
            Ok(m)
        } else {
            Err(Error::InvalidSetting {
                field: "NormalEncoding::view_from_world",
                value: format!("{m:?} (determinant {det})"),
                expected: "a finite rotation (the view matrix's upper-left 3x3), not degenerate or mirrored",
            })
        }
    }
}

/// Depth linearization in the form shared by every convention:
/// `d = 1 / (a * z + b)` when `reciprocal`, else `d = a * z + b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linearize {
    pub a: f32,
    pub b: f32,
    pub reciprocal: bool,
    /// Raw depth values at or beyond this (in the convention's "far" direction) are sky.
    pub sky: SkyTest,
}

/// Which raw depth values mean "no surface": the far plane (sky) and values outside the
/// convention's [0, 1] range, which would lie in front of the near plane and must never
/// act as near occluders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyTest {
    /// `z >= 1` (standard depth cleared to the far plane) or `z < 0`.
    AtLeastOne,
    /// `z <= 0` (reversed depth cleared to the far plane) or `z > 1`.
    AtMostZero,
    /// Only non-finite or non-positive linear depth is missing.
    NonPositive,
}

impl SkyTest {
    /// Numeric code used by the shader (`common.wgsl`, `raw_is_sky`).
    pub fn code(self) -> u32 {
        match self {
            SkyTest::AtLeastOne => 0,
            SkyTest::AtMostZero => 1,
            SkyTest::NonPositive => 2,
        }
    }
}

impl Linearize {
    /// Linear view depth for a raw depth value, or `None` for sky / missing depth.
    /// Non-finite and non-positive results are always treated as missing, never as a
    /// near occluder.
    pub fn apply(&self, z: f32) -> Option<f32> {
        if !z.is_finite() {
            return None;
        }
        let sky = match self.sky {
            SkyTest::AtLeastOne => !(0.0..1.0).contains(&z),
            SkyTest::AtMostZero => z <= 0.0 || z > 1.0,
            SkyTest::NonPositive => false,
        };
        if sky {
            return None;
        }
        let v = self.a * z + self.b;
        let d = if self.reciprocal { 1.0 / v } else { v };
        (d.is_finite() && d > 0.0).then_some(d)
    }
}

impl Projection {
    /// Checks that the projection describes a real camera.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidProjection(m));
        match *self {
            Projection::Perspective {
                fov_y,
                aspect,
                near,
                far,
            } => {
                if !(fov_y.is_finite() && fov_y > 1e-4 && fov_y < std::f32::consts::PI - 1e-4) {
                    return bad(format!(
                        "vertical field of view {fov_y} rad must be in (0, π)"
                    ));
                }
                if !(aspect.is_finite() && aspect > 0.0) {
                    return bad(format!("aspect ratio {aspect} must be finite and > 0"));
                }
                if !(near.is_finite() && near > 0.0) {
                    return bad(format!("near plane {near} must be finite and > 0"));
                }
                if far.is_nan() || far <= near {
                    return bad(format!("far plane {far} must be greater than near {near}"));
                }
            }
            Projection::Orthographic {
                half_width,
                half_height,
                near,
                far,
            } => {
                if !(half_width.is_finite() && half_width > 0.0) {
                    return bad(format!("half width {half_width} must be finite and > 0"));
                }
                if !(half_height.is_finite() && half_height > 0.0) {
                    return bad(format!("half height {half_height} must be finite and > 0"));
                }
                if !(near.is_finite() && far.is_finite() && far > near) {
                    return bad(format!(
                        "near {near} and far {far} must be finite with far > near"
                    ));
                }
            }
        }
        Ok(())
    }

    /// The projection a matrix encodes. Layout: column-major (`m[column][row]`, glam's
    /// `to_cols_array_2d`), taking right-handed view space (x right, y up, camera looking
    /// down −z) to clip space with NDC depth in [0, 1] (wgpu, Vulkan, Metal, D3D), encoded in
    /// `convention` (`LinearView`: read as `Standard`). Perspective when `m[2][3] = −1`,
    /// orthographic when it is 0 and `m[3][3] = 1`. Off-centre (`m[2][0]`, `m[2][1]` ≠ 0 for
    /// perspective, `m[3][0]`, `m[3][1]` ≠ 0 for orthographic), mirrored (negative scale) or
    /// degenerate matrices are a typed error.
    pub fn from_matrix(m: [[f32; 4]; 4], convention: DepthConvention) -> Result<Self> {
        let bad = |msg: &str| {
            Err(Error::InvalidProjection(format!(
                "projection matrix: {msg}"
            )))
        };
        if m.iter().flatten().any(|v| !v.is_finite()) {
            return bad("has a non-finite entry");
        }
        let (sx, sy, a, b) = (m[0][0], m[1][1], m[2][2], m[3][2]);
        if sx < 0.0 || sy < 0.0 {
            return bad("is mirrored (negative x or y scale); flip the image instead");
        }
        if sx == 0.0 || sy == 0.0 {
            return bad("is degenerate (zero x or y scale)");
        }
        let eps = 1e-6 * sx.max(sy);
        let perspective = (m[2][3] + 1.0).abs() < 1e-6 && m[3][3].abs() < 1e-6;
        let orthographic = m[2][3].abs() < 1e-6 && (m[3][3] - 1.0).abs() < 1e-6;
        // NDC depth z = (a·v.z + b) / w, with v.z = −d and w = d (perspective) or 1.
        let projection = if perspective {
            if m[2][0].abs() > eps || m[2][1].abs() > eps {
                return bad("is off-centre (asymmetric frusta are not supported)");
            }
            // z = −a + b/d: standard 0 at near, 1 at far; reversed 1 at near, 0 at far.
            let (near, far) = match convention {
                DepthConvention::Standard | DepthConvention::LinearView => (b / a, b / (1.0 + a)),
                DepthConvention::ReversedZ => (b / (1.0 + a), b / a),
                DepthConvention::ReversedZInfinite => (b, f32::INFINITY),
            };
            Projection::Perspective {
                fov_y: 2.0 * (1.0 / sy).atan(),
                aspect: sy / sx,
                near,
                far,
            }
        } else if orthographic {
            if m[3][0].abs() > eps || m[3][1].abs() > eps {
                return bad("is off-centre (asymmetric volumes are not supported)");
            }
            // z = −a·d + b.
            let (near, far) = match convention {
                DepthConvention::Standard | DepthConvention::LinearView => (b / a, (b - 1.0) / a),
                DepthConvention::ReversedZ => ((b - 1.0) / a, b / a),
                DepthConvention::ReversedZInfinite => {
                    return bad("orthographic projections have no infinite far plane");
                }
            };
            Projection::Orthographic {
                half_width: 1.0 / sx,
                half_height: 1.0 / sy,
                near,
                far,
            }
        } else {
            return bad("is neither perspective (m[2][3] = −1, m[3][3] = 0) nor orthographic (m[2][3] = 0, m[3][3] = 1)");
        };
        projection.validate()?;
        Ok(projection)
    }

    /// Is this a perspective projection?
    pub fn is_perspective(&self) -> bool {
        matches!(self, Projection::Perspective { .. })
    }

    fn near_far(&self) -> (f32, f32) {
        match *self {
            Projection::Perspective { near, far, .. }
            | Projection::Orthographic { near, far, .. } => (near, far),
        }
    }

    /// View-space xy of NDC (−1..1) at linear depth 1 (perspective) or any depth
    /// (orthographic): `view.xy = ndc.xy * scale` (times `d` for perspective).
    pub fn ndc_to_view_scale(&self) -> [f32; 2] {
        match *self {
            Projection::Perspective { fov_y, aspect, .. } => {
                let t = (fov_y * 0.5).tan();
                [t * aspect, t]
            }
            Projection::Orthographic {
                half_width,
                half_height,
                ..
            } => [half_width, half_height],
        }
    }

    /// The raw depth a surface at linear depth `d` has in `convention`: the inverse of
    /// [`Projection::linearize`], used to make test inputs and by callers converting data.
    pub fn encode_depth(&self, convention: DepthConvention, d: f32) -> f32 {
        let (n, f) = self.near_far();
        match (self.is_perspective(), convention) {
            (_, DepthConvention::LinearView) => d,
            (true, DepthConvention::Standard) => f / (f - n) * (1.0 - n / d),
            (true, DepthConvention::ReversedZ) => n / (f - n) * (f / d - 1.0),
            (true, DepthConvention::ReversedZInfinite) => n / d,
            (false, DepthConvention::Standard) => (d - n) / (f - n),
            (false, DepthConvention::ReversedZ) => (f - d) / (f - n),
            (false, DepthConvention::ReversedZInfinite) => f32::NAN,
        }
    }

    /// The linearization of raw depth for this projection and convention.
    pub fn linearize(&self, convention: DepthConvention) -> Result<Linearize> {
        self.validate()?;
        let (n, f) = self.near_far();
        let persp = self.is_perspective();
        let finite_far = |c: DepthConvention| -> Result<()> {
            if f.is_finite() {
                Ok(())
            } else {
                Err(Error::ConventionMismatch {
                    convention: c,
                    projection: "an infinite far plane (use ReversedZInfinite)",
                })
            }
        };
        Ok(match (persp, convention) {
            (_, DepthConvention::LinearView) => Linearize {
                a: 1.0,
                b: 0.0,
                reciprocal: false,
                sky: SkyTest::NonPositive,
            },
            // z = f/(f−n)·(1 − n/d)  ⇒  1/d = 1/n − z·(f−n)/(f·n)
            (true, DepthConvention::Standard) => {
                finite_far(convention)?;
                Linearize {
                    a: -(f - n) / (f * n),
                    b: 1.0 / n,
                    reciprocal: true,
                    sky: SkyTest::AtLeastOne,
                }
            }
            // z = n/(f−n)·(f/d − 1)  ⇒  1/d = 1/f + z·(f−n)/(f·n)
            (true, DepthConvention::ReversedZ) => {
                finite_far(convention)?;
                Linearize {
                    a: (f - n) / (f * n),
                    b: 1.0 / f,
                    reciprocal: true,
                    sky: SkyTest::AtMostZero,
                }
            }
            // z = n/d  ⇒  1/d = z/n
            (true, DepthConvention::ReversedZInfinite) => Linearize {
                a: 1.0 / n,
                b: 0.0,
                reciprocal: true,
                sky: SkyTest::AtMostZero,
            },
            // z = (d−n)/(f−n)
            (false, DepthConvention::Standard) => Linearize {
                a: f - n,
                b: n,
                reciprocal: false,
                sky: SkyTest::AtLeastOne,
            },
            // z = (f−d)/(f−n)
            (false, DepthConvention::ReversedZ) => Linearize {
                a: -(f - n),
                b: f,
                reciprocal: false,
                sky: SkyTest::AtMostZero,
            },
            (false, DepthConvention::ReversedZInfinite) => {
                return Err(Error::ConventionMismatch {
                    convention,
                    projection: "an orthographic projection",
                })
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Matrices from glam (an independent implementation of the usual conventions) give back
    /// the parameters they were made from; mirrored and off-centre ones are refused.
    #[test]
    fn projection_from_matrix_round_trips_glam() {
        use glam::camera::rh::proj::directx as dx;
        use glam::Mat4;
        let (fov, aspect, n, f) = (1.1f32, 1.6f32, 0.3f32, 250.0f32);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.abs().max(1.0);
        let cases = [
            (
                dx::perspective(fov, aspect, n, f),
                DepthConvention::Standard,
                f,
            ),
            // Reversed Z: near and far swapped.
            (
                dx::perspective(fov, aspect, f, n),
                DepthConvention::ReversedZ,
                f,
            ),
            (
                dx::perspective_infinite_reverse(fov, aspect, n),
                DepthConvention::ReversedZInfinite,
                f32::INFINITY,
            ),
        ];
        for (m, conv, far) in cases {
            match Projection::from_matrix(m.to_cols_array_2d(), conv).unwrap() {
                Projection::Perspective {
                    fov_y,
                    aspect: a,
                    near,
                    far: fa,
                } => {
                    assert!(
                        close(fov_y, fov) && close(a, aspect) && close(near, n),
                        "{conv:?}"
                    );
                    assert!(fa == far || close(fa, far), "{conv:?}: far {fa}");
                }
                p => panic!("{conv:?}: {p:?}"),
            }
        }
        let o = dx::orthographic(-4.0, 4.0, -2.5, 2.5, 0.5, 40.0);
        match Projection::from_matrix(o.to_cols_array_2d(), DepthConvention::Standard).unwrap() {
            Projection::Orthographic {
                half_width,
                half_height,
                near,
                far,
            } => assert!(
                close(half_width, 4.0)
                    && close(half_height, 2.5)
                    && close(near, 0.5)
                    && close(far, 40.0)
            ),
            p => panic!("{p:?}"),
        }
        let mirrored =
            Mat4::from_scale(glam::Vec3::new(-1.0, 1.0, 1.0)) * dx::perspective(fov, aspect, n, f);
        let off_centre = dx::orthographic(-1.0, 3.0, -2.0, 2.0, 0.5, 40.0);
        let mut nan = dx::perspective(fov, aspect, n, f).to_cols_array_2d();
        nan[1][1] = f32::NAN;
        for (m, what) in [
            (mirrored.to_cols_array_2d(), "mirrored"),
            (off_centre.to_cols_array_2d(), "off-centre"),
            (nan, "non-finite"),
            (Mat4::IDENTITY.to_cols_array_2d(), "degenerate depth"),
            ([[0.0; 4]; 4], "degenerate"),
        ] {
            assert!(
                matches!(
                    Projection::from_matrix(m, DepthConvention::Standard),
                    Err(Error::InvalidProjection(_))
                ),
                "{what} accepted"
            );
        }
    }

    const CONVENTIONS: [DepthConvention; 4] = [
        DepthConvention::Standard,
        DepthConvention::ReversedZ,
        DepthConvention::ReversedZInfinite,
        DepthConvention::LinearView,
    ];

    fn projections() -> [Projection; 2] {
        [
            Projection::Perspective {
                fov_y: 1.0,
                aspect: 1.5,
                near: 0.1,
                far: 100.0,
            },
            Projection::Orthographic {
                half_width: 3.0,
                half_height: 2.0,
                near: 0.5,
                far: 50.0,
            },
        ]
    }

    #[test]
    fn linearize_inverts_encode_for_every_convention() {
        for p in projections() {
            for c in CONVENTIONS {
                let Ok(lin) = p.linearize(c) else {
                    assert!(!p.is_perspective() && c == DepthConvention::ReversedZInfinite);
                    continue;
                };
                for d in [0.6f32, 1.0, 3.7, 10.0, 42.0] {
                    let z = p.encode_depth(c, d);
                    let back = lin
                        .apply(z)
                        .expect("a surface inside the frustum is not sky");
                    // Reciprocal depth loses relative precision ~ d/near · ε; 1e-4 relative is loose enough.
                    assert!(
                        (back - d).abs() <= 1e-4 * d,
                        "{p:?} {c:?}: d={d} encoded {z} decoded {back}"
                    );
                }
            }
        }
    }

    #[test]
    fn far_plane_and_invalid_values_are_sky() {
        for p in projections() {
            for c in CONVENTIONS {
                let Ok(lin) = p.linearize(c) else { continue };
                for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                    assert_eq!(lin.apply(bad), None, "{p:?} {c:?} {bad}");
                }
                match c {
                    DepthConvention::Standard => assert_eq!(lin.apply(1.0), None),
                    DepthConvention::ReversedZ | DepthConvention::ReversedZInfinite => {
                        assert_eq!(lin.apply(0.0), None)
                    }
                    DepthConvention::LinearView => {
                        assert_eq!(lin.apply(0.0), None);
                        assert_eq!(lin.apply(-2.0), None);
                    }
                }
            }
        }
    }

    #[test]
    fn bad_projections_are_rejected() {
        let bad = [
            Projection::Perspective {
                fov_y: f32::NAN,
                aspect: 1.0,
                near: 0.1,
                far: 10.0,
            },
            Projection::Perspective {
                fov_y: 1.0,
                aspect: 0.0,
                near: 0.1,
                far: 10.0,
            },
            Projection::Perspective {
                fov_y: 1.0,
                aspect: 1.0,
                near: 1.0,
                far: 0.5,
            },
            Projection::Orthographic {
                half_width: -1.0,
                half_height: 1.0,
                near: 0.1,
                far: 10.0,
            },
        ];
        for p in bad {
            assert!(
                matches!(p.validate(), Err(Error::InvalidProjection(_))),
                "{p:?}"
            );
        }
        let ortho = projections()[1];
        assert!(matches!(
            ortho.linearize(DepthConvention::ReversedZInfinite),
            Err(Error::ConventionMismatch { .. })
        ));
    }
}

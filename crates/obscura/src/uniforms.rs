//! The per-frame uniform block shared by every pass, and how it is derived from the inputs.

use crate::jitter::{fixed_table, pattern_table, PATTERN_COUNT};
use crate::{AoOptions, AoParams, DepthConvention, NormalEncoding, Projection, Result, Viewport};

crate::gpu_struct! {
    /// Everything a pass needs to know about the frame. Built by [`FrameUniforms::new`].
    pub struct FrameUniforms {
        /// Top-left of the viewport in the input textures, pixels.
        pub viewport_origin: [u32; 2],
        /// Viewport (and output) size, pixels.
        pub size: [u32; 2],
        /// 1 / size.
        pub inv_size: [f32; 2],
        /// `view.xy = ndc.xy * ndc_to_view` (times linear depth for perspective).
        pub ndc_to_view: [f32; 2],
        /// Depth linearization `d = a*z + b`, or its reciprocal (see [`crate::Linearize`]).
        pub lin_a: f32,
        pub lin_b: f32,
        /// 1 when `d = 1 / (a*z + b)`.
        pub lin_reciprocal: u32,
        /// [`crate::SkyTest::code`].
        pub sky_test: u32,
        /// 1 for perspective, 0 for orthographic.
        pub perspective: u32,
        /// 0: reconstruct normals from depth; 1: signed view-space input; 2: unorm input.
        pub normals_mode: u32,
        /// AO radius, view-space units, and 1 / radius².
        pub radius: f32,
        pub inv_radius2: f32,
        /// Pixels covered by one view-space unit at linear depth 1 (perspective) or anywhere (ortho).
        pub radius_to_px: f32,
        /// Clamp of the on-screen radius, pixels.
        pub max_radius_px: f32,
        /// sin(tangent bias angle).
        pub sin_bias: f32,
        /// Maps the estimator's summed occlusion to [0, 1]: HBAO strength / (directions ·
        /// (1 − sin_bias)); GTAO strength / directions; VO and VAO strength; SAO
        /// 2 · strength / samples.
        pub ao_scale: f32,
        /// Full-resolution pixels per pixel of the AO the upsampler reads (1, 2, 4 or 8).
        pub up_factor: u32,
        /// log2 of the full-resolution pixels per pixel of this frame's grid: depth pyramid
        /// level L of the full-resolution buffer is level L − pyramid_offset here.
        pub pyramid_offset: u32,
        /// The viewport size at full resolution, pixels.
        pub full_size: [u32; 2],
        /// Per-pixel sampling patterns, see [`crate::jitter`].
        pub patterns: [[f32; 4]; PATTERN_COUNT],
    }
}

impl FrameUniforms {
    /// Validates the inputs and derives the uniform values. No GPU work.
    pub fn new(
        projection: &Projection,
        convention: DepthConvention,
        normals: Option<NormalEncoding>,
        viewport: Viewport,
        options: &AoOptions,
        params: &AoParams,
    ) -> Result<Self> {
        options.validate()?;
        params.validate()?;
        let lin = projection.linearize(convention)?;
        if viewport.width == 0 || viewport.height == 0 {
            return Err(crate::Error::InvalidViewport(format!(
                "{}x{} is empty",
                viewport.width, viewport.height
            )));
        }
        let scale = projection.ndc_to_view_scale();
        let sin_bias = params.bias_angle_deg.to_radians().sin();
        Ok(Self {
            viewport_origin: [viewport.x, viewport.y],
            size: [viewport.width, viewport.height],
            inv_size: [1.0 / viewport.width as f32, 1.0 / viewport.height as f32],
            ndc_to_view: scale,
            lin_a: lin.a,
            lin_b: lin.b,
            lin_reciprocal: lin.reciprocal as u32,
            sky_test: lin.sky.code(),
            perspective: projection.is_perspective() as u32,
            normals_mode: match normals {
                None => 0,
                Some(NormalEncoding::ViewSigned) => 1,
                Some(NormalEncoding::ViewUnorm) => 2,
            },
            radius: params.radius,
            inv_radius2: 1.0 / (params.radius * params.radius),
            radius_to_px: viewport.height as f32 / (2.0 * scale[1]),
            max_radius_px: params.max_radius_px,
            sin_bias,
            ao_scale: match options.estimator {
                crate::Estimator::Hbao => {
                    params.strength / (options.directions as f32 * (1.0 - sin_bias))
                }
                crate::Estimator::Gtao => params.strength / options.directions as f32,
                crate::Estimator::Vo | crate::Estimator::Vao => params.strength,
                // Alchemy AO's 2σ/s with σ = R folded into the sum (shaders/sao.wgsl).
                crate::Estimator::Sao => {
                    2.0 * params.strength / (options.directions * options.steps) as f32
                }
            },
            up_factor: options.upsample_factor(),
            pyramid_offset: 0,
            full_size: [viewport.width, viewport.height],
            patterns: if options.jitter {
                pattern_table(options.directions)
            } else {
                fixed_table(options.directions)
            },
        })
    }

    /// The same frame on a grid of `factor` × `factor` full-resolution pixels per pixel
    /// (`factor` a power of two): `ceil(size / factor)` pixels whose centres sit at the
    /// centres of their full-resolution blocks (`inv_size = factor / full size`), with the
    /// on-screen radius in this grid's pixels.
    pub fn at_factor(&self, factor: u32) -> Self {
        let f = factor as f32;
        Self {
            size: self.full_size.map(|s| s.div_ceil(factor)),
            inv_size: self.full_size.map(|s| f / s as f32),
            radius_to_px: self.radius_to_px / f,
            max_radius_px: self.max_radius_px / f,
            pyramid_offset: factor.ilog2(),
            ..*self
        }
    }

    /// The [`crate::Linearize`] these uniforms encode (for the CPU reference).
    pub fn linearize(&self) -> crate::Linearize {
        crate::Linearize {
            a: self.lin_a,
            b: self.lin_b,
            reciprocal: self.lin_reciprocal != 0,
            sky: match self.sky_test {
                0 => crate::SkyTest::AtLeastOne,
                1 => crate::SkyTest::AtMostZero,
                _ => crate::SkyTest::NonPositive,
            },
        }
    }

    /// Ray-march step in pixels at linear depth `d`; mirrors `march_step_px` in
    /// shaders/common.wgsl.
    pub fn step_px(&self, d: f32, steps: u32) -> f32 {
        let mut radius_px = self.radius * self.radius_to_px;
        if self.perspective != 0 {
            radius_px /= d;
        }
        radius_px.min(self.max_radius_px) / (steps + 1) as f32
    }

    /// View-space position of pixel centre `p` (viewport-local, in pixels) at linear depth `d`.
    /// Mirrors `view_position` in shaders/common.wgsl.
    pub fn view_position(&self, p: [f32; 2], d: f32) -> glam::Vec3 {
        let ndc = glam::Vec2::new(
            p[0] * self.inv_size[0] * 2.0 - 1.0,
            1.0 - p[1] * self.inv_size[1] * 2.0,
        );
        let mut xy = ndc * glam::Vec2::from(self.ndc_to_view);
        if self.perspective != 0 {
            xy *= d;
        }
        xy.extend(-d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AoMode, Estimator, Resolution};

    /// Property test of settings validation: thousands of random option, parameter,
    /// projection, convention and viewport combinations (floats drawn from a bag of
    /// awkward values) never panic; whatever validates yields finite uniforms.
    #[test]
    fn random_settings_validate_or_refuse_never_panic() {
        let bag = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            1e-8,
            1e8,
            3.0,
            60.0,
            4096.0,
            1e30,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE,
            f32::MAX,
        ];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let cases: usize = std::env::var("OBSCURA_FUZZ_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(20000);
        let (mut ok, mut refused) = (0, 0);
        for _ in 0..cases {
            let mut f = || bag[(next() % bag.len() as u64) as usize];
            let options = AoOptions {
                estimator: Estimator::ALL[(f().to_bits() % 5) as usize],
                directions: (f().abs().min(100.0)) as u32,
                steps: (f().abs().min(100.0)) as u32,
                mode: AoMode::ALL[(f().to_bits() % 3) as usize],
                resolution: Resolution::ALL[(f().to_bits() % 3) as usize],
                ..Default::default()
            };
            let params = AoParams {
                radius: f(),
                bias_angle_deg: f(),
                strength: f(),
                max_radius_px: f(),
            };
            let projection = if f() > 0.0 {
                Projection::Perspective {
                    fov_y: f(),
                    aspect: f(),
                    near: f(),
                    far: f(),
                }
            } else {
                Projection::Orthographic {
                    half_width: f(),
                    half_height: f(),
                    near: f(),
                    far: f(),
                }
            };
            let convention = DepthConvention::ALL[(f().to_bits() % 4) as usize];
            let viewport = Viewport {
                x: 0,
                y: 0,
                width: (f().abs().min(1e5)) as u32,
                height: (f().abs().min(1e5)) as u32,
            };
            match FrameUniforms::new(&projection, convention, None, viewport, &options, &params) {
                Ok(u) => {
                    ok += 1;
                    let floats = [
                        u.inv_size[0],
                        u.inv_size[1],
                        u.ndc_to_view[0],
                        u.ndc_to_view[1],
                        u.lin_a,
                        u.lin_b,
                        u.radius,
                        u.inv_radius2,
                        u.radius_to_px,
                        u.ao_scale,
                    ];
                    assert!(
                        floats.iter().all(|v| v.is_finite()),
                        "{options:?} {params:?} {projection:?}: {u:?}"
                    );
                    assert!((1..=64).contains(&options.directions) && params.radius > 0.0);
                }
                Err(_) => refused += 1,
            }
        }
        assert!(ok > 0 && refused > 0, "{ok} accepted, {refused} refused");
    }
}

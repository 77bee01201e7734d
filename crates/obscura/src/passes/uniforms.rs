//! The per-frame uniform block shared by every pass, and how it is derived from the inputs.

use crate::passes::jitter::{fixed_table, pattern_table, PATTERN_COUNT};
use crate::{AoOptions, AoParams, DepthConvention, NormalEncoding, Projection, Result, Viewport};

crate::gpu_struct! {
    /// Everything a pass needs to know about the frame. Built by [`FrameUniforms::new`].
    pub struct FrameUniforms {
        /// Top-left of the viewport in the input textures, pixels.
        pub viewport_origin: [u32; 2],
        /// Size of the processed rectangle, pixels: the viewport grown by the guard band
        /// ([`crate::AoInput::guard_band`]) on each side.
        pub size: [u32; 2],
        /// Where the output (the viewport) starts in the processed rectangle: the guard
        /// band, pixels.
        pub output_offset: [u32; 2],
        /// The output's size, pixels: the viewport's.
        pub output_size: [u32; 2],
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
        /// 0: reconstruct normals from depth; 1: signed input; 2: unorm input.
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
        /// Full-resolution pixels per pixel of the AO the upsampler reads (1, 2, 4 or 8; 1
        /// with [`crate::Resolution::Scaled`], whose upsampler maps by `scale`).
        pub up_factor: u32,
        /// log2 of the full-resolution pixels per pixel of this frame's grid: depth pyramid
        /// level L of the full-resolution buffer is level L − pyramid_offset here.
        pub pyramid_offset: u32,
        /// The viewport size at full resolution, pixels.
        pub full_size: [u32; 2],
        /// The AO's working grid, pixels: `ceil(full_size × scale)`.
        pub work_size: [u32; 2],
        /// Working pixels per full-resolution pixel (1 / the resolution's factor, or
        /// [`crate::AoParams::scale`] with [`crate::Resolution::Scaled`]), and its inverse.
        pub scale: f32,
        pub inv_scale: f32,
        /// Columns (xyz; w unused) of the rotation taking the caller's normals to view
        /// space (identity for view-space normals, see [`NormalEncoding::to_view`]).
        pub normal_to_view: [[f32; 4]; 3],
        /// Temporal accumulation: takes this frame's view-space points to the previous
        /// frame's (columns).
        pub prev_from_view: [[f32; 4]; 4],
        /// The previous frame's `ndc_to_view`.
        pub prev_ndc_to_view: [f32; 2],
        /// The previous frame's grid, whose texels the history holds: its size and
        /// `inv_size` (this frame's own but with [`crate::Resolution::Scaled`], whose grid
        /// changes with the scale).
        pub prev_size: [u32; 2],
        pub prev_inv_size: [f32; 2],
        /// 1 when the history holds the previous frame (same viewport size, no cut or
        /// reset; with [`crate::Resolution::Scaled`] on a grid of `prev_size`).
        pub history: u32,
        /// Most frames the history averages ([`crate::AoOptions::history`]).
        pub history_max: f32,
        /// The sampling model: x the bitmask estimator's thickness prior, view units
        /// ([`crate::AoParams::thickness`] times the radius; 0 means infinitely thick);
        /// yzw unused.
        pub model: [f32; 4],
        /// Depth noise σ(d) = noise.x + noise.y · d + noise.z · d², clamped at 0
        /// ([`crate::AoParams::depth_noise`]); w unused (keeps the next field 16-byte
        /// aligned).
        pub noise: [f32; 4],
        /// The depth terraces' step max(x, y · d²) ([`crate::DepthNoise::step`]); zw unused.
        pub noise_step: [f32; 4],
        /// Per-pixel sampling patterns, see [`crate::jitter`].
        pub patterns: [[f32; 4]; PATTERN_COUNT],
    }
}

/// `viewport` grown by `guard` pixels on each side: the rectangle the passes process.
pub fn guarded(viewport: Viewport, guard: u32) -> Result<Viewport> {
    let grow = |s: u32| s.checked_add(guard.checked_mul(2)?);
    match (
        viewport.x.checked_sub(guard),
        viewport.y.checked_sub(guard),
        grow(viewport.width),
        grow(viewport.height),
    ) {
        (Some(x), Some(y), Some(width), Some(height)) => Ok(Viewport {
            x,
            y,
            width,
            height,
        }),
        _ => Err(crate::Error::InvalidViewport(format!(
            "a guard band of {guard} px around {viewport:?} leaves the depth texture; \
             the depth texture must hold the viewport and the band on every side"
        ))),
    }
}

/// `ceil(size × scale)`, at least 1 and at most `size`: the working grid's side.
pub fn scaled_size(size: u32, scale: f32) -> u32 {
    ((size as f32 * scale).ceil() as u32).clamp(1, size.max(1))
}

impl FrameUniforms {
    /// Validates the inputs and derives the uniform values. No GPU work. The passes
    /// process `viewport` grown by `guard` pixels on each side (the guard band, whose
    /// depth the samples read); `projection` is the viewport's, so the processed
    /// rectangle's frustum is widened by the same factor.
    pub fn new(
        projection: &Projection,
        convention: DepthConvention,
        normals: Option<NormalEncoding>,
        (output, guard): (Viewport, u32),
        options: &AoOptions,
        params: &AoParams,
    ) -> Result<Self> {
        options.validate()?;
        params.validate()?;
        let lin = projection.linearize(convention)?;
        let rotation = normals.map_or(Ok(crate::depth::input::IDENTITY3), |e| e.to_view())?;
        if output.width == 0 || output.height == 0 {
            return Err(crate::Error::InvalidViewport(format!(
                "{}x{} is empty",
                output.width, output.height
            )));
        }
        let viewport = guarded(output, guard)?;
        let widen = |s: u32, o: u32| s as f32 / o as f32;
        let scale = projection.ndc_to_view_scale();
        let scale = [
            scale[0] * widen(viewport.width, output.width),
            scale[1] * widen(viewport.height, output.height),
        ];
        let work_scale = if options.resolution == crate::Resolution::Scaled {
            params.scale
        } else if params.scale != 1.0 {
            return Err(crate::Error::InvalidSetting {
                field: "scale",
                value: params.scale.to_string(),
                expected: "1 unless the resolution is scaled",
            });
        } else {
            1.0 / options.resolution.factor() as f32
        };
        let sin_bias = params.bias_angle_deg.to_radians().sin();
        let u = Self {
            viewport_origin: [viewport.x, viewport.y],
            size: [viewport.width, viewport.height],
            output_offset: [guard, guard],
            output_size: [output.width, output.height],
            inv_size: [1.0 / viewport.width as f32, 1.0 / viewport.height as f32],
            ndc_to_view: scale,
            lin_a: lin.a,
            lin_b: lin.b,
            lin_reciprocal: lin.reciprocal as u32,
            sky_test: lin.sky.code(),
            perspective: projection.is_perspective() as u32,
            normals_mode: match normals {
                None => 0,
                Some(e) if e.is_unorm() => 2,
                Some(_) => 1,
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
                crate::Estimator::Gtao | crate::Estimator::Bitmask => {
                    params.strength / options.directions as f32
                }
                crate::Estimator::Vo | crate::Estimator::Vao | crate::Estimator::VoArea => {
                    params.strength
                }
                // Alchemy AO's 2σ/s with σ = R folded into the sum (passes/estimators/sao.wgsl).
                crate::Estimator::Sao => {
                    2.0 * params.strength / (options.directions * options.steps) as f32
                }
            },
            up_factor: options.upsample_factor(),
            pyramid_offset: 0,
            full_size: [viewport.width, viewport.height],
            work_size: [viewport.width, viewport.height].map(|s| scaled_size(s, work_scale)),
            scale: work_scale,
            inv_scale: 1.0 / work_scale,
            normal_to_view: rotation.map(|c| [c[0], c[1], c[2], 0.0]),
            prev_from_view: glam::Mat4::IDENTITY.to_cols_array_2d(),
            prev_ndc_to_view: scale,
            prev_size: [viewport.width, viewport.height],
            prev_inv_size: [1.0 / viewport.width as f32, 1.0 / viewport.height as f32],
            history: 0,
            history_max: options.history.max(1) as f32,
            model: [
                Some(params.thickness * params.radius)
                    .filter(|t| t.is_finite())
                    .unwrap_or(0.0),
                0.0,
                0.0,
                0.0,
            ],
            noise: [
                params.depth_noise.constant,
                params.depth_noise.linear,
                params.depth_noise.quadratic,
                0.0,
            ],
            noise_step: [
                params.depth_noise.step_constant,
                params.depth_noise.step_quadratic,
                0.0,
                0.0,
            ],
            patterns: if options.jitter {
                pattern_table(crate::passes::jitter::rotation_sector(
                    options.estimator,
                    options.directions,
                ))
            } else {
                fixed_table(crate::passes::jitter::rotation_sector(
                    options.estimator,
                    options.directions,
                ))
            },
        };
        // Extreme but individually valid parameters (a half height of 1e-38, radius 1e30)
        // can still overflow what the passes compute with (found by the property test).
        let derived = [
            u.inv_size[0],
            u.inv_size[1],
            u.ndc_to_view[0],
            u.ndc_to_view[1],
            u.lin_a,
            u.lin_b,
            u.inv_radius2,
            u.radius_to_px,
            u.ao_scale,
        ];
        if derived.iter().any(|v| !v.is_finite()) || u.inv_radius2 <= 0.0 {
            return Err(crate::Error::InvalidProjection(format!(
                "the projection and radius give non-finite screen-space scales \
                 (ndc_to_view {:?}, radius_to_px {}, 1/radius² {}); use values nearer 1",
                u.ndc_to_view, u.radius_to_px, u.inv_radius2
            )));
        }
        Ok(u)
    }

    /// The same frame on a grid of `factor` × `factor` full-resolution pixels per pixel
    /// (`factor` a power of two): `ceil(size / factor)` pixels whose centres sit at the
    /// centres of their full-resolution blocks (`inv_size = factor / full size`), with the
    /// on-screen radius in this grid's pixels.
    pub fn at_factor(&self, factor: u32) -> Self {
        let f = factor as f32;
        let size = self.full_size.map(|s| s.div_ceil(factor));
        let inv_size = self.full_size.map(|s| f / s as f32);
        Self {
            size,
            inv_size,
            prev_size: size,
            prev_inv_size: inv_size,
            radius_to_px: self.radius_to_px / f,
            max_radius_px: self.max_radius_px / f,
            pyramid_offset: factor.ilog2(),
            ..*self
        }
    }

    /// The same frame on the working grid of [`crate::Resolution::Scaled`]: `work_size`
    /// pixels, each standing for `1 / scale` full-resolution pixels, whose centres map to
    /// full-resolution `(q + 0.5) / scale` (`inv_size = 1 / (scale × full size)`), with the
    /// on-screen radius in this grid's pixels.
    /// Its `prev_size` and `prev_inv_size` are its own grid's; the caller sets the previous
    /// frame's when the scale changed.
    pub fn at_scale(&self) -> Self {
        let inv_size = self.full_size.map(|s| self.inv_scale / s as f32);
        Self {
            size: self.work_size,
            inv_size,
            prev_size: self.work_size,
            prev_inv_size: inv_size,
            radius_to_px: self.radius_to_px * self.scale,
            max_radius_px: self.max_radius_px * self.scale,
            pyramid_offset: 0,
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

    /// The AO radius in pixels at linear depth `d`; mirrors `radius_px` in
    /// passes/common.wgsl.
    pub fn radius_px(&self, d: f32) -> f32 {
        let mut r = self.radius * self.radius_to_px;
        if self.perspective != 0 {
            r /= d;
        }
        r.min(self.max_radius_px)
    }

    /// Ray-march step in pixels at linear depth `d`; mirrors `march_step_px` in
    /// passes/common.wgsl.
    pub fn step_px(&self, d: f32, steps: u32) -> f32 {
        self.radius_px(d) / (steps + 1) as f32
    }

    /// Depth noise σ at linear depth `d`; mirrors `depth_sigma` in passes/common.wgsl.
    pub fn depth_sigma(&self, d: f32) -> f32 {
        (self.noise[0] + (self.noise[1] + self.noise[2] * d) * d).max(0.0)
    }

    /// Tangent-plane tolerance of the depth-aware passes at linear depth `d`; mirrors
    /// `plane_tolerance` in passes/common.wgsl.
    pub fn plane_tolerance(&self, d: f32) -> f32 {
        (crate::passes::constants::PLANE_TOLERANCE * d)
            .max(crate::passes::constants::NOISE_TOLERANCE_SIGMAS * self.depth_sigma(d))
    }

    /// The depth terraces' step at linear depth `d`; mirrors `depth_step` in
    /// passes/common.wgsl.
    pub fn depth_step(&self, d: f32) -> f32 {
        self.noise_step[0].max(self.noise_step[1] * d * d)
    }

    /// Where the estimators measure occluders from; mirrors `estimator_origin` in
    /// passes/common.wgsl.
    pub fn estimator_origin(&self, p: [f32; 2], d: f32, n: glam::Vec3) -> glam::Vec3 {
        self.view_position(p, d)
            + n * (crate::passes::constants::NOISE_OFFSET_SIGMAS * self.depth_sigma(d))
    }

    /// View-space position of pixel centre `p` (viewport-local, in pixels) at linear depth `d`.
    /// Mirrors `view_position` in passes/common.wgsl.
    pub fn view_position(&self, p: [f32; 2], d: f32) -> glam::Vec3 {
        self.view_position_scaled(p, d, self.ndc_to_view, self.inv_size)
    }

    /// [`FrameUniforms::view_position`] with another projection's `ndc_to_view` on another
    /// grid's `inv_size` (the previous frame's); mirrors `view_position_scaled` in
    /// passes/common.wgsl.
    pub fn view_position_scaled(
        &self,
        p: [f32; 2],
        d: f32,
        ndc_to_view: [f32; 2],
        inv_size: [f32; 2],
    ) -> glam::Vec3 {
        let ndc = glam::Vec2::new(
            p[0] * inv_size[0] * 2.0 - 1.0,
            1.0 - p[1] * inv_size[1] * 2.0,
        );
        let mut xy = ndc * glam::Vec2::from(ndc_to_view);
        if self.perspective != 0 {
            xy *= d;
        }
        xy.extend(-d)
    }
}

/// A test frame: orthographic, one view unit per pixel, radius 4, linear depth, the whole
/// `w` × `h` image (the denoiser's and the bitmask clip's unit tests).
#[cfg(test)]
pub(crate) fn ortho_test_frame(w: u32, h: u32) -> FrameUniforms {
    use crate::{AoOptions, AoParams, DepthConvention, Projection, Viewport};
    let projection = Projection::Orthographic {
        half_width: w as f32 / 2.0,
        half_height: h as f32 / 2.0,
        near: 0.1,
        far: 100.0,
    };
    let params = AoParams {
        radius: 4.0,
        ..Default::default()
    };
    let viewport = Viewport {
        x: 0,
        y: 0,
        width: w,
        height: h,
    };
    FrameUniforms::new(
        &projection,
        DepthConvention::LinearView,
        None,
        (viewport, 0),
        &AoOptions::default(),
        &params,
    )
    .unwrap()
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
        let state = std::cell::Cell::new(0x2545_f491_4f6c_dd1du64);
        let next = || {
            let mut x = state.get();
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            state.set(x);
            x
        };
        let budget = crate::fuzz::Budget::from_env(20000, 10);
        let (mut ok, mut refused) = (0, 0);
        for _ in (0..).take_while(|&c| budget.more(c)) {
            // Start from valid values and replace each with an awkward one with
            // probability 1/8, so both valid and invalid combinations occur.
            let f = |valid: f32| {
                let r = next();
                if r % 8 == 0 {
                    bag[((r >> 8) % bag.len() as u64) as usize]
                } else {
                    valid
                }
            };
            let pick = |n: u64| (next() % n) as usize;
            let options = AoOptions {
                estimator: Estimator::ALL[pick(5)],
                directions: f(4.0).abs().min(100.0) as u32,
                steps: f(4.0).abs().min(100.0) as u32,
                march_exponent: f(1.0),
                mode: AoMode::ALL[pick(3)],
                resolution: [
                    Resolution::Full,
                    Resolution::Half,
                    Resolution::Quarter,
                    Resolution::Scaled,
                ][pick(4)],
                downsample: crate::DepthDownsample::ALL[pick(4)],
                upsample: crate::Upsampler::ALL[pick(4)],
                denoise: crate::Denoise::ALL[pick(4)],
                fused: pick(2) == 0,
                jitter: pick(2) == 0,
                recentre: pick(2) == 0,
                pyramid: crate::PyramidBuild::ALL[pick(3)],
                history: [0, 1, 2, 16, 300][pick(5)],
                bent_normals: pick(2) == 0,
                second_layer: pick(4) == 0,
            };
            // Caller normals: none, view space, or world space with a rotation whose
            // entries may be awkward too.
            let rotation = [
                [f(1.0), f(0.0), f(0.0)],
                [f(0.0), f(1.0), f(0.0)],
                [f(0.0), f(0.0), f(1.0)],
            ];
            let normals = match pick(4) {
                0 => None,
                1 => Some(NormalEncoding::ViewUnorm),
                2 => Some(NormalEncoding::WorldSigned {
                    view_from_world: rotation,
                }),
                _ => Some(NormalEncoding::WorldUnorm {
                    view_from_world: rotation,
                }),
            };
            let params = AoParams {
                radius: f(1.0),
                bias_angle_deg: f(10.0),
                strength: f(1.0),
                max_radius_px: f(256.0),
                scale: f(1.0),
                thickness: f(0.5),
                depth_noise: crate::DepthNoise {
                    constant: f(0.0),
                    linear: f(0.0),
                    quadratic: f(0.0),
                    step_constant: f(0.0),
                    step_quadratic: f(0.0),
                },
                motion: match pick(3) {
                    0 => crate::CameraMotion::Still,
                    1 => crate::CameraMotion::Cut,
                    _ => crate::CameraMotion::Moved {
                        previous_from_current: [
                            [f(1.0), f(0.0), f(0.0), f(0.0)],
                            [f(0.0), f(1.0), f(0.0), f(0.0)],
                            [f(0.0), f(0.0), f(1.0), f(0.0)],
                            [f(0.0), f(0.0), f(0.0), f(1.0)],
                        ],
                    },
                },
            };
            let projection = if pick(2) == 0 {
                Projection::Perspective {
                    fov_y: f(1.0),
                    aspect: f(1.5),
                    near: f(0.1),
                    far: f(100.0),
                }
            } else {
                Projection::Orthographic {
                    half_width: f(4.0),
                    half_height: f(3.0),
                    near: f(0.1),
                    far: f(100.0),
                }
            };
            let convention = DepthConvention::ALL[pick(4)];
            // Viewports at the texture's corner or inside it, with or without a guard
            // band (one that leaves the texture is refused).
            let corner = 16 * pick(2) as u32;
            let guard = 8 * pick(3) as u32;
            let viewport = Viewport {
                x: corner,
                y: corner,
                width: f(640.0).abs().min(1e5) as u32,
                height: f(400.0).abs().min(1e5) as u32,
            };
            match FrameUniforms::new(
                &projection,
                convention,
                normals,
                (viewport, guard),
                &options,
                &params,
            ) {
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
                        floats
                            .iter()
                            .chain(u.normal_to_view.iter().flatten())
                            .all(|v| v.is_finite()),
                        "{options:?} {params:?} {projection:?}: {u:?}"
                    );
                    assert!((1..=64).contains(&options.directions) && params.radius > 0.0);
                }
                Err(_) => refused += 1,
            }
        }
        eprintln!("fuzz settings: {ok} accepted, {refused} refused, no panic");
        assert!(ok > 0 && refused > 0, "{ok} accepted, {refused} refused");
    }
}

//! Screen-space directional occlusion: one diffuse bounce and the environment's combine.
//! The WGSL and the struct it reads are here; the CPU mirror below reads like the WGSL.

use crate::passes::estimators::{gtao_side, gtao_slice, Pixels, Surface};
use crate::passes::prepare::centre;
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// Pixel classes of the largest period: the uniform holds one pattern per class (as many
/// as the AO's jitter patterns, whose WGSL array type it shares).
pub const SSDO_PATTERNS: usize = crate::passes::jitter::PATTERN_COUNT;
const _: () = assert!(SSDO_PATTERNS >= 16);

crate::gpu_struct! {
    /// Per-frame parameters of the SSDO passes.
    pub struct SsdoUniforms {
        /// The environment's irradiance harmonics (rgb, w unused), [`IrradianceSh`].
        pub irradiance: [[f32; 4]; 9],
        /// Columns (xyz) of the rotation from view space to the environment's world space.
        pub view_to_world: [[f32; 4]; 3],
        /// Per pixel class: the first slice's screen direction (xy) and the march's step
        /// offset in [0, 1) (z).
        pub patterns: [[f32; 4]; SSDO_PATTERNS],
        /// x: 1 when bent normals are bound; y: 1 when the bounce is added.
        pub flags: [u32; 4],
    }
}

/// Environment irradiance / π at view-space `n`; mirrors `env_irradiance` in
/// passes/ssdo/ssdo_env.wgsl.
fn env_irradiance(lighting: &crate::SsdoLighting, n: Vec3) -> Vec3 {
    let m = lighting.view_to_world.map(Vec3::from);
    let d = m[0] * n.x + m[1] * n.y + m[2] * n.z;
    Vec3::from(lighting.irradiance.eval(d.to_array()))
}

/// SSDO's bounce (passes/ssdo/ssdo_bounce.wgsl): per pixel, GTAO's slices with the pattern
/// of the pixel's class of `options.period`, each side's covered arc lit by its horizon
/// sample (albedo × environment irradiance at its normal); 0 on sky. `albedo` is
/// row-major at the frame's size; `options` must pass [`crate::SsdoOptions::validate`].
pub fn ssdo_bounce(
    f: &FrameUniforms,
    prepared: &[Vec4],
    albedo: &[Vec3],
    lighting: &crate::SsdoLighting,
    options: &crate::SsdoOptions,
) -> Vec<Vec3> {
    use std::f32::consts::PI;
    let px = Pixels {
        f,
        directions: options.directions,
        steps: options.steps,
        // SSDO's march is its own (ssdo_bounce.wgsl).
        march_exponent: 1.0,
        prepared,
        lattice: 1,
        pyramid: &[],
        moments: &[],
        second: &[],
    };
    let patterns = options.patterns();
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..h {
        for x in 0..w {
            let p = [x, y];
            let Some(Surface { d, n: normal, pos }) = px.surface(p) else {
                out.push(Vec3::ZERO);
                continue;
            };
            let v = if f.perspective != 0 {
                (-pos).normalize()
            } else {
                Vec3::Z
            };
            let pattern = patterns
                [crate::passes::layers::layer_of(x as u32, y as u32, options.period) as usize];
            let step_px = f.step_px(d, options.steps);
            let tolerance = crate::passes::constants::SSDO_SELF_TOLERANCE * d
                + crate::passes::constants::NOISE_TOLERANCE_SIGMAS * f.depth_sigma(d);
            let (ts, tc) = (PI / options.directions as f32).sin_cos();
            let mut dir = [pattern[0], pattern[1]];
            let (mut weights, mut bounce) = (0.0, Vec3::ZERO);
            for i in 0..options.directions {
                if i > 0 {
                    dir = [dir[0] * tc - dir[1] * ts, dir[0] * ts + dir[1] * tc];
                }
                let s = gtao_slice(dir, v, normal);
                weights += s.weight;
                if s.proj_len < 1e-6 {
                    continue;
                }
                let mut hc = [-s.sin_n, s.sin_n];
                let mut hq = [p, p];
                let mut ray = pattern[2] * step_px + 1.0;
                for _ in 0..options.steps {
                    let off = px.snap([dir[0] * ray, dir[1] * ray]);
                    ray += step_px;
                    if off == [0, 0] {
                        continue;
                    }
                    for side in 0..2 {
                        let q = if side == 0 {
                            [p[0] + off[0], p[1] + off[1]]
                        } else {
                            [p[0] - off[0], p[1] - off[1]]
                        };
                        let Some(sd) = px.depth_at(q) else {
                            continue;
                        };
                        if sd.is_nan() || sd <= 0.0 {
                            continue;
                        }
                        let full = f.view_position(centre(q), sd) - pos;
                        let r2 = full.dot(full) * f.inv_radius2;
                        let wv = full - s.axis * full.dot(s.axis);
                        if r2 >= 1.0 || wv.dot(wv) <= 0.0 || full.dot(normal) <= tolerance {
                            continue;
                        }
                        let c = (wv.dot(v) / wv.dot(wv).sqrt()).clamp(-1.0, 1.0);
                        if c > hc[side] {
                            hc[side] = c;
                            hq[side] = q;
                        }
                    }
                }
                for side in 0..2 {
                    let (sgn, tangent) = if side == 0 {
                        (1.0, -s.sin_n)
                    } else {
                        (-1.0, s.sin_n)
                    };
                    let covered = gtao_side(tangent, sgn, s.n, s.cos_n, s.sin_n)
                        - gtao_side(hc[side], sgn, s.n, s.cos_n, s.sin_n);
                    if covered > 0.0 {
                        let q = hq[side];
                        let i = (q[1] * w + q[0]) as usize;
                        let sn = prepared[i];
                        let radiance =
                            albedo[i] * env_irradiance(lighting, Vec3::new(sn.y, sn.z, sn.w));
                        bounce += (s.weight * s.proj_len * covered) * radiance;
                    }
                }
            }
            out.push(bounce / weights);
        }
    }
    out
}

/// SSDO's combine (passes/ssdo/ssdo_combine.wgsl): `albedo · (ao · E(bent) + bounce)` with the
/// surface normal where `bent` is `None` or zero; 0 on sky.
pub fn ssdo_combine(
    prepared: &[Vec4],
    albedo: &[Vec3],
    ao: &[f32],
    bent: Option<&[Vec3]>,
    bounce: Option<&[Vec3]>,
    lighting: &crate::SsdoLighting,
) -> Vec<Vec3> {
    (0..prepared.len())
        .map(|i| {
            let c = prepared[i];
            if c.x.is_nan() || c.x <= 0.0 {
                return Vec3::ZERO;
            }
            let mut dir = Vec3::new(c.y, c.z, c.w);
            if let Some(b) = bent.map(|b| b[i]).filter(|b| b.length_squared() > 1e-12) {
                dir = b.normalize();
            }
            let mut e = ao[i] * env_irradiance(lighting, dir);
            if let Some(b) = bounce {
                e += b[i];
            }
            albedo[i] * e
        })
        .collect()
}

//! CPU reference of every pass, written to read like the WGSL (same names, same order of
//! operations) so GPU output can be checked against it in tests. Slow; not for production.

use crate::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// Linear depth of viewport-local pixel `p` of a raw depth image (`width` × `height`,
/// row-major, covering the whole input texture); 0 outside the viewport or for sky.
fn linear_depth_at(f: &FrameUniforms, raw: &[f32], raw_width: u32, p: [i32; 2]) -> f32 {
    if p[0] < 0 || p[1] < 0 || p[0] >= f.size[0] as i32 || p[1] >= f.size[1] as i32 {
        return 0.0;
    }
    let x = p[0] as u32 + f.viewport_origin[0];
    let y = p[1] as u32 + f.viewport_origin[1];
    f.linearize()
        .apply(raw[(y * raw_width + x) as usize])
        .unwrap_or(0.0)
}

fn centre(p: [i32; 2]) -> [f32; 2] {
    [p[0] as f32 + 0.5, p[1] as f32 + 0.5]
}

fn axis_derivative(
    f: &FrameUniforms,
    raw: &[f32],
    raw_width: u32,
    p: [i32; 2],
    axis: [i32; 2],
    c: Vec3,
    dc: f32,
) -> Option<Vec3> {
    for k in 1..=2 {
        let m = [p[0] - axis[0] * k, p[1] - axis[1] * k];
        let pp = [p[0] + axis[0] * k, p[1] + axis[1] * k];
        let dm = linear_depth_at(f, raw, raw_width, m);
        let dp = linear_depth_at(f, raw, raw_width, pp);
        if dp > 0.0 && (dm <= 0.0 || (dp - dc).abs() < (dm - dc).abs()) {
            return Some(f.view_position(centre(pp), dp) - c);
        }
        if dm > 0.0 {
            return Some(c - f.view_position(centre(m), dm));
        }
    }
    None
}

/// The three-pixel normal of shaders/normals_reconstruct.wgsl (`view_normal`).
fn reconstructed_normal(
    f: &FrameUniforms,
    raw: &[f32],
    raw_width: u32,
    p: [i32; 2],
    d: f32,
) -> Vec3 {
    let c = f.view_position(centre(p), d);
    let dx = axis_derivative(f, raw, raw_width, p, [1, 0], c, d);
    let dy = axis_derivative(f, raw, raw_width, p, [0, 1], c, d);
    match (dx, dy) {
        (Some(dx), Some(dy)) if dy.cross(dx).length_squared() > 0.0 => {
            let nn = dy.cross(dx).normalize();
            if nn.dot(c) > 0.0 {
                -nn
            } else {
                nn
            }
        }
        _ => (-c).normalize(),
    }
}

/// The MSAA resolve of one pixel (shaders/resolve_depth.wgsl) from its raw sample depths:
/// their mean when every sample is a surface and their linear depths lie within
/// `PLANE_TOLERANCE` of the nearest, else the raw depth of the nearest non-sky sample (the
/// first sample when all are sky).
pub fn resolve_msaa_depth(f: &FrameUniforms, samples: &[f32]) -> f32 {
    use crate::shader::PLANE_TOLERANCE;
    let lin = f.linearize();
    let surfaces: Vec<(f32, f32)> = samples
        .iter()
        .filter_map(|&raw| lin.apply(raw).map(|d| (d, raw)))
        .collect();
    let Some(&(nearest, nearest_raw)) = surfaces.iter().min_by(|a, b| a.0.total_cmp(&b.0)) else {
        return samples[0];
    };
    let farthest = surfaces.iter().map(|s| s.0).fold(nearest, f32::max);
    if surfaces.len() == samples.len() && farthest - nearest <= PLANE_TOLERANCE * nearest {
        samples.iter().sum::<f32>() / samples.len() as f32
    } else {
        nearest_raw
    }
}

/// The prepare pass with normals reconstructed from depth: `vec4(d, n)` per viewport pixel;
/// with a depth noise model in `f`, depth and normal from plane fits ([`fit_surface`]).
pub fn prepare(f: &FrameUniforms, raw: &[f32], raw_width: u32) -> Vec<Vec4> {
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let noisy = f.noise[..3].iter().any(|c| *c != 0.0);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let p = [x, y];
            let d = linear_depth_at(f, raw, raw_width, p);
            if d <= 0.0 {
                out.push(Vec4::new(0.0, 0.0, 0.0, 1.0));
            } else if noisy {
                out.push(fit_surface(f, raw, raw_width, p, d));
            } else {
                out.push(Vec4::from((
                    d,
                    reconstructed_normal(f, raw, raw_width, p, d),
                )));
            }
        }
    }
    out
}

/// Weighted plane sums: `m` = Σ x xᵀ and `r` = Σ x (f − fc) for x = (1, tap x, tap y).
struct PlaneSums {
    m: glam::Mat3,
    r: Vec3,
}

impl PlaneSums {
    /// No taps (glam's `Mat3::default()` is the identity, not zero).
    const EMPTY: PlaneSums = PlaneSums {
        m: glam::Mat3::ZERO,
        r: Vec3::ZERO,
    };

    fn add(&mut self, o: [f32; 2], g: f32) {
        let x = Vec3::new(1.0, o[0], o[1]);
        self.m += glam::Mat3::from_cols(x * x.x, x * x.y, x * x.z);
        self.r += x * g;
    }

    /// `solve_plane` of shaders/normals_fit.wgsl: (f0, a, b) and whether it is a plane.
    fn solve(&self, min_taps: f32) -> Option<Vec3> {
        let m = self.m;
        let det = m.determinant();
        let n = m.x_axis.x;
        // `det > …` is false for NaN too.
        if n < min_taps || det.partial_cmp(&(1e-3 * n * n * n)) != Some(std::cmp::Ordering::Greater)
        {
            return None;
        }
        Some(Vec3::new(
            glam::Mat3::from_cols(self.r, m.y_axis, m.z_axis).determinant() / det,
            glam::Mat3::from_cols(m.x_axis, self.r, m.z_axis).determinant() / det,
            glam::Mat3::from_cols(m.x_axis, m.y_axis, self.r).determinant() / det,
        ))
    }
}

/// Depth and normal of a pixel of noisy depth; mirrors `surface` in
/// shaders/normals_fit.wgsl.
pub fn fit_surface(f: &FrameUniforms, raw: &[f32], raw_width: u32, p: [i32; 2], d: f32) -> Vec4 {
    use crate::shader::{FIT_MAX_STRIDE, FIT_NORMAL_TAN, FIT_RADIUS, FIT_SIGMAS, FIT_SLOPE};
    let persp = f.perspective != 0;
    let sigma = f.depth_sigma(d);
    let footprint = if persp { d } else { 1.0 } / f.radius_to_px;
    let need = sigma / (footprint * FIT_NORMAL_TAN);
    let mut reach = if need * need <= 6.0 {
        1
    } else if need * need <= 50.0 {
        2
    } else {
        FIT_RADIUS
    };
    let mut stride = (need / 14.0).ceil().clamp(1.0, FIT_MAX_STRIDE as f32) as i32;
    let step = f.depth_step(d);
    let need_step = step / (2.0 * footprint * FIT_NORMAL_TAN);
    if need_step > (reach * stride) as f32 {
        reach = FIT_RADIUS;
        stride = stride.max(
            (need_step / FIT_RADIUS as f32)
                .ceil()
                .clamp(1.0, FIT_MAX_STRIDE as f32) as i32,
        );
    }
    let to_f = |v: f32| if persp { 1.0 / v } else { v };
    let fc = to_f(d);
    let side = 2 * FIT_RADIUS + 1;
    let mut taps = Vec::with_capacity((side * side) as usize);
    let mut first = PlaneSums::EMPTY;
    for k in 0..side * side {
        let o = [k % side - FIT_RADIUS, k / side - FIT_RADIUS];
        if o[0].abs() > reach || o[1].abs() > reach {
            taps.push(0.0);
            continue;
        }
        let dq = linear_depth_at(
            f,
            raw,
            raw_width,
            [p[0] + o[0] * stride, p[1] + o[1] * stride],
        );
        let fq = if dq > 0.0 { to_f(dq) } else { 0.0 };
        taps.push(fq);
        let tol = std::f32::consts::SQRT_2 * FIT_SIGMAS * sigma
            + step
            + FIT_SLOPE * footprint * stride as f32;
        if o[0].abs() <= 1 && o[1].abs() <= 1 && dq > 0.0 && (dq - d).abs() <= tol {
            first.add([o[0] as f32, o[1] as f32], fq - fc);
        }
    }
    let fallback = || Vec4::from((d, reconstructed_normal(f, raw, raw_width, p, d)));
    let Some(first) = first.solve(5.0) else {
        return fallback();
    };
    let mut second = PlaneSums::EMPTY;
    for (k, &fq) in taps.iter().enumerate() {
        let k = k as i32;
        let o = [
            (k % side - FIT_RADIUS) as f32,
            (k / side - FIT_RADIUS) as f32,
        ];
        let fp = fc + first.x + first.y * o[0] + first.z * o[1];
        let (dq, dp) = (to_f(fq), to_f(fp));
        let tol = FIT_SIGMAS * f.depth_sigma(dp) * (1.0 + (o[0] * o[0] + o[1] * o[1]) / 6.0).sqrt()
            + f.depth_step(dp);
        if fq != 0.0 && dp > 0.0 && (dq - dp).abs() <= tol {
            second.add(o, fq - fc);
        }
    }
    let Some(plane) = second.solve(6.0) else {
        return fallback();
    };
    let f0 = fc + plane.x;
    let dfit = to_f(f0);
    if !(dfit > 0.0 && dfit.is_finite()) {
        return fallback();
    }
    let k = glam::Vec2::new(
        2.0 * f.inv_size[0] * f.ndc_to_view[0],
        -2.0 * f.inv_size[1] * f.ndc_to_view[1],
    );
    let g = glam::Vec2::new(plane.y, plane.z) / (stride as f32 * k);
    let ray = f.view_position(centre(p), 1.0);
    let n = if persp {
        g.extend(g.dot(ray.truncate()) - f0)
    } else {
        g.extend(1.0)
    };
    let len2 = n.length_squared();
    if !(len2 > 0.0 && len2.is_finite()) {
        return fallback();
    }
    let mut n = n / len2.sqrt();
    if persp && n.dot(ray) > 0.0 {
        n = -n;
    }
    Vec4::from((dfit, n))
}

/// What every estimator's pixel function reads: the frame, the compiled sample counts,
/// the prepared buffer (viewport-sized) and the sampling lattice of the mode (1: any pixel;
/// N: offsets snapped to multiples of N, which is what the N×N deinterleaved pass samples).
#[derive(Clone, Copy, Debug)]
pub struct Pixels<'a> {
    pub f: &'a FrameUniforms,
    pub directions: u32,
    pub steps: u32,
    pub prepared: &'a [Vec4],
    pub lattice: u32,
    /// The depth pyramid of the full-resolution buffer ([`pyramid`]), for estimators that
    /// read it; may be empty.
    pub pyramid: &'a [PyramidLevel],
    /// The depth moments pyramid ([`moments`]) for VO's area integral; may be empty.
    pub moments: &'a [PyramidLevel],
}

/// One level of the depth pyramid: `[select, min, max]` per texel, row-major (or of the
/// moments pyramid: `[valid fraction, mean, variance]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PyramidLevel {
    pub size: [u32; 2],
    pub texels: Vec<[f32; 3]>,
}

impl PyramidLevel {
    fn at(&self, p: [i32; 2]) -> [f32; 3] {
        self.texels[(p[1] * self.size[0] as i32 + p[0]) as usize]
    }
}

/// The depth pyramid of a prepared buffer (`size` pixels); mirrors shaders/pyramid.wgsl.
/// Level `k` of the result is pyramid level `k + 1` (texture mip `k`).
pub fn pyramid(size: [u32; 2], prepared: &[Vec4]) -> Vec<PyramidLevel> {
    let level0 = PyramidLevel {
        size,
        texels: prepared.iter().map(|v| [v.x; 3]).collect(),
    };
    let base = [1.max(size[0] >> 1), 1.max(size[1] >> 1)];
    let count = base[0].max(base[1]).ilog2() + 1;
    let mut levels = vec![level0];
    for _ in 0..count {
        let src = levels.last().unwrap();
        let dst = [1.max(src.size[0] >> 1), 1.max(src.size[1] >> 1)];
        let ssz = [src.size[0] as i32, src.size[1] as i32];
        let mut texels = Vec::with_capacity((dst[0] * dst[1]) as usize);
        for ty in 0..dst[1] as i32 {
            for tx in 0..dst[0] as i32 {
                let (lo, hi) = footprint([tx, ty], dst, src.size);
                let pick = [
                    (lo[0] + ((ty & 1) ^ 1)).min(ssz[0] - 1),
                    (lo[1] + ((tx & 1) ^ 1)).min(ssz[1] - 1),
                ];
                let (mut mn, mut mx) = (f32::MAX, 0.0f32);
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let s = src.at([x, y]);
                        if s[2] > 0.0 {
                            mn = mn.min(s[1]);
                            mx = mx.max(s[2]);
                        }
                    }
                }
                if mx <= 0.0 {
                    mn = 0.0;
                }
                texels.push([src.at(pick)[0], mn, mx]);
            }
        }
        levels.push(PyramidLevel { size: dst, texels });
    }
    levels.remove(0);
    levels
}

/// Footprint of texel `t` of a level of size `dst` over the level above (size `src`): 2t ..
/// 2t + 1, the last texel also covering an odd-sized level's orphan column/row.
fn footprint(t: [i32; 2], dst: [u32; 2], src: [u32; 2]) -> ([i32; 2], [i32; 2]) {
    let lo = [2 * t[0], 2 * t[1]];
    let hi = std::array::from_fn(|a| {
        let last = t[a] == dst[a] as i32 - 1;
        (if last { src[a] as i32 - 1 } else { lo[a] + 1 }).min(src[a] as i32 - 1)
    });
    (lo, hi)
}

/// The depth moments pyramid of a prepared buffer (`size` pixels); mirrors
/// shaders/moments.wgsl. Level `k` of the result is level `k + 1` (texture mip `k`), texels
/// `[valid fraction, mean, variance]` of the non-sky linear depths under them.
pub fn moments(size: [u32; 2], prepared: &[Vec4]) -> Vec<PyramidLevel> {
    let base = [1.max(size[0] >> 1), 1.max(size[1] >> 1)];
    let count = base[0].max(base[1]).ilog2() + 1;
    let mut levels = vec![PyramidLevel {
        size,
        texels: prepared
            .iter()
            .map(|v| if v.x > 0.0 { [1.0, v.x, 0.0] } else { [0.0; 3] })
            .collect(),
    }];
    for _ in 0..count {
        let src = levels.last().unwrap();
        let dst = [1.max(src.size[0] >> 1), 1.max(src.size[1] >> 1)];
        let mut texels = Vec::with_capacity((dst[0] * dst[1]) as usize);
        for ty in 0..dst[1] as i32 {
            for tx in 0..dst[0] as i32 {
                let (lo, hi) = footprint([tx, ty], dst, src.size);
                let (mut count, mut weight, mut mean, mut deviations) =
                    (0.0f32, 0.0f32, 0.0f32, 0.0f32);
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let c = src.at([x, y]);
                        count += 1.0;
                        if c[0] > 0.0 {
                            let merged = weight + c[0];
                            let delta = c[1] - mean;
                            mean += delta * c[0] / merged;
                            deviations += c[2] * c[0] + delta * delta * weight * c[0] / merged;
                            weight = merged;
                        }
                    }
                }
                let variance = if weight > 0.0 {
                    deviations / weight
                } else {
                    0.0
                };
                texels.push([weight / count, mean, variance]);
            }
        }
        levels.push(PyramidLevel { size: dst, texels });
    }
    levels.remove(0);
    levels
}

/// E[max(z − c, 0)] for z uniform on [lo, hi] (a point where lo = hi); mirrors
/// `expected_ramp` in shaders/sphere_area.wgsl.
pub fn expected_ramp(lo: f32, hi: f32, c: f32) -> f32 {
    if hi <= c {
        0.0
    } else if lo >= c {
        0.5 * (lo + hi) - c
    } else {
        let x = hi - c;
        x * x / (2.0 * (hi - lo))
    }
}

/// The occupied length of the chord `dc ± h` by a surface at depth `sd > 0` whose solid is
/// `thickness` deep (VO's thickness model; `occupied_length` in shaders/sphere.wgsl).
pub fn occupied_length(sd: f32, dc: f32, h: f32, thickness: f32) -> f32 {
    ((dc + h).min(sd + thickness) - sd.max(dc - h)).clamp(0.0, 2.0 * h)
}

/// The expected occupied length of the chord `dc ± h` over depths uniform with `mean` and
/// `variance` (`chord_occupied` in shaders/sphere_area.wgsl, before the valid fraction).
pub fn expected_occupied(mean: f32, variance: f32, dc: f32, h: f32, thickness: f32) -> f32 {
    let w = (3.0 * variance.max(0.0)).sqrt();
    let (lo, hi) = (mean - w, mean + w);
    let (a, b) = (dc + h, dc - h);
    let e = expected_ramp(lo, hi, b - thickness)
        - expected_ramp(lo, hi, a - thickness)
        - expected_ramp(lo, hi, b)
        + expected_ramp(lo, hi, a);
    e.clamp(0.0, 2.0 * h)
}

/// The surface seen at a pixel: linear depth, normal, view position.
struct Surface {
    d: f32,
    n: Vec3,
    pos: Vec3,
}

impl Pixels<'_> {
    /// The surface at `p`, or `None` for sky (every estimator then returns 1).
    fn surface(&self, p: [i32; 2]) -> Option<Surface> {
        let v = self.prepared[(p[1] * self.f.size[0] as i32 + p[0]) as usize];
        (v.x > 0.0).then(|| Surface {
            d: v.x,
            n: Vec3::new(v.y, v.z, v.w),
            pos: self
                .f
                .estimator_origin(centre(p), v.x, Vec3::new(v.y, v.z, v.w)),
        })
    }

    /// `v` (pixels) snapped to the lattice, as WGSL's round() does (half to even).
    fn snap(&self, v: [f32; 2]) -> [i32; 2] {
        let l = self.lattice as f32;
        v.map(|c| (c / l).round_ties_even() as i32 * self.lattice as i32)
    }

    /// Linear depth at `q`, or `None` outside the viewport.
    fn depth_at(&self, q: [i32; 2]) -> Option<f32> {
        let (w, h) = (self.f.size[0] as i32, self.f.size[1] as i32);
        (q[0] >= 0 && q[1] >= 0 && q[0] < w && q[1] < h)
            .then(|| self.prepared[(q[1] * w + q[0]) as usize].x)
    }
}

/// HBAO of one pixel; mirrors `estimate` in shaders/hbao.wgsl.
pub fn hbao_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    hbao_pixel_bent(px, p, pattern).0
}

/// HBAO of one pixel and its bent normal (unit, view space; zero on sky); mirrors
/// `estimate` in shaders/hbao.wgsl with BENT_NORMALS.
pub fn hbao_pixel_bent(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> (f32, Vec3) {
    let f = px.f;
    let Some(Surface { d, n, pos }) = px.surface(p) else {
        return (1.0, Vec3::ZERO);
    };
    let step_px = f.step_px(d, px.steps);
    let mut occlusion = 0.0;
    let mut bent = Vec3::ZERO;
    for i in 0..px.directions {
        let a = i as f32 * (std::f32::consts::TAU / px.directions as f32);
        let (bs, bc) = a.sin_cos();
        let dir = [
            bc * pattern[0] - bs * pattern[1],
            bc * pattern[1] + bs * pattern[0],
        ];
        let mut ray = pattern[2] * step_px + 1.0;
        let mut sin_h = f.sin_bias;
        for _ in 0..px.steps {
            let off = px.snap([dir[0] * ray, dir[1] * ray]);
            let q = [p[0] + off[0], p[1] + off[1]];
            ray += step_px;
            let Some(sd) = px.depth_at(q) else {
                break;
            };
            if sd <= 0.0 {
                continue;
            }
            let v = f.view_position(centre(q), sd) - pos;
            let r2 = v.dot(v) * f.inv_radius2;
            if r2 >= 1.0 || r2 <= 0.0 {
                continue;
            }
            let sin_e = n.dot(v) / v.dot(v).sqrt();
            if sin_e > sin_h {
                occlusion += (sin_e - sin_h) * (1.0 - r2);
                sin_h = sin_e;
            }
        }
        // Above the horizon in this direction: t cos³h / 3 + n (1 − sin³h) / 3, t the
        // screen direction moved along the view vector into the tangent plane.
        let view = if f.perspective != 0 {
            (-pos).normalize()
        } else {
            Vec3::Z
        };
        let d3 = Vec3::new(dir[0], -dir[1], 0.0);
        let along = d3 * view.dot(n).max(1e-4) - view * d3.dot(n);
        let t = along / along.dot(along).max(1e-12).sqrt();
        let s = sin_h.clamp(-1.0, 1.0);
        let c2 = 1.0 - s * s;
        bent += t * (c2 * c2.sqrt() / 3.0) + n * ((1.0 - s * s * s) / 3.0);
    }
    let bent = if bent.length_squared() > 1e-12 {
        bent.normalize()
    } else {
        n
    };
    ((1.0 - occlusion * f.ao_scale).clamp(0.0, 1.0), bent)
}

/// acos with |error| ≤ 1e-4 rad on [-1, 1] (Abramowitz & Stegun 4.4.45); mirrors
/// `fast_acos` in shaders/gtao_arcs.wgsl.
fn fast_acos(x: f32) -> f32 {
    use crate::shader::ACOS_POLY as k;
    let a = x.abs();
    let r = (1.0 - a).sqrt() * (k[0] + a * (k[1] + a * (k[2] + a * k[3])));
    if x < 0.0 {
        std::f32::consts::PI - r
    } else {
        r
    }
}

/// One side's visible arc of a GTAO slice; mirrors `gtao_side` in shaders/gtao_arcs.wgsl.
fn gtao_side(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    use std::f32::consts::FRAC_PI_2;
    let t = s * fast_acos(c) - n;
    let h = n + t.clamp(-FRAC_PI_2, FRAC_PI_2);
    let sin_h = s * (1.0 - c * c).max(0.0).sqrt();
    let cos_2h_n = if t.abs() > FRAC_PI_2 {
        -cos_n
    } else {
        (2.0 * c * c - 1.0) * cos_n + 2.0 * sin_h * c * sin_n
    };
    (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25
}

/// One side's share of a GTAO slice's bent normal in (ortho, V) coordinates; mirrors
/// `gtao_bent` in shaders/gtao_arcs.wgsl (closed form there).
fn gtao_bent(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> glam::Vec2 {
    use std::f32::consts::FRAC_PI_2;
    let t = s * fast_acos(c) - n;
    let (ch, sh) = if t > FRAC_PI_2 {
        (-sin_n, cos_n)
    } else if t < -FRAC_PI_2 {
        (sin_n, -cos_n)
    } else {
        (c, s * (1.0 - c * c).max(0.0).sqrt())
    };
    let (sh3, ch3) = (sh * sh * sh, ch * ch * ch);
    glam::Vec2::new(
        cos_n * sh3 + sin_n * (2.0 - 3.0 * ch + ch3),
        cos_n * (1.0 - ch3) + sin_n * sh3,
    ) / 3.0
}

/// One GTAO slice's frame; mirrors `GtaoSlice` in shaders/gtao_arcs.wgsl.
struct GtaoSlice {
    axis: Vec3,
    /// Unit.
    ortho: Vec3,
    weight: f32,
    proj_len: f32,
    n: f32,
    cos_n: f32,
    sin_n: f32,
}

/// Mirrors `gtao_slice` in shaders/gtao_arcs.wgsl.
fn gtao_slice(dir: [f32; 2], v: Vec3, normal: Vec3) -> GtaoSlice {
    let dir3 = Vec3::new(dir[0], -dir[1], 0.0);
    let ortho = dir3 - dir3.dot(v) * v;
    let axis = ortho.cross(v).normalize();
    let ddir3 = Vec3::new(-dir[1], -dir[0], 0.0);
    let dortho = ddir3 - ddir3.dot(v) * v;
    let weight = dortho.dot(axis).abs() / ortho.length();
    let proj_n = normal - axis * normal.dot(axis);
    let proj_len = proj_n.length();
    let cos_n = (proj_n.dot(v) / proj_len.max(1e-30)).clamp(-1.0, 1.0);
    // WGSL's sign(0) is 0 (f32::signum(0.0) is 1).
    let x = ortho.dot(proj_n);
    let sgn = if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    };
    GtaoSlice {
        axis,
        ortho: ortho.normalize(),
        weight,
        proj_len,
        n: sgn * fast_acos(cos_n),
        cos_n,
        sin_n: sgn * (1.0 - cos_n * cos_n).sqrt(),
    }
}

/// GTAO of one pixel; mirrors `estimate` in shaders/gtao.wgsl.
pub fn gtao_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    gtao_pixel_bent(px, p, pattern).0
}

/// GTAO of one pixel and its bent normal (unit, view space; zero on sky); mirrors
/// `estimate` in shaders/gtao.wgsl with BENT_NORMALS.
pub fn gtao_pixel_bent(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> (f32, Vec3) {
    use std::f32::consts::PI;
    let f = px.f;
    let Some(Surface { d, n: normal, pos }) = px.surface(p) else {
        return (1.0, Vec3::ZERO);
    };
    let v = if f.perspective != 0 {
        (-pos).normalize()
    } else {
        Vec3::Z
    };
    let step_px = f.step_px(d, px.steps);
    let mut visibility = 0.0;
    let mut weights = 0.0;
    let mut bent = Vec3::ZERO;
    let (ts, tc) = (PI / px.directions as f32).sin_cos();
    let mut dir = [pattern[0], pattern[1]];
    for i in 0..px.directions {
        if i > 0 {
            dir = [dir[0] * tc - dir[1] * ts, dir[0] * ts + dir[1] * tc];
        }
        let GtaoSlice {
            axis,
            ortho,
            weight,
            proj_len,
            n,
            cos_n,
            sin_n,
        } = gtao_slice(dir, v, normal);
        weights += weight;
        if proj_len < 1e-6 {
            visibility += weight;
            continue;
        }
        let mut hc = [-sin_n, sin_n];
        let mut ray = pattern[2] * step_px + 1.0;
        for _ in 0..px.steps {
            let off = px.snap([dir[0] * ray, dir[1] * ray]);
            ray += step_px;
            // The centre is never its own occluder (gtao.wgsl).
            if off == [0, 0] {
                continue;
            }
            for (side, h) in hc.iter_mut().enumerate() {
                let q = if side == 0 {
                    [p[0] + off[0], p[1] + off[1]]
                } else {
                    [p[0] - off[0], p[1] - off[1]]
                };
                let Some(sd) = px.depth_at(q) else {
                    continue;
                };
                if sd <= 0.0 {
                    continue;
                }
                let full = f.view_position(centre(q), sd) - pos;
                let r2 = full.dot(full) * f.inv_radius2;
                let w = full - axis * full.dot(axis);
                if r2 >= 1.0 || w.dot(w) <= 0.0 {
                    continue;
                }
                *h = h.max((w.dot(v) / w.dot(w).sqrt()).clamp(-1.0, 1.0));
            }
        }
        let arcs = gtao_side(hc[0], 1.0, n, cos_n, sin_n) + gtao_side(hc[1], -1.0, n, cos_n, sin_n);
        visibility += weight * proj_len * arcs;
        let b = gtao_bent(hc[0], 1.0, n, cos_n, sin_n) + gtao_bent(hc[1], -1.0, n, cos_n, sin_n);
        bent += weight * proj_len * (b.x * ortho + b.y * v);
    }
    let dirs = px.directions as f32;
    let per_slice = dirs * visibility / weights;
    let bent = if bent.length_squared() > 1e-12 {
        bent.normalize()
    } else {
        normal
    };
    (
        (1.0 - (dirs - per_slice) * f.ao_scale).clamp(0.0, 1.0),
        bent,
    )
}

/// VO (`offset` 0) or VAO (`offset` 0.5) of one pixel; mirrors `estimate` in
/// shaders/sphere.wgsl.
/// With `area`, VO's area integral: samples whose share of the disk is 4 px² or more read
/// `px.moments` (shaders/sphere_area.wgsl).
pub fn sphere_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4], offset: f32, area: bool) -> f32 {
    let f = px.f;
    let Some(Surface { n, pos, .. }) = px.surface(p) else {
        return 1.0;
    };
    let rs = f.radius * (1.0 - offset);
    let c = pos + n * (f.radius * offset);
    let dc = -c.z;
    if dc <= 0.0 {
        return 1.0;
    }
    let rs_px = f.radius_px(dc) * (1.0 - offset);
    // Projection of the centre to pixels, relative to this pixel's centre.
    let mut xy = glam::Vec2::new(c.x, c.y) / glam::Vec2::from(f.ndc_to_view);
    if f.perspective != 0 {
        xy /= -c.z;
    }
    let c_px = [
        (xy.x + 1.0) * 0.5 / f.inv_size[0] - (p[0] as f32 + 0.5),
        (1.0 - xy.y) * 0.5 / f.inv_size[1] - (p[1] as f32 + 0.5),
    ];
    let level = if area {
        let share = std::f32::consts::PI * rs_px * rs_px / (px.directions * px.steps) as f32;
        let most = px.moments.len() as i32 - f.pyramid_offset as i32;
        (((share.max(1.0) as u32).ilog2() / 2) as i32).min(most.max(0))
    } else {
        0
    };
    let thickness = crate::shader::SPHERE_THICKNESS * f.radius;
    let (mut occupied, mut total) = (0.0f32, 0.0f32);
    for i in 0..px.directions {
        let a = i as f32 * (std::f32::consts::TAU / px.directions as f32);
        let (bs, bc) = a.sin_cos();
        let dir = [
            bc * pattern[0] - bs * pattern[1],
            bc * pattern[1] + bs * pattern[0],
        ];
        for s in 0..px.steps {
            let r = ((s as f32 + pattern[2]) / px.steps as f32).sqrt();
            let off = px.snap([
                c_px[0] + dir[0] * (r * rs_px),
                c_px[1] + dir[1] * (r * rs_px),
            ]);
            let q = [p[0] + off[0], p[1] + off[1]];
            let Some(sd) = px.depth_at(q) else {
                continue;
            };
            // The chord runs through the sample's pixel, or the centre of its moments texel.
            let point = if level > 0 {
                let side = (1 << level) as f32;
                [
                    ((q[0] >> level) as f32 + 0.5) * side,
                    ((q[1] >> level) as f32 + 0.5) * side,
                ]
            } else {
                centre(q)
            };
            let lateral = f.view_position(point, dc) - c;
            let l2 = (lateral.x * lateral.x + lateral.y * lateral.y) / (rs * rs);
            if l2 >= 1.0 {
                continue;
            }
            let h = rs * (1.0 - l2).sqrt();
            total += 2.0 * h;
            if level > 0 {
                let l = &px.moments[(level as u32 + f.pyramid_offset) as usize - 1];
                let t = [
                    (q[0] >> level).min(l.size[0] as i32 - 1),
                    (q[1] >> level).min(l.size[1] as i32 - 1),
                ];
                let [fraction, mean, variance] = l.at(t);
                if fraction > 0.0 {
                    occupied += fraction * expected_occupied(mean, variance, dc, h, thickness);
                }
            } else if sd > 0.0 {
                occupied += occupied_length(sd, dc, h, thickness);
            }
        }
    }
    if total <= 0.0 {
        return 1.0;
    }
    let mut open = 1.0 - occupied / total;
    if offset == 0.0 {
        open *= 2.0;
    }
    (1.0 - (1.0 - open.min(1.0)) * f.ao_scale).clamp(0.0, 1.0)
}

/// SAO of one pixel; mirrors `estimate` in shaders/sao.wgsl. With an empty `px.pyramid`
/// every sample reads full-resolution depth (used by tests to show the mips matter).
pub fn sao_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    const GOLDEN_TURN: f32 = 0.381_966_02;
    let f = px.f;
    let Some(Surface { d, n, pos }) = px.surface(p) else {
        return 1.0;
    };
    let r_px = f.radius_px(d);
    let r2 = f.radius * f.radius;
    let count = px.directions * px.steps;
    let mut sum = 0.0;
    for i in 0..count {
        let (bs, bc) = ((i as f32 * GOLDEN_TURN).fract() * std::f32::consts::TAU).sin_cos();
        let dir = [
            bc * pattern[0] - bs * pattern[1],
            bc * pattern[1] + bs * pattern[0],
        ];
        let ss_r = (i as f32 + pattern[2]) / count as f32 * r_px;
        let off = px.snap([dir[0] * ss_r, dir[1] * ss_r]);
        let q = [p[0] + off[0], p[1] + off[1]];
        let Some(full_depth) = px.depth_at(q) else {
            continue;
        };
        let most = px.pyramid.len() as i32 - f.pyramid_offset as i32;
        let level = ((ss_r.max(1.0) as u32).ilog2() as i32 - 3).min(most).max(0);
        let sd = if level == 0 {
            full_depth
        } else {
            let l = &px.pyramid[(level as u32 + f.pyramid_offset) as usize - 1];
            let t = [
                (q[0] >> level).min(l.size[0] as i32 - 1),
                (q[1] >> level).min(l.size[1] as i32 - 1),
            ];
            l.at(t)[0]
        };
        if sd <= 0.0 {
            continue;
        }
        let v = f.view_position(centre(q), sd) - pos;
        let vv = v.dot(v);
        if vv >= r2 {
            continue;
        }
        sum += (v.dot(n) - vv.sqrt() * f.sin_bias).max(0.0) / (vv + 0.01 * r2);
    }
    (1.0 - sum * f.radius * f.ao_scale).clamp(0.0, 1.0)
}

/// AO over the whole viewport with `options`' estimator in its mode, computed per
/// full-resolution pixel: the
/// randomized pass takes the pattern of the pixel's place in the 4×4 tile; an N×N
/// deinterleaved mode takes the pattern of the pixel's layer and samples on the N-pixel
/// lattice. The GPU's deinterleaved layout must give exactly this.
pub fn ao(f: &FrameUniforms, options: &crate::AoOptions, prepared: &[Vec4]) -> Vec<f32> {
    ao_over(f, options, prepared, f.size, prepared)
}

/// [`ao`] on a working grid below full resolution (`f` the working frame, `prepared` its
/// level), with the depth pyramid and moments built, as on the GPU, from the
/// full-resolution buffer `full` (`full_size` pixels; only `.x`, linear depth, is read).
pub fn ao_over(
    f: &FrameUniforms,
    options: &crate::AoOptions,
    prepared: &[Vec4],
    full_size: [u32; 2],
    full: &[Vec4],
) -> Vec<f32> {
    over_pixels(
        f,
        options,
        prepared,
        full_size,
        full,
        |px, q, pattern| match options.estimator {
            crate::Estimator::Hbao => hbao_pixel(px, q, pattern),
            crate::Estimator::Gtao => gtao_pixel(px, q, pattern),
            crate::Estimator::Vo => sphere_pixel(px, q, pattern, 0.0, false),
            crate::Estimator::Vao => sphere_pixel(px, q, pattern, 0.5, false),
            crate::Estimator::VoArea => sphere_pixel(px, q, pattern, 0.0, true),
            crate::Estimator::Sao => sao_pixel(px, q, pattern),
        },
    )
}

/// The bent normals of GTAO or HBAO ([`crate::AoOptions::bent_normals`]) over the grid of
/// `f` (the working frame; `prepared` its level) with the patterns and lattice of the
/// mode, as the AO pass writes them before any denoiser (unit, view space; zero on sky).
pub fn bent_normals(f: &FrameUniforms, options: &crate::AoOptions, prepared: &[Vec4]) -> Vec<Vec3> {
    let hbao = options.estimator == crate::Estimator::Hbao;
    over_pixels(f, options, prepared, f.size, prepared, |px, q, pattern| {
        if hbao {
            hbao_pixel_bent(px, q, pattern).1
        } else {
            gtao_pixel_bent(px, q, pattern).1
        }
    })
}

/// `pixel` at every pixel of `f`'s grid with the pattern and sampling lattice of the mode
/// (what [`ao_over`] runs the estimator with).
fn over_pixels<T>(
    f: &FrameUniforms,
    options: &crate::AoOptions,
    prepared: &[Vec4],
    full_size: [u32; 2],
    full: &[Vec4],
    pixel: impl Fn(&Pixels, [i32; 2], [f32; 4]) -> T,
) -> Vec<T> {
    let n = options.mode.split();
    let (dim, lattice) = if n == 1 {
        (crate::jitter::PATTERN_DIM, 1)
    } else {
        (n, n)
    };
    let levels = if options.estimator.uses_pyramid() {
        pyramid(full_size, full)
    } else {
        Vec::new()
    };
    let moment_levels = if options.estimator.uses_moments() {
        moments(full_size, full)
    } else {
        Vec::new()
    };
    let px = Pixels {
        f,
        directions: options.directions,
        steps: options.steps,
        prepared,
        lattice,
        pyramid: &levels,
        moments: &moment_levels,
    };
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..f.size[1] {
        for x in 0..f.size[0] {
            let pattern = f.patterns[crate::jitter::pattern_index(x, y, dim)];
            out.push(pixel(&px, [x as i32, y as i32], pattern));
        }
    }
    out
}

/// Depth downsampling 2×2 → 1 of prepared level `level − 1` (`size` pixels) into level
/// `level` by `rule`, recentring the pick when `recentre`; mirrors shaders/downsample.wgsl.
/// `f`: the full-resolution frame. Returns the `ceil(size / 2)` result.
pub fn downsample(
    rule: crate::DepthDownsample,
    f: &FrameUniforms,
    level: u32,
    recentre: bool,
    size: [u32; 2],
    prepared: &[Vec4],
) -> ([u32; 2], Vec<Vec4>) {
    let dst = size.map(|s| s.div_ceil(2));
    let mut out = Vec::with_capacity((dst[0] * dst[1]) as usize);
    for ty in 0..dst[1] {
        for tx in 0..dst[0] {
            // (child index, value): the index places the pick for recentring.
            let children: Vec<(u32, Vec4)> = (0..4)
                .filter_map(|i| {
                    let (x, y) = (2 * tx + (i & 1), 2 * ty + (i >> 1));
                    (x < size[0] && y < size[1])
                        .then(|| (i, prepared[(y * size[0] + x) as usize]))
                        .filter(|v| v.1.x > 0.0)
                })
                .collect();
            if children.is_empty() {
                out.push(Vec4::new(0.0, 0.0, 0.0, 1.0));
                continue;
            }
            let pick = pick_child(rule, [tx, ty], &children);
            out.push(if recentre {
                recentred(f, level, [tx, ty], pick.0, pick.1)
            } else {
                pick.1
            });
        }
    }
    (dst, out)
}

/// The child `rule` picks for texel `t` among `children` (index, value), none of them sky;
/// mirrors `pick_child` in shaders/downsample_rule.wgsl.
fn pick_child(rule: crate::DepthDownsample, t: [u32; 2], children: &[(u32, Vec4)]) -> (u32, Vec4) {
    use crate::DepthDownsample as R;
    let rule = match rule {
        R::Checkerboard if (t[0] + t[1]) % 2 == 1 => R::Max,
        R::Checkerboard => R::Min,
        r => r,
    };
    match rule {
        R::Max => children
            .iter()
            .fold(children[0], |a, &b| if b.1.x > a.1.x { b } else { a }),
        R::Min => children
            .iter()
            .fold(children[0], |a, &b| if b.1.x < a.1.x { b } else { a }),
        _ => most_representative(children),
    }
}

/// The pick moved along its tangent plane to the centre of texel `t`; mirrors `recentred`
/// in shaders/downsample_rule.wgsl.
fn recentred(f: &FrameUniforms, level: u32, t: [u32; 2], pick: u32, v: Vec4) -> Vec4 {
    let s = (1u32 << (level - 1)) as f32;
    let child = [
        (2 * t[0] + (pick & 1)) as f32,
        (2 * t[1] + (pick >> 1)) as f32,
    ];
    let from = [(child[0] + 0.5) * s, (child[1] + 0.5) * s];
    let centre = [(t[0] as f32 + 0.5) * 2.0 * s, (t[1] as f32 + 0.5) * 2.0 * s];
    recentred_to(f, from, centre, v)
}

/// Prepared value `v` seen at pixel-space point `from`, moved along its tangent plane to the
/// ray through `centre`; mirrors `recentred_to` in shaders/common.wgsl.
pub fn recentred_to(f: &FrameUniforms, from: [f32; 2], centre: [f32; 2], v: Vec4) -> Vec4 {
    let p = f.view_position(from, v.x);
    let n = Vec3::new(v.y, v.z, v.w);
    let mut d = v.x;
    if f.perspective != 0 {
        let r = f.view_position(centre, 1.0);
        let nr = n.dot(r);
        if nr.abs() >= 0.2 * r.length() {
            d = n.dot(p) / nr;
        }
    } else if n.z.abs() >= 0.2 {
        let q = f.view_position(centre, v.x);
        d = v.x + (n.x * (q.x - p.x) + n.y * (q.y - p.y)) / n.z;
    }
    if d.is_nan() || d <= 0.0 || (d - v.x).abs() > 0.1 * v.x {
        return v;
    }
    Vec4::new(d, v.y, v.z, v.w)
}

/// The prepared buffer on the working grid of [`crate::Resolution::Scaled`] (`work`: the
/// working frame, [`FrameUniforms::at_scale`]), from the full-resolution `prepared`: for
/// each texel, `rule` picks among the pixels of the 2 × 2 nearest its centre whose centres
/// it covers (else the pixel nearest its centre), recentred when `recentre`; mirrors
/// shaders/rescale.wgsl. Returns `work.size` texels.
pub fn rescale(
    rule: crate::DepthDownsample,
    work: &FrameUniforms,
    recentre: bool,
    prepared: &[Vec4],
) -> Vec<Vec4> {
    let full = work.full_size;
    let last = [full[0] as i32 - 1, full[1] as i32 - 1];
    let mut out = Vec::with_capacity((work.size[0] * work.size[1]) as usize);
    for y in 0..work.size[1] {
        for x in 0..work.size[0] {
            let q = [x as f32 + 0.5, y as f32 + 0.5];
            let c = [q[0] * work.inv_scale, q[1] * work.inv_scale];
            let first = [(c[0] - 0.5).floor() as i32, (c[1] - 0.5).floor() as i32];
            let pixel = |i: u32| [first[0] + (i & 1) as i32, first[1] + (i >> 1) as i32];
            let at = |p: [i32; 2]| prepared[(p[1] * full[0] as i32 + p[0]) as usize];
            let children: Vec<(u32, Vec4)> = (0..4)
                .filter(|&i| {
                    let p = pixel(i);
                    let mine = |k: usize, t: u32| {
                        (0..=last[k]).contains(&p[k])
                            && ((p[k] as f32 + 0.5) * work.scale) as u32 == t
                    };
                    mine(0, x) && mine(1, y) && at(p).x > 0.0
                })
                .map(|i| (i, at(pixel(i))))
                .collect();
            if children.is_empty() {
                let nearest = [(c[0] as i32).min(last[0]), (c[1] as i32).min(last[1])];
                out.push(at(nearest));
                continue;
            }
            let (i, v) = pick_child(rule, [x, y], &children);
            out.push(if recentre {
                let p = pixel(i);
                let from = [
                    (p[0] as f32 + 0.5) * work.scale,
                    (p[1] as f32 + 0.5) * work.scale,
                ];
                recentred_to(work, from, q, v)
            } else {
                v
            });
        }
    }
    out
}

/// Seed 004's rule: drop the sample farthest from the centroid of those left until two
/// remain, then keep the one closer to the last centroid (ties: the earlier).
fn most_representative(c: &[(u32, Vec4)]) -> (u32, Vec4) {
    let mut anchor = c.iter().map(|v| v.1.x).sum::<f32>() / c.len() as f32;
    let mut alive: Vec<(u32, Vec4)> = c.to_vec();
    while alive.len() > 2 {
        let centroid = alive.iter().map(|v| v.1.x).sum::<f32>() / alive.len() as f32;
        anchor = centroid;
        let mut worst = 0;
        for i in 1..alive.len() {
            if (alive[i].1.x - centroid).abs() > (alive[worst].1.x - centroid).abs() {
                worst = i;
            }
        }
        alive.remove(worst);
    }
    if alive.len() == 2 && (alive[1].1.x - anchor).abs() < (alive[0].1.x - anchor).abs() {
        alive[1]
    } else {
        alive[0]
    }
}

/// Upsampling of low-resolution AO (`low_size`, with its prepared buffer) to the full
/// resolution of `f` (whose `up_factor` relates them), given the full-resolution `prepared`
/// buffer (normals used by the bilateral upsampler only); mirrors shaders/upsample*.wgsl.
/// `pyramid`: the full-resolution depth pyramid (classified upsampler).
pub fn upsample(
    upsampler: crate::Upsampler,
    f: &FrameUniforms,
    prepared: &[Vec4],
    low_size: [u32; 2],
    low_ao: &[f32],
    low_prepared: &[Vec4],
    pyramid: &[PyramidLevel],
) -> Vec<f32> {
    let fac = f.up_factor as f32;
    let map = [1.0 / fac, fac];
    let weights = upsample_weights(upsampler, f, map, prepared, low_size, low_prepared, pyramid);
    weighted_ao(&weights, low_ao)
}

/// Each pixel's weighted sum of its footprint's AO, clamped to [0, 1]; 1 on sky.
fn weighted_ao(weights: &[Option<([usize; 4], [f32; 4])>], low_ao: &[f32]) -> Vec<f32> {
    weights
        .iter()
        .map(|fw| {
            fw.map_or(1.0, |(t, w)| {
                (0..4)
                    .map(|i| w[i] * low_ao[t[i]])
                    .sum::<f32>()
                    .clamp(0.0, 1.0)
            })
        })
        .collect()
}

/// Bent normals through the upsampler (shaders/upsample_bent.wgsl): with [`upsample`]'s
/// weights, this pixel's normal plus the low texels' offsets of `low_bent` from their
/// normals when `full_normals` (else the bent normals themselves), renormalised; zero on
/// sky.
#[allow(
    clippy::too_many_arguments,
    reason = "the upsampler's inputs, spelled out"
)]
pub fn upsample_bent(
    upsampler: crate::Upsampler,
    f: &FrameUniforms,
    prepared: &[Vec4],
    low_size: [u32; 2],
    low_bent: &[Vec3],
    low_prepared: &[Vec4],
    pyramid: &[PyramidLevel],
    full_normals: bool,
) -> Vec<Vec3> {
    let normal = |v: Vec4| Vec3::new(v.y, v.z, v.w);
    let fac = f.up_factor as f32;
    let map = [1.0 / fac, fac];
    upsample_weights(upsampler, f, map, prepared, low_size, low_prepared, pyramid)
        .into_iter()
        .zip(prepared)
        .map(|(fw, c)| {
            let Some((t, w)) = fw else {
                return Vec3::ZERO;
            };
            let mut sum = if full_normals { normal(*c) } else { Vec3::ZERO };
            for i in 0..4 {
                let off = if full_normals {
                    normal(low_prepared[t[i]])
                } else {
                    Vec3::ZERO
                };
                sum += w[i] * (low_bent[t[i]] - off);
            }
            if sum.length_squared() > 1e-12 {
                sum.normalize()
            } else {
                Vec3::ZERO
            }
        })
        .collect()
}

/// The AO of the working grid of [`crate::Resolution::Scaled`] (`f.work_size`, with its
/// prepared buffer) upsampled to the full resolution of `f` by the joint bilateral weights
/// at `f.scale`; mirrors shaders/upsample_scaled.wgsl.
pub fn upsample_scaled(
    f: &FrameUniforms,
    prepared: &[Vec4],
    low_ao: &[f32],
    low_prepared: &[Vec4],
) -> Vec<f32> {
    let map = [f.scale, f.inv_scale];
    let weights = upsample_weights(
        crate::Upsampler::Bilateral,
        f,
        map,
        prepared,
        f.work_size,
        low_prepared,
        &[],
    );
    weighted_ao(&weights, low_ao)
}

/// The upsampler's weights of each full-resolution pixel: its four footprint texels (as
/// indices into the low-resolution buffers) and their weights, summing to 1; `None` on sky.
/// `map`: low-resolution texels per full-resolution pixel and its inverse.
#[allow(
    clippy::too_many_arguments,
    reason = "the upsampler's inputs, spelled out"
)]
fn upsample_weights(
    upsampler: crate::Upsampler,
    f: &FrameUniforms,
    map: [f32; 2],
    prepared: &[Vec4],
    low_size: [u32; 2],
    low_prepared: &[Vec4],
    pyramid: &[PyramidLevel],
) -> Vec<Option<([usize; 4], [f32; 4])>> {
    use crate::shader::DEPTH_RANGE_TOLERANCE;
    use crate::Upsampler as U;
    let [scale, inv_scale] = map;
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..h {
        for x in 0..w {
            let c = prepared[(y * w + x) as usize];
            let d = c.x;
            if d <= 0.0 {
                out.push(None);
                continue;
            }
            let n = Vec3::new(c.y, c.z, c.w);
            let pos = f.view_position(centre([x, y]), d);
            let u = [
                (x as f32 + 0.5) * scale - 0.5,
                (y as f32 + 0.5) * scale - 0.5,
            ];
            let base = [u[0].floor() as i32, u[1].floor() as i32];
            let t = [u[0] - u[0].floor(), u[1] - u[1].floor()];
            let wts = [
                (1.0 - t[0]) * (1.0 - t[1]),
                t[0] * (1.0 - t[1]),
                (1.0 - t[0]) * t[1],
                t[0] * t[1],
            ];
            let texel: [[i32; 2]; 4] = std::array::from_fn(|i| {
                [
                    (base[0] + (i as i32 & 1)).clamp(0, low_size[0] as i32 - 1),
                    (base[1] + (i as i32 >> 1)).clamp(0, low_size[1] as i32 - 1),
                ]
            });
            let at = |q: [i32; 2]| (q[1] * low_size[0] as i32 + q[0]) as usize;
            let low: [Vec4; 4] = texel.map(|q| low_prepared[at(q)]);
            let lpos: [Vec3; 4] = std::array::from_fn(|i| {
                let q = texel[i];
                f.view_position(
                    [
                        (q[0] as f32 + 0.5) * inv_scale,
                        (q[1] as f32 + 0.5) * inv_scale,
                    ],
                    low[i].x,
                )
            });
            let ln = |i: usize| Vec3::new(low[i].y, low[i].z, low[i].w);
            let nearest = || {
                let mut best: Option<usize> = None;
                for i in 0..4 {
                    if low[i].x > 0.0
                        && best.is_none_or(|b| (low[i].x - d).abs() < (low[b].x - d).abs())
                    {
                        best = Some(i);
                    }
                }
                best.map_or(wts, |i| std::array::from_fn(|k| (k == i) as u32 as f32))
            };
            // This pixel's distance from texel i's tangent plane.
            let plane = |i: usize| (pos - lpos[i]).dot(ln(i)).abs();
            let weights = match upsampler {
                U::Bilinear => wts,
                U::NearestDepth => nearest(),
                U::Classified => {
                    // A footprint of one pixel (factor 1, tests only) has no depth range.
                    let level = (f.up_factor > 1)
                        .then(|| &pyramid[f.up_factor.trailing_zeros() as usize - 1]);
                    let mut surface = true;
                    let mut mean = Vec3::ZERO;
                    for i in 0..4 {
                        if low[i].x <= 0.0 {
                            surface = false;
                            continue;
                        }
                        mean += ln(i);
                        if plane(i) > f.plane_tolerance(d) {
                            surface = false;
                        }
                        if let Some(l) = level {
                            let q = [
                                texel[i][0].min(l.size[0] as i32 - 1),
                                texel[i][1].min(l.size[1] as i32 - 1),
                            ];
                            let r = l.at(q);
                            if r[2] - r[1] > DEPTH_RANGE_TOLERANCE * r[1] {
                                surface = false;
                            }
                        }
                    }
                    let m = mean.normalize();
                    if (0..4).any(|i| ln(i).dot(m) < 0.906_307_8) {
                        surface = false;
                    }
                    if surface {
                        wts
                    } else {
                        nearest()
                    }
                }
                U::Bilateral => {
                    let mut wb = [0.0f32; 4];
                    for (i, wi) in wb.iter_mut().enumerate() {
                        if low[i].x <= 0.0 {
                            continue;
                        }
                        let z = (lpos[i] - pos).dot(n).abs() / f.plane_tolerance(d);
                        let cs = ln(i).dot(n).max(0.0);
                        *wi = wts[i] * (-z * z).exp() * cs.powi(8);
                    }
                    let total: f32 = wb.iter().sum();
                    if total > 1e-4 {
                        wb.map(|v| v / total)
                    } else {
                        nearest()
                    }
                }
            };
            out.push(Some((texel.map(at), weights)));
        }
    }
    out
}

/// The edge-aware spatial denoiser at working resolution (`f` the working frame,
/// `prepared` its prepared values per pixel, `period` the pattern period 2 or 4); mirrors
/// shaders/denoise.wgsl.
pub fn denoise(f: &FrameUniforms, prepared: &[Vec4], ao: &[f32], period: u32) -> Vec<f32> {
    use crate::shader::DENOISE_RIDGE;
    let w = f.size[0] as i32;
    let mut out = Vec::with_capacity(ao.len());
    for (i, taps) in denoise_taps(f, prepared, period).enumerate() {
        let Some(taps) = taps else {
            out.push(ao[i]);
            continue;
        };
        // Weighted sums of 1, v, d, v·d and d⊗d (xx, yy, xy), d the tap's offset.
        let (mut total, mut sum) = (0.0f32, 0.0f32);
        let (mut sum_d, mut sum_vd) = (glam::Vec2::ZERO, glam::Vec2::ZERO);
        let mut sum_dd = Vec3::ZERO;
        for (q, d, wgt) in taps {
            let v = ao[(q[1] * w + q[0]) as usize];
            total += wgt;
            sum += wgt * v;
            sum_d += wgt * d;
            sum_vd += wgt * v * d;
            sum_dd += wgt * Vec3::new(d.x * d.x, d.y * d.y, d.x * d.y);
        }
        // The weighted least-squares plane's value at the centre.
        let mean = sum / total;
        let m = sum_d / total;
        let xx = sum_dd.x / total - m.x * m.x + DENOISE_RIDGE;
        let yy = sum_dd.y / total - m.y * m.y + DENOISE_RIDGE;
        let xy = sum_dd.z / total - m.x * m.y;
        let c = sum_vd / total - m * mean;
        let g = glam::Vec2::new(yy * c.x - xy * c.y, xx * c.y - xy * c.x) / (xx * yy - xy * xy);
        out.push((mean - g.dot(m)).clamp(0.0, 1.0));
    }
    out
}

/// The denoiser's bent normals (shaders/denoise_bent.wgsl): each pixel its own normal plus
/// the plane fit, with the AO's weights, of its taps' offsets of `bent` from their normals
/// (per component), renormalised; sky pixels pass through.
pub fn denoise_bent(f: &FrameUniforms, prepared: &[Vec4], bent: &[Vec3], period: u32) -> Vec<Vec3> {
    use crate::shader::DENOISE_RIDGE;
    let w = f.size[0] as i32;
    let normal = |v: Vec4| Vec3::new(v.y, v.z, v.w);
    denoise_taps(f, prepared, period)
        .enumerate()
        .map(|(i, taps)| {
            let Some(taps) = taps else {
                return bent[i];
            };
            // Weighted sums of 1, d, d⊗d, the offset o, o·dx and o·dy.
            let (mut total, mut sum_d, mut sum_dd) = (0.0f32, glam::Vec2::ZERO, Vec3::ZERO);
            let (mut sum, mut sum_dx, mut sum_dy) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
            for (q, d, wgt) in taps {
                let j = (q[1] * w + q[0]) as usize;
                let o = bent[j] - normal(prepared[j]);
                total += wgt;
                sum_d += wgt * d;
                sum_dd += wgt * Vec3::new(d.x * d.x, d.y * d.y, d.x * d.y);
                sum += wgt * o;
                sum_dx += wgt * d.x * o;
                sum_dy += wgt * d.y * o;
            }
            let m = sum_d / total;
            let xx = sum_dd.x / total - m.x * m.x + DENOISE_RIDGE;
            let yy = sum_dd.y / total - m.y * m.y + DENOISE_RIDGE;
            let xy = sum_dd.z / total - m.x * m.y;
            let mean = sum / total;
            let (cx, cy) = (sum_dx / total - m.x * mean, sum_dy / total - m.y * mean);
            let det = xx * yy - xy * xy;
            let (gx, gy) = ((yy * cx - xy * cy) / det, (xx * cy - xy * cx) / det);
            let fitted = normal(prepared[i]) + mean - gx * m.x - gy * m.y;
            if fitted.length_squared() > 1e-12 {
                fitted.normalize()
            } else {
                bent[i]
            }
        })
        .collect()
}

/// Many-light shading (shaders/lights_shade.wgsl): per pixel the unshadowed diffuse
/// irradiance of `lights`, all of them (`period` 1) or, with `period` n, those whose
/// index is congruent to the pixel's layer modulo n², times n². Sky pixels are 0.
pub fn shade_lights(
    f: &FrameUniforms,
    prepared: &[Vec4],
    lights: &[crate::PointLight],
    period: u32,
) -> Vec<Vec3> {
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let stride = (period * period) as usize;
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..h {
        for x in 0..w {
            let c = prepared[(y * w + x) as usize];
            if c.x.is_nan() || c.x <= 0.0 {
                out.push(Vec3::ZERO);
                continue;
            }
            let pos = f.view_position(centre([x, y]), c.x);
            let n = Vec3::new(c.y, c.z, c.w);
            let first = crate::layout::layer_of(x as u32, y as u32, period) as usize;
            let mut e = Vec3::ZERO;
            for light in lights.iter().skip(first).step_by(stride) {
                let v = Vec3::from(light.position) - pos;
                let d2 = v.length_squared();
                let x = d2 / (light.range * light.range);
                let window = (1.0 - x * x).clamp(0.0, 1.0);
                let cosine = n.dot(v).max(0.0) / d2.max(1e-30).sqrt();
                let min_d = crate::lights::LIGHT_MIN_DISTANCE * light.range;
                e += Vec3::from(light.colour) * (cosine * window * window / d2.max(min_d * min_d));
            }
            out.push(e * stride as f32);
        }
    }
    out
}

/// The merge of interleaved shading (shaders/lights_merge.wgsl): along x, then along y,
/// per pixel each class of the `period` lattice interpolated linearly at the pixel from
/// its two lattice neighbours (× geometric weights, taps past the border dropped),
/// classes whose weights sum below `LIGHTS_CLASS_MIN_WEIGHT` left out, the rest
/// averaged; sky passes through.
pub fn merge_lights(f: &FrameUniforms, prepared: &[Vec4], lit: &[Vec3], period: u32) -> Vec<Vec3> {
    let taps: Vec<(Vec4, Vec3)> = prepared.iter().copied().zip(lit.iter().copied()).collect();
    let along_x = merge_lights_axis(f, &taps, period, 0);
    let taps: Vec<(Vec4, Vec3)> = prepared.iter().copied().zip(along_x).collect();
    merge_lights_axis(f, &taps, period, 1)
}

/// [`merge_lights`] as the GPU runs it (shaders/lights_merge.wgsl, shaders/lit_packed.wgsl):
/// from the packed shading `packed` (the GPU's [`crate::Lights::raw`], or the SSDO bounce's
/// [`crate::Ssdo::bounce_raw`]), the pass along x writing packed texels (each pixel's
/// geometry and its merged irradiance) for the pass along y.
pub fn merge_lights_packed(f: &FrameUniforms, packed: &[[u32; 4]], period: u32) -> Vec<Vec3> {
    let taps: Vec<(Vec4, Vec3)> = packed.iter().map(|t| unpack_lit(*t)).collect();
    let along_x = merge_lights_axis(f, &taps, period, 0);
    let taps: Vec<(Vec4, Vec3)> = taps
        .iter()
        .zip(along_x)
        .map(|(&(g, _), e)| unpack_lit(pack_lit(g, e)))
        .collect();
    merge_lights_axis(f, &taps, period, 1)
}

/// The packed texel of many-light shading (shaders/lit_packed.wgsl, `pack_lit`): linear
/// depth's bits, the normal's (v + 1) / 2 rounded to `LIT_NORMAL_MAX` (3 × 10 bits; 0 on
/// sky), the largest irradiance component m's bits, and r / m, g / m, b / m rounded to
/// `LIT_RATIO_MAX` (11, 11, 10 bits).
pub fn pack_lit(g: Vec4, e: Vec3) -> [u32; 4] {
    use crate::shader::{LIT_NORMAL_MAX, LIT_RATIO_MAX};
    let u = (Vec3::new(g.y, g.z, g.w) * 0.5 + 0.5).clamp(Vec3::ZERO, Vec3::ONE);
    let n = (u * LIT_NORMAL_MAX + 0.5).to_array().map(|v| v as u32);
    let normal = if g.x > 0.0 {
        n[0] | n[1] << 10 | n[2] << 20
    } else {
        0
    };
    let c = e.min(Vec3::splat(f32::MAX));
    let m = c.x.max(c.y).max(c.z);
    let r = if m > 0.0 { c / m } else { Vec3::ZERO };
    let q = (r * Vec3::from(LIT_RATIO_MAX) + 0.5)
        .to_array()
        .map(|v| v as u32);
    [
        g.x.to_bits(),
        normal,
        m.to_bits(),
        q[0] | q[1] << 11 | q[2] << 22,
    ]
}

/// The geometry `vec4(linear depth, view normal)` and irradiance of a packed texel
/// (shaders/lit_packed.wgsl, `unpack_geometry`, `unpack_irradiance`).
pub fn unpack_lit(t: [u32; 4]) -> (Vec4, Vec3) {
    use crate::shader::{LIT_NORMAL_MAX, LIT_RATIO_MAX};
    let n = Vec3::new(
        (t[1] & 0x3ff) as f32,
        ((t[1] >> 10) & 0x3ff) as f32,
        (t[1] >> 20) as f32,
    ) * (2.0 / LIT_NORMAL_MAX)
        - 1.0;
    let q = Vec3::new(
        (t[3] & 0x7ff) as f32,
        ((t[3] >> 11) & 0x7ff) as f32,
        (t[3] >> 22) as f32,
    );
    (
        Vec4::new(f32::from_bits(t[0]), n.x, n.y, n.z),
        f32::from_bits(t[2]) * (q / Vec3::from(LIT_RATIO_MAX)),
    )
}

/// Environment irradiance / π at view-space `n`; mirrors `env_irradiance` in
/// shaders/ssdo_env.wgsl.
fn env_irradiance(lighting: &crate::SsdoLighting, n: Vec3) -> Vec3 {
    let m = lighting.view_to_world.map(Vec3::from);
    let d = m[0] * n.x + m[1] * n.y + m[2] * n.z;
    Vec3::from(lighting.irradiance.eval(d.to_array()))
}

/// SSDO's bounce (shaders/ssdo_bounce.wgsl): per pixel, GTAO's slices with the pattern
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
        prepared,
        lattice: 1,
        pyramid: &[],
        moments: &[],
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
            let pattern =
                patterns[crate::layout::layer_of(x as u32, y as u32, options.period) as usize];
            let step_px = f.step_px(d, options.steps);
            let tolerance = crate::ssdo::SSDO_SELF_TOLERANCE * d
                + crate::shader::NOISE_TOLERANCE_SIGMAS * f.depth_sigma(d);
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

/// SSDO's combine (shaders/ssdo_combine.wgsl): `albedo · (ao · E(bent) + bounce)` with the
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

/// One axis of the merge over `taps`: each pixel's geometry and irradiance.
fn merge_lights_axis(
    f: &FrameUniforms,
    taps: &[(Vec4, Vec3)],
    period: u32,
    axis: usize,
) -> Vec<Vec3> {
    use crate::lights::LIGHTS_CLASS_MIN_WEIGHT;
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let n = period as i32;
    let at = |q: [i32; 2]| (q[1] * w + q[0]) as usize;
    let extent = [w, h][axis];
    let mut out = Vec::with_capacity(taps.len());
    for y in 0..h {
        for x in 0..w {
            let p = [x, y];
            let (c, own) = taps[at(p)];
            if c.x.is_nan() || c.x <= 0.0 {
                out.push(own);
                continue;
            }
            let pos = f.view_position(centre(p), c.x);
            let normal = Vec3::new(c.y, c.z, c.w);
            let tol = f.plane_tolerance(c.x);
            // The pixel's own class is the pixel alone, and always counts.
            let (mut sum, mut classes) = (own, 1.0f32);
            for k in 0..n {
                let first = -(p[axis] - k).rem_euclid(n);
                if first == 0 {
                    continue;
                }
                let (mut total, mut acc) = (0.0f32, Vec3::ZERO);
                for d in [first, first + n] {
                    let linear = (n - d.abs()) as f32;
                    if linear <= 0.0 || p[axis] + d < 0 || p[axis] + d >= extent {
                        continue;
                    }
                    let mut q = p;
                    q[axis] += d;
                    let (s, e) = taps[at(q)];
                    if s.x.is_nan() || s.x <= 0.0 {
                        continue;
                    }
                    let wgt = linear * merge_weight(f, pos, normal, tol, q, s);
                    total += wgt;
                    acc += wgt * e;
                }
                if total >= LIGHTS_CLASS_MIN_WEIGHT {
                    sum += acc / total;
                    classes += 1.0;
                }
            }
            out.push(sum / classes);
        }
    }
    out
}

/// The geometric weight of tap `q` (prepared `s`) for a centre at `pos` with normal `n`
/// and plane tolerance `tol` (shaders/merge.wgsl): plane × normal.
fn merge_weight(f: &FrameUniforms, pos: Vec3, n: Vec3, tol: f32, q: [i32; 2], s: Vec4) -> f32 {
    let sn = Vec3::new(s.y, s.z, s.w);
    let off = f.view_position(centre(q), s.x) - pos;
    let z = off.dot(n).abs().max(off.dot(sn).abs()) / tol;
    (-z * z).exp() * sn.dot(n).max(0.0).powi(8)
}

/// The denoiser's taps of every pixel in row order: `None` for sky, else each tap's pixel,
/// offset and weight (shaders/denoise.wgsl; the geometric part from shaders/merge.wgsl).
fn denoise_taps<'a>(
    f: &'a FrameUniforms,
    prepared: &'a [Vec4],
    period: u32,
) -> impl Iterator<Item = Option<Vec<([i32; 2], glam::Vec2, f32)>>> + 'a {
    use crate::shader::{DENOISE_RADIUS_TOLERANCE, NOISE_TOLERANCE_SIGMAS, PLANE_TOLERANCE};
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let at = move |p: [i32; 2]| (p[1] * w + p[0]) as usize;
    let r = (period / 2) as i32;
    (0..h)
        .flat_map(move |y| (0..w).map(move |x| (x, y)))
        .map(move |(x, y)| {
            let c = prepared[at([x, y])];
            if c.x <= 0.0 {
                return None;
            }
            let pos = f.view_position(centre([x, y]), c.x);
            let n = Vec3::new(c.y, c.z, c.w);
            let tol = (PLANE_TOLERANCE * c.x)
                .min(DENOISE_RADIUS_TOLERANCE * f.radius)
                .max(NOISE_TOLERANCE_SIGMAS * f.depth_sigma(c.x));
            let mut taps = Vec::with_capacity(((2 * r + 1) * (2 * r + 1)) as usize);
            for dy in -r..=r {
                for dx in -r..=r {
                    // Mirrored at the image border, as the shader.
                    let mirror = |c: i32, n: i32| {
                        let c = c.abs();
                        (if c >= n { 2 * (n - 1) - c } else { c }).clamp(0, n - 1)
                    };
                    let q = [mirror(x + dx, w), mirror(y + dy, h)];
                    let s = prepared[at(q)];
                    if s.x <= 0.0 {
                        continue;
                    }
                    let spatial = |d: i32| if d.abs() == r { 1.0 } else { 2.0 };
                    let wgt = spatial(dx) * spatial(dy) * merge_weight(f, pos, n, tol, q, s);
                    taps.push((q, glam::Vec2::new(dx as f32, dy as f32), wgt));
                }
            }
            Some(taps)
        })
}

/// A unit normal as one float (shaders/temporal.wgsl, `pack_normal`): octahedral
/// coordinates quantised to 12 bits each, `q.x * 4096 + q.y`.
pub fn pack_normal(n: Vec3) -> f32 {
    let mut o = glam::Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs());
    if n.z < 0.0 {
        let s = glam::Vec2::new(wgsl_sign_ge(o.x), wgsl_sign_ge(o.y));
        o = (glam::Vec2::ONE - glam::Vec2::new(o.y.abs(), o.x.abs())) * s;
    }
    let q = ((o * 0.5 + 0.5).clamp(glam::Vec2::ZERO, glam::Vec2::ONE) * 4095.0)
        .map(f32::round_ties_even);
    q.x * 4096.0 + q.y
}

/// The inverse of [`pack_normal`] (shaders/temporal.wgsl, `unpack_normal`).
pub fn unpack_normal(w: f32) -> Vec3 {
    let qx = (w / 4096.0).floor();
    let o = glam::Vec2::new(qx, w - qx * 4096.0) / 4095.0 * 2.0 - 1.0;
    let mut n = Vec3::new(o.x, o.y, 1.0 - o.x.abs() - o.y.abs());
    if n.z < 0.0 {
        let s = glam::Vec2::new(wgsl_sign_ge(n.x), wgsl_sign_ge(n.y));
        let xy = (glam::Vec2::ONE - glam::Vec2::new(n.y.abs(), n.x.abs())) * s;
        n = Vec3::new(xy.x, xy.y, n.z);
    }
    n.normalize()
}

/// `select(-1, 1, x >= 0)`.
fn wgsl_sign_ge(x: f32) -> f32 {
    if x >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// One frame of temporal accumulation at working resolution (`f` the working frame with
/// its temporal fields, `prepared` per pixel, `ao` this frame's raw AO, `history` last
/// frame's `vec4(AO, frames, depth, packed normal)`, row-major on last frame's grid of
/// `f.prev_size`); returns this frame's history and AO.
/// Mirrors shaders/temporal.wgsl.
pub fn temporal(
    f: &FrameUniforms,
    prepared: &[Vec4],
    ao: &[f32],
    history: &[Vec4],
) -> (Vec<Vec4>, Vec<f32>) {
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let at = |p: [i32; 2]| (p[1] * w + p[0]) as usize;
    let mut hist_out = Vec::with_capacity(ao.len());
    let mut out = Vec::with_capacity(ao.len());
    for y in 0..h {
        for x in 0..w {
            let current = ao[at([x, y])];
            let c = prepared[at([x, y])];
            let (mut a, mut frames) = (current, 1.0);
            if let Some(hv) = reprojected(f, prepared, history, [x, y]).map(|(hv, _)| hv) {
                let (mut lo, mut hi) = (current, current);
                for i in 0..9 {
                    let q = [x + i % 3 - 1, y + i / 3 - 1];
                    if q[0] >= 0 && q[1] >= 0 && q[0] < w && q[1] < h {
                        lo = lo.min(ao[at(q)]);
                        hi = hi.max(ao[at(q)]);
                    }
                }
                frames = (hv.y + 1.0).min(f.history_max);
                let held = hv.x.clamp(lo, hi);
                a = held + (current - held) * (1.0 / frames);
            }
            if c.x <= 0.0 {
                frames = 0.0;
            }
            hist_out.push(Vec4::new(
                a,
                frames,
                c.x,
                pack_normal(Vec3::new(c.y, c.z, c.w)),
            ));
            out.push(a);
        }
    }
    (hist_out, out)
}

/// The bent normals of one frame of temporal accumulation (shaders/temporal_bent.wgsl):
/// `bent` this frame's, `bent_history` last frame's, read with the AO history's texels and
/// weights (`history` as for [`temporal`]), turned into this frame's view space and blended
/// by the AO's weight. Returns this frame's bent normals (also its bent history).
pub fn temporal_bent(
    f: &FrameUniforms,
    prepared: &[Vec4],
    history: &[Vec4],
    bent: &[Vec3],
    bent_history: &[Vec3],
) -> Vec<Vec3> {
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let r = glam::Mat3::from_mat4(glam::Mat4::from_cols_array_2d(&f.prev_from_view));
    (0..h)
        .flat_map(|y| (0..w).map(move |x| [x, y]))
        .map(|p| {
            let b = bent[(p[1] * w + p[0]) as usize];
            let Some((hv, taps)) = reprojected(f, prepared, history, p) else {
                return b;
            };
            let sum: Vec3 = taps.iter().map(|&(i, wt)| wt * bent_history[i]).sum();
            if sum.length_squared() <= 1e-12 {
                return b;
            }
            let held = r.transpose() * sum.normalize();
            let frames = (hv.y + 1.0).min(f.history_max);
            let m = held + (b - held) * (1.0 / frames);
            if m.length_squared() > 1e-12 {
                m.normalize()
            } else {
                b
            }
        })
        .collect()
}

/// The history `(AO, frames)` where pixel `p`'s surface point was last frame, and the
/// texels it was read from with their bilinear weights (shaders/temporal.wgsl,
/// `reprojected`); `None` where there is no history: no history this frame, sky, or no
/// texel kept.
fn reprojected(
    f: &FrameUniforms,
    prepared: &[Vec4],
    history: &[Vec4],
    p: [i32; 2],
) -> Option<(glam::Vec2, Vec<(usize, f32)>)> {
    let w = f.size[0] as i32;
    let at = |p: [i32; 2]| (p[1] * w + p[0]) as usize;
    let c = prepared[at(p)];
    if f.history == 0 || c.x <= 0.0 {
        return None;
    }
    let m = glam::Mat4::from_cols_array_2d(&f.prev_from_view);
    let prev = m.transform_point3(f.view_position(centre(p), c.x));
    let prev_n = m.transform_vector3(Vec3::new(c.y, c.z, c.w));
    let depth = -prev.z;
    if depth <= 0.0 {
        return None;
    }
    let mut ndc = glam::Vec2::new(prev.x, prev.y) / glam::Vec2::from(f.prev_ndc_to_view);
    if f.perspective != 0 {
        ndc /= depth;
    }
    let px = glam::Vec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 / glam::Vec2::from(f.prev_inv_size);
    let base = (px - 0.5).floor();
    let (pw, ph) = (f.prev_size[0] as i32, f.prev_size[1] as i32);
    let fr = px - 0.5 - base;
    let (mut sum, mut total, mut taps) = (glam::Vec2::ZERO, 0.0, Vec::new());
    for i in 0..4 {
        let o = [i & 1, i >> 1];
        let t = [base.x as i32 + o[0], base.y as i32 + o[1]];
        if t[0] < 0 || t[1] < 0 || t[0] >= pw || t[1] >= ph {
            continue;
        }
        let hi = (t[1] * pw + t[0]) as usize;
        let hv = history[hi];
        if hv.z <= 0.0 {
            continue;
        }
        let q = f.view_position_scaled(centre(t), hv.z, f.prev_ndc_to_view, f.prev_inv_size);
        if (q - prev).dot(prev_n).abs() >= f.plane_tolerance(depth)
            || unpack_normal(hv.w).dot(prev_n) < crate::shader::HISTORY_NORMAL_COS
        {
            continue;
        }
        let wx = if o[0] == 1 { fr.x } else { 1.0 - fr.x };
        let wy = if o[1] == 1 { fr.y } else { 1.0 - fr.y };
        sum += wx * wy * glam::Vec2::new(hv.x, hv.y);
        total += wx * wy;
        taps.push((hi, wx * wy));
    }
    // The shader returns (0, 0) below a total weight of 1e-3, and uses the history only
    // where its frame count is positive.
    let hv = if total < 1e-3 {
        glam::Vec2::ZERO
    } else {
        sum / total
    };
    (hv.y > 0.0).then_some((hv, taps))
}

/// Seed 003's box (`tent` false) or tent AO downsample, `size` → `ceil(size / 2)`;
/// mirrors shaders/ao_downsample.wgsl.
pub fn ao_downsample(tent: bool, size: [u32; 2], ao: &[f32]) -> ([u32; 2], Vec<f32>) {
    use crate::shader::{TENT_SPACING, TENT_WEIGHTS};
    let (w, h) = (size[0] as i32, size[1] as i32);
    // Sum and count of the texels in [lo, lo + 1]².
    let block = |lo: [i32; 2]| {
        let mut acc = (0.0f32, 0.0f32);
        for i in 0..4 {
            let q = [lo[0] + (i & 1), lo[1] + (i >> 1)];
            if q[0] >= 0 && q[1] >= 0 && q[0] < w && q[1] < h {
                acc.0 += ao[(q[1] * w + q[0]) as usize];
                acc.1 += 1.0;
            }
        }
        acc
    };
    let dst = size.map(|s| s.div_ceil(2));
    let mut out = Vec::with_capacity((dst[0] * dst[1]) as usize);
    for ty in 0..dst[1] as i32 {
        for tx in 0..dst[0] as i32 {
            let t = [2 * tx, 2 * ty];
            if !tent {
                let b = block(t);
                out.push(b.0 / b.1);
                continue;
            }
            let (mut sum, mut total) = (0.0, 0.0);
            for i in 0..9 {
                let tap = [i % 3, i / 3];
                let b = block([
                    t[0] + (tap[0] - 1) * TENT_SPACING,
                    t[1] + (tap[1] - 1) * TENT_SPACING,
                ]);
                let wgt = TENT_WEIGHTS[tap[0] as usize] * TENT_WEIGHTS[tap[1] as usize];
                if b.1 > 0.0 {
                    sum += wgt * b.0 / b.1;
                    total += wgt;
                }
            }
            out.push(sum / total);
        }
    }
    (dst, out)
}

#[cfg(test)]
mod tests {
    use super::{denoise, expected_occupied, fast_acos, gtao_side, moments, occupied_length};
    use glam::Vec4;
    use std::f64::consts::FRAC_PI_2;

    /// The frame of the denoiser tests: orthographic, one view unit per pixel, radius 4.
    fn ortho_frame(w: u32, h: u32) -> crate::uniforms::FrameUniforms {
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
        crate::uniforms::FrameUniforms::new(
            &projection,
            DepthConvention::LinearView,
            None,
            viewport,
            &AoOptions::default(),
            &params,
        )
        .unwrap()
    }

    /// Runs the 2×2-period denoiser on `prepared(x, y)` and `ao(x, y)` and checks every
    /// pixel off the image border (where kernels are cut by the image) against `want(x, y)`
    /// within 1e-4 (the ridge shrinks slopes by under 0.05%).
    fn check_denoise(
        (w, h): (u32, u32),
        prepared: impl Fn(i32, i32) -> Vec4,
        ao: impl Fn(i32, i32) -> f32,
        want: impl Fn(i32, i32) -> f32,
    ) {
        let f = ortho_frame(w, h);
        let (w, h) = (w as i32, h as i32);
        let grid = |g: &dyn Fn(i32, i32) -> f32| -> Vec<f32> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| g(x, y))
                .collect()
        };
        let prep: Vec<Vec4> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| prepared(x, y))
            .collect();
        let out = denoise(&f, &prep, &grid(&ao), 2);
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                let (got, want) = (out[(y * w + x) as usize], want(x, y));
                assert!((got - want).abs() <= 1e-4, "pixel {x},{y}: {got} vs {want}");
            }
        }
    }

    /// The denoiser on a crease (analytic answers): a plane facing the camera meets a 45°
    /// plane along column `edge`, so each side's taps across the crease are rejected. The
    /// AO is a ramp in x plus a 2×2 dither of ±0.1. Where the kernel is whole the dither
    /// cancels over one period and the ramp is left. Beside the crease the pixel gets the
    /// ramp plus its own column's x-dither (the y-dither still cancels): unbiased, as
    /// noisy across the crease as the raw AO, not the ramp shifted by a third of a step
    /// as a one-sided mean would give (which fails this by 0.06).
    #[test]
    fn denoiser_is_unbiased_beside_a_crease_and_cancels_the_dither() {
        let edge = 12;
        let n = glam::Vec3::new(1.0, 0.0, 1.0).normalize();
        let ramp = |x: i32| 0.3 + 0.02 * x as f32;
        let dither = |v: i32| if v % 2 == 0 { 0.1 } else { -0.1 };
        check_denoise(
            (24, 12),
            |x, _| {
                if x < edge {
                    Vec4::new(10.0, 0.0, 0.0, 1.0)
                } else {
                    Vec4::new(10.0 + (x - edge) as f32, n.x, 0.0, n.z)
                }
            },
            |x, y| ramp(x) + dither(x) + dither(y),
            |x, _| {
                ramp(x)
                    + if x == edge - 1 || x == edge {
                        dither(x)
                    } else {
                        0.0
                    }
            },
        );
    }

    /// A diagonal crease (x + y = 16 between a plane facing the camera and one sloping
    /// along both axes) cuts kernels into triangles, whose taps' offsets correlate in x
    /// and y: the fit's cross terms. An AO linear in x and y must come out unchanged at
    /// every pixel, whatever taps each kernel keeps (a weighted mean fails it).
    #[test]
    fn denoiser_keeps_a_linear_ao_across_a_diagonal_crease() {
        let edge = 16;
        let n = glam::Vec3::new(0.7, -0.7, 1.0).normalize();
        let ramp = |x: i32, y: i32| 0.1 + 0.02 * x as f32 + 0.025 * y as f32;
        check_denoise(
            (24, 16),
            |x, y| {
                if x + y < edge {
                    Vec4::new(10.0, 0.0, 0.0, 1.0)
                } else {
                    Vec4::new(10.0 + 0.7 * (x + y - edge) as f32, n.x, n.y, n.z)
                }
            },
            ramp,
            ramp,
        );
    }

    /// At the image border the taps are mirrored: on a flat surface the 2×2 dither (±0.1
    /// per axis) cancels at every pixel, edges and corners included (analytic answer 0.5,
    /// tolerance 1e-4). Dropping the taps past the border instead fits a line through the
    /// two remaining columns, which returns the edge pixel's own dither (off by 0.1).
    #[test]
    fn denoiser_cancels_the_dither_at_the_image_border() {
        for (w, h) in [(10u32, 6u32), (9, 7)] {
            let f = ortho_frame(w, h);
            let dither = |v: u32| if v.is_multiple_of(2) { 0.1 } else { -0.1 };
            let pixels = || (0..h).flat_map(move |y| (0..w).map(move |x| (x, y)));
            let prepared = vec![Vec4::new(10.0, 0.0, 0.0, 1.0); (w * h) as usize];
            let ao: Vec<f32> = pixels().map(|(x, y)| 0.5 + dither(x) + dither(y)).collect();
            let out = denoise(&f, &prepared, &ao, 2);
            for ((x, y), got) in pixels().zip(out) {
                assert!((got - 0.5).abs() <= 1e-4, "{w}×{h}, pixel {x},{y}: {got}");
            }
        }
    }

    /// The denoiser filters the bent normal's offset from the surface normal: on a curved
    /// surface with nothing occluding it (bent normal = normal at every pixel) it returns
    /// each pixel's own normal (within 1e-5), in both kernels; a mean of the directions
    /// leans each toward its neighbours and fails this. And a uniform tilt survives.
    #[test]
    fn denoised_bent_normals_keep_a_curved_surface() {
        use glam::Vec3;
        let (w, h) = (12u32, 9u32);
        let f = ortho_frame(w, h);
        let normal = |x: u32, y: u32| {
            Vec3::new(0.15 * (x as f32 - 5.5), 0.15 * (y as f32 - 4.0), 1.0).normalize()
        };
        let pixels = || (0..h).flat_map(move |y| (0..w).map(move |x| (x, y)));
        let prepared: Vec<Vec4> = pixels()
            .map(|(x, y)| {
                let n = normal(x, y);
                Vec4::new(10.0, n.x, n.y, n.z)
            })
            .collect();
        let bent: Vec<Vec3> = pixels().map(|(x, y)| normal(x, y)).collect();
        let tilt = Vec3::new(0.0, 0.2, 0.0);
        let tilted: Vec<Vec3> = bent.iter().map(|b| *b + tilt).collect();
        for period in [2, 4] {
            let out = super::denoise_bent(&f, &prepared, &bent, period);
            for (i, (got, want)) in out.iter().zip(&bent).enumerate() {
                assert!((*got - *want).abs().max_element() < 1e-5, "{period}: {i}");
            }
            let out = super::denoise_bent(&f, &prepared, &tilted, period);
            for (i, (got, n)) in out.iter().zip(&bent).enumerate() {
                let want = (*n + tilt).normalize();
                assert!((*got - want).abs().max_element() < 1e-5, "{period}: {i}");
            }
        }
    }

    /// The closed-form expectation of a chord's occupied length over depths uniform with a
    /// mean and variance against a midpoint-rule average over that interval (10⁵ points), on
    /// chords in front of, across and behind the depths, thick and thin solids, and σ = 0.
    /// Tolerance 1e-4 of the chord.
    #[test]
    fn expected_occupancy_matches_numerical_integration() {
        let (dc, h) = (10.0f32, 1.0f32);
        for thickness in [0.5f32, 2.0, 4.0, 1e6] {
            for mean in [7.0f32, 8.2, 9.0, 9.7, 10.0, 10.4, 11.0, 11.5, 13.0] {
                for sigma in [0.0f32, 0.05, 0.3, 1.0, 2.5] {
                    let w = 3f64.sqrt() * sigma as f64;
                    let n = 100_000;
                    let numeric = if sigma == 0.0 {
                        occupied_length(mean, dc, h, thickness) as f64
                    } else {
                        (0..n)
                            .map(|i| {
                                let z = mean as f64 - w + 2.0 * w * (i as f64 + 0.5) / n as f64;
                                occupied_length(z as f32, dc, h, thickness) as f64
                            })
                            .sum::<f64>()
                            / n as f64
                    };
                    let closed = expected_occupied(mean, sigma * sigma, dc, h, thickness) as f64;
                    assert!(
                        (closed - numeric).abs() <= 1e-4 * 2.0 * h as f64,
                        "mean {mean} σ {sigma} thickness {thickness}: {closed} vs {numeric}"
                    );
                }
            }
        }
    }

    /// Moments levels of a 16 × 8 buffer (every footprint an exact 2^k block) against the
    /// fraction, mean and variance of the depths under each texel computed directly in f64;
    /// a third of the pixels are sky. Tolerance: 1e-6 on the fraction, 1e-5 relative on the
    /// mean, 1e-4 on the variance (depths near 50, variances 0.3–4).
    #[test]
    fn moments_are_the_footprints_fraction_mean_and_variance() {
        let (w, h) = (16u32, 8u32);
        let depth = |x: u32, y: u32| -> f32 {
            if (x * 7 + y * 3).is_multiple_of(3) {
                0.0
            } else {
                50.0 + 0.37 * x as f32 - 0.21 * y as f32 + ((x * y) % 5) as f32 * 0.8
            }
        };
        let prepared: Vec<Vec4> = (0..h)
            .flat_map(|y| (0..w).map(move |x| Vec4::new(depth(x, y), 0.0, 0.0, 1.0)))
            .collect();
        let levels = moments([w, h], &prepared);
        assert_eq!(
            levels.len(),
            4,
            "levels 1..=4 of 16 × 8 (8 × 4 down to 1 × 1)"
        );
        for (k, level) in levels.iter().enumerate() {
            let side = 2u32 << k;
            assert_eq!(level.size, [1.max(w / side), 1.max(h / side)]);
            for ty in 0..level.size[1] {
                for tx in 0..level.size[0] {
                    // The last level's footprint covers the whole 8-row buffer.
                    let rows = (ty * side)..((ty + 1) * side).min(h);
                    let cols = (tx * side)..((tx + 1) * side).min(w);
                    let all: Vec<f64> = rows
                        .flat_map(|y| cols.clone().map(move |x| depth(x, y) as f64))
                        .collect();
                    let valid: Vec<f64> = all.iter().cloned().filter(|&d| d > 0.0).collect();
                    let fraction = valid.len() as f64 / all.len() as f64;
                    let mean = valid.iter().sum::<f64>() / valid.len().max(1) as f64;
                    let variance = valid.iter().map(|d| (d - mean).powi(2)).sum::<f64>()
                        / valid.len().max(1) as f64;
                    let [f, m, v] = level.texels[(ty * level.size[0] + tx) as usize];
                    let at = format!("level {} texel {tx},{ty}", k + 1);
                    assert!(
                        (f as f64 - fraction).abs() <= 1e-6,
                        "{at}: fraction {f} vs {fraction}"
                    );
                    assert!(
                        (m as f64 - mean).abs() <= 1e-5 * mean,
                        "{at}: mean {m} vs {mean}"
                    );
                    assert!(
                        (v as f64 - variance).abs() <= 1e-4,
                        "{at}: variance {v} vs {variance}"
                    );
                }
            }
        }
    }

    #[test]
    fn fast_acos_is_within_its_stated_bound() {
        let mut worst = 0.0f64;
        for i in 0..=200_000 {
            let x = -1.0 + 2.0 * i as f64 / 200_000.0;
            worst = worst.max((fast_acos(x as f32) as f64 - x.acos()).abs());
        }
        assert!(worst <= 1e-4, "fast_acos error {worst:e} rad");
    }

    /// The trigonometric form of Jimenez et al.'s eq. 10 for one side, in f64.
    fn arc_trig(c: f64, s: f64, n: f64) -> f64 {
        let h = n + (s * c.acos() - n).clamp(-FRAC_PI_2, FRAC_PI_2);
        (n.cos() + 2.0 * h * n.sin() - (2.0 * h - n).cos()) * 0.25
    }

    #[test]
    fn gtao_side_matches_the_trigonometric_arc() {
        let mut worst = 0.0f64;
        for i in 0..=60 {
            // Normal angles over the whole circle: the clamp holds on some of them.
            let n = -3.1 + 6.2 * i as f64 / 60.0;
            for j in 0..=60 {
                let c = -1.0 + 2.0 * j as f64 / 60.0;
                for s in [1.0, -1.0] {
                    let got =
                        gtao_side(c as f32, s as f32, n as f32, n.cos() as f32, n.sin() as f32);
                    worst = worst.max((got as f64 - arc_trig(c, s, n)).abs());
                }
            }
        }
        assert!(worst <= 2e-4, "arc error {worst:e}");
    }
}

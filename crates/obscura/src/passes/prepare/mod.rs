//! Prepare: linearise the depth and build view-space normals (given, reconstructed from three
//! pixels, or fitted planes for noisy depth), and the MSAA depth resolve. The WGSL is beside
//! this file; the CPU mirror below reads like it (same names, same order of operations).

use crate::passes::uniforms::FrameUniforms;
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

pub(crate) fn centre(p: [i32; 2]) -> [f32; 2] {
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

/// The three-pixel normal of passes/prepare/normals_reconstruct.wgsl (`view_normal`).
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

/// The MSAA resolve of one pixel (passes/prepare/resolve_depth.wgsl) from its raw sample depths:
/// their mean when every sample is a surface and their linear depths lie within
/// `PLANE_TOLERANCE` of the nearest, else the raw depth of the nearest non-sky sample (the
/// first sample when all are sky).
pub fn resolve_msaa_depth(f: &FrameUniforms, samples: &[f32]) -> f32 {
    use crate::passes::constants::PLANE_TOLERANCE;
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

    /// `solve_plane` of passes/prepare/normals_fit.wgsl: (f0, a, b) and whether it is a plane.
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
/// passes/prepare/normals_fit.wgsl.
pub fn fit_surface(f: &FrameUniforms, raw: &[f32], raw_width: u32, p: [i32; 2], d: f32) -> Vec4 {
    use crate::passes::constants::{
        FIT_MAX_STRIDE, FIT_NORMAL_TAN, FIT_RADIUS, FIT_SIGMAS, FIT_SLOPE,
    };
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

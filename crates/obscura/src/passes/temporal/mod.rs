//! Temporal accumulation: reprojection into last frame's history and the blend. The WGSL is
//! beside this file; the CPU mirror below reads like it.

use crate::passes::prepare::centre;
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// A unit normal as one float (passes/temporal/temporal.wgsl, `pack_normal`): octahedral
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

/// The inverse of [`pack_normal`] (passes/temporal/temporal.wgsl, `unpack_normal`).
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
/// Mirrors passes/temporal/temporal.wgsl.
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

/// The bent normals of one frame of temporal accumulation (passes/temporal/temporal_bent.wgsl):
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
/// texels it was read from with their bilinear weights (passes/temporal/temporal.wgsl,
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
            || unpack_normal(hv.w).dot(prev_n) < crate::passes::constants::HISTORY_NORMAL_COS
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

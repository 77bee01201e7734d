//! The edge-aware spatial denoiser (over one jitter period), the box/tent AO downsample, and
//! the geometric weights the merges share. The WGSL is beside this file; the CPU mirror
//! below reads like it.

use crate::passes::prepare::centre;
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// The edge-aware spatial denoiser at working resolution (`f` the working frame,
/// `prepared` its prepared values per pixel, `period` the pattern period 2 or 4); mirrors
/// passes/denoise/denoise.wgsl.
pub fn denoise(f: &FrameUniforms, prepared: &[Vec4], ao: &[f32], period: u32) -> Vec<f32> {
    use crate::passes::constants::DENOISE_RIDGE;
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

/// The denoiser's bent normals (passes/denoise/denoise_bent.wgsl): each pixel its own normal plus
/// the plane fit, with the AO's weights, of its taps' offsets of `bent` from their normals
/// (per component), renormalised; sky pixels pass through.
pub fn denoise_bent(f: &FrameUniforms, prepared: &[Vec4], bent: &[Vec3], period: u32) -> Vec<Vec3> {
    use crate::passes::constants::DENOISE_RIDGE;
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

/// The geometric weight of tap `q` (prepared `s`) for a centre at `pos` with normal `n`
/// and plane tolerance `tol` (passes/denoise/merge.wgsl): plane × normal.
pub(crate) fn merge_weight(
    f: &FrameUniforms,
    pos: Vec3,
    n: Vec3,
    tol: f32,
    q: [i32; 2],
    s: Vec4,
) -> f32 {
    let sn = Vec3::new(s.y, s.z, s.w);
    let off = f.view_position(centre(q), s.x) - pos;
    let z = off.dot(n).abs().max(off.dot(sn).abs()) / tol;
    (-z * z).exp() * sn.dot(n).max(0.0).powi(8)
}

/// The denoiser's taps of every pixel in row order: `None` for sky, else each tap's pixel,
/// offset and weight (passes/denoise/denoise.wgsl; the geometric part from passes/denoise/merge.wgsl).
fn denoise_taps<'a>(
    f: &'a FrameUniforms,
    prepared: &'a [Vec4],
    period: u32,
) -> impl Iterator<Item = Option<Vec<([i32; 2], glam::Vec2, f32)>>> + 'a {
    use crate::passes::constants::{
        DENOISE_RADIUS_TOLERANCE, NOISE_TOLERANCE_SIGMAS, PLANE_TOLERANCE,
    };
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

/// Seed 003's box (`tent` false) or tent AO downsample, `size` → `ceil(size / 2)`;
/// mirrors passes/denoise/ao_downsample.wgsl.
pub fn ao_downsample(tent: bool, size: [u32; 2], ao: &[f32]) -> ([u32; 2], Vec<f32>) {
    use crate::passes::constants::{TENT_SPACING, TENT_WEIGHTS};
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
    use super::*;
    use glam::Vec4;

    use crate::passes::uniforms::ortho_test_frame as ortho_frame;

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
}

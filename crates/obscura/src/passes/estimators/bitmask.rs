//! CPU mirror of the visibility-bitmask estimator (passes/estimators/bitmask.wgsl; same
//! names, the same arithmetic, which the shader reorders to project once per sample).

use super::{fast_acos, gtao_slice, GtaoSlice, Pixels, Surface};
use crate::passes::prepare::centre;
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// Sectors per slice: the bits of a `u32`.
const SECTORS: f32 = 32.0;

/// Mirrors `slice_cumulative` in bitmask.wgsl (which takes the unit in-slice direction,
/// `c` its cosine): the slice's running cosine-weighted integral from 0 to `s · acos(c)`,
/// clamped to the normal's hemisphere.
pub(crate) fn slice_cumulative(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let t = s * fast_acos(c) - n;
    let h = n + t.clamp(-FRAC_PI_2, FRAC_PI_2);
    let sin_h = s * (1.0 - c * c).max(0.0).sqrt();
    let cos_2h_n = if t.abs() > FRAC_PI_2 {
        -cos_n
    } else {
        (2.0 * c * c - 1.0) * cos_n + 2.0 * sin_h * c * sin_n
    };
    let g = (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25;
    if h < 0.0 {
        -g
    } else {
        g
    }
}

/// Mirrors `slice_edge` in bitmask.wgsl.
pub(crate) fn slice_edge(e: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let h = n + e * FRAC_PI_2;
    let g = (cos_n + h * sin_n) * 0.5;
    if h < 0.0 {
        -g
    } else {
        g
    }
}

/// Mirrors `slice_at` in bitmask.wgsl.
fn slice_at(h: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let g = (cos_n + 2.0 * h * sin_n - (2.0 * h - n).cos()) * 0.25;
    if h < 0.0 {
        -g
    } else {
        g
    }
}

/// Mirrors `bent_at` in bitmask.wgsl.
fn bent_at(h: f32, cos_n: f32, sin_n: f32) -> Vec2 {
    let (sh, ch) = h.sin_cos();
    let (sh3, ch3) = (sh * sh * sh, ch * ch * ch);
    let f = Vec2::new(
        cos_n * sh3 + sin_n * (2.0 - 3.0 * ch + ch3),
        cos_n * (1.0 - ch3) + sin_n * sh3,
    ) / 3.0;
    if h < 0.0 {
        -f
    } else {
        f
    }
}

/// Knots of the angle-from-share interpolation (`BENT_KNOTS` in bitmask.wgsl).
const BENT_KNOTS: usize = 8;

/// Mirrors `bitmask_bent` in bitmask.wgsl: the slice's bent-normal integral over its runs
/// of clear sectors, in (ortho, V) coordinates.
pub(crate) fn bitmask_bent(
    occluded: u32,
    n: f32,
    cos_n: f32,
    sin_n: f32,
    lower: f32,
    total: f32,
) -> Vec2 {
    let first = n - FRAC_PI_2;
    let width = PI / BENT_KNOTS as f32;
    let knots: [f32; BENT_KNOTS + 1] = std::array::from_fn(|i| {
        (slice_at(first + i as f32 * width, n, cos_n, sin_n) - lower) / total.max(1e-6)
    });
    let mut bent = Vec2::ZERO;
    let mut run_start: Option<f32> = None;
    for k in 0..=32u32 {
        let clear = k < 32 && occluded & (1 << k) == 0;
        if clear == run_start.is_some() {
            continue;
        }
        let u = k as f32 / SECTORS;
        let mut h = first + PI;
        for i in 0..BENT_KNOTS {
            if u <= knots[i + 1] {
                let t = ((u - knots[i]) / (knots[i + 1] - knots[i]).max(1e-6)).clamp(0.0, 1.0);
                h = first + (i as f32 + t) * width;
                break;
            }
        }
        match run_start {
            None => run_start = Some(h),
            Some(a) => {
                bent += bent_at(h, cos_n, sin_n) - bent_at(a, cos_n, sin_n);
                run_start = None;
            }
        }
    }
    bent
}

/// The part of a sample's solid that can occlude the centre at `pos` (view space): the
/// stretch of pixel `at`'s view ray from linear depth `front` to `back` that lies within
/// the radius of `pos`, since the reference counts only hits within R. The front may lie
/// beyond R when the solid reaches into the sphere from in front (a ledge above the
/// centre). An infinitely thick solid (`back` infinite: GTAO's assumption) counts only
/// where its front lies within R and reaches the hemisphere's edge (a `None` back). Ends
/// relative to `pos`; `None` where nothing lies within R. Mirrors the clipping in
/// bitmask.wgsl.
pub(crate) fn clip_solid(
    f: &crate::passes::uniforms::FrameUniforms,
    at: [f32; 2],
    pos: Vec3,
    front: f32,
    back: f32,
) -> Option<(Vec3, Option<Vec3>)> {
    let front0 = f.view_position(at, front) - pos;
    let c = front0.dot(front0) * f.inv_radius2 - 1.0;
    if !back.is_finite() {
        return (c < 0.0).then_some((front0, None));
    }
    // The roots s of |front0 + s seg| = R, clamped to [0, 1].
    let seg = f.view_position(at, back) - pos - front0;
    let qa = seg.dot(seg) * f.inv_radius2;
    let qb = front0.dot(seg) * f.inv_radius2;
    let disc = qb * qb - qa * c;
    let sq = disc.max(0.0).sqrt();
    let s0 = ((-qb - sq) / qa).max(0.0);
    let s1 = ((-qb + sq) / qa).min(1.0);
    (qa > 0.0 && disc > 0.0 && s1 > s0).then(|| (front0 + seg * s0, Some(front0 + seg * s1)))
}

/// Mirrors `sector_bits` in bitmask.wgsl: bits `[a, b)`.
pub(crate) fn sector_bits(a: u32, b: u32) -> u32 {
    let below = |k: u32| if k >= 32 { u32::MAX } else { (1u32 << k) - 1 };
    below(b) & !below(a)
}

/// The visibility-bitmask AO of one pixel; mirrors `estimate` in
/// passes/estimators/bitmask.wgsl.
pub fn bitmask_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    bitmask_pixel_bent(px, p, pattern).0
}

/// What a sample sees along its view ray: up to two solids, each `(front, back)` in linear
/// view depth (`back` infinite: infinitely thick). One layer with the thickness prior gives
/// the first; renderer layers (back faces, a second layer) the others.
pub type Solids = [Option<(f32, f32)>; 2];

/// The visibility-bitmask AO of one pixel and its bent normal (unit, view space; zero on
/// sky); mirrors `estimate` in passes/estimators/bitmask.wgsl with BENT_NORMALS.
pub fn bitmask_pixel_bent(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> (f32, Vec3) {
    let thickness = px.f.model[0];
    let solid = |d: f32| {
        let back = if thickness > 0.0 {
            d + thickness
        } else {
            f32::INFINITY
        };
        (d, back)
    };
    // The first layer, and the second where one lies behind it (bitmask.wgsl's `DEPTH_LAYERS`).
    let solids = |q: [i32; 2]| -> Solids {
        let Some(sd) = px.depth_at(q).filter(|&sd| sd > 0.0) else {
            return [None, None];
        };
        let sd2 = (!px.second.is_empty())
            .then(|| px.second[(q[1] * px.f.size[0] as i32 + q[0]) as usize])
            .filter(|&sd2| sd2 > sd);
        [Some(solid(sd)), sd2.map(solid)]
    };
    bitmask_pixel_solids(px, p, pattern, solids)
}

/// [`bitmask_pixel_bent`] with the solids each sample sees given by `solids(q)` instead of
/// one layer and the thickness prior: the model of renderer layers, for the CPU's
/// screen-space limits of each representation (obscura-eval's `layers`).
pub fn bitmask_pixel_solids(
    px: &Pixels,
    p: [i32; 2],
    pattern: [f32; 4],
    solids: impl Fn([i32; 2]) -> Solids,
) -> (f32, Vec3) {
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
        let lower = slice_edge(-1.0, n, cos_n, sin_n);
        let total = slice_edge(1.0, n, cos_n, sin_n) - lower;
        let to_bits = SECTORS / total.max(1e-6);
        let mut occluded = 0u32;
        for s in 0..px.steps {
            let ray = super::march_ray(
                s,
                px.steps,
                pattern[2],
                step_px,
                px.lattice as f32,
                px.march_exponent,
            );
            let off = px.snap([dir[0] * ray, dir[1] * ray]);
            if off == [0, 0] {
                continue;
            }
            for sgn in [1.0f32, -1.0] {
                let q = if sgn > 0.0 {
                    [p[0] + off[0], p[1] + off[1]]
                } else {
                    [p[0] - off[0], p[1] - off[1]]
                };
                let at = centre(q);
                for (sd, sb) in solids(q).into_iter().flatten() {
                    let Some((front, back)) = clip_solid(f, at, pos, sd, sb) else {
                        continue;
                    };
                    let wf = front - axis * front.dot(axis);
                    if wf.dot(wf) <= 0.0 {
                        continue;
                    }
                    let cf = (wf.dot(v) / wf.dot(wf).sqrt()).clamp(-1.0, 1.0);
                    let uf = slice_cumulative(cf, sgn, n, cos_n, sin_n) - lower;
                    let mut ub = if sgn > 0.0 { total } else { 0.0 };
                    if let Some(back) = back {
                        let wb = back - axis * back.dot(axis);
                        if wb.dot(wb) > 0.0 {
                            let cb = (wb.dot(v) / wb.dot(wb).sqrt()).clamp(-1.0, 1.0);
                            ub = slice_cumulative(cb, sgn, n, cos_n, sin_n) - lower;
                        }
                    }
                    let bit = |u: f32| (u * to_bits).round_ties_even().clamp(0.0, SECTORS) as u32;
                    occluded |= sector_bits(bit(uf.min(ub)), bit(uf.max(ub)));
                }
            }
        }
        let clear = 1.0 - occluded.count_ones() as f32 / SECTORS;
        visibility += weight * proj_len * total * clear;
        let b = bitmask_bent(occluded, n, cos_n, sin_n, lower, total);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// With every sector clear the slice's bent integral is the whole hemisphere's, which
    /// is gtao_bent's from one edge to the other: the knots' interpolation is exact at the
    /// ends. With the upper half of the sectors occluded it is the lower half's alone.
    #[test]
    fn bitmask_bent_integrates_the_clear_runs() {
        for &n in &[-0.9f32, 0.0, 0.4] {
            let (sin_n, cos_n) = n.sin_cos();
            let lower = slice_edge(-1.0, n, cos_n, sin_n);
            let total = slice_edge(1.0, n, cos_n, sin_n) - lower;
            let all = bitmask_bent(0, n, cos_n, sin_n, lower, total);
            let want = bent_at(n + FRAC_PI_2, cos_n, sin_n) - bent_at(n - FRAC_PI_2, cos_n, sin_n);
            assert!((all - want).length() < 1e-5, "n {n}: {all} vs {want}");
            assert_eq!(
                bitmask_bent(u32::MAX, n, cos_n, sin_n, lower, total),
                Vec2::ZERO
            );
            let low = bitmask_bent(0xffff_0000, n, cos_n, sin_n, lower, total);
            let high = bitmask_bent(0x0000_ffff, n, cos_n, sin_n, lower, total);
            assert!(
                (low + high - all).length() < 1e-5,
                "n {n}: halves {low} + {high} vs {all}"
            );
        }
    }

    /// `clip_solid` against the sphere's closed form, orthographic (one view unit per
    /// pixel, radius 4, the centre at depth 10): a view ray `r` units from the centre
    /// crosses the sphere between depths 10 ± √(16 − r²). Tolerance 1e-4 view units.
    #[test]
    fn clip_solid_keeps_the_stretch_within_the_radius() {
        let f = crate::passes::uniforms::ortho_test_frame(32, 32);
        let pos = f.view_position([16.5, 16.5], 10.0);
        // The depth of a returned end (relative to `pos`) along its view ray.
        let depth = |v: Vec3| 10.0 - v.z;
        let half = |r: f32| (16.0 - r * r).sqrt();
        for (dx, front, back) in [
            (2.0f32, 5.0f32, 9.0f32), // reaches in from in front
            (2.0, 8.0, 20.0),         // reaches out behind
            (3.0, 9.5, 10.5),         // inside
            (0.0, 2.0, 30.0),         // through the centre's ray
        ] {
            let at = [16.5 + dx, 16.5];
            let (a, b) = clip_solid(&f, at, pos, front, back).expect("crosses the sphere");
            let b = b.expect("a finite solid has a back");
            let (lo, hi) = (front.max(10.0 - half(dx)), back.min(10.0 + half(dx)));
            assert!(
                (depth(a) - lo).abs() < 1e-4,
                "{dx} {front}..{back}: front {}",
                depth(a)
            );
            assert!(
                (depth(b) - hi).abs() < 1e-4,
                "{dx} {front}..{back}: back {}",
                depth(b)
            );
            assert!((a.x - dx).abs() < 1e-4 && (b.x - dx).abs() < 1e-4);
        }
        // In front of the sphere, beside it, and infinitely thick from in front of it.
        assert!(clip_solid(&f, [18.5, 16.5], pos, 3.0, 6.0).is_none());
        assert!(clip_solid(&f, [21.5, 16.5], pos, 8.0, 12.0).is_none());
        assert!(clip_solid(&f, [18.5, 16.5], pos, 5.0, f32::INFINITY).is_none());
        // A solid of no depth.
        assert!(clip_solid(&f, [18.5, 16.5], pos, 9.0, 9.0).is_none());
        // Infinitely thick from within R: the front as it is, no back.
        let (a, b) = clip_solid(&f, [18.5, 16.5], pos, 9.0, f32::INFINITY).unwrap();
        assert!((depth(a) - 9.0).abs() < 1e-4 && b.is_none());
    }

    #[test]
    fn sector_bits_cover_the_half_open_range() {
        assert_eq!(sector_bits(0, 0), 0);
        assert_eq!(sector_bits(0, 32), u32::MAX);
        assert_eq!(sector_bits(3, 5), 0b11000);
        assert_eq!(sector_bits(31, 32), 1 << 31);
        assert_eq!(sector_bits(5, 3), 0);
    }

    /// The running integral between the hemisphere's edges is the slice's closed-form
    /// total cos n + n sin n (Jimenez et al. 2016), and it is monotone in the angle, so
    /// sectors are well ordered. Checked against a midpoint sum of cos(t − n) |sin t|.
    #[test]
    fn slice_cumulative_is_the_running_cosine_weighted_integral() {
        for &n in &[-1.2f32, -0.5, 0.0, 0.3, 1.0, 1.5] {
            let (sin_n, cos_n) = n.sin_cos();
            let lower = slice_edge(-1.0, n, cos_n, sin_n);
            let total = slice_edge(1.0, n, cos_n, sin_n) - lower;
            assert!((total - (cos_n + n * sin_n)).abs() < 1e-5, "n {n}: {total}");
            let mut prev = f32::NEG_INFINITY;
            for k in 0..=40 {
                let h = n - FRAC_PI_2 + PI * k as f32 / 40.0;
                let (s, c) = if h < 0.0 {
                    (-1.0, h.cos())
                } else {
                    (1.0, h.cos())
                };
                let got = slice_cumulative(c, s, n, cos_n, sin_n) - lower;
                // Midpoint rule from the lower edge to h.
                let m = 2000;
                let lo = n - FRAC_PI_2;
                let dt = (h - lo) / m as f32;
                let want: f32 = (0..m)
                    .map(|i| {
                        let t = lo + (i as f32 + 0.5) * dt;
                        (t - n).cos() * t.sin().abs() * dt
                    })
                    .sum();
                // fast_acos's 1e-4 rad error bounds the difference.
                assert!((got - want).abs() < 2e-3, "n {n} h {h}: {got} vs {want}");
                assert!(got >= prev - 1e-4, "not monotone at n {n} h {h}");
                prev = got;
            }
        }
    }
}

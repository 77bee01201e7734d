//! CPU mirror of the visibility-bitmask estimator (passes/estimators/bitmask.wgsl; same
//! names and the same geometry, which the shader reorders: it projects each sample onto
//! the slice's tangent and normal once, and scales the clipped ends so that neither the
//! clip nor the two ends' sectors need more than one division).

use super::{gtao_falloff, mix, slice_ao, slice_samples, GtaoSlice, Pixels};
use crate::passes::constants::{ACOS_POLY_FINE, GTAO_FALLOFF_END};
use crate::passes::prepare::centre;
use glam::{Vec2, Vec3};
#[cfg(test)]
use std::f32::consts::{FRAC_PI_2, PI};

/// Sectors per slice: the bits of a `u32`.
const SECTORS: f32 = crate::passes::constants::SECTORS as f32;

/// The running integral D at the hemisphere's edge n + e π/2 (e = ±1), where
/// cos(2h − n) = −cos n.
#[cfg(test)]
fn slice_edge(e: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let h = n + e * FRAC_PI_2;
    let g = (cos_n + h * sin_n) * 0.5;
    if h < 0.0 {
        -g
    } else {
        g
    }
}

/// The slice's integral over the whole hemisphere, D(n + π/2) − D(n − π/2) = cos n + n sin n;
/// mirrors `total` in bitmask.wgsl.
fn slice_total(n: f32, cos_n: f32, sin_n: f32) -> f32 {
    cos_n + n * sin_n
}

/// Mirrors `sector_edge` in bitmask.wgsl: sector edge `k`'s angle a from the normal, cos a
/// and sin a.
pub(crate) fn sector_edge(k: u32) -> [f32; 3] {
    let p = k as f32 * (2.0 / SECTORS) - 1.0;
    let b = 1.0 - p.abs();
    let inv_len = 1.0 / (p * p + b * b).sqrt();
    let x = b * inv_len;
    let poly = ACOS_POLY_FINE.iter().rev().fold(0.0, |acc, &c| acc * x + c);
    let a = (1.0 - x).sqrt() * poly;
    [if p < 0.0 { -a } else { a }, x, p * inv_len]
}

/// Mirrors `slice_at_edge` in bitmask.wgsl: D at sector edge `k`, cos(2h − n) from the
/// edge's cos a and sin a.
fn slice_at_edge(k: u32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let [a, ca, sa] = sector_edge(k);
    let h = n + a;
    let cos_2h_n = cos_n * (ca * ca - sa * sa) - sin_n * (2.0 * ca * sa);
    let g = (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25;
    if h < 0.0 {
        -g
    } else {
        g
    }
}

/// gtao_bent's closed form at cos h and sin h, signed like D.
fn bent_from(h: f32, ch: f32, sh: f32, cos_n: f32, sin_n: f32) -> Vec2 {
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

/// The running bent-normal integral at slice angle h (`bent_at_edge` at any angle).
#[cfg(test)]
fn bent_at(h: f32, cos_n: f32, sin_n: f32) -> Vec2 {
    let (sh, ch) = h.sin_cos();
    bent_from(h, ch, sh, cos_n, sin_n)
}

/// Mirrors `bent_at_edge` in bitmask.wgsl: the bent-normal integral at sector edge `k`,
/// cos h and sin h from the edge's cos a and sin a.
fn bent_at_edge(k: u32, n: f32, cos_n: f32, sin_n: f32) -> Vec2 {
    let [a, ca, sa] = sector_edge(k);
    let (ch, sh) = (cos_n * ca - sin_n * sa, sin_n * ca + cos_n * sa);
    bent_from(n + a, ch, sh, cos_n, sin_n)
}

/// Mirrors `sector_pair` in bitmask.wgsl for one direction: the sector position (0 to 32,
/// in equal steps of the pseudo-angle a / (|a| + b), a along `tangent`, b along `normal2`)
/// of the in-slice direction `w` (ortho, V) on side `s`; below the hemisphere, the side's
/// edge.
pub(crate) fn sector_of(w: Vec2, s: f32, tangent: Vec2, normal2: Vec2) -> f32 {
    let (a, b) = (w.dot(tangent), w.dot(normal2));
    let p = if b <= 0.0 { s } else { a / (a.abs() + b) };
    (p + 1.0) * (0.5 * SECTORS)
}

/// The slice angle of sector edge `k` (0 to 32): the normal's angle n plus the edge's.
#[cfg(test)]
fn edge_angle(k: u32, n: f32) -> f32 {
    n + sector_edge(k)[0]
}

/// The runs of set bits of `bits`, lowest first, each `[start, end)` (`lowest_run` in
/// bitmask.wgsl).
fn runs(mut bits: u32) -> impl Iterator<Item = (u32, u32)> {
    std::iter::from_fn(move || {
        if bits == 0 {
            return None;
        }
        let start = bits.trailing_zeros();
        let end = (bits | ((1u32 << start) - 1)).trailing_ones();
        bits &= !sector_bits(start, end);
        Some((start, end))
    })
}

/// Mirrors `sectors_integral` in bitmask.wgsl: the slice's cosine-weighted integral over
/// the sectors set in `bits`, exact between the sector edges.
pub(crate) fn sectors_integral(bits: u32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    runs(bits)
        .map(|(a, b)| slice_at_edge(b, n, cos_n, sin_n) - slice_at_edge(a, n, cos_n, sin_n))
        .sum()
}

/// Mirrors `bitmask_bent` in bitmask.wgsl: the slice's bent-normal integral over its runs
/// of clear sectors, in (ortho, V) coordinates.
pub(crate) fn bitmask_bent(occluded: u32, n: f32, cos_n: f32, sin_n: f32) -> Vec2 {
    runs(!occluded)
        .map(|(a, b)| bent_at_edge(b, n, cos_n, sin_n) - bent_at_edge(a, n, cos_n, sin_n))
        .sum()
}

/// The part of a sample's solid that can occlude the centre at `pos` (view space): the
/// stretch of pixel `at`'s view ray from linear depth `front` to `back` that lies within
/// the radius of `pos`, since the reference counts only hits within R. The front may lie
/// beyond R when the solid reaches into the sphere from in front (a ledge above the
/// centre). An infinitely thick solid (`back` infinite: GTAO's assumption) counts only
/// where its front lies within GTAO_FALLOFF_END radii (constants.rs) and reaches the
/// hemisphere's edge (a `None` back; beyond R the caller lowers its front by
/// `falloff_front`). Ends relative to `pos`; `None` where nothing lies within R. Mirrors the
/// clipping in bitmask.wgsl.
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
        let end2 = GTAO_FALLOFF_END * GTAO_FALLOFF_END;
        return (c < end2 - 1.0).then_some((front0, None));
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

/// An infinitely thick front beyond R, its direction `w` in (ortho, V) coordinates on side
/// `sgn`, at `r2` radii² from the centre: the direction whose cosine to V is GTAO's horizon
/// there (mirrors `falloff_front` in bitmask.wgsl, which works in the slice's tangent and
/// normal frame).
fn falloff_front(w: Vec2, sgn: f32, r2: f32, sin_n: f32) -> Vec2 {
    let c = (w.y / w.length()).clamp(-1.0, 1.0);
    let h = mix(-sgn * sin_n, c, gtao_falloff(r2));
    Vec2::new(sgn * (1.0 - h * h).max(0.0).sqrt(), h)
}

/// Bits `[a, b)` (none where a ≥ b); bitmask.wgsl sets and clears runs with `insertBits`.
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
            .then(|| {
                super::count_read();
                px.second[(q[1] * px.f.size[0] as i32 + q[0]) as usize]
            })
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
    slice_ao(px, p, pattern, |at| {
        let GtaoSlice {
            ortho,
            n,
            cos_n,
            sin_n,
            ..
        } = at.slice;
        let total = slice_total(n, cos_n, sin_n);
        let (tangent, normal2) = (Vec2::new(cos_n, -sin_n), Vec2::new(sin_n, cos_n));
        // In-slice (ortho, V) coordinates of a point relative to the centre.
        let in_slice = |w: Vec3| Vec2::new(w.dot(ortho), w.dot(at.v));
        let mut occluded = 0u32;
        for (side, q) in slice_samples(px, p, at, pattern[2]) {
            let sgn = if side == 0 { 1.0 } else { -1.0 };
            let c = centre(q);
            for (sd, sb) in solids(q).into_iter().flatten() {
                let Some((front, back)) = clip_solid(f, c, at.pos, sd, sb) else {
                    continue;
                };
                let mut wf = in_slice(front);
                if wf.dot(wf) <= 0.0 {
                    continue;
                }
                if back.is_none() {
                    let r2 = front.dot(front) * f.inv_radius2;
                    if r2 > 1.0 {
                        wf = falloff_front(wf, sgn, r2, sin_n);
                    }
                }
                let uf = sector_of(wf, sgn, tangent, normal2);
                let mut ub = if sgn > 0.0 { SECTORS } else { 0.0 };
                if let Some(wb) = back.map(in_slice).filter(|wb| wb.dot(*wb) > 0.0) {
                    ub = sector_of(wb, sgn, tangent, normal2);
                }
                let bit = |u: f32| u.round_ties_even().clamp(0.0, SECTORS) as u32;
                occluded |= sector_bits(bit(uf.min(ub)), bit(uf.max(ub)));
            }
        }
        let visible = (total - sectors_integral(occluded, n, cos_n, sin_n)).max(0.0);
        (visible, bitmask_bent(occluded, n, cos_n, sin_n))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With every sector clear the slice's bent integral is the whole hemisphere's,
    /// gtao_bent's closed form from one edge to the other (the outer edges are exactly
    /// n ∓ π/2); with none clear it is zero; the two halves' (bit 16 is the normal's
    /// direction) add up to the whole, and the lower half is gtao_bent's from n − π/2 to n.
    #[test]
    fn bitmask_bent_integrates_the_clear_runs() {
        for &n in &[-0.9f32, 0.0, 0.4] {
            let (sin_n, cos_n) = n.sin_cos();
            let all = bitmask_bent(0, n, cos_n, sin_n);
            let want = bent_at(n + FRAC_PI_2, cos_n, sin_n) - bent_at(n - FRAC_PI_2, cos_n, sin_n);
            assert!((all - want).length() < 1e-5, "n {n}: {all} vs {want}");
            assert_eq!(bitmask_bent(u32::MAX, n, cos_n, sin_n), Vec2::ZERO);
            let low = bitmask_bent(0xffff_0000, n, cos_n, sin_n);
            let high = bitmask_bent(0x0000_ffff, n, cos_n, sin_n);
            assert!(
                (low + high - all).length() < 1e-5,
                "n {n}: halves {low} + {high} vs {all}"
            );
            let want_low = bent_at(n, cos_n, sin_n) - bent_at(n - FRAC_PI_2, cos_n, sin_n);
            assert!(
                (low - want_low).length() < 1e-5,
                "n {n}: {low} vs {want_low}"
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
        // In front of the sphere, beside it, and infinitely thick from beyond
        // GTAO_FALLOFF_END radii (9.2 > 8) in front of it.
        assert!(clip_solid(&f, [18.5, 16.5], pos, 3.0, 6.0).is_none());
        assert!(clip_solid(&f, [21.5, 16.5], pos, 8.0, 12.0).is_none());
        assert!(clip_solid(&f, [18.5, 16.5], pos, 1.0, f32::INFINITY).is_none());
        // Infinitely thick from between R and GTAO_FALLOFF_END radii (5.4): kept, for its
        // caller's falloff.
        let (a, b) = clip_solid(&f, [18.5, 16.5], pos, 5.0, f32::INFINITY).unwrap();
        assert!((depth(a) - 5.0).abs() < 1e-4 && b.is_none());
        // A solid of no depth.
        assert!(clip_solid(&f, [18.5, 16.5], pos, 9.0, 9.0).is_none());
        // Infinitely thick from within R: the front as it is, no back.
        let (a, b) = clip_solid(&f, [18.5, 16.5], pos, 9.0, f32::INFINITY).unwrap();
        assert!((depth(a) - 9.0).abs() < 1e-4 && b.is_none());
    }

    /// `falloff_front` against GTAO's mixed horizon: the direction's cosine to V is
    /// mix(low, c, k) on the front's own side, so within R (k = 1) the front's own direction
    /// and at the falloff's end (k = 0) the tangent plane's, (sgn cos n, −sgn sin n) in
    /// (ortho, V). Tolerance 1e-5.
    #[test]
    fn falloff_front_mixes_the_horizon_toward_the_tangent_plane() {
        let end2 = GTAO_FALLOFF_END * GTAO_FALLOFF_END;
        for (n, sgn) in [(0.3f32, 1.0f32), (0.3, -1.0), (-0.7, 1.0), (-0.7, -1.0)] {
            let (sin_n, cos_n) = n.sin_cos();
            let w = Vec2::new(sgn * 2.0, 1.5);
            let c = w.y / w.length();
            let near = falloff_front(w, sgn, 1.0, sin_n);
            assert!((near - w.normalize()).length() < 1e-5, "{n} {sgn}: {near}");
            let far = falloff_front(w, sgn, end2, sin_n);
            let edge = Vec2::new(sgn * cos_n, -sgn * sin_n);
            assert!((far - edge).length() < 1e-5, "{n} {sgn}: {far} vs {edge}");
            let half = falloff_front(w, sgn, (1.0 + end2) / 2.0, sin_n);
            let h = (-sgn * sin_n + c) / 2.0;
            assert!(
                (half.y - h).abs() < 1e-5 && half.x * sgn > 0.0,
                "{n} {sgn}: {half}"
            );
        }
    }

    /// The sector edges' angle (A&S 4.4.46's arc cosine), cosine and sine agree with
    /// atan2's edge (p, 1 − |p|) to 1e-5 at every edge, the hemisphere's ends included (a
    /// sector is 0.06 rad or more; near the normal the arc cosine of a cosine close to 1
    /// keeps about 1e-6 of f32's rounding).
    #[test]
    fn sector_edges_match_atan2() {
        for k in 0..=32 {
            let p = k as f64 / 16.0 - 1.0;
            let a = p.atan2(1.0 - p.abs());
            let [ga, gc, gs] = sector_edge(k).map(f64::from);
            let err = (ga - a)
                .abs()
                .max((gc - a.cos()).abs())
                .max((gs - a.sin()).abs());
            assert!(err < 1e-5, "edge {k}: ({ga}, {gc}, {gs}) against {a}");
        }
    }

    #[test]
    fn sector_bits_cover_the_half_open_range() {
        assert_eq!(sector_bits(0, 0), 0);
        assert_eq!(sector_bits(0, 32), u32::MAX);
        assert_eq!(sector_bits(3, 5), 0b11000);
        assert_eq!(sector_bits(31, 32), 1 << 31);
        assert_eq!(sector_bits(5, 3), 0);
    }

    /// The pseudo-angle sectors, for normals across the slice: `sector_of` rises
    /// monotonically from 0 at the hemisphere's edge n − π/2 to 32 at n + π/2, takes each
    /// `edge_angle(k)` to k (they invert each other within 1e-3 of a sector), and gives a
    /// direction below the hemisphere its side's edge. `sectors_integral` over one or two
    /// runs is the slice's measure cos(t − n) |sin t| integrated between the runs' edge
    /// angles (a midpoint sum; within 1e-4), and over every sector the slice's closed-form
    /// total cos n + n sin n (Jimenez et al. 2016).
    #[test]
    fn pseudo_angle_sectors_span_the_hemisphere_and_integrate_exactly() {
        for &n in &[-1.2f32, -0.5, 0.0, 0.3, 1.0, 1.5] {
            let (sin_n, cos_n) = n.sin_cos();
            let (tangent, normal2) = (Vec2::new(cos_n, -sin_n), Vec2::new(sin_n, cos_n));
            let total = slice_total(n, cos_n, sin_n);
            let edges = slice_edge(1.0, n, cos_n, sin_n) - slice_edge(-1.0, n, cos_n, sin_n);
            assert!((total - edges).abs() < 1e-5, "n {n}: {total} vs {edges}");
            // The unit direction at slice angle h, (ortho, V), and its side.
            let sector = |h: f32| {
                let s = if h < 0.0 { -1.0 } else { 1.0 };
                sector_of(Vec2::new(h.sin(), h.cos()), s, tangent, normal2)
            };
            let mut prev = -1.0;
            for i in 0..=400 {
                let h = n - FRAC_PI_2 + PI * i as f32 / 400.0;
                let u = sector(h);
                assert!(u >= prev - 1e-4, "n {n}: not monotone at h {h}");
                assert!((-1e-4..=32.0 + 1e-4).contains(&u), "n {n} h {h}: {u}");
                prev = u;
            }
            for k in 0..=32 {
                let u = sector(edge_angle(k, n));
                assert!((u - k as f32).abs() < 1e-3, "n {n}: edge {k} at {u}");
            }
            // Below the hemisphere, on either side.
            if n + FRAC_PI_2 + 0.2 < PI {
                assert_eq!(sector(n + FRAC_PI_2 + 0.2), 32.0, "n {n}");
            }
            if n - FRAC_PI_2 - 0.2 > -PI {
                assert_eq!(sector(n - FRAC_PI_2 - 0.2), 0.0, "n {n}");
            }
            let measure = |a: u32, b: u32| -> f64 {
                let (lo, hi) = (edge_angle(a, n) as f64, edge_angle(b, n) as f64);
                let m = 4000;
                let dt = (hi - lo) / m as f64;
                (0..m)
                    .map(|i| {
                        let t = lo + (i as f64 + 0.5) * dt;
                        (t - n as f64).cos() * t.sin().abs() * dt
                    })
                    .sum()
            };
            let got = sectors_integral(u32::MAX, n, cos_n, sin_n);
            assert!((got - total).abs() < 1e-5, "n {n}: all {got} vs {total}");
            for (a, b) in [(0, 16), (16, 32), (5, 9), (3, 4), (30, 32)] {
                let got = sectors_integral(sector_bits(a, b), n, cos_n, sin_n) as f64;
                let want = measure(a, b);
                assert!(
                    (got - want).abs() < 1e-4,
                    "n {n} [{a}, {b}): {got} vs {want}"
                );
            }
            let two = sectors_integral(sector_bits(2, 6) | sector_bits(20, 25), n, cos_n, sin_n);
            let want = measure(2, 6) + measure(20, 25);
            assert!(
                (two as f64 - want).abs() < 1e-4,
                "n {n}: two runs {two} vs {want}"
            );
        }
    }
}

//! CPU mirror of GTAO (passes/estimators/gtao.wgsl and gtao_arcs.wgsl), and the slice
//! loop it shares with the bitmask's mirror.

use super::{march_ray, Pixels, Surface};
use crate::passes::constants::GTAO_FALLOFF_END;
use crate::passes::prepare::centre;
use glam::Vec3;

/// acos with |error| ≤ 1e-4 rad on [-1, 1] (Abramowitz & Stegun 4.4.45); mirrors
/// `fast_acos` in passes/estimators/gtao_arcs.wgsl.
fn fast_acos(x: f32) -> f32 {
    use crate::passes::constants::ACOS_POLY as k;
    let a = x.abs();
    let r = (1.0 - a).sqrt() * (k[0] + a * (k[1] + a * (k[2] + a * k[3])));
    if x < 0.0 {
        std::f32::consts::PI - r
    } else {
        r
    }
}

/// A front's weight as a horizon at squared distance `r2` (radii²) from the centre: 1
/// within R, 0 from GTAO_FALLOFF_END radii; mirrors `gtao_falloff` in
/// passes/estimators/gtao_arcs.wgsl.
pub(crate) fn gtao_falloff(r2: f32) -> f32 {
    let end2 = GTAO_FALLOFF_END * GTAO_FALLOFF_END;
    ((end2 - r2) * (1.0 / (end2 - 1.0))).clamp(0.0, 1.0)
}

/// WGSL's `mix`: `a` where `t` is 0, `b` where it is 1.
pub(crate) fn mix(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// One side's visible arc of a GTAO slice; mirrors `gtao_side` in passes/estimators/gtao_arcs.wgsl.
pub(crate) fn gtao_side(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
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
/// `gtao_bent` in passes/estimators/gtao_arcs.wgsl (closed form there).
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

/// One GTAO slice's frame; mirrors `GtaoSlice` in passes/estimators/gtao_arcs.wgsl.
pub(crate) struct GtaoSlice {
    pub(crate) axis: Vec3,
    /// Unit.
    pub(crate) ortho: Vec3,
    pub(crate) weight: f32,
    pub(crate) proj_len: f32,
    pub(crate) n: f32,
    pub(crate) cos_n: f32,
    pub(crate) sin_n: f32,
}

/// Mirrors `gtao_slice` in passes/estimators/gtao_arcs.wgsl.
pub(crate) fn gtao_slice(dir: [f32; 2], v: Vec3, normal: Vec3) -> GtaoSlice {
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

/// GTAO of one pixel; mirrors `estimate` in passes/estimators/gtao.wgsl.
pub fn gtao_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    gtao_pixel_bent(px, p, pattern).0
}

/// What [`slice_ao`] gives a slice's body: the pixel's view-space position and view
/// vector, its step length in pixels, the slice's screen direction and frame.
pub(crate) struct SliceAt {
    pub(crate) pos: Vec3,
    pub(crate) v: Vec3,
    pub(crate) step_px: f32,
    pub(crate) dir: [f32; 2],
    pub(crate) slice: GtaoSlice,
}

/// The slice loop GTAO and the bitmask share (`estimate` in gtao.wgsl and bitmask.wgsl):
/// the pattern's direction turned by π / directions after each slice, each slice weighted
/// by d(azimuth)/d(screen angle) and by its projected normal's length. `body` returns a
/// slice's visible integral and its bent-normal share in (ortho, V) coordinates; it is not
/// called for a slice whose projected normal vanishes (fully visible). Returns the AO and
/// the unit bent normal (the surface's normal where nothing bends it; zero on sky).
pub(crate) fn slice_ao(
    px: &Pixels,
    p: [i32; 2],
    pattern: [f32; 4],
    mut body: impl FnMut(&SliceAt) -> (f32, glam::Vec2),
) -> (f32, Vec3) {
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
        let slice = gtao_slice(dir, v, normal);
        weights += slice.weight;
        if slice.proj_len < 1e-6 {
            visibility += slice.weight;
            continue;
        }
        let (weight, proj_len, ortho) = (slice.weight, slice.proj_len, slice.ortho);
        let (arcs, b) = body(&SliceAt {
            pos,
            v,
            step_px,
            dir,
            slice,
        });
        visibility += weight * proj_len * arcs;
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

/// The pixels a slice's march visits, nearest step first, each step's offset taken to
/// both sides: `(0, p + offset)` along the slice's direction, `(1, p − offset)` against it.
/// A step that rounds to the centre is skipped: the centre is never its own occluder
/// (gtao.wgsl).
pub(crate) fn slice_samples<'a>(
    px: &'a Pixels,
    p: [i32; 2],
    at: &SliceAt,
    jitter: f32,
) -> impl Iterator<Item = (usize, [i32; 2])> + 'a {
    let (dir, step_px) = (at.dir, at.step_px);
    (0..px.steps).flat_map(move |s| {
        // The first step's cell is one pixel in every layout (the near field is at full
        // resolution).
        let ray = march_ray(s, px.steps, jitter, step_px, 1.0, px.march_exponent);
        let off = px.snap([dir[0] * ray, dir[1] * ray]);
        let sides = [
            (0, [p[0] + off[0], p[1] + off[1]]),
            (1, [p[0] - off[0], p[1] - off[1]]),
        ];
        sides.into_iter().filter(move |_| off != [0, 0])
    })
}

/// GTAO of one pixel and its bent normal (unit, view space; zero on sky); mirrors
/// `estimate` in passes/estimators/gtao.wgsl with BENT_NORMALS.
pub fn gtao_pixel_bent(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> (f32, Vec3) {
    let f = px.f;
    slice_ao(px, p, pattern, |at| {
        let GtaoSlice {
            axis,
            n,
            cos_n,
            sin_n,
            ..
        } = at.slice;
        let low = [-sin_n, sin_n];
        let mut hc = low;
        for (side, q) in slice_samples(px, p, at, pattern[2]) {
            let Some(sd) = px.depth_at(q) else {
                continue;
            };
            if sd <= 0.0 {
                continue;
            }
            let full = f.view_position(centre(q), sd) - at.pos;
            let r2 = full.dot(full) * f.inv_radius2;
            let w = full - axis * full.dot(axis);
            let k = gtao_falloff(r2);
            if k <= 0.0 || w.dot(w) <= 0.0 {
                continue;
            }
            let c = (w.dot(at.v) / w.dot(w).sqrt()).clamp(-1.0, 1.0);
            hc[side] = hc[side].max(mix(low[side], c, k));
        }
        let arcs = gtao_side(hc[0], 1.0, n, cos_n, sin_n) + gtao_side(hc[1], -1.0, n, cos_n, sin_n);
        let b = gtao_bent(hc[0], 1.0, n, cos_n, sin_n) + gtao_bent(hc[1], -1.0, n, cos_n, sin_n);
        (arcs, b)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// The falloff's definition: 1 within R, 0 from GTAO_FALLOFF_END radii, linear in r²
    /// between (a half at the middle of r²'s range). Tolerance 1e-6.
    #[test]
    fn gtao_falloff_is_linear_in_r2_from_r_to_its_end() {
        let end2 = GTAO_FALLOFF_END * GTAO_FALLOFF_END;
        for (r2, want) in [
            (0.0, 1.0),
            (1.0, 1.0),
            ((1.0 + end2) / 2.0, 0.5),
            (end2, 0.0),
        ] {
            let k = gtao_falloff(r2);
            assert!((k - want).abs() < 1e-6, "r² {r2}: {k} against {want}");
        }
        assert_eq!(gtao_falloff(end2 * 2.0), 0.0);
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

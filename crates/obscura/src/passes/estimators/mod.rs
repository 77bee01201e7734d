//! The AO estimators (GTAO, HBAO, VO, VAO, VO area, SAO, bitmask) and the passes that run them over
//! full-resolution pixels or deinterleaved layers. The WGSL is beside this file; the CPU
//! mirror below reads like it (same names, same order of operations).

mod bitmask;
mod gtao;
pub use bitmask::{bitmask_pixel, bitmask_pixel_bent, bitmask_pixel_solids, Solids};
pub(crate) use gtao::{
    gtao_falloff, gtao_side, gtao_slice, mix, slice_ao, slice_samples, GtaoSlice,
};
pub use gtao::{gtao_pixel, gtao_pixel_bent};

use crate::passes::prepare::centre;
use crate::passes::pyramid::{moments, pyramid, PyramidLevel};
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// What every estimator's pixel function reads: the frame, the compiled sample counts,
/// the prepared buffer (viewport-sized) and the sampling lattice of the mode (1: any pixel;
/// N: offsets snapped to multiples of N, which is what the N×N deinterleaved pass samples).
#[derive(Clone, Copy, Debug)]
pub struct Pixels<'a> {
    pub f: &'a FrameUniforms,
    pub directions: u32,
    pub steps: u32,
    /// [`crate::AoOptions::march_exponent`] (GTAO and the bitmask).
    pub march_exponent: f32,
    pub prepared: &'a [Vec4],
    pub lattice: u32,
    /// The depth pyramid of the full-resolution buffer ([`pyramid`]), for estimators that
    /// read it; may be empty.
    pub pyramid: &'a [PyramidLevel],
    /// The depth moments pyramid ([`moments`]) for VO's area integral; may be empty.
    pub moments: &'a [PyramidLevel],
    /// The second depth layer's linear depth (viewport-sized, 0 = none) for the bitmask
    /// ([`crate::AoOptions::second_layer`]); empty without one.
    pub second: &'a [f32],
}

/// [`Pixels::snap`] on a lattice of `lattice` pixels.
fn snap_offset(v: [f32; 2], lattice: u32) -> [i32; 2] {
    let near = (crate::passes::constants::NEAR_FIELD_CELLS * lattice) as f32;
    if v[0] * v[0] + v[1] * v[1] < near * near {
        return v.map(|c| c.round_ties_even() as i32);
    }
    let l = lattice as f32;
    v.map(|c| (c / l).round_ties_even() as i32 * lattice as i32)
}

/// Where step `s` of `steps` (offset `j`) lands along a GTAO or bitmask direction on a
/// lattice of `cell` pixels with march exponent `e`, pixels from the centre; mirrors
/// `march_ray` in passes/common.wgsl.
pub fn march_ray(s: u32, steps: u32, j: f32, step_px: f32, cell: f32, e: f32) -> f32 {
    let n = steps as f32;
    if e == 1.0 {
        return 1.0 + (s as f32 + j) * step_px;
    }
    cell + (1.0 + step_px * n - cell) * march_power((s as f32 + j) / n, e)
}

/// t^e, with the exponents 1.25, 1.5 and 2 by square roots and a product; mirrors
/// `march_power` in passes/common.wgsl.
pub fn march_power(t: f32, e: f32) -> f32 {
    if e == 1.25 {
        t * t.sqrt().sqrt()
    } else if e == 1.5 {
        t * t.sqrt()
    } else if e == 2.0 {
        t * t
    } else {
        t.powf(e)
    }
}

/// E[max(z − c, 0)] for z uniform on [lo, hi] (a point where lo = hi); mirrors
/// `expected_ramp` in passes/estimators/sphere_area.wgsl.
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
/// `thickness` deep (VO's thickness model; `occupied_length` in passes/estimators/sphere.wgsl).
pub fn occupied_length(sd: f32, dc: f32, h: f32, thickness: f32) -> f32 {
    ((dc + h).min(sd + thickness) - sd.max(dc - h)).clamp(0.0, 2.0 * h)
}

/// The expected occupied length of the chord `dc ± h` over depths uniform with `mean` and
/// `variance` (`chord_occupied` in passes/estimators/sphere_area.wgsl, before the valid fraction).
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
pub(crate) struct Surface {
    pub(crate) d: f32,
    pub(crate) n: Vec3,
    pub(crate) pos: Vec3,
}

// Texel reads of the mirror, counted in tests: the cost model's fetch counts are checked
// against them (frame/cost_tests.rs).
#[cfg(test)]
thread_local! {
    pub(crate) static READS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// One texel read by the mirror (a `textureLoad` of the WGSL).
#[inline]
pub(crate) fn count_read() {
    #[cfg(test)]
    READS.with(|r| r.set(r.get() + 1));
}

impl Pixels<'_> {
    /// The surface at `p`, or `None` for sky (every estimator then returns 1).
    pub(crate) fn surface(&self, p: [i32; 2]) -> Option<Surface> {
        count_read();
        let v = self.prepared[(p[1] * self.f.size[0] as i32 + p[0]) as usize];
        (v.x > 0.0).then(|| Surface {
            d: v.x,
            n: Vec3::new(v.y, v.z, v.w),
            pos: self
                .f
                .estimator_origin(centre(p), v.x, Vec3::new(v.y, v.z, v.w)),
        })
    }

    /// `v` (pixels) as a whole-pixel offset, as WGSL's round() does (half to even): to the
    /// pixel within [`NEAR_FIELD_CELLS`](crate::passes::constants::NEAR_FIELD_CELLS) cells
    /// of the lattice, to the lattice beyond (`snap_offset` of the layouts' WGSL).
    pub(crate) fn snap(&self, v: [f32; 2]) -> [i32; 2] {
        snap_offset(v, self.lattice)
    }

    /// Linear depth at `q`, or `None` outside the viewport.
    pub(crate) fn depth_at(&self, q: [i32; 2]) -> Option<f32> {
        let (w, h) = (self.f.size[0] as i32, self.f.size[1] as i32);
        (q[0] >= 0 && q[1] >= 0 && q[0] < w && q[1] < h).then(|| {
            count_read();
            self.prepared[(q[1] * w + q[0]) as usize].x
        })
    }
}

/// HBAO of one pixel; mirrors `estimate` in passes/estimators/hbao.wgsl.
pub fn hbao_pixel(px: &Pixels, p: [i32; 2], pattern: [f32; 4]) -> f32 {
    hbao_pixel_bent(px, p, pattern).0
}

/// HBAO of one pixel and its bent normal (unit, view space; zero on sky); mirrors
/// `estimate` in passes/estimators/hbao.wgsl with BENT_NORMALS.
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

/// VO (`offset` 0) or VAO (`offset` 0.5) of one pixel; mirrors `estimate` in
/// passes/estimators/sphere.wgsl.
/// With `area`, VO's area integral: samples whose share of the disk is 4 px² or more read
/// `px.moments` (passes/estimators/sphere_area.wgsl).
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
    let thickness = crate::passes::constants::SPHERE_THICKNESS * f.radius;
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

/// SAO of one pixel; mirrors `estimate` in passes/estimators/sao.wgsl. With an empty `px.pyramid`
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

/// [`ao`] with the bitmask reading a second depth layer: `second`, its linear depth per
/// pixel (0 = none), as the prepare pass writes it ([`crate::AoOptions::second_layer`]).
pub fn ao_second_layer(
    f: &FrameUniforms,
    options: &crate::AoOptions,
    prepared: &[Vec4],
    second: &[f32],
) -> Vec<f32> {
    over_pixels(
        f,
        options,
        prepared,
        (f.size, prepared),
        second,
        bitmask_pixel,
    )
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
        (full_size, full),
        &[],
        |px, q, pattern| match options.estimator {
            crate::Estimator::Hbao => hbao_pixel(px, q, pattern),
            crate::Estimator::Gtao => gtao_pixel(px, q, pattern),
            crate::Estimator::Vo => sphere_pixel(px, q, pattern, 0.0, false),
            crate::Estimator::Vao => sphere_pixel(px, q, pattern, 0.5, false),
            crate::Estimator::VoArea => sphere_pixel(px, q, pattern, 0.0, true),
            crate::Estimator::Sao => sao_pixel(px, q, pattern),
            crate::Estimator::Bitmask => bitmask_pixel(px, q, pattern),
        },
    )
}

/// The bent normals of GTAO, HBAO or the bitmask ([`crate::AoOptions::bent_normals`]) over the grid of
/// `f` (the working frame; `prepared` its level) with the patterns and lattice of the
/// mode, as the AO pass writes them before any denoiser (unit, view space; zero on sky).
pub fn bent_normals(f: &FrameUniforms, options: &crate::AoOptions, prepared: &[Vec4]) -> Vec<Vec3> {
    over_pixels(
        f,
        options,
        prepared,
        (f.size, prepared),
        &[],
        |px, q, pattern| match options.estimator {
            crate::Estimator::Hbao => hbao_pixel_bent(px, q, pattern).1,
            crate::Estimator::Bitmask => bitmask_pixel_bent(px, q, pattern).1,
            _ => gtao_pixel_bent(px, q, pattern).1,
        },
    )
}

/// `pixel` at every pixel of `f`'s grid with the pattern and sampling lattice of the mode
/// (what [`ao_over`] runs the estimator with); `second`: [`Pixels::second`].
fn over_pixels<T>(
    f: &FrameUniforms,
    options: &crate::AoOptions,
    prepared: &[Vec4],
    (full_size, full): ([u32; 2], &[Vec4]),
    second: &[f32],
    pixel: impl Fn(&Pixels, [i32; 2], [f32; 4]) -> T,
) -> Vec<T> {
    let n = options.mode.split();
    let (dim, lattice) = if n == 1 {
        (crate::passes::jitter::PATTERN_DIM, 1)
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
        march_exponent: options.march_exponent,
        prepared,
        lattice,
        pyramid: &levels,
        moments: &moment_levels,
        second,
    };
    let sector = crate::passes::shader::pattern_sector(options) as f32;
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..f.size[1] {
        for x in 0..f.size[0] {
            let base = f.patterns[crate::passes::jitter::pattern_index(x, y, dim)];
            let pattern = if n == 1 {
                base
            } else {
                crate::passes::jitter::pixel_pattern(base, x as i32, y as i32, n, sector)
            };
            out.push(pixel(&px, [x as i32, y as i32], pattern));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In the N×N layouts an offset within NEAR_FIELD_CELLS cells lands on its own pixel
    /// (rounded), one beyond on the layer's lattice; full resolution rounds everywhere.
    #[test]
    fn the_near_field_is_sampled_at_full_resolution() {
        use crate::passes::constants::NEAR_FIELD_CELLS;
        for lattice in [2u32, 4] {
            let edge = (NEAR_FIELD_CELLS * lattice) as f32;
            assert_eq!(snap_offset([1.2, 0.0], lattice), [1, 0]);
            assert_eq!(snap_offset([-0.6, 1.4], lattice), [-1, 1]);
            let far = snap_offset([edge + 0.7, 1.2], lattice);
            assert!(
                far.iter().all(|c| c % lattice as i32 == 0),
                "{lattice}: {far:?}"
            );
            assert_eq!(
                snap_offset([edge - 0.6, 0.0], lattice)[0],
                (edge - 0.6).round() as i32
            );
        }
        assert_eq!(snap_offset([7.4, -3.6], 1), [7, -4]);
    }

    /// The powers by square roots against f64's powf over [0, 1], to 2e-6 (a few float
    /// roundings); other exponents take powf itself.
    #[test]
    fn march_powers_by_square_roots_are_the_powers() {
        for e in [1.25f32, 1.5, 2.0, 1.3] {
            for i in 0..=1000 {
                let t = i as f32 / 1000.0;
                let exact = (t as f64).powf(e as f64);
                let got = march_power(t, e) as f64;
                assert!((got - exact).abs() <= 2e-6, "t {t} e {e}: {got} vs {exact}");
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
}

//! Depth hierarchies: the min/max depth pyramid, the depth moments pyramid, downsampling by a
//! depth rule and rescaling to any working scale. The WGSL is beside this file; the CPU
//! mirror below reads like it.

use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// One level of the depth pyramid: `[select, min, max]` per texel, row-major (or of the
/// moments pyramid: `[valid fraction, mean, variance]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PyramidLevel {
    pub size: [u32; 2],
    pub texels: Vec<[f32; 3]>,
}

impl PyramidLevel {
    pub(crate) fn at(&self, p: [i32; 2]) -> [f32; 3] {
        self.texels[(p[1] * self.size[0] as i32 + p[0]) as usize]
    }
}

/// The depth pyramid of a prepared buffer (`size` pixels); mirrors passes/pyramid/pyramid.wgsl.
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
/// passes/pyramid/moments.wgsl. Level `k` of the result is level `k + 1` (texture mip `k`), texels
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

/// Depth downsampling 2×2 → 1 of prepared level `level − 1` (`size` pixels) into level
/// `level` by `rule`, recentring the pick when `recentre`; mirrors passes/pyramid/downsample.wgsl.
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
/// mirrors `pick_child` in passes/pyramid/downsample_rule.wgsl.
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
/// in passes/pyramid/downsample_rule.wgsl.
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
/// ray through `centre`; mirrors `recentred_to` in passes/common.wgsl.
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
/// passes/pyramid/rescale.wgsl. Returns `work.size` texels.
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

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
}

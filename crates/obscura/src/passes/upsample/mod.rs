//! Depth-aware upsampling of low-resolution AO (nearest, bilinear, bilateral, classified,
//! and the scaled grid's). The WGSL is beside this file; the CPU mirror below reads like it.

use crate::passes::prepare::centre;
use crate::passes::pyramid::PyramidLevel;
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

/// Upsampling of low-resolution AO (`low_size`, with its prepared buffer) to the full
/// resolution of `f` (whose `up_factor` relates them), given the full-resolution `prepared`
/// buffer (normals used by the bilateral upsampler only); mirrors passes/upsample/upsample*.wgsl.
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

/// Bent normals through the upsampler (passes/upsample/upsample_bent.wgsl): with [`upsample`]'s
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
/// at `f.scale`; mirrors passes/upsample/upsample_scaled.wgsl.
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
    use crate::passes::constants::DEPTH_RANGE_TOLERANCE;
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

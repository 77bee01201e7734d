//! Ray-traced ground-truth ambient occlusion over the scene's triangles:
//! `AO(p) = 1 − (1/π) ∫_Ω W(t(ω)) (n·ω) dω`, with `t(ω)` the distance to the first hit
//! along ω and `W(t) = 1` for `t < R` (binary visibility within the radius, the usual
//! definition) or `W(t) = 1 − t²/R²` (HBAO's falloff), 0 beyond R. Cosine-weighted
//! directions (Malley's method) from a stratified 2D point set with a per-pixel random
//! rotation (Cranley–Patterson), so the estimate's standard error can be reported.

use crate::bvh::Bvh;
use glam::{Mat4, Vec3};
use obscura_scene::{Camera, CameraProjection};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// How a hit at distance t < R occludes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Falloff {
    /// Any hit within R occludes fully.
    None,
    /// A hit at t occludes by `1 − t²/R²` (HBAO's weight).
    Quadratic,
}

/// Where a pixel's primary rays go.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelSampling {
    /// Through the pixel centre, where a single-sampled rasterizer samples depth.
    #[default]
    Centre,
    /// Through the four sample positions of 4× MSAA (the standard sample locations of
    /// Vulkan and Direct3D), a quarter of the rays each; the pixel's AO is their mean,
    /// unoccluded (1) for samples that see sky: the AO a 4× MSAA image resolves to.
    Msaa4,
}

/// The standard 4× MSAA sample positions within a pixel (Vulkan's standard sample
/// locations, also Direct3D's), x right and y down from the pixel's top-left corner.
pub const MSAA4_POSITIONS: [[f32; 2]; 4] = [
    [0.375, 0.125],
    [0.875, 0.375],
    [0.125, 0.625],
    [0.625, 0.875],
];

/// Parameters of the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    /// AO radius in scene units.
    pub radius: f32,
    /// Rays per pixel.
    pub rays: u32,
    pub falloff: Falloff,
    pub sampling: PixelSampling,
}

/// The reference image of one view.
#[derive(Clone, Debug)]
pub struct ReferenceAo {
    pub width: u32,
    pub height: u32,
    /// AO per pixel, 1 = unoccluded; 1 on sky.
    pub ao: Vec<f32>,
    /// Linear view depth per pixel, 0 on sky.
    pub depth: Vec<f32>,
    /// Bent normal per pixel: the mean direction of the unoccluded rays (cosine-weighted
    /// rays, so the cosine-weighted mean of the unoccluded directions), view space, unit;
    /// zero on sky and where every ray is occluded.
    pub bent: Vec<[f32; 3]>,
    /// Mean over surface pixels of each pixel's standard error.
    pub mean_std_error: f32,
}

/// An orthonormal basis around unit `n` (Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited").
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let s = 1.0f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

fn radical_inverse(mut i: u32) -> f32 {
    i = i.reverse_bits();
    i as f32 * (1.0 / 4294967296.0)
}

fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// AO at surface point `p` with unit normal `n`, and the standard error of the estimate.
/// `seed` decorrelates the sample rotation between pixels.
pub fn ao_at(bvh: &Bvh, p: Vec3, n: Vec3, s: &TraceSettings, seed: u32) -> (f32, f32) {
    let (ao, se, _) = ao_bent_at(bvh, p, n, s, seed);
    (ao, se)
}

/// [`ao_at`] and the sum of the ray directions weighted by their visibility (1 − their
/// occlusion), whose direction is the bent normal (zero when every ray is occluded).
pub fn ao_bent_at(bvh: &Bvh, p: Vec3, n: Vec3, s: &TraceSettings, seed: u32) -> (f32, f32, Vec3) {
    let (t, b) = basis(n);
    let rot = (
        hash(seed) as f32 / 4294967296.0,
        hash(seed ^ 0x9e37_79b9) as f32 / 4294967296.0,
    );
    // Offset the origin off the surface, relative to the radius and to float precision
    // at this distance from the origin.
    let origin = p + n * (1e-4 * s.radius + 4.0 * f32::EPSILON * p.abs().max_element());
    let inv_r2 = 1.0 / (s.radius * s.radius);
    let (mut sum, mut sum2, mut bent) = (0.0f64, 0.0f64, Vec3::ZERO);
    for i in 0..s.rays {
        let u1 = ((i as f32 + 0.5) / s.rays as f32 + rot.0).fract();
        let u2 = (radical_inverse(i) + rot.1).fract();
        let r = u1.sqrt();
        let phi = std::f32::consts::TAU * u2;
        let dir = t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt();
        let occ = match bvh.closest(origin, dir, s.radius) {
            None => 0.0,
            Some((d, _)) => match s.falloff {
                Falloff::None => 1.0,
                Falloff::Quadratic => (1.0 - d * d * inv_r2).max(0.0),
            },
        } as f64;
        sum += occ;
        sum2 += occ * occ;
        bent += dir * (1.0 - occ as f32);
    }
    let n_rays = s.rays as f64;
    let mean = sum / n_rays;
    let var = (sum2 / n_rays - mean * mean).max(0.0);
    ((1.0 - mean) as f32, (var / n_rays).sqrt() as f32, bent)
}

/// One traced row: AO, depth, standard error (−1 on sky) and bent normal per pixel.
type Row = (Vec<f32>, Vec<f32>, Vec<f32>, Vec<[f32; 3]>);

/// Traces AO for every pixel of `camera`'s view at `width` × `height`, with primary rays
/// through pixel centres (the rasterizer's sampling points) or the 4× MSAA sample
/// positions ([`TraceSettings::sampling`]). The depth of a pixel is its centre's, or the
/// mean of its samples that see a surface. `progress(done_rows, rows)` is called as rows
/// finish.
pub fn trace_view(
    bvh: &Bvh,
    camera: &Camera,
    width: u32,
    height: u32,
    s: &TraceSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> ReferenceAo {
    let aspect = width as f32 / height as f32;
    let scale = camera.obscura_projection(aspect).ndc_to_view_scale();
    let view_to_world: Mat4 = camera.view_matrix().inverse();
    let world_to_view = camera.view_matrix();
    let ortho = matches!(camera.projection, CameraProjection::Orthographic { .. });
    let done = AtomicUsize::new(0);
    let rows: Vec<Row> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut ao = vec![1.0; width as usize];
            let mut depth = vec![0.0; width as usize];
            let mut err = vec![-1.0; width as usize];
            let mut bent = vec![[0.0; 3]; width as usize];
            let to_view = |b: Vec3| {
                world_to_view
                    .transform_vector3(b)
                    .normalize_or_zero()
                    .to_array()
            };
            // The surface point, normal and view depth through pixel position `at`.
            let primary = |at: [f32; 2]| {
                let ndc = [
                    at[0] / width as f32 * 2.0 - 1.0,
                    1.0 - at[1] / height as f32 * 2.0,
                ];
                let (o_view, d_view) = if ortho {
                    (
                        Vec3::new(ndc[0] * scale[0], ndc[1] * scale[1], 0.0),
                        Vec3::NEG_Z,
                    )
                } else {
                    (
                        Vec3::ZERO,
                        Vec3::new(ndc[0] * scale[0], ndc[1] * scale[1], -1.0),
                    )
                };
                let o = view_to_world.transform_point3(o_view);
                let d = view_to_world.transform_vector3(d_view);
                let (t, tri) = bvh.closest(o, d, f32::INFINITY)?;
                let p = o + d * t;
                let view_depth = -world_to_view.transform_point3(p).z;
                if view_depth < camera.near || view_depth > camera.far {
                    return None; // clipped by the rasterizer too
                }
                let mut n = bvh.normal(tri).normalize_or_zero();
                if n.dot(d) > 0.0 {
                    n = -n;
                }
                Some((p, n, view_depth))
            };
            for x in 0..width {
                let seed = y * width + x;
                let (cx, cy) = (x as f32, y as f32);
                match s.sampling {
                    PixelSampling::Centre => {
                        let Some((p, n, view_depth)) = primary([cx + 0.5, cy + 0.5]) else {
                            continue;
                        };
                        let (a, e, b) = ao_bent_at(bvh, p, n, s, seed);
                        ao[x as usize] = a;
                        depth[x as usize] = view_depth;
                        err[x as usize] = e;
                        bent[x as usize] = to_view(b);
                    }
                    PixelSampling::Msaa4 => {
                        let quarter = TraceSettings {
                            rays: (s.rays / 4).max(1),
                            ..*s
                        };
                        let (mut sum, mut var, mut dsum, mut hits) = (0.0, 0.0, 0.0, 0);
                        let mut bsum = Vec3::ZERO;
                        for (i, at) in MSAA4_POSITIONS.iter().enumerate() {
                            let Some((p, n, view_depth)) = primary([cx + at[0], cy + at[1]]) else {
                                sum += 1.0;
                                continue;
                            };
                            let (a, e, b) =
                                ao_bent_at(bvh, p, n, &quarter, seed.wrapping_mul(4) + i as u32);
                            sum += a;
                            bsum += b;
                            var += e * e;
                            dsum += view_depth;
                            hits += 1;
                        }
                        if hits > 0 {
                            ao[x as usize] = sum / 4.0;
                            depth[x as usize] = dsum / hits as f32;
                            err[x as usize] = var.sqrt() / 4.0;
                            bent[x as usize] = to_view(bsum);
                        }
                    }
                }
            }
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(k, height as usize);
            (ao, depth, err, bent)
        })
        .collect();
    let mut out = ReferenceAo {
        width,
        height,
        ao: Vec::with_capacity((width * height) as usize),
        depth: Vec::with_capacity((width * height) as usize),
        bent: Vec::with_capacity((width * height) as usize),
        mean_std_error: 0.0,
    };
    let (mut se, mut n) = (0.0f64, 0usize);
    for (a, d, e, b) in rows {
        out.ao.extend(a);
        out.depth.extend(d);
        out.bent.extend(b);
        for v in e.into_iter().filter(|v| *v >= 0.0) {
            se += v as f64;
            n += 1;
        }
    }
    out.mean_std_error = if n == 0 { 0.0 } else { (se / n as f64) as f32 };
    out
}

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

/// The rays of a surface point `p` with unit normal `n`: the origin, raised off the
/// surface relative to the radius and to float precision at this distance from the world
/// origin, and `s.rays` cosine-weighted directions (Malley's method over a stratified 2D
/// set, rotated per `seed`, Cranley–Patterson).
fn hemisphere_rays(
    p: Vec3,
    n: Vec3,
    s: &TraceSettings,
    seed: u32,
) -> (Vec3, impl Iterator<Item = Vec3>) {
    let (t, b) = basis(n);
    let rot = (
        hash(seed) as f32 / 4294967296.0,
        hash(seed ^ 0x9e37_79b9) as f32 / 4294967296.0,
    );
    let origin = p + n * (1e-4 * s.radius + 4.0 * f32::EPSILON * p.abs().max_element());
    let rays = s.rays;
    let dirs = (0..rays).map(move |i| {
        let u1 = ((i as f32 + 0.5) / rays as f32 + rot.0).fract();
        let u2 = (radical_inverse(i) + rot.1).fract();
        let r = u1.sqrt();
        let phi = std::f32::consts::TAU * u2;
        t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt()
    });
    (origin, dirs)
}

/// [`ao_at`] and the sum of the ray directions weighted by their visibility (1 − their
/// occlusion), whose direction is the bent normal (zero when every ray is occluded).
pub fn ao_bent_at(bvh: &Bvh, p: Vec3, n: Vec3, s: &TraceSettings, seed: u32) -> (f32, f32, Vec3) {
    let (origin, dirs) = hemisphere_rays(p, n, s, seed);
    let inv_r2 = 1.0 / (s.radius * s.radius);
    let (mut sum, mut sum2, mut bent) = (0.0f64, 0.0f64, Vec3::ZERO);
    for dir in dirs {
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

/// A primary ray's hit: the surface point and its normal (world space, facing the
/// camera), its linear view depth and the hit triangle as [`Bvh::closest`] numbers it.
#[derive(Clone, Copy, Debug)]
pub struct PrimaryHit {
    pub point: Vec3,
    pub normal: Vec3,
    pub view_depth: f32,
    pub triangle: u32,
}

/// Primary rays of a camera at a resolution, as the rasterizer samples them.
#[derive(Clone, Copy, Debug)]
pub struct Primary {
    width: u32,
    height: u32,
    scale: [f32; 2],
    ortho: bool,
    view_to_world: Mat4,
    world_to_view: Mat4,
    near: f32,
    far: f32,
}

impl Primary {
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let aspect = width as f32 / height as f32;
        Self {
            width,
            height,
            scale: camera.obscura_projection(aspect).ndc_to_view_scale(),
            ortho: matches!(camera.projection, CameraProjection::Orthographic { .. }),
            view_to_world: camera.view_matrix().inverse(),
            world_to_view: camera.view_matrix(),
            near: camera.near,
            far: camera.far,
        }
    }

    /// The world-space ray through pixel position `at` (pixels, y down): origin and a
    /// direction whose distance `t` along it is the linear view depth (the view ray's z
    /// component is −1).
    pub fn ray(&self, at: [f32; 2]) -> (Vec3, Vec3) {
        let ndc = [
            at[0] / self.width as f32 * 2.0 - 1.0,
            1.0 - at[1] / self.height as f32 * 2.0,
        ];
        let xy = Vec3::new(ndc[0] * self.scale[0], ndc[1] * self.scale[1], 0.0);
        let (o_view, d_view) = if self.ortho {
            (xy, Vec3::NEG_Z)
        } else {
            (Vec3::ZERO, xy + Vec3::NEG_Z)
        };
        (
            self.view_to_world.transform_point3(o_view),
            self.view_to_world.transform_vector3(d_view),
        )
    }

    /// A world-space direction in view space.
    pub fn to_view(&self, v: Vec3) -> Vec3 {
        self.world_to_view.transform_vector3(v)
    }

    /// The near and far clip distances (linear view depth).
    pub fn clip(&self) -> (f32, f32) {
        (self.near, self.far)
    }

    /// The surface through pixel position `at` (pixels, y down), if any within the clip
    /// range.
    pub fn hit(&self, bvh: &Bvh, at: [f32; 2]) -> Option<PrimaryHit> {
        let (o, d) = self.ray(at);
        let (t, triangle) = bvh.closest(o, d, f32::INFINITY)?;
        let point = o + d * t;
        let view_depth = -self.world_to_view.transform_point3(point).z;
        if view_depth < self.near || view_depth > self.far {
            return None; // clipped by the rasterizer too
        }
        let mut normal = bvh.normal(triangle).normalize_or_zero();
        if normal.dot(d) > 0.0 {
            normal = -normal;
        }
        Some(PrimaryHit {
            point,
            normal,
            view_depth,
            triangle,
        })
    }
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
    let primary = Primary::new(camera, width, height);
    let world_to_view = camera.view_matrix();
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
            let primary = |at: [f32; 2]| {
                primary
                    .hit(bvh, at)
                    .map(|h| (h.point, h.normal, h.view_depth))
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

/// The reference of screen-space directional occlusion ([`obscura::Ssdo`]) for one view:
/// outgoing diffuse radiance per pixel, linear rgb.
#[derive(Clone, Debug)]
pub struct ReferenceSsdo {
    pub width: u32,
    pub height: u32,
    /// `albedo · E`, 0 on sky.
    pub radiance: Vec<[f32; 3]>,
    /// The pixel's albedo, 0 on sky.
    pub albedo: Vec<[f32; 3]>,
    /// Linear view depth, 0 on sky.
    pub depth: Vec<f32>,
}

/// Radiance at surface point `p` (normal `n`, albedo `albedo`) lit by `env` within
/// `s.radius` and one diffuse bounce: cosine-weighted rays (as [`ao_bent_at`]); a ray with
/// no hit within the radius brings the environment's radiance along it (visibility within
/// the radius, as the AO reference defines it); a ray that hits brings the hit surface's
/// albedo times the environment's irradiance at its normal (facing the ray), unshadowed:
/// the same single bounce [`obscura::Ssdo`] models. Returns `albedo · E`.
#[allow(clippy::too_many_arguments)]
pub fn ssdo_at(
    bvh: &Bvh,
    triangle_albedo: &[[f32; 3]],
    env: &obscura::Environment,
    irradiance: &obscura::IrradianceSh,
    p: Vec3,
    n: Vec3,
    albedo: Vec3,
    s: &TraceSettings,
    seed: u32,
) -> Vec3 {
    let (origin, dirs) = hemisphere_rays(p, n, s, seed);
    let mut e = Vec3::ZERO;
    for dir in dirs {
        e += match bvh.closest(origin, dir, s.radius) {
            None => Vec3::from(env.radiance(dir.to_array())),
            Some((_, tri)) => {
                let mut hn = bvh.normal(tri).normalize_or_zero();
                if hn.dot(dir) > 0.0 {
                    hn = -hn;
                }
                let a = triangle_albedo
                    .get(bvh.original_index(tri) as usize)
                    .copied()
                    .unwrap_or(obscura_scene::DEFAULT_ALBEDO);
                Vec3::from(a) * Vec3::from(irradiance.eval(hn.to_array()))
            }
        };
    }
    albedo * e / s.rays as f32
}

/// Traces [`ssdo_at`] for every pixel centre of `camera`'s view at `width` × `height`.
/// `triangle_albedo` is per triangle in the order given to [`Bvh::new`]; `lighting` is the
/// environment and its [`obscura::Environment::irradiance_sh`], computed once by the
/// caller (a map's projection visits every texel).
pub fn trace_ssdo_view(
    bvh: &Bvh,
    triangle_albedo: &[[f32; 3]],
    lighting: (&obscura::Environment, &obscura::IrradianceSh),
    camera: &Camera,
    (width, height): (u32, u32),
    s: &TraceSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> ReferenceSsdo {
    let primary = Primary::new(camera, width, height);
    let (env, irradiance) = lighting;
    let done = AtomicUsize::new(0);
    type SsdoRow = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<f32>);
    let rows: Vec<SsdoRow> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut radiance = vec![[0.0; 3]; width as usize];
            let mut albedo = vec![[0.0; 3]; width as usize];
            let mut depth = vec![0.0; width as usize];
            for x in 0..width {
                let Some(h) = primary.hit(bvh, [x as f32 + 0.5, y as f32 + 0.5]) else {
                    continue;
                };
                let a = triangle_albedo
                    .get(bvh.original_index(h.triangle) as usize)
                    .copied()
                    .unwrap_or(obscura_scene::DEFAULT_ALBEDO);
                let l = ssdo_at(
                    bvh,
                    triangle_albedo,
                    env,
                    irradiance,
                    h.point,
                    h.normal,
                    Vec3::from(a),
                    s,
                    y * width + x,
                );
                radiance[x as usize] = l.to_array();
                albedo[x as usize] = a;
                depth[x as usize] = h.view_depth;
            }
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(k, height as usize);
            (radiance, albedo, depth)
        })
        .collect();
    let mut out = ReferenceSsdo {
        width,
        height,
        radiance: Vec::with_capacity((width * height) as usize),
        albedo: Vec::with_capacity((width * height) as usize),
        depth: Vec::with_capacity((width * height) as usize),
    };
    for (r, a, d) in rows {
        out.radiance.extend(r);
        out.albedo.extend(a);
        out.depth.extend(d);
    }
    out
}

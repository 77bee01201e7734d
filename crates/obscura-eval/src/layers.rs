//! Renderer layers as a ray tracer finds them, and the visibility-bitmask estimator's
//! screen-space limit with each: what one layer with a thickness prior, back-face
//! thickness, a second layer and a guard band allow before any GPU pass is built for them.
//!
//! Along each pixel's primary ray: layer 1's front is the first surface (the G-buffer's);
//! its back, the nearest back face behind it (a renderer's back-face depth pass, read
//! behind the front); layer 2's front, the nearest front face behind layer 1's solid (its
//! back, at most the prior behind its front: depth peeling with a minimum separation,
//! Mara, McGuire, Nowrouzezahrai & Luebke 2016); layer 2's back likewise. A single-sided
//! surface (a floor, an open roof) has no back face of its own: the nearest one behind it
//! may be another object's, which is why each back is bounded by the prior.

use crate::bvh::Bvh;
use crate::trace::Primary;
use glam::{Vec3, Vec4};
use obscura::jitter::{pattern_index, PATTERN_DIM};
use obscura::reference::{bitmask_pixel_solids, Pixels, Solids};
use obscura::uniforms::FrameUniforms;
use obscura::{AoMode, AoOptions, AoParams, Denoise, Estimator, NormalEncoding, Viewport};
use obscura_scene::Camera;
use rayon::prelude::*;

/// Hits followed along one primary ray at most.
const MAX_HITS: usize = 8;

/// The layers of a view and of a guard band around it.
#[derive(Clone, Debug)]
pub struct DeepLayers {
    /// The view's size and the band on each side; the vectors cover the view and band.
    pub width: u32,
    pub height: u32,
    pub guard: u32,
    /// Per pixel `[front 1, back 1, front 2, back 2, front 2', back 2']`, linear view depth,
    /// 0 = none: layer 2 peeled behind layer 1's solid as bounded by its back face, and
    /// layer 2' peeled at the prior behind layer 1's front (a renderer without back faces).
    pub depth: Vec<[f32; 6]>,
    /// Layer 1's view-space normal, facing the camera (zero where there is no surface).
    pub normal: Vec<Vec3>,
}

/// Ray-traces the layers of `camera`'s `width` × `height` view and `guard` pixels around it
/// (the view widened as `Camera::widened` does), with `prior` (linear depth units) as layer
/// 2's separation where layer 1 has no back face.
pub fn deep_layers(
    bvh: &Bvh,
    camera: &Camera,
    (width, height): (u32, u32),
    guard: u32,
    prior: f32,
) -> DeepLayers {
    let (bw, bh) = (width + 2 * guard, height + 2 * guard);
    let primary = Primary::new(&camera.widened(height, guard), bw, bh);
    let (near, far) = primary.clip();
    let rows: Vec<Vec<([f32; 6], Vec3)>> = parallel_rows(bh, |y| {
        (0..bw)
            .map(|x| {
                let (o, d) = primary.ray([x as f32 + 0.5, y as f32 + 0.5]);
                // (t, front-facing, world normal) of the hits, nearest first.
                let mut hits: Vec<(f32, bool, Vec3)> = Vec::new();
                let mut t0 = 0.0f32;
                while hits.len() < MAX_HITS {
                    let start = o + d * t0;
                    let Some((t, tri)) = bvh.closest(start, d, f32::INFINITY) else {
                        break;
                    };
                    let t = t0 + t;
                    let n = bvh.normal(tri).normalize_or_zero();
                    hits.push((t, n.dot(d) < 0.0, n));
                    t0 = t + 1e-4 * t.max(1e-3);
                }
                let Some(&(t1, front1, n1)) = hits.first().filter(|h| h.0 >= near && h.0 <= far)
                else {
                    return ([0.0; 6], Vec3::ZERO);
                };
                let after = |t: f32, front: bool| {
                    hits.iter().find(|h| h.0 > t && h.1 == front).map(|h| h.0)
                };
                // A back face seen first (a single-sided surface from behind) has no back.
                let b1 = if front1 { after(t1, false) } else { None };
                // Layer 1's solid ends at its back face, at most the prior behind it.
                let separation = b1.map_or(prior, |b| (b - t1).min(prior));
                let f2 = after(t1 + separation, true);
                let b2 = f2.and_then(|f| after(f, false));
                // Without back faces a renderer peels at the prior.
                let f2p = after(t1 + prior, true);
                let b2p = f2p.and_then(|f| after(f, false));
                let n = primary.to_view(if n1.dot(d) > 0.0 { -n1 } else { n1 });
                let z = |t: Option<f32>| t.filter(|&t| t <= far).unwrap_or(0.0);
                let depths = [t1, z(b1), z(f2), z(b2), z(f2p), z(b2p)];
                (depths, n.normalize_or_zero())
            })
            .collect()
    });
    let (depth, normal) = rows.into_iter().flatten().unzip();
    DeepLayers {
        width,
        height,
        guard,
        depth,
        normal,
    }
}

/// What the solids behind a pixel are, by representation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Representation {
    /// One layer, infinitely thick (GTAO's assumption).
    Infinite,
    /// One layer, each surface `prior` deep.
    Prior,
    /// One layer, as deep as its back face where there is one, at most `prior` ("back
    /// faces" in labels: bounded by the prior).
    BackFaces,
    /// Two layers, each `prior` deep (a renderer with a second layer but no back faces).
    TwoLayersPrior,
    /// Two layers, each as deep as its back face, at most `prior`.
    TwoLayers,
}

impl Representation {
    pub const ALL: [Representation; 5] = [
        Representation::Infinite,
        Representation::Prior,
        Representation::BackFaces,
        Representation::TwoLayersPrior,
        Representation::TwoLayers,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Representation::Infinite => "1 layer infinite",
            Representation::Prior => "1 layer prior",
            Representation::BackFaces => "1 layer back faces",
            Representation::TwoLayersPrior => "2 layers prior",
            Representation::TwoLayers => "2 layers back faces",
        }
    }

    /// The solids of a pixel's layers `l` ([`DeepLayers::depth`]) for a prior of `prior`
    /// depth units.
    pub fn solids(self, l: [f32; 6], prior: f32) -> Solids {
        if l[0] <= 0.0 {
            return [None, None];
        }
        let bounded = |front: f32, back: f32| {
            if back > front {
                back.min(front + prior)
            } else {
                front + prior
            }
        };
        match self {
            Representation::Infinite => [Some((l[0], f32::INFINITY)), None],
            Representation::Prior => [Some((l[0], l[0] + prior)), None],
            Representation::BackFaces => [Some((l[0], bounded(l[0], l[1]))), None],
            Representation::TwoLayersPrior => [
                Some((l[0], l[0] + prior)),
                (l[4] > 0.0).then(|| (l[4], l[4] + prior)),
            ],
            Representation::TwoLayers => [
                Some((l[0], bounded(l[0], l[1]))),
                (l[2] > 0.0).then(|| (l[2], bounded(l[2], l[3]))),
            ],
        }
    }
}

/// The bitmask estimator's screen-space integral (`directions` × `steps`; the CPU mirror's
/// arithmetic) over the view, reading the layers as `rep` says and the band when `guarded`
/// (else the view alone, as without a guard band). Without `jitter` every pixel samples the
/// same directions; with it each takes the randomized layout's pattern of its 4 × 4 class
/// (what the GPU estimator at these counts gives before a denoiser). `thickness`: the
/// prior, times `radius`. The view's AO, row-major.
pub fn layer_limit(
    layers: &DeepLayers,
    camera: &Camera,
    (radius, thickness): (f32, f32),
    (directions, steps, jitter): (u32, u32, bool),
    rep: Representation,
    guarded: bool,
) -> obscura::Result<Vec<f32>> {
    let (w, h, g) = (layers.width, layers.height, layers.guard);
    let bw = w + 2 * g;
    // The processed rectangle in the layers' pixels: the band and view, or the view.
    let (pg, x0) = if guarded { (g, 0) } else { (0, g) };
    let (pw, ph) = (w + 2 * pg, h + 2 * pg);
    let at = |x: u32, y: u32| ((y + x0) * bw + x + x0) as usize;
    let prepared: Vec<Vec4> = (0..ph)
        .flat_map(|y| (0..pw).map(move |x| (x, y)))
        .map(|(x, y)| {
            let i = at(x, y);
            let n = layers.normal[i];
            Vec4::new(layers.depth[i][0], n.x, n.y, n.z)
        })
        .collect();
    let options = AoOptions {
        estimator: Estimator::Bitmask,
        directions,
        steps,
        mode: AoMode::Randomized,
        jitter,
        denoise: Denoise::None,
        ..AoOptions::default()
    };
    let params = AoParams {
        radius,
        thickness,
        ..AoParams::default()
    };
    let viewport = Viewport {
        x: pg,
        y: pg,
        width: w,
        height: h,
    };
    let f = FrameUniforms::new(
        &camera.obscura_projection(w as f32 / h as f32),
        obscura::DepthConvention::LinearView,
        Some(NormalEncoding::ViewSigned),
        (viewport, pg),
        &options,
        &params,
    )?;
    let px = Pixels {
        f: &f,
        directions,
        steps,
        march_exponent: 1.0,
        prepared: &prepared,
        lattice: 1,
        pyramid: &[],
        moments: &[],
        second: &[],
    };
    let prior = thickness * radius;
    let solids = |q: [i32; 2]| -> Solids {
        if q[0] < 0 || q[1] < 0 || q[0] >= pw as i32 || q[1] >= ph as i32 {
            return [None, None];
        }
        rep.solids(layers.depth[at(q[0] as u32, q[1] as u32)], prior)
    };
    let rows = parallel_rows(h, |y| {
        (0..w)
            .map(|x| {
                let p = [(x + pg) as i32, (y + pg) as i32];
                let pattern = f.patterns[pattern_index(x + pg, y + pg, PATTERN_DIM)];
                bitmask_pixel_solids(&px, p, pattern, solids).0
            })
            .collect::<Vec<f32>>()
    });
    Ok(rows.into_iter().flatten().collect())
}

/// `row(y)` for every row, in order, on every core (rayon, as the ray tracer).
fn parallel_rows<T: Send>(rows: u32, row: impl Fn(u32) -> T + Sync + Send) -> Vec<T> {
    (0..rows).into_par_iter().map(row).collect()
}

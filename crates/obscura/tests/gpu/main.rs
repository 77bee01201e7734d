//! GPU tests on synthetic depth buffers: the GPU passes against the CPU reference, and
//! analytic cases with known answers. Runs on lavapipe in CI. One binary and one device for
//! every GPU test (the AO passes here; the shading, temporal, shader-source and WebGPU-limit
//! tests in the modules below), but the lost-device test, which destroys its own.

use glam::{Vec3, Vec4};
use obscura::{
    layout, reference, Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, DepthConvention,
    DepthDownsample, Error, Estimator, GpuContext, Projection, PyramidBuild, Resolution,
    ResourceCount, Timing, Upsampler, Viewport,
};
use std::sync::{OnceLock, RwLock};

#[path = "../common/analytic.rs"]
mod analytic;
mod api;
mod bent;
mod bitmask;
mod closed_forms;
#[path = "../common/mod.rs"]
mod common;
mod denoise;
mod guard;
mod lights;
mod modes;
mod noise;
mod prepare;
mod resolution;
mod shaders;
mod ssdo;
mod surfaces;
mod temporal;
mod web_frame;
mod webgpu_limits;
use analytic::assert_matches_mirror;
use common::linear_input;

pub(crate) fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| common::context(None))
}

static LOCK: RwLock<()> = RwLock::new(());

/// The device is shared and tests run side by side (wgpu's error scopes are per thread, and
/// every test makes its own `Ao`s and buffers); a test that counts the device's live
/// objects runs alone ([`lock_alone`]).
pub(crate) fn lock() -> std::sync::RwLockReadGuard<'static, ()> {
    LOCK.read().unwrap_or_else(|p| p.into_inner())
}

/// No other test on the device while the guard lives.
fn lock_alone() -> std::sync::RwLockWriteGuard<'static, ()> {
    LOCK.write().unwrap_or_else(|p| p.into_inner())
}

const W: u32 = 67;
const H: u32 = 45;

fn persp(w: u32, h: u32) -> Projection {
    Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: w as f32 / h as f32,
        near: 0.1,
        far: 100.0,
    }
}

fn upload_r32(data: &[f32], w: u32, h: u32) -> wgpu::Texture {
    common::upload_r32(ctx(), data, w, h)
}

struct Run {
    prepared: Vec<Vec4>,
    /// The depth pyramid's levels (`[select, min, max]` per texel), when the estimator has one.
    pyramid: Vec<Vec<[f32; 3]>>,
    /// The depth moments levels (`[fraction, mean, variance]`), for VO's area integral.
    moments: Vec<Vec<[f32; 3]>>,
    /// The prepared buffer downsampled 1, 2, … times (below full resolution).
    levels: Vec<Vec<Vec4>>,
    /// The AO at working resolution before upsampling (when there is one).
    work_ao: Vec<f32>,
    /// The prepared buffer at the frame's scale (`Resolution::Scaled`; its texture is
    /// full-size, the working grid its top-left corner), else empty.
    scaled: Vec<Vec4>,
    /// Full-resolution linear depth written by the fused downsampling prepare (below full
    /// resolution), else empty.
    linear_depth: Vec<f32>,
    ao: Vec<f32>,
    /// The bent normals (full resolution, or working below it with box/tent), when on, and
    /// the AO pass's own when a later pass takes them.
    bent: Vec<Vec3>,
    bent_raw: Vec<Vec3>,
    frame: obscura::uniforms::FrameUniforms,
}

/// [`run_ao`] on linear view depth over the whole texture.
fn run_linear(
    raw: &[f32],
    w: u32,
    h: u32,
    projection: Projection,
    options: AoOptions,
    params: &AoParams,
) -> Run {
    run_ao(
        raw,
        w,
        h,
        projection,
        DepthConvention::LinearView,
        None,
        options,
        params,
    )
}

#[allow(
    clippy::too_many_arguments,
    reason = "a test helper whose call sites read best with every input spelled out"
)]
fn run_ao(
    raw: &[f32],
    w: u32,
    h: u32,
    projection: Projection,
    convention: DepthConvention,
    viewport: Option<Viewport>,
    options: AoOptions,
    params: &AoParams,
) -> Run {
    let c = ctx();
    let tex = upload_r32(raw, w, h);
    let view = tex.create_view(&Default::default());
    let mut ao = Ao::new(&c.device, options).unwrap();
    let input = AoInput {
        depth: &view,
        convention,
        projection,
        normals: None,
        viewport,
        guard_band: 0,
        second_layer: None,
        output: None,
    };
    let frame = ao.validate(&input, params).unwrap();
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, params))
        .unwrap();
    // Fused deinterleaved modes have no full-resolution prepared buffer.
    let prepared: Vec<f32> = match ao.prepared_view() {
        Some(v) => c.read_f32(v.texture()).unwrap(),
        None => Vec::new(),
    };
    let mips = |t: &wgpu::Texture| -> Vec<Vec<[f32; 3]>> {
        (0..t.mip_level_count())
            .map(|m| {
                let texels: Vec<f32> =
                    bytemuck::pod_collect_to_vec(&c.read_texture_mip(t, m).unwrap());
                texels.chunks_exact(4).map(|v| [v[0], v[1], v[2]]).collect()
            })
            .collect()
    };
    let pyramid = ao.pyramid().map_or(Vec::new(), mips);
    let moments = ao.moments().map_or(Vec::new(), mips);
    let vec4s = |v: Vec<f32>| -> Vec<Vec4> { v.chunks_exact(4).map(Vec4::from_slice).collect() };
    let levels = (1..)
        .map_while(|k| ao.prepared_level(k))
        .map(|t| vec4s(c.read_f32(t).unwrap()))
        .collect();
    let work_ao = ao
        .working_ao()
        .map_or(Vec::new(), |t| c.read_f32(t).unwrap());
    let scaled = ao
        .scaled_prepared()
        .map_or(Vec::new(), |t| vec4s(c.read_f32(t).unwrap()));
    let linear_depth = ao
        .linear_depth()
        .map_or(Vec::new(), |t| c.read_f32(t).unwrap());
    let vectors = |t: Option<&wgpu::Texture>| -> Vec<Vec3> {
        t.map_or(Vec::new(), |t| {
            vec4s(c.read_f32(t).unwrap())
                .into_iter()
                .map(|v| v.truncate())
                .collect()
        })
    };
    Run {
        bent: vectors(ao.bent_normals()),
        bent_raw: vectors(ao.bent_normals_raw()),
        prepared: vec4s(prepared),
        pyramid,
        moments,
        levels,
        work_ao,
        scaled,
        linear_depth,
        ao: c.read_f32(ao.output().unwrap()).unwrap(),
        frame,
    }
}

const MAX_DEPTH: f32 = 10.0;

/// Linear depth of the first hit of the pixel-centre ray with any of `planes`
/// (`(point, normal)`) and `spheres` (`(centre, radius)`), 0 when nothing is hit.
fn ray_cast(
    projection: &Projection,
    w: u32,
    h: u32,
    planes: &[(Vec3, Vec3)],
    spheres: &[(Vec3, f32)],
) -> Vec<f32> {
    let s = projection.ndc_to_view_scale();
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let ndc = [
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            ];
            // Perspective: rays from the origin through (ndc*s, -1); orthographic: parallel.
            let (o, d) = if projection.is_perspective() {
                (Vec3::ZERO, Vec3::new(ndc[0] * s[0], ndc[1] * s[1], -1.0))
            } else {
                (Vec3::new(ndc[0] * s[0], ndc[1] * s[1], 0.0), Vec3::NEG_Z)
            };
            let mut best = f32::INFINITY;
            for &(p, n) in planes {
                let t = (p - o).dot(n) / d.dot(n);
                if t > 0.0 {
                    best = best.min(t);
                }
            }
            for &(c, r) in spheres {
                let oc = o - c;
                let b = oc.dot(d);
                let disc = b * b - d.dot(d) * (oc.dot(oc) - r * r);
                if disc >= 0.0 {
                    let t = (-b - disc.sqrt()) / d.dot(d);
                    if t > 0.0 {
                        best = best.min(t);
                    }
                }
            }
            // With d.z = -1, t is the linear depth for perspective; for ortho, too.
            // Beyond MAX_DEPTH is sky.
            let depth = -(o + d * best).z;
            out.push(if depth.is_finite() && depth < MAX_DEPTH {
                depth
            } else {
                0.0
            });
        }
    }
    out
}

/// A floor, a back wall and two spheres: creases, contact, silhouettes, sky.
/// The perspective and orthographic cameras the prepare tests look at the test scene with.
fn test_projections() -> [Projection; 2] {
    [
        persp(W, H),
        Projection::Orthographic {
            half_width: 3.0 * W as f32 / H as f32,
            half_height: 3.0,
            near: 0.1,
            far: 20.0,
        },
    ]
}

fn test_scene(projection: &Projection, w: u32, h: u32) -> Vec<f32> {
    ray_cast(
        projection,
        w,
        h,
        &[
            (Vec3::new(0.0, -1.0, 0.0), Vec3::Y),
            (
                Vec3::new(0.0, 0.0, -7.0),
                Vec3::new(0.6, 0.6, 1.0).normalize(),
            ),
        ],
        &[
            (Vec3::new(-0.6, -0.4, -4.0), 0.6),
            (Vec3::new(0.9, 0.0, -5.0), 0.5),
        ],
    )
}

fn encode(projection: &Projection, conv: DepthConvention, lin: &[f32]) -> Vec<f32> {
    lin.iter()
        .map(|&d| {
            if d > 0.0 {
                projection.encode_depth(conv, d)
            } else {
                match conv {
                    DepthConvention::Standard => 1.0,
                    DepthConvention::LinearView => 0.0,
                    _ => 0.0,
                }
            }
        })
        .collect()
}

trait Yzw {
    fn yzw(&self) -> Vec3;
}
impl Yzw for Vec4 {
    fn yzw(&self) -> Vec3 {
        Vec3::new(self.y, self.z, self.w)
    }
}

/// The randomized single pass, without denoising (the estimator's own output).
fn randomized() -> AoOptions {
    AoOptions {
        mode: AoMode::Randomized,
        denoise: Denoise::None,
        ..Default::default()
    }
}

/// Every estimator in every mode, deinterleaved ones both fused and unfused.
fn all_variants() -> Vec<AoOptions> {
    let mut v = Vec::new();
    for estimator in Estimator::ALL {
        v.push(AoOptions {
            estimator,
            ..randomized()
        });
        for mode in [AoMode::Deinterleaved2, AoMode::Deinterleaved4] {
            for fused in [true, false] {
                v.push(AoOptions {
                    estimator,
                    mode,
                    fused,
                    denoise: Denoise::None,
                    ..Default::default()
                });
            }
        }
    }
    v
}

fn ortho(w: u32, h: u32) -> Projection {
    Projection::Orthographic {
        half_width: 4.0 * w as f32 / h as f32,
        half_height: 4.0,
        near: 0.1,
        far: 20.0,
    }
}

/// Rows of a step edge seen orthographically: depth `near` left of column `edge`, `far` from
/// it on. The far side near the edge is occluded by the near side; the near side is open.
fn step_edge(w: u32, h: u32, edge: u32, near: f32, far: f32) -> Vec<f32> {
    (0..w * h)
        .map(|i| if i % w < edge { near } else { far })
        .collect()
}

/// A caller's AO output: `R32Float`, `w` × `h`, storage and copy-source usage.
fn caller_output(w: u32, h: u32) -> wgpu::Texture {
    ctx().device.create_texture(&wgpu::TextureDescriptor {
        label: Some("caller ao"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The top-left `size` texels of a row-major image `width` texels wide.
fn crop<T: Copy>(v: &[T], width: u32, size: [u32; 2]) -> Vec<T> {
    (0..size[1])
        .flat_map(|y| (0..size[0]).map(move |x| (y * width + x) as usize))
        .map(|i| v[i])
        .collect()
}

/// AO of a plane's linear depth `raw` (radius 0.5) with `depth_noise`, over the valid
/// pixels of `xs` × `ys`: each pixel's prepared normal's angle from `normal` (degrees,
/// sorted; none for layouts without a full-resolution prepared buffer) and its AO
/// (sorted).
fn plane_ao(
    raw: &[f32],
    (w, h): (u32, u32),
    projection: Projection,
    options: AoOptions,
    depth_noise: obscura::DepthNoise,
    (xs, ys): (std::ops::Range<u32>, std::ops::Range<u32>),
    normal: Vec3,
) -> (Vec<f32>, Vec<f32>) {
    let params = AoParams {
        radius: 0.5,
        depth_noise,
        ..Default::default()
    };
    let r = run_linear(raw, w, h, projection, options, &params);
    let pixels: Vec<usize> = ys
        .flat_map(|y| xs.clone().map(move |x| (y * w + x) as usize))
        .filter(|&i| raw[i] > 0.0)
        .collect();
    // Fused deinterleaved layouts keep no full-resolution prepared buffer: no angles.
    let mut angles: Vec<f32> = if r.prepared.is_empty() {
        Vec::new()
    } else {
        pixels
            .iter()
            .map(|&i| r.prepared[i].yzw().angle_between(normal).to_degrees())
            .collect()
    };
    let mut ao: Vec<f32> = pixels.iter().map(|&i| r.ao[i]).collect();
    angles.sort_by(f32::total_cmp);
    ao.sort_by(f32::total_cmp);
    (angles, ao)
}

/// A floor 1.5 below the camera, seen from 1.8 to the far distance (~38° to 80° to the
/// view).
fn floor_depth(projection: &Projection, w: u32, h: u32) -> Vec<f32> {
    ray_cast(
        projection,
        w,
        h,
        &[(Vec3::new(0.0, -1.5, 0.0), Vec3::Y)],
        &[],
    )
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len() as f32
}

/// Bent normals (AoOptions::bent_normals) against the CPU mirror in every layout (fused and
/// unfused), with and without the spatial denoiser, at full and half resolution (upsampled
/// by the default bilateral upsampler), on the GPU's own prepared values; and turning them
/// on leaves the AO bit for bit as it was.
/// Vectors against their mirror: 99% of pixels within 2e-3 per component, none beyond 0.5 (a
/// sample on a pixel boundary may round to the neighbour, as for the AO).
fn assert_close(gpu: &[Vec3], cpu: &[Vec3], what: &str) {
    assert_eq!(gpu.len(), cpu.len(), "{what}: size");
    let diffs: Vec<f32> = gpu
        .iter()
        .zip(cpu)
        .map(|(g, c)| (*g - *c).abs().max_element())
        .collect();
    let close = diffs.iter().filter(|d| **d <= 2e-3).count();
    let max = diffs.iter().cloned().fold(0.0, f32::max);
    assert!(
        close * 100 >= diffs.len() * 99 && max <= 0.5,
        "{what}: {close}/{} within 2e-3, max {max}",
        diffs.len()
    );
}

/// The components of `v`, in order.
fn flat(v: &[Vec4]) -> Vec<f32> {
    v.iter().flat_map(|x| x.to_array()).collect()
}

/// Results that may differ only in how a shader compiler rounds the same arithmetic: another
/// pipeline variant (fused or not, bent normals on or off) or a CPU mirror of the same
/// expressions. lavapipe gives the same bits; hardware compilers contract `a * b + c` into
/// fused multiply-adds differently per pipeline, which moves results by a few ulps (seen on an
/// NVIDIA H100). Every value within 1e-5 of the expected one, relative to max(|expected|, 1);
/// equal non-finite values (sky) pass, a non-finite value against a finite one fails.
fn assert_rounding_only(got: &[f32], want: &[f32], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: size");
    let (i, d) = got
        .iter()
        .zip(want)
        .map(|(g, w)| rounding_distance(*g, *w))
        .enumerate()
        .fold((0, 0.0f32), |m, (i, d)| if d > m.1 { (i, d) } else { m });
    assert!(
        d <= ROUNDING,
        "{what}: value {i} is {} where {} was expected ({d:e} relative)",
        got[i],
        want[i]
    );
}

/// Differences up to this, relative to max(|expected|, 1), are rounding.
const ROUNDING: f32 = 1e-5;

/// `|got − want| / max(|want|, 1)`: 0 for the same bits (sky, NaN included), infinite for a
/// non-finite value against another.
fn rounding_distance(got: f32, want: f32) -> f32 {
    if got.to_bits() == want.to_bits() {
        0.0
    } else if got.is_finite() && want.is_finite() {
        (got - want).abs() / want.abs().max(1.0)
    } else {
        f32::INFINITY
    }
}

/// As [`assert_rounding_only`] for the results of comparisons (a downsampling rule's pick):
/// at most 0.5% of values may differ by more, where a near tie flipped between two valid
/// picks (seen on an NVIDIA H100; lavapipe gives the mirror's bits).
fn assert_rounding_only_but_ties(got: &[f32], want: &[f32], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: size");
    let off = got
        .iter()
        .zip(want)
        .filter(|(g, w)| rounding_distance(**g, **w) > ROUNDING)
        .count();
    assert!(
        off * 200 <= got.len(),
        "{what}: {off} of {} values beyond rounding",
        got.len()
    );
}

//! Helpers shared by the GPU test binaries (each binary owns its device).

use obscura::{AoInput, DepthConvention, GpuContext, Projection};

/// A context on the adapter `OBSCURA_ADAPTER` picks, with `limits` (None: the adapter's).
pub fn context(limits: Option<wgpu::Limits>) -> GpuContext {
    GpuContext::with_limits(&obscura::AdapterChoice::from_env(), limits)
        .unwrap_or_else(|e| panic!("these tests need a Vulkan adapter (lavapipe is enough): {e}"))
}

/// An `R32Float` texture holding `data` (row-major, `w` × `h`), readable by shaders.
pub fn upload_r32(c: &GpuContext, data: &[f32], w: u32, h: u32) -> wgpu::Texture {
    c.upload_r32("test depth", data, w, h)
}

/// Linear view depth in `view`, normals reconstructed, the whole texture, library output.
pub fn linear_input(view: &wgpu::TextureView, projection: Projection) -> AoInput<'_> {
    AoInput {
        depth: view,
        convention: DepthConvention::LinearView,
        projection,
        normals: None,
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    }
}

/// The texels of a packed lit texture (`obscura::shader::LIT_PACKED_FORMAT`).
#[allow(dead_code)] // gpu/lights.rs and gpu/ssdo.rs, not device_lost.rs
pub fn read_packed(c: &GpuContext, t: &wgpu::Texture) -> Vec<[u32; 4]> {
    bytemuck::pod_collect_to_vec(&c.read_texture(t).unwrap())
}

/// A packed merge (passes/lights/lights_merge.wgsl) against its mirror
/// (`reference::merge_lights_packed`). Both round the pass along x's result to the
/// encoding's steps, so a rounding difference (~1e-7) can put one ratio a step apart (a
/// tie, as a depth rule's picks in tests/gpu/resolution.rs): at most 0.5% of the pixels may differ by
/// more than 1e-4 of the mean, and none by more than one step of the brightest pixel (its
/// largest component / 1023) beyond that.
#[allow(dead_code)] // gpu/lights.rs and gpu/ssdo.rs, not device_lost.rs
pub fn assert_packed_merge(got: &[glam::Vec3], want: &[glam::Vec3], what: &str) {
    let mean = want.iter().map(|v| v.length()).sum::<f32>() / want.len() as f32;
    let step = want.iter().map(|v| v.max_element()).fold(0.0, f32::max) / 1023.0;
    let errors: Vec<f32> = got
        .iter()
        .zip(want)
        .map(|(g, w)| (*g - *w).length())
        .collect();
    let off = errors.iter().filter(|&&e| e > 1e-4 * mean).count();
    assert!(
        off * 200 <= got.len(),
        "{what}: {off} of {} pixels beyond 1e-4 of the mean",
        got.len()
    );
    let worst = errors.iter().fold(0.0f32, |a, &e| a.max(e));
    assert!(
        worst <= 1e-4 * mean + step,
        "{what}: merge off by {worst} (mean {mean}, step {step})"
    );
}

/// The frame of a `w` × `h` viewport inside a guard band of `g` pixels on every side, and
/// the same uniforms with the whole processed rectangle as the output (the frame "without
/// a band" that a banded pass must crop to).
#[allow(dead_code)] // gpu/lights.rs and gpu/ssdo.rs, not device_lost.rs
pub fn banded_frames(
    projection: &Projection,
    params: &obscura::AoParams,
    (w, h, g): (u32, u32, u32),
) -> (
    obscura::uniforms::FrameUniforms,
    obscura::uniforms::FrameUniforms,
) {
    let viewport = obscura::Viewport {
        x: g,
        y: g,
        width: w,
        height: h,
    };
    let banded = obscura::uniforms::FrameUniforms::new(
        projection,
        DepthConvention::LinearView,
        None,
        (viewport, g),
        &obscura::AoOptions::default(),
        params,
    )
    .unwrap();
    assert_eq!(banded.size, [w + 2 * g, h + 2 * g]);
    assert_eq!((banded.output_offset, banded.output_size), ([g, g], [w, h]));
    let whole = obscura::uniforms::FrameUniforms {
        output_offset: [0, 0],
        output_size: banded.size,
        ..banded
    };
    (banded, whole)
}

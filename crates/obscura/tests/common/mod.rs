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
        output: None,
    }
}

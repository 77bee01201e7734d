//! Helpers shared by the GPU test binaries (each binary owns its device).

use obscura::{AoInput, DepthConvention, GpuContext, Projection};

/// A context on the adapter `OBSCURA_ADAPTER` picks, with `limits` (None: the adapter's).
pub fn context(limits: Option<wgpu::Limits>) -> GpuContext {
    GpuContext::with_limits(&obscura::AdapterChoice::from_env(), limits)
        .unwrap_or_else(|e| panic!("these tests need a Vulkan adapter (lavapipe is enough): {e}"))
}

/// An `R32Float` texture holding `data` (row-major, `w` × `h`), readable by shaders.
pub fn upload_r32(c: &GpuContext, data: &[f32], w: u32, h: u32) -> wgpu::Texture {
    let tex = c.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test depth"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    c.queue.write_texture(
        tex.as_image_copy(),
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * 4),
            rows_per_image: Some(h),
        },
        tex.size(),
    );
    tex
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

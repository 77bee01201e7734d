//! wgpu plumbing shared by every pipeline object ([`crate::Ao`], [`crate::Lights`],
//! [`crate::Ssdo`]): compiling a pass with its bind group layout, binding textures,
//! creating storage textures, and error scopes around resource creation.

use crate::passes::bindings::layout_entries;
use crate::passes::shader::Pass;
use crate::{AoOptions, Result};

/// A compiled pass: pipeline and the layout of its bind group.
#[derive(Debug)]
pub struct Compiled {
    pub(crate) pass: Pass,
    pub(crate) pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

pub(crate) fn compile(device: &wgpu::Device, pass: Pass, options: &AoOptions) -> Compiled {
    compile_with(device, pass, &pass.constants(options))
}

/// Compiles `pass` with its bind group layout and the override `constants`.
pub(crate) fn compile_with(
    device: &wgpu::Device,
    pass: Pass,
    constants: &[(&str, f64)],
) -> Compiled {
    let label = Some(pass.label());
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label,
        entries: &layout_entries(pass),
    });
    let module = crate::passes::shader::create_module(device, label, pass.source());
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label,
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    });
    Compiled {
        pass,
        pipeline,
        layout,
    }
}

/// Binds the frame uniforms at 0 and `views` at the given binding numbers.
pub(crate) fn bind_group(
    device: &wgpu::Device,
    c: &Compiled,
    uniforms: &wgpu::Buffer,
    views: &[(u32, &wgpu::TextureView)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = std::iter::once(wgpu::BindGroupEntry {
        binding: 0,
        resource: uniforms.as_entire_binding(),
    })
    .chain(views.iter().map(|&(binding, v)| wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(v),
    }))
    .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(c.pass.label()),
        layout: &c.layout,
        entries: &entries,
    })
}

/// Out-of-memory and validation error scopes around resource creation on the caller's
/// device (never around per-frame recording), so failures come back as typed errors
/// instead of reaching the device's uncaptured-error handler. On the web a scope's result
/// can only be awaited, and `Ao`'s calls are synchronous, so there no scope is pushed and
/// errors reach the uncaptured-error handler ([`crate::GpuContext::take_errors`]).
#[cfg(not(target_arch = "wasm32"))]
pub(crate) struct ErrorScope {
    oom: wgpu::ErrorScopeGuard,
    validation: wgpu::ErrorScopeGuard,
}

#[cfg(target_arch = "wasm32")]
pub(crate) struct ErrorScope;

#[cfg(target_arch = "wasm32")]
impl ErrorScope {
    pub(crate) fn push(_: &wgpu::Device) -> Self {
        ErrorScope
    }

    pub(crate) fn pop(self, _: &str) -> Result<()> {
        Ok(())
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl ErrorScope {
    pub(crate) fn push(device: &wgpu::Device) -> Self {
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        Self { oom, validation }
    }

    pub(crate) fn pop(self, doing: &str) -> Result<()> {
        let v = pollster::block_on(self.validation.pop());
        let o = pollster::block_on(self.oom.pop());
        use crate::Error;
        match o.or(v).map(Error::from) {
            None => Ok(()),
            Some(Error::OutOfMemory(e)) => Err(Error::OutOfMemory(format!("{doing}: {e}"))),
            Some(Error::Gpu(e)) => Err(Error::Gpu(format!("{doing}: {e}"))),
            Some(e) => Err(e),
        }
    }
}

pub(crate) fn make_texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    layers: u32,
    mips: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

pub(crate) fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// A uniform buffer of `size` bytes, written with `queue.write_buffer` each frame.
pub(crate) fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

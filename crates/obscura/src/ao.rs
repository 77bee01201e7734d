//! [`Ao`]: the AO pipeline object. Creation compiles the passes for an [`AoOptions`];
//! each frame, [`Ao::record`] validates the inputs, writes one small uniform buffer and
//! records `prepare → hbao` into the caller's command encoder.

use crate::shader::{dispatch_size, Pass, AO_FORMAT, PREPARED_FORMAT};
use crate::uniforms::FrameUniforms;
use crate::{
    AoOptions, AoParams, DepthConvention, Error, NormalEncoding, Projection, Result, Viewport,
};

/// What the caller hands over each frame.
#[derive(Clone, Copy, Debug)]
pub struct AoInput<'a> {
    /// Depth, as a depth format (Depth32Float, Depth24Plus, Depth16Unorm; depth-only view
    /// for combined depth-stencil formats) or a float format (R32Float, R16Float), not
    /// multisampled, with `TEXTURE_BINDING` usage.
    pub depth: &'a wgpu::TextureView,
    /// How the depth values are encoded.
    pub convention: DepthConvention,
    /// The camera projection that produced the depth.
    pub projection: Projection,
    /// Optional view-space normals, same size as the depth texture; reconstructed from
    /// depth when `None`.
    pub normals: Option<(&'a wgpu::TextureView, NormalEncoding)>,
    /// The region to process; `None` means the whole depth texture.
    pub viewport: Option<Viewport>,
}

#[derive(Debug)]
struct SizedResources {
    size: [u32; 2],
    prepared_view: wgpu::TextureView,
    output: wgpu::Texture,
    output_view: wgpu::TextureView,
    hbao_bind: wgpu::BindGroup,
}

/// The AO pipeline. Create once; call [`Ao::record`] per frame.
#[derive(Debug)]
pub struct Ao {
    options: AoOptions,
    prepare_depth: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    prepare_float: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    hbao: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    uniforms: wgpu::Buffer,
    dummy_normals: wgpu::TextureView,
    max_dim: u32,
    sized: Option<SizedResources>,
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn storage_entry(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

const UNIFORM_ENTRY: wgpu::BindGroupLayoutEntry = wgpu::BindGroupLayoutEntry {
    binding: 0,
    visibility: wgpu::ShaderStages::COMPUTE,
    ty: wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    },
    count: None,
};

const UNFILTERED: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };

fn pipeline(
    device: &wgpu::Device,
    pass: Pass,
    entries: &[wgpu::BindGroupLayoutEntry],
    constants: &[(&str, f64)],
) -> (wgpu::ComputePipeline, wgpu::BindGroupLayout) {
    let label = Some(pass.label());
    let layout =
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label, entries });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label,
        source: wgpu::ShaderSource::Wgsl(pass.source().into()),
    });
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
    (pipeline, layout)
}

/// Every pass binds the frame uniforms at 0 and its texture views at 1, 2, ...
fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    views: &[&wgpu::TextureView],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = std::iter::once(wgpu::BindGroupEntry {
        binding: 0,
        resource: uniforms.as_entire_binding(),
    })
    .chain(
        views
            .iter()
            .zip(1..)
            .map(|(v, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(v),
            }),
    )
    .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// Whether a depth input binds as a depth texture (`true`) or a float texture (`false`).
fn depth_binding_kind(format: wgpu::TextureFormat) -> Result<bool> {
    use wgpu::TextureFormat as F;
    match format {
        F::Depth32Float | F::Depth24Plus | F::Depth16Unorm | F::Depth24PlusStencil8 | F::Depth32FloatStencil8 => {
            Ok(true)
        }
        F::R32Float | F::R16Float => Ok(false),
        _ => Err(Error::UnsupportedFormat {
            what: "depth",
            format,
            expected: "Depth32Float, Depth24Plus, Depth16Unorm, a depth-stencil format, R32Float or R16Float",
        }),
    }
}

impl Ao {
    /// Validates `options` and compiles every pipeline they need.
    pub fn new(device: &wgpu::Device, options: AoOptions) -> Result<Self> {
        options.validate()?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let prepare_entries = |depth: wgpu::TextureSampleType| {
            [
                UNIFORM_ENTRY,
                texture_entry(1, depth),
                texture_entry(2, UNFILTERED),
                storage_entry(3, PREPARED_FORMAT),
            ]
        };
        let prepare_depth = pipeline(
            device,
            Pass::PrepareDepth,
            &prepare_entries(wgpu::TextureSampleType::Depth),
            &[],
        );
        let prepare_float = pipeline(
            device,
            Pass::PrepareFloat,
            &prepare_entries(UNFILTERED),
            &[],
        );
        let hbao = pipeline(
            device,
            Pass::Hbao,
            &[
                UNIFORM_ENTRY,
                texture_entry(1, UNFILTERED),
                storage_entry(2, AO_FORMAT),
            ],
            &[
                ("DIRECTIONS", options.directions as f64),
                ("STEPS", options.steps as f64),
            ],
        );
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("obscura frame uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let dummy_normals = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("obscura no-normals placeholder"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "creating obscura's pipelines failed: {e}"
            )));
        }
        Ok(Self {
            options,
            prepare_depth,
            prepare_float,
            hbao,
            uniforms,
            dummy_normals,
            max_dim: device.limits().max_texture_dimension_2d,
            sized: None,
        })
    }

    /// The options the pipelines were compiled for.
    pub fn options(&self) -> &AoOptions {
        &self.options
    }

    /// Checks `input` and `params` and derives the frame uniforms. No GPU work.
    pub fn validate(&self, input: &AoInput<'_>, params: &AoParams) -> Result<FrameUniforms> {
        let tex = input.depth.texture();
        depth_binding_kind(tex.format())?;
        if tex.sample_count() != 1 {
            return Err(Error::UnsupportedFormat {
                what: "multisampled depth",
                format: tex.format(),
                expected: "a single-sampled texture (resolve MSAA depth first)",
            });
        }
        if !tex.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
            return Err(Error::InvalidViewport(
                "the depth texture lacks TEXTURE_BINDING usage".into(),
            ));
        }
        let viewport = input
            .viewport
            .unwrap_or(Viewport::full(tex.width(), tex.height()));
        let fits = |w: u32, h: u32| {
            viewport
                .x
                .checked_add(viewport.width)
                .is_some_and(|r| r <= w)
                && viewport
                    .y
                    .checked_add(viewport.height)
                    .is_some_and(|b| b <= h)
        };
        if !fits(tex.width(), tex.height()) {
            return Err(Error::InvalidViewport(format!(
                "{viewport:?} does not fit the {}x{} depth texture",
                tex.width(),
                tex.height()
            )));
        }
        if viewport.width > self.max_dim || viewport.height > self.max_dim {
            return Err(Error::TooLarge {
                width: viewport.width,
                height: viewport.height,
                max: self.max_dim,
            });
        }
        if let Some((n, _)) = input.normals {
            let nt = n.texture();
            if !matches!(
                nt.format().sample_type(None, None),
                Some(wgpu::TextureSampleType::Float { .. })
            ) || nt.sample_count() != 1
            {
                return Err(Error::UnsupportedFormat {
                    what: "normal",
                    format: nt.format(),
                    expected: "a single-sampled float or unorm colour format",
                });
            }
            if nt.width() != tex.width() || nt.height() != tex.height() {
                return Err(Error::InvalidViewport(format!(
                    "normals are {}x{} but depth is {}x{}",
                    nt.width(),
                    nt.height(),
                    tex.width(),
                    tex.height()
                )));
            }
        }
        FrameUniforms::new(
            &input.projection,
            input.convention,
            input.normals.map(|n| n.1),
            viewport,
            &self.options,
            params,
        )
    }

    /// Creates the size-dependent resources unless they already match `size`.
    fn ensure_size(&mut self, device: &wgpu::Device, size: [u32; 2]) {
        if self.sized.as_ref().is_some_and(|s| s.size == size) {
            return;
        }
        let extent = wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        };
        let make = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let prepared = make(
            "obscura prepared depth+normal",
            PREPARED_FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let output = make(
            "obscura ao",
            AO_FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let prepared_view = prepared.create_view(&Default::default());
        let output_view = output.create_view(&Default::default());
        let hbao_bind = bind_group(
            device,
            "hbao",
            &self.hbao.1,
            &self.uniforms,
            &[&prepared_view, &output_view],
        );
        self.sized = Some(SizedResources {
            size,
            prepared_view,
            output,
            output_view,
            hbao_bind,
        });
    }

    /// Validates the inputs, writes the frame uniforms and records the AO passes into
    /// `encoder`. The result is [`Ao::output`] once the encoder's commands have run.
    /// Record at most once per queue submission (the uniforms are shared).
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<()> {
        let frame = self.validate(input, params)?;
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&frame));
        let is_depth = depth_binding_kind(input.depth.texture().format())?;
        self.ensure_size(device, frame.size);
        let Some(sized) = self.sized.as_ref() else {
            return Err(Error::Gpu("size-dependent resources missing".into()));
        };
        let normals = input.normals.map_or(&self.dummy_normals, |n| n.0);
        let (prep_pipeline, prep_layout) = if is_depth {
            &self.prepare_depth
        } else {
            &self.prepare_float
        };
        let prepare_bind = bind_group(
            device,
            "prepare",
            prep_layout,
            &self.uniforms,
            &[input.depth, normals, &sized.prepared_view],
        );
        let (gx, gy) = dispatch_size(frame.size);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("obscura"),
            timestamp_writes: None,
        });
        pass.push_debug_group(if is_depth {
            "prepare_depth"
        } else {
            "prepare_float"
        });
        pass.set_pipeline(prep_pipeline);
        pass.set_bind_group(0, &prepare_bind, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.pop_debug_group();
        pass.push_debug_group("hbao");
        pass.set_pipeline(&self.hbao.0);
        pass.set_bind_group(0, &sized.hbao_bind, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.pop_debug_group();
        Ok(())
    }

    /// The AO texture (`R32Float`, viewport-sized, 1 = unoccluded), once a frame was recorded.
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().map(|s| &s.output)
    }

    /// A view of [`Ao::output`].
    pub fn output_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().map(|s| &s.output_view)
    }

    /// The prepared `vec4(linear depth, view normal)` texture (`Rgba32Float`), for
    /// debugging and tests.
    pub fn prepared_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().map(|s| &s.prepared_view)
    }
}

//! [`Ao`]: the AO pipeline object. Creation compiles the passes for an [`AoOptions`];
//! each frame, [`Ao::record`] validates the inputs, writes one small uniform buffer and
//! records the passes into the caller's command encoder:
//!
//! ```text
//! randomized:           prepare ─▶ hbao (full resolution, 4×4 per-pixel patterns)
//! deinterleaved, fused: prepare_split (writes N×N layers) ─▶ hbao_layers_merge (writes full res)
//! deinterleaved:        prepare ─▶ deinterleave ─▶ hbao_layers ─▶ interleave
//! ```
//!
//! Estimators that read the depth pyramid (SAO) get its levels built between prepare and
//! the AO pass: `pyramid_from_full` (or `_from_layers`) then one `pyramid` pass per level.

use crate::layout::layer_size;
use crate::shader::{
    dispatch_size, DepthBinding, Pass, PyramidSource, AO_FORMAT, PREPARED_FORMAT, PYRAMID_FORMAT,
};
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

/// Textures and bind groups that depend on the viewport size. Declared in one place:
/// name, size rule, format, layers.
#[derive(Debug)]
struct SizedResources {
    size: [u32; 2],
    /// `prepared`: full size, PREPARED_FORMAT (randomized, or unfused deinterleaved).
    prepared: Option<wgpu::TextureView>,
    /// `prepared_layers`: layer size × N² layers, PREPARED_FORMAT (deinterleaved).
    prepared_layers: Option<wgpu::TextureView>,
    // `ao_layers` (layer size × N² layers, AO_FORMAT, unfused deinterleaved only) lives
    // in the bind groups of `later`.
    /// `pyramid`: max(1, size >> 1) with every mip, PYRAMID_FORMAT (estimators that use it).
    pyramid: Option<wgpu::Texture>,
    /// `output`: full size, AO_FORMAT.
    output: wgpu::Texture,
    output_view: wgpu::TextureView,
    /// Workgroups of the prepare pass (over pixels, or over layer texels when it splits).
    prepare_dispatch: [u32; 3],
    /// Bind groups of every pass after prepare, in order, with their dispatch sizes.
    later: Vec<(usize, wgpu::BindGroup, [u32; 3])>,
}

/// How [`Ao::run_timed`] measures each pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timing {
    /// Wall clock around submit + wait of each pass on its own: the only honest clock on
    /// lavapipe, whose timestamps do not bracket dispatches.
    WallClock,
    /// GPU timestamp queries around each pass, all passes in one submission (hardware
    /// adapters with `TIMESTAMP_QUERY`).
    Timestamps,
}

impl Timing {
    /// Timestamps where the context says they bracket dispatches, else the wall clock.
    pub fn best_for(ctx: &crate::GpuContext) -> Self {
        if ctx.has_timestamps() {
            Timing::Timestamps
        } else {
            Timing::WallClock
        }
    }
}

/// A compiled pass: pipeline and the layout of its bind group.
#[derive(Debug)]
struct Compiled {
    pass: Pass,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// The AO pipeline. Create once; call [`Ao::record`] per frame.
#[derive(Debug)]
pub struct Ao {
    options: AoOptions,
    /// Prepare for [depth-format, float] inputs × [given, reconstructed] normals.
    prepare: [[Compiled; 2]; 2],
    /// The passes after prepare, in execution order.
    later: Vec<Compiled>,
    uniforms: wgpu::Buffer,
    dummy_normals: wgpu::TextureView,
    max_dim: u32,
    sized: Option<SizedResources>,
}

fn texture_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

fn storage_entry(
    binding: u32,
    format: wgpu::TextureFormat,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension,
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
const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;
const D2_ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// The bind group layout of `pass`: uniforms at 0, then its textures.
fn layout_entries(pass: Pass) -> Vec<wgpu::BindGroupLayoutEntry> {
    let dim = |layers: bool| if layers { D2_ARRAY } else { D2 };
    let rest = match pass {
        Pass::Prepare { depth, layers, .. } => vec![
            texture_entry(
                1,
                match depth {
                    DepthBinding::Depth => wgpu::TextureSampleType::Depth,
                    DepthBinding::Float => UNFILTERED,
                },
                D2,
            ),
            texture_entry(2, UNFILTERED, D2),
            storage_entry(3, PREPARED_FORMAT, dim(layers)),
        ],
        Pass::AoFull { .. } => vec![
            texture_entry(1, UNFILTERED, D2),
            storage_entry(2, AO_FORMAT, D2),
        ],
        Pass::AoLayered { merge, .. } => vec![
            texture_entry(1, UNFILTERED, D2_ARRAY),
            storage_entry(2, AO_FORMAT, dim(!merge)),
        ],
        // The split reuses the prepare store fragment (binding 3); 2 is unused.
        Pass::Deinterleave => vec![
            texture_entry(1, UNFILTERED, D2),
            storage_entry(3, PREPARED_FORMAT, D2_ARRAY),
        ],
        Pass::Interleave => vec![
            texture_entry(1, UNFILTERED, D2_ARRAY),
            storage_entry(2, AO_FORMAT, D2),
        ],
        Pass::Pyramid { source } => vec![
            texture_entry(1, UNFILTERED, dim(source == PyramidSource::Layers)),
            storage_entry(2, PYRAMID_FORMAT, D2),
        ],
    };
    let pyramid = match pass {
        Pass::AoFull { estimator } | Pass::AoLayered { estimator, .. } => estimator.uses_pyramid(),
        _ => false,
    };
    let rest = rest
        .into_iter()
        .chain(pyramid.then(|| texture_entry(3, UNFILTERED, D2)));
    std::iter::once(UNIFORM_ENTRY).chain(rest).collect()
}

fn compile(device: &wgpu::Device, pass: Pass, options: &AoOptions) -> Compiled {
    let label = Some(pass.label());
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label,
        entries: &layout_entries(pass),
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label,
        source: wgpu::ShaderSource::Wgsl(pass.source().into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let constants = pass.constants(options);
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label,
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
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
fn bind_group(
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

/// How a depth input binds.
fn depth_binding(format: wgpu::TextureFormat) -> Result<DepthBinding> {
    use wgpu::TextureFormat as F;
    match format {
        F::Depth32Float
        | F::Depth24Plus
        | F::Depth16Unorm
        | F::Depth24PlusStencil8
        | F::Depth32FloatStencil8 => Ok(DepthBinding::Depth),
        F::R32Float | F::R16Float => Ok(DepthBinding::Float),
        _ => Err(Error::UnsupportedFormat {
            what: "depth",
            format,
            expected: "Depth32Float, Depth24Plus, Depth16Unorm, a depth-stencil format, R32Float or R16Float",
        }),
    }
}

fn make_texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    layers: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    make_texture_mips(device, label, size, layers, 1, format)
}

fn make_texture_mips(
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

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(D2_ARRAY),
        ..Default::default()
    })
}

impl Ao {
    /// Validates `options` and compiles every pipeline they need.
    pub fn new(device: &wgpu::Device, options: AoOptions) -> Result<Self> {
        options.validate()?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let layered = options.mode.split() > 1;
        let split_in_prepare = layered && options.fused;
        let prepare = [DepthBinding::Depth, DepthBinding::Float].map(|depth| {
            [false, true].map(|reconstruct| {
                compile(
                    device,
                    Pass::Prepare {
                        depth,
                        layers: split_in_prepare,
                        reconstruct,
                    },
                    &options,
                )
            })
        });
        let estimator = options.estimator;
        let pyramid_passes = if estimator.uses_pyramid() {
            let source = if split_in_prepare {
                PyramidSource::Layers
            } else {
                PyramidSource::Full
            };
            vec![
                Pass::Pyramid { source },
                Pass::Pyramid {
                    source: PyramidSource::Mip,
                },
            ]
        } else {
            vec![]
        };
        let ao_passes = match (layered, options.fused) {
            (false, _) => vec![Pass::AoFull { estimator }],
            (true, true) => vec![Pass::AoLayered {
                merge: true,
                estimator,
            }],
            (true, false) => vec![
                Pass::Deinterleave,
                Pass::AoLayered {
                    merge: false,
                    estimator,
                },
                Pass::Interleave,
            ],
        };
        // The pyramid reads the full-resolution buffer, so in unfused modes it runs after
        // prepare and before the split; in every mode before the AO pass.
        let later = pyramid_passes
            .into_iter()
            .chain(ao_passes)
            .map(|p| compile(device, p, &options))
            .collect();
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
            prepare,
            later,
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
        depth_binding(tex.format())?;
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
        let n = self.options.mode.split();
        let full = (size[0], size[1]);
        let lsize = layer_size(size[0], size[1], n);
        let layered = n > 1;
        let needs_full_prepared = !layered || !self.options.fused;
        let prepared = needs_full_prepared.then(|| {
            make_texture(device, "obscura prepared", full, 1, PREPARED_FORMAT)
                .create_view(&Default::default())
        });
        let prepared_layers = layered.then(|| {
            array_view(&make_texture(
                device,
                "obscura prepared layers",
                lsize,
                n * n,
                PREPARED_FORMAT,
            ))
        });
        let ao_layers = (layered && !self.options.fused).then(|| {
            array_view(&make_texture(
                device,
                "obscura ao layers",
                lsize,
                n * n,
                AO_FORMAT,
            ))
        });
        let output = make_texture(device, "obscura ao", full, 1, AO_FORMAT);
        let output_view = output.create_view(&Default::default());
        let pyramid = self.options.estimator.uses_pyramid().then(|| {
            let base = (1.max(size[0] >> 1), 1.max(size[1] >> 1));
            let mips = base.0.max(base.1).ilog2() + 1;
            make_texture_mips(
                device,
                "obscura depth pyramid",
                base,
                1,
                mips,
                PYRAMID_FORMAT,
            )
        });
        let pyramid_all = pyramid.as_ref().map(|t| t.create_view(&Default::default()));
        let pyramid_mip = |t: &wgpu::Texture, level: u32| {
            t.create_view(&wgpu::TextureViewDescriptor {
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        let (fx, fy) = dispatch_size(size);
        let (lx, ly) = dispatch_size([lsize.0, lsize.1]);
        let full_dispatch = [fx, fy, 1];
        let layer_dispatch = [lx, ly, n * n];
        // Binding 3 of the AO pass, for estimators that read the pyramid.
        let pyramid_binding = |e: crate::Estimator| {
            pyramid_all
                .as_ref()
                .filter(|_| e.uses_pyramid())
                .map(|v| (3, v))
        };
        let mut later = Vec::new();
        for (i, c) in self.later.iter().enumerate() {
            let mut push = |views: Vec<(u32, &wgpu::TextureView)>, dispatch| {
                later.push((i, bind_group(device, c, &self.uniforms, &views), dispatch));
            };
            match c.pass {
                Pass::AoFull { estimator } => {
                    if let Some(prepared) = &prepared {
                        let mut views = vec![(1, prepared), (2, &output_view)];
                        views.extend(pyramid_binding(estimator));
                        push(views, full_dispatch);
                    }
                }
                Pass::AoLayered { merge, estimator } => {
                    let out = if merge {
                        Some(&output_view)
                    } else {
                        ao_layers.as_ref()
                    };
                    if let (Some(layers), Some(out)) = (&prepared_layers, out) {
                        let mut views = vec![(1, layers), (2, out)];
                        views.extend(pyramid_binding(estimator));
                        push(views, layer_dispatch);
                    }
                }
                Pass::Deinterleave => {
                    if let (Some(p), Some(l)) = (&prepared, &prepared_layers) {
                        push(vec![(1, p), (3, l)], layer_dispatch);
                    }
                }
                Pass::Interleave => {
                    if let Some(l) = &ao_layers {
                        push(vec![(1, l), (2, &output_view)], full_dispatch);
                    }
                }
                Pass::Pyramid { source } => {
                    let Some(t) = &pyramid else { continue };
                    let dispatch = |level: u32| {
                        let (x, y) =
                            dispatch_size([1.max(t.width() >> level), 1.max(t.height() >> level)]);
                        [x, y, 1]
                    };
                    match source {
                        PyramidSource::Full | PyramidSource::Layers => {
                            let src = if source == PyramidSource::Full {
                                prepared.as_ref()
                            } else {
                                prepared_layers.as_ref()
                            };
                            if let Some(src) = src {
                                push(vec![(1, src), (2, &pyramid_mip(t, 0))], dispatch(0));
                            }
                        }
                        PyramidSource::Mip => {
                            for level in 1..t.mip_level_count() {
                                let (from, to) = (pyramid_mip(t, level - 1), pyramid_mip(t, level));
                                push(vec![(1, &from), (2, &to)], dispatch(level));
                            }
                        }
                    }
                }
                Pass::Prepare { .. } => {}
            }
        }
        self.sized = Some(SizedResources {
            size,
            prepare_dispatch: if needs_full_prepared {
                full_dispatch
            } else {
                layer_dispatch
            },
            prepared,
            prepared_layers,
            pyramid,
            output,
            output_view,
            later,
        });
    }

    /// Validates, uploads uniforms, and returns the passes of this frame in order as
    /// (compiled pass, bind group, dispatch size).
    fn plan(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<Vec<(&Compiled, wgpu::BindGroup, [u32; 3])>> {
        let frame = self.validate(input, params)?;
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&frame));
        let binding = depth_binding(input.depth.texture().format())?;
        self.ensure_size(device, frame.size);
        let Some(sized) = self.sized.as_ref() else {
            return Err(Error::Gpu("size-dependent resources missing".into()));
        };
        let normals = input.normals.map_or(&self.dummy_normals, |n| n.0);
        let prepare = &self.prepare[match binding {
            DepthBinding::Depth => 0,
            DepthBinding::Float => 1,
        }][input.normals.is_none() as usize];
        let target = match (&sized.prepared, &sized.prepared_layers) {
            (Some(full), _) => full,
            (None, Some(layers)) => layers,
            (None, None) => return Err(Error::Gpu("no prepare target".into())),
        };
        let prepare_bind = bind_group(
            device,
            prepare,
            &self.uniforms,
            &[(1, input.depth), (2, normals), (3, target)],
        );
        let mut passes = vec![(prepare, prepare_bind, sized.prepare_dispatch)];
        for (i, bg, d) in &sized.later {
            passes.push((&self.later[*i], bg.clone(), *d));
        }
        Ok(passes)
    }

    /// Validates the inputs, writes the frame uniforms and records the AO passes into
    /// `encoder`, in one compute pass with a debug group per pass. The result is
    /// [`Ao::output`] once the encoder's commands have run. Record at most once per queue
    /// submission (the uniforms are shared).
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<()> {
        let passes = self.plan(device, queue, input, params)?;
        let mut cpass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("obscura"),
            timestamp_writes: None,
        });
        for (c, bg, d) in &passes {
            cpass.push_debug_group(c.pass.label());
            cpass.set_pipeline(&c.pipeline);
            cpass.set_bind_group(0, bg, &[]);
            cpass.dispatch_workgroups(d[0], d[1], d[2]);
            cpass.pop_debug_group();
        }
        Ok(())
    }

    /// Runs one frame and returns each pass's label and milliseconds, measured as `timing`
    /// says. For benchmarks: it creates timing resources per call.
    pub fn run_timed(
        &mut self,
        ctx: &crate::GpuContext,
        input: &AoInput<'_>,
        params: &AoParams,
        timing: Timing,
    ) -> Result<Vec<(&'static str, f64)>> {
        let passes = self.plan(&ctx.device, &ctx.queue, input, params)?;
        let dispatch = |enc: &mut wgpu::CommandEncoder,
                        (c, bg, d): &(&Compiled, wgpu::BindGroup, [u32; 3]),
                        ts: Option<wgpu::ComputePassTimestampWrites>| {
            let mut cpass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(c.pass.label()),
                timestamp_writes: ts,
            });
            cpass.set_pipeline(&c.pipeline);
            cpass.set_bind_group(0, bg, &[]);
            cpass.dispatch_workgroups(d[0], d[1], d[2]);
        };
        match timing {
            Timing::WallClock => {
                let mut times = Vec::with_capacity(passes.len());
                for p in &passes {
                    let t = std::time::Instant::now();
                    ctx.run(|enc| {
                        dispatch(enc, p, None);
                        Ok(())
                    })?;
                    times.push((p.0.pass.label(), t.elapsed().as_secs_f64() * 1e3));
                }
                Ok(times)
            }
            Timing::Timestamps => {
                if !ctx
                    .device
                    .features()
                    .contains(wgpu::Features::TIMESTAMP_QUERY)
                {
                    return Err(Error::Gpu("the device has no timestamp queries".into()));
                }
                let count = 2 * passes.len() as u32;
                let bytes = 8 * count as u64;
                let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("obscura pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                });
                let buffer = |usage| {
                    ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("obscura timestamps"),
                        size: bytes,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let resolved =
                    buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
                let readback = buffer(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
                ctx.run(|enc| {
                    for (i, p) in passes.iter().enumerate() {
                        let writes = wgpu::ComputePassTimestampWrites {
                            query_set: &set,
                            beginning_of_pass_write_index: Some(2 * i as u32),
                            end_of_pass_write_index: Some(2 * i as u32 + 1),
                        };
                        dispatch(enc, p, Some(writes));
                    }
                    enc.resolve_query_set(&set, 0..count, &resolved, 0);
                    enc.copy_buffer_to_buffer(&resolved, 0, &readback, 0, bytes);
                    Ok(())
                })?;
                let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&ctx.map_read(&readback)?);
                let ns_per_tick = ctx.queue.get_timestamp_period() as f64;
                Ok(passes
                    .iter()
                    .zip(ticks.chunks_exact(2))
                    .map(|(p, t)| {
                        let ms = t[1].saturating_sub(t[0]) as f64 * ns_per_tick / 1e6;
                        (p.0.pass.label(), ms)
                    })
                    .collect())
            }
        }
    }

    /// The AO texture (`R32Float`, viewport-sized, 1 = unoccluded), once a frame was recorded.
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().map(|s| &s.output)
    }

    /// A view of [`Ao::output`].
    pub fn output_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().map(|s| &s.output_view)
    }

    /// The full-resolution prepared `vec4(linear depth, view normal)` texture
    /// (`Rgba32Float`) when the mode has one (not fused deinterleaved), for debugging/tests.
    pub fn prepared_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.prepared.as_ref())
    }

    /// The depth pyramid (`Rgba32Float`, `vec4(select, min, max, 0)`, mip m = level m + 1)
    /// when the estimator uses one.
    pub fn pyramid(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.pyramid.as_ref())
    }

    /// The deinterleaved prepared layers (`Rgba32Float` array, N² layers) in deinterleaved modes.
    pub fn prepared_layers_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.prepared_layers.as_ref())
    }
}

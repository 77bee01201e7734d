//! Rasterizes a [`Mesh`] seen by a [`Camera`] into a G-buffer: `Depth32Float` depth
//! (reversed-Z, [`DEPTH_CONVENTION`]), `Rgba16Float` view-space normals and `Rgba8Unorm`
//! linear albedo.

use crate::camera::{DEPTH_CONVENTION, SKY_DEPTH};
use crate::{Camera, Mesh, SceneError};
use obscura::GpuContext;
use wgpu::util::DeviceExt;

/// Depth format of the G-buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Normal format of the G-buffer (view-space xyz, signed).
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Albedo format of the G-buffer: the mesh's linear albedo (not sRGB-encoded), alpha 1 on
/// surfaces and 0 on sky.
pub const ALBEDO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Samples per pixel of [`GBufferRenderer::render_msaa_depth`]: 4, the count every WebGPU
/// device supports for depth formats.
pub const MSAA_SAMPLES: u32 = 4;

/// Uploaded geometry, ready to draw from any camera.
#[derive(Debug)]
pub struct GpuMesh {
    vertices: wgpu::Buffer,
    colours: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// Depth and normals of one view.
#[derive(Debug)]
pub struct GBuffer {
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    pub normals: wgpu::Texture,
    pub normals_view: wgpu::TextureView,
    pub albedo: wgpu::Texture,
    pub albedo_view: wgpu::TextureView,
    /// The textures' size: the view's, plus the guard band on each side.
    pub width: u32,
    pub height: u32,
    /// Pixels rendered around the view on each side ([`GBufferRenderer::render_guarded`]).
    pub guard_band: u32,
}

/// A second depth layer of a [`GBuffer`] ([`GBufferRenderer::peel`]): [`DEPTH_FORMAT`],
/// reversed-Z ([`DEPTH_CONVENTION`]), the G-buffer's size; for [`obscura::AoInput::second_layer`].
#[derive(Debug)]
pub struct DepthLayer {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

impl GBuffer {
    /// obscura's input for this G-buffer seen by `camera` (the view's camera, not the
    /// widened one): reversed-Z depth, the camera's projection, the G-buffer's normals when
    /// `with_normals` (else reconstructed), and the view inside its guard band.
    pub fn ao_input(&self, camera: &Camera, with_normals: bool) -> obscura::AoInput<'_> {
        let g = self.guard_band;
        // (A band wider than the textures gives an empty viewport, refused by obscura.)
        let inner = |s: u32| s.saturating_sub(g.saturating_mul(2));
        let (w, h) = (inner(self.width), inner(self.height));
        obscura::AoInput {
            depth: &self.depth_view,
            convention: DEPTH_CONVENTION,
            projection: camera.obscura_projection(w as f32 / h as f32),
            normals: with_normals
                .then_some((&self.normals_view, obscura::NormalEncoding::ViewSigned)),
            viewport: (g > 0).then_some(obscura::Viewport {
                x: g,
                y: g,
                width: w,
                height: h,
            }),
            guard_band: g,
            second_layer: None,
            output: None,
        }
    }
}

/// Multisampled depth of one view ([`MSAA_SAMPLES`] per pixel, [`DEPTH_FORMAT`]), as an
/// MSAA renderer's depth attachment holds it; with a guard band the texture holds the view
/// and the band around it, as [`GBuffer`]'s.
#[derive(Debug)]
pub struct MsaaDepth {
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    /// The texture's size, the band included.
    pub width: u32,
    pub height: u32,
    /// Pixels rasterized beyond each side of the view (0: none).
    pub guard_band: u32,
}

impl MsaaDepth {
    /// obscura's input for this depth seen by `camera` (normals reconstructed): the view,
    /// and with a guard band the band around it ([`obscura::AoInput::guard_band`]).
    pub fn ao_input(&self, camera: &Camera) -> obscura::AoInput<'_> {
        let g = self.guard_band;
        let inner = |s: u32| s.saturating_sub(g.saturating_mul(2));
        let (w, h) = (inner(self.width), inner(self.height));
        obscura::AoInput {
            depth: &self.depth_view,
            convention: DEPTH_CONVENTION,
            projection: camera.obscura_projection(w as f32 / h as f32),
            normals: None,
            viewport: (g > 0).then_some(obscura::Viewport {
                x: g,
                y: g,
                width: w,
                height: h,
            }),
            second_layer: None,
            guard_band: g,
            output: None,
        }
    }
}

/// The G-buffer render pipelines: depth and normals, multisampled depth alone, and the
/// depth peel of a second layer.
#[derive(Debug)]
pub struct GBufferRenderer {
    pipeline: wgpu::RenderPipeline,
    msaa_pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
    peel_pipeline: wgpu::RenderPipeline,
    peel_layout: wgpu::BindGroupLayout,
    peel: wgpu::Buffer,
}

/// shaders/peel.wgsl's `Peel`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PeelUniform {
    a: f32,
    b: f32,
    reciprocal: u32,
    separation: f32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniform {
    view: [[f32; 4]; 4],
    proj: [[f32; 4]; 4],
}

impl GBufferRenderer {
    pub fn new(device: &wgpu::Device) -> Self {
        let label = Some("gbuffer");
        // gbuffer.wgsl with the peel's fragment stage after it (one module, three passes).
        let source = concat!(
            include_str!("../shaders/gbuffer.wgsl"),
            "\n",
            include_str!("../shaders/peel.wgsl")
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label,
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let uniform = |binding, visibility| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label,
            entries: &[uniform(0, wgpu::ShaderStages::VERTEX)],
        });
        let peel_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("peel"),
            entries: &[
                uniform(0, wgpu::ShaderStages::VERTEX),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                uniform(2, wgpu::ShaderStages::FRAGMENT),
            ],
        });
        let pipeline_layout = |layout| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label,
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            })
        };
        let (gbuffer_layout, peel_pipeline_layout) =
            (pipeline_layout(&layout), pipeline_layout(&peel_layout));
        let targets = [Some(NORMAL_FORMAT.into()), Some(ALBEDO_FORMAT.into())];
        // `samples` per pixel; `peel`: the second layer's pass (front faces, depth only).
        let make = |samples: u32, peel: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label,
                layout: Some(if peel {
                    &peel_pipeline_layout
                } else {
                    &gbuffer_layout
                }),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[
                        Some(wgpu::VertexBufferLayout {
                            array_stride: 12,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                        }),
                        Some(wgpu::VertexBufferLayout {
                            array_stride: 12,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &wgpu::vertex_attr_array![1 => Float32x3],
                        }),
                    ],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: peel.then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    // Reversed-Z: nearer is greater.
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                // Multisampled: depth only; the peel: depth, with fragments discarded.
                fragment: match (samples, peel) {
                    (_, true) => Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_peel"),
                        compilation_options: Default::default(),
                        targets: &[],
                    }),
                    (1, false) => Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        targets: &targets,
                    }),
                    _ => None,
                },
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = make(1, false);
        let msaa_pipeline = make(MSAA_SAMPLES, false);
        let peel_pipeline = make(1, true);
        let peel = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("peel"),
            size: std::mem::size_of::<PeelUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let camera = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("gbuffer camera"),
            size: std::mem::size_of::<CameraUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            pipeline,
            msaa_pipeline,
            layout,
            camera,
            peel_pipeline,
            peel_layout,
            peel,
        }
    }

    /// Uploads a mesh. Fails cleanly if it exceeds the device's buffer size limit.
    pub fn upload(&self, ctx: &GpuContext, mesh: &Mesh) -> Result<GpuMesh, SceneError> {
        let max = ctx.device.limits().max_buffer_size;
        let bytes = (mesh.positions.len() * 12).max(mesh.indices.len() * 4) as u64;
        if bytes > max {
            return Err(obscura::Error::Gpu(format!(
                "mesh needs a {bytes}-byte buffer; the device allows {max}"
            ))
            .into());
        }
        let device = &ctx.device;
        Ok(GpuMesh {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh vertices"),
                contents: bytemuck::cast_slice(&mesh.positions),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            colours: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh colours"),
                contents: bytemuck::cast_slice(&mesh.vertex_colours()),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            index_count: mesh.indices.len() as u32,
        })
    }

    /// Renders `mesh` from `camera` at `width` × `height`, waiting for completion.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn render(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<GBuffer, SceneError> {
        self.render_guarded(ctx, mesh, camera, (width, height), 0)
    }

    /// Renders `mesh` from `camera`'s `width` × `height` view and a guard band of `guard`
    /// pixels around it ([`Camera::widened`]), waiting for completion.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn render_guarded(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        size: (u32, u32),
        guard: u32,
    ) -> Result<GBuffer, SceneError> {
        self.guarded_into((ctx, None), mesh, camera, size, guard)
    }

    /// [`Self::render_guarded`] recorded into `encoder` without waiting (the web's form;
    /// the G-buffer is drawn once `encoder` is submitted). One camera at a time: the camera
    /// uniform is written now, so two views recorded into one encoder share the last one.
    pub fn record_guarded(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &GpuMesh,
        camera: &Camera,
        size: (u32, u32),
        guard: u32,
    ) -> Result<GBuffer, SceneError> {
        self.guarded_into((ctx, Some(encoder)), mesh, camera, size, guard)
    }

    fn guarded_into(
        &self,
        (ctx, encoder): (&GpuContext, Option<&mut wgpu::CommandEncoder>),
        mesh: &GpuMesh,
        camera: &Camera,
        (width, height): (u32, u32),
        guard: u32,
    ) -> Result<GBuffer, SceneError> {
        let (width, height) = guarded_size(ctx, (width, height), guard)?;
        let camera = &camera.widened(height - 2 * guard, guard);
        self.set_camera(ctx, camera, width, height)?;
        let depth = target(ctx, width, height, DEPTH_FORMAT, 1);
        let normals = target(ctx, width, height, NORMAL_FORMAT, 1);
        let albedo = target(ctx, width, height, ALBEDO_FORMAT, 1);
        let depth_view = depth.create_view(&Default::default());
        let normals_view = normals.create_view(&Default::default());
        let albedo_view = albedo.create_view(&Default::default());
        self.draw(
            (ctx, encoder),
            mesh,
            (&self.pipeline, &self.camera_bind(ctx)),
            Some((&normals_view, &albedo_view)),
            &depth_view,
        )?;
        Ok(GBuffer {
            depth,
            depth_view,
            normals,
            normals_view,
            albedo,
            albedo_view,
            width,
            height,
            guard_band: guard,
        })
    }

    /// Peels `gbuffer`'s second depth layer (rendered from `camera` by [`Self::render`] or
    /// [`Self::render_guarded`]): per pixel the nearest front face at least `separation`
    /// (linear view depth; obscura's thickness prior, [`obscura::AoParams::thickness`]
    /// times the radius) behind the first layer, as [`obscura::AoInput::second_layer`]
    /// wants it; the far plane (sky) where there is none. Waits for completion.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn peel(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        gbuffer: &GBuffer,
        separation: f32,
    ) -> Result<DepthLayer, SceneError> {
        self.peel_into((ctx, None), mesh, camera, gbuffer, separation)
    }

    /// [`Self::peel`] recorded into `encoder` after `gbuffer`'s own draw, without waiting
    /// (the web's form).
    pub fn record_peel(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &GpuMesh,
        camera: &Camera,
        gbuffer: &GBuffer,
        separation: f32,
    ) -> Result<DepthLayer, SceneError> {
        self.peel_into((ctx, Some(encoder)), mesh, camera, gbuffer, separation)
    }

    fn peel_into(
        &self,
        (ctx, encoder): (&GpuContext, Option<&mut wgpu::CommandEncoder>),
        mesh: &GpuMesh,
        camera: &Camera,
        gbuffer: &GBuffer,
        separation: f32,
    ) -> Result<DepthLayer, SceneError> {
        if !(separation.is_finite() && separation > 0.0) {
            return Err(SceneError::Camera(format!(
                "the second layer's separation {separation} must be finite and > 0"
            )));
        }
        let (w, h, g) = (gbuffer.width, gbuffer.height, gbuffer.guard_band);
        let camera = &camera.widened(h - 2 * g, g);
        self.set_camera(ctx, camera, w, h)?;
        let lin = camera
            .obscura_projection(w as f32 / h as f32)
            .linearize(DEPTH_CONVENTION)?;
        let uniform = PeelUniform {
            a: lin.a,
            b: lin.b,
            reciprocal: lin.reciprocal as u32,
            separation,
        };
        ctx.queue
            .write_buffer(&self.peel, 0, bytemuck::bytes_of(&uniform));
        let depth = target(ctx, w, h, DEPTH_FORMAT, 1);
        let view = depth.create_view(&Default::default());
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("peel"),
            layout: &self.peel_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.camera.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&gbuffer.depth_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.peel.as_entire_binding(),
                },
            ],
        });
        self.draw(
            (ctx, encoder),
            mesh,
            (&self.peel_pipeline, &bind),
            None,
            &view,
        )?;
        Ok(DepthLayer {
            texture: depth,
            view,
        })
    }

    /// Renders the depth of `mesh` from `camera` with [`MSAA_SAMPLES`] samples per pixel,
    /// waiting for completion.
    pub fn render_msaa_depth(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<MsaaDepth, SceneError> {
        self.render_msaa_depth_guarded(ctx, mesh, camera, (width, height), 0)
    }

    /// [`Self::render_msaa_depth`] of `camera`'s `width` × `height` view and a guard band
    /// of `guard` pixels around it ([`Camera::widened`], as [`Self::render_guarded`]).
    pub fn render_msaa_depth_guarded(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        (width, height): (u32, u32),
        guard: u32,
    ) -> Result<MsaaDepth, SceneError> {
        let (width, height) = guarded_size(ctx, (width, height), guard)?;
        let camera = &camera.widened(height - 2 * guard, guard);
        self.set_camera(ctx, camera, width, height)?;
        let depth = target(ctx, width, height, DEPTH_FORMAT, MSAA_SAMPLES);
        let depth_view = depth.create_view(&Default::default());
        let bind = self.camera_bind(ctx);
        self.draw(
            (ctx, None),
            mesh,
            (&self.msaa_pipeline, &bind),
            None,
            &depth_view,
        )?;
        Ok(MsaaDepth {
            depth,
            depth_view,
            width,
            height,
            guard_band: guard,
        })
    }

    /// The G-buffer's bind group: the camera.
    fn camera_bind(&self, ctx: &GpuContext) -> wgpu::BindGroup {
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: self.camera.as_entire_binding(),
            }],
        })
    }

    /// Checks the camera and the size, and uploads the camera for the next draw.
    fn set_camera(
        &self,
        ctx: &GpuContext,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<(), SceneError> {
        camera.validate()?;
        let max = ctx.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(obscura::Error::TooLarge { width, height, max }.into());
        }
        let aspect = width as f32 / height as f32;
        let uniform = CameraUniform {
            view: camera.view_matrix().to_cols_array_2d(),
            proj: camera.projection_matrix(aspect).to_cols_array_2d(),
        };
        ctx.queue
            .write_buffer(&self.camera, 0, bytemuck::bytes_of(&uniform));
        Ok(())
    }

    /// Draws `mesh` with `pipeline` into the targets, waiting for completion.
    /// Draws into `encoder`, or (natively, with `None`) submits and waits.
    fn draw(
        &self,
        (ctx, encoder): (&GpuContext, Option<&mut wgpu::CommandEncoder>),
        mesh: &GpuMesh,
        (pipeline, bind): (&wgpu::RenderPipeline, &wgpu::BindGroup),
        colour_views: Option<(&wgpu::TextureView, &wgpu::TextureView)>,
        depth_view: &wgpu::TextureView,
    ) -> Result<(), SceneError> {
        let attachment = |view, clear| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        // Sky: normal +z, albedo 0 (alpha 0).
        let sky_normal = wgpu::Color {
            r: 0.0,
            g: 0.0,
            b: 1.0,
            a: 0.0,
        };
        let color: Vec<_> = colour_views
            .map(|(n, a)| {
                vec![
                    attachment(n, sky_normal),
                    attachment(a, wgpu::Color::TRANSPARENT),
                ]
            })
            .unwrap_or_default();
        let record = |enc: &mut wgpu::CommandEncoder| {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                // The depth-only pipeline has no colour target at all (not a `None` one).
                color_attachments: &color,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(SKY_DEPTH),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind, &[]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_vertex_buffer(1, mesh.colours.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        };
        match encoder {
            Some(enc) => record(enc),
            #[cfg(not(target_arch = "wasm32"))]
            None => ctx.run(|enc| {
                record(enc);
                Ok(())
            })?,
            #[cfg(target_arch = "wasm32")]
            None => {
                let _ = ctx;
                return Err(obscura::Error::Gpu(
                    "on the web, record into an encoder (GBufferRenderer::record_guarded)".into(),
                )
                .into());
            }
        }
        Ok(())
    }
}

/// One render target of `format` and `samples` per pixel (the size checked by `set_camera`).
fn target(
    ctx: &GpuContext,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    samples: u32,
) -> wgpu::Texture {
    // Multisampled textures cannot be copied out; single-sampled ones can (tests).
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::TEXTURE_BINDING
        | if samples == 1 {
            wgpu::TextureUsages::COPY_SRC
        } else {
            wgpu::TextureUsages::empty()
        };
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(match format {
            DEPTH_FORMAT => "gbuffer depth",
            NORMAL_FORMAT => "gbuffer normals",
            _ => "gbuffer albedo",
        }),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The size of a `width` × `height` view with a guard band of `guard` pixels on each side;
/// an empty view or a band past `u32` is an error.
fn guarded_size(
    ctx: &GpuContext,
    (width, height): (u32, u32),
    guard: u32,
) -> Result<(u32, u32), SceneError> {
    if width == 0 || height == 0 {
        let max = ctx.device.limits().max_texture_dimension_2d;
        return Err(obscura::Error::TooLarge { width, height, max }.into());
    }
    let too_wide = || SceneError::Camera(format!("a guard band of {guard} px is too wide"));
    let grow = |s: u32| s.checked_add(guard.checked_mul(2)?);
    Ok((
        grow(width).ok_or_else(too_wide)?,
        grow(height).ok_or_else(too_wide)?,
    ))
}

//! Rasterizes a [`Mesh`] seen by a [`Camera`] into a G-buffer: `Depth32Float` depth
//! (standard convention), `Rgba16Float` view-space normals and `Rgba8Unorm` linear albedo.

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

impl GBuffer {
    /// obscura's input for this G-buffer seen by `camera` (the view's camera, not the
    /// widened one): standard depth, the camera's projection, the G-buffer's normals when
    /// `with_normals` (else reconstructed), and the view inside its guard band.
    pub fn ao_input(&self, camera: &Camera, with_normals: bool) -> obscura::AoInput<'_> {
        let g = self.guard_band;
        // (A band wider than the textures gives an empty viewport, refused by obscura.)
        let inner = |s: u32| s.saturating_sub(g.saturating_mul(2));
        let (w, h) = (inner(self.width), inner(self.height));
        obscura::AoInput {
            depth: &self.depth_view,
            convention: obscura::DepthConvention::Standard,
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
            output: None,
        }
    }
}

/// Multisampled depth of one view ([`MSAA_SAMPLES`] per pixel, [`DEPTH_FORMAT`]), as an
/// MSAA renderer's depth attachment holds it.
#[derive(Debug)]
pub struct MsaaDepth {
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    pub width: u32,
    pub height: u32,
}

impl MsaaDepth {
    /// obscura's input for this depth seen by `camera` (normals reconstructed).
    pub fn ao_input(&self, camera: &Camera) -> obscura::AoInput<'_> {
        obscura::AoInput {
            depth: &self.depth_view,
            convention: obscura::DepthConvention::Standard,
            projection: camera.obscura_projection(self.width as f32 / self.height as f32),
            normals: None,
            viewport: None,
            guard_band: 0,
            output: None,
        }
    }
}

/// The G-buffer render pipelines: depth and normals, and multisampled depth alone.
#[derive(Debug)]
pub struct GBufferRenderer {
    pipeline: wgpu::RenderPipeline,
    msaa_pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
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
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label,
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/gbuffer.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label,
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let targets = [Some(NORMAL_FORMAT.into()), Some(ALBEDO_FORMAT.into())];
        let make = |samples: u32| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label,
                layout: Some(&pipeline_layout),
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
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                // Multisampled: depth only.
                fragment: (samples == 1).then(|| wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = make(1);
        let msaa_pipeline = make(MSAA_SAMPLES);
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
    pub fn render_guarded(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        camera: &Camera,
        (width, height): (u32, u32),
        guard: u32,
    ) -> Result<GBuffer, SceneError> {
        if width == 0 || height == 0 {
            let max = ctx.device.limits().max_texture_dimension_2d;
            return Err(obscura::Error::TooLarge { width, height, max }.into());
        }
        let too_wide = || SceneError::Camera(format!("a guard band of {guard} px is too wide"));
        let grow = |s: u32| s.checked_add(guard.checked_mul(2)?);
        let (width, height) = (
            grow(width).ok_or_else(too_wide)?,
            grow(height).ok_or_else(too_wide)?,
        );
        let camera = &camera.widened(height - 2 * guard, guard);
        self.set_camera(ctx, camera, width, height)?;
        let depth = target(ctx, width, height, DEPTH_FORMAT, 1);
        let normals = target(ctx, width, height, NORMAL_FORMAT, 1);
        let albedo = target(ctx, width, height, ALBEDO_FORMAT, 1);
        let depth_view = depth.create_view(&Default::default());
        let normals_view = normals.create_view(&Default::default());
        let albedo_view = albedo.create_view(&Default::default());
        self.draw(
            ctx,
            mesh,
            &self.pipeline,
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
        self.set_camera(ctx, camera, width, height)?;
        let depth = target(ctx, width, height, DEPTH_FORMAT, MSAA_SAMPLES);
        let depth_view = depth.create_view(&Default::default());
        self.draw(ctx, mesh, &self.msaa_pipeline, None, &depth_view)?;
        Ok(MsaaDepth {
            depth,
            depth_view,
            width,
            height,
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
    fn draw(
        &self,
        ctx: &GpuContext,
        mesh: &GpuMesh,
        pipeline: &wgpu::RenderPipeline,
        colour_views: Option<(&wgpu::TextureView, &wgpu::TextureView)>,
        depth_view: &wgpu::TextureView,
    ) -> Result<(), SceneError> {
        let bind = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: self.camera.as_entire_binding(),
            }],
        });
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
        ctx.run(|enc| {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                // The depth-only pipeline has no colour target at all (not a `None` one).
                color_attachments: &color,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_vertex_buffer(1, mesh.colours.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
            Ok(())
        })?;
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

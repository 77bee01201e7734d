//! obscura's ambient occlusion in Bevy 0.19, in place of Bevy's SSAO.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use obscura_bevy::{ObscuraAo, ObscuraPlugin};
//!
//! fn setup(mut commands: Commands) {
//!     // The radius is in world units; everything else takes obscura's defaults.
//!     commands.spawn((Camera3d::default(), Msaa::Off, ObscuraAo { radius: 0.5, ..default() }));
//! }
//!
//! App::new().add_plugins((DefaultPlugins, ObscuraPlugin)).add_systems(Startup, setup);
//! ```
//!
//! The component requires Bevy's [`ScreenSpaceAmbientOcclusion`], so Bevy sets up what
//! its PBR lighting reads (the depth and normal prepasses, the AO texture, the shader's
//! occlusion of ambient and indirect light); the plugin keeps Bevy's SSAO passes from
//! running for that camera and writes obscura's AO into the texture instead, each frame
//! after the prepass and before the main pass. obscura reads the prepass depth as Bevy
//! writes it (reversed Z, infinite far plane: [`obscura::DepthConvention::ReversedZInfinite`])
//! with the view's projection matrix ([`obscura::Projection::from_matrix`]) and the
//! prepass's world-space normals ([`obscura::NormalEncoding::WorldUnorm`]).
//!
//! Bevy 0.19 makes its AO texture only where MSAA is off (its SSAO refuses multisampled
//! depth), so the camera needs `Msaa::Off`, as with Bevy's own SSAO.

use bevy::core_pipeline::core_3d::main_opaque_pass_3d;
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::ecs::query::Has;
use bevy::log::error_once;
use bevy::pbr::{
    ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionResources, SsaoBindGroups,
};
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy::render::renderer::{
    RenderContext, RenderDevice, RenderGraph, RenderGraphSystems, RenderQueue, ViewQuery,
};
use bevy::render::view::ExtractedView;
use bevy::render::RenderApp;
use obscura::wgpu;
use std::collections::hash_map::{Entry, HashMap};

pub use obscura;

pub mod headless;

/// obscura's AO on a 3D camera, in place of Bevy's SSAO: put it on a camera with
/// `Msaa::Off`. Its fields are obscura's settings, with obscura's defaults.
#[derive(Component, ExtractComponent, Clone, Debug, PartialEq)]
#[require(ScreenSpaceAmbientOcclusion)]
pub struct ObscuraAo {
    /// The AO radius in world units: occluders farther than this from a point do not
    /// shade it.
    pub radius: f32,
    /// The estimator (obscura's default: GTAO).
    pub estimator: obscura::Estimator,
    /// Samples per pixel by preset (obscura's default: High).
    pub preset: obscura::Preset,
    /// The pass layout (default: 2×2 deinterleaved).
    pub mode: obscura::AoMode,
    /// The AO's working resolution (default: full).
    pub resolution: obscura::Resolution,
    /// Filtering at the working resolution (default: the edge-aware spatial denoiser).
    pub denoise: obscura::Denoise,
    /// The bitmask estimator's thickness prior, times the radius (default 1).
    pub thickness: f32,
    /// Read the prepass's normals (the default); `false` reconstructs them from the depth.
    pub prepass_normals: bool,
    /// Temporal accumulation: at most this many frames of history, reprojected with the
    /// camera's motion between frames (0 = off, obscura's default; else 2..=256).
    pub history: u32,
}

impl Default for ObscuraAo {
    fn default() -> Self {
        let o = obscura::AoOptions::default();
        Self {
            radius: 0.5,
            estimator: o.estimator,
            preset: obscura::Preset::default(),
            mode: o.mode,
            resolution: o.resolution,
            denoise: o.denoise,
            thickness: obscura::DEFAULT_THICKNESS,
            prepass_normals: true,
            history: o.history,
        }
    }
}

impl ObscuraAo {
    /// The library's options for these settings.
    pub fn options(&self) -> obscura::AoOptions {
        obscura::AoOptions {
            estimator: self.estimator,
            mode: self.mode,
            resolution: self.resolution,
            denoise: self.denoise,
            history: self.history,
            ..Default::default()
        }
        .with_preset(self.preset)
    }

    /// The library's per-frame parameters for these settings.
    pub fn params(&self) -> obscura::AoParams {
        obscura::AoParams {
            radius: self.radius,
            thickness: self.thickness,
            ..Default::default()
        }
    }
}

/// Adds obscura's AO to every camera with [`ObscuraAo`].
pub struct ObscuraPlugin;

impl Plugin for ObscuraPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(ExtractComponentPlugin::<ObscuraAo>::default());
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<ObscuraViews>()
            .add_systems(
                RenderGraph,
                skip_bevy_ssao.in_set(RenderGraphSystems::Begin),
            )
            .add_systems(
                Core3d,
                obscura_pass
                    .in_set(Core3dSystems::MainPass)
                    .before(main_opaque_pass_3d),
            );
    }
}

/// Bevy's SSAO pass runs only for views with its bind groups: without them its system
/// skips the view, and the texture it would have written is obscura's to fill. The state
/// of views that no longer carry [`ObscuraAo`] is dropped.
fn skip_bevy_ssao(
    mut commands: Commands,
    views: Query<(Entity, Has<SsaoBindGroups>), With<ObscuraAo>>,
    mut state: ResMut<ObscuraViews>,
) {
    for (view, ssao) in &views {
        if ssao {
            commands.entity(view).remove::<SsaoBindGroups>();
        }
    }
    state.views.retain(|view, _| views.contains(*view));
}

/// obscura's AO of the last frame of render-world view `view` (`R32Float`, the view's size,
/// 1 = unoccluded; `COPY_SRC`), the texture the plugin copied into Bevy's: for tests and
/// tools that read it back. `None` before the view's first frame.
pub fn ao_texture(render_world: &World, view: Entity) -> Option<&wgpu::Texture> {
    render_world
        .get_resource::<ObscuraViews>()?
        .views
        .get(&view)?
        .ao
        .output()
}

/// Per camera: obscura's passes for its options, and the view matrix of its last frame
/// (for the temporal history's reprojection).
struct ViewAo {
    options: obscura::AoOptions,
    ao: obscura::Ao,
    view_from_world: Option<Mat4>,
}

/// The render world's obscura state: one [`ViewAo`] per camera, and the copy pipelines by
/// the format of Bevy's AO texture.
#[derive(Resource, Default)]
struct ObscuraViews {
    views: HashMap<Entity, ViewAo>,
    copies: HashMap<wgpu::TextureFormat, (wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
}

/// The copy from obscura's `R32Float` AO into Bevy's AO texture (`R16Float` or `R32Float`).
fn copy_source(format: &str) -> String {
    format!(
        "@group(0) @binding(0) var src: texture_2d<f32>;\n\
         @group(0) @binding(1) var dst: texture_storage_2d<{format}, write>;\n\
         @compute @workgroup_size(8, 8, 1)\n\
         fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{\n\
             if any(gid.xy >= textureDimensions(dst)) {{ return; }}\n\
             textureStore(dst, gid.xy, vec4<f32>(textureLoad(src, gid.xy, 0).x, 0.0, 0.0, 1.0));\n\
         }}\n"
    )
}

fn copy_pipeline(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
) -> Option<(wgpu::BindGroupLayout, wgpu::ComputePipeline)> {
    let name = match format {
        wgpu::TextureFormat::R16Float => "r16float",
        wgpu::TextureFormat::R32Float => "r32float",
        _ => return None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("obscura-bevy copy"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
        ],
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("obscura-bevy copy"),
        source: wgpu::ShaderSource::Wgsl(copy_source(name).into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("obscura-bevy copy"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("obscura-bevy copy"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    Some((layout, pipeline))
}

/// obscura's AO for one view, written into Bevy's AO texture.
#[allow(clippy::too_many_arguments)]
fn obscura_pass(
    view: ViewQuery<(
        Entity,
        &ObscuraAo,
        &ScreenSpaceAmbientOcclusionResources,
        &ViewPrepassTextures,
        &ExtractedView,
    )>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut state: ResMut<ObscuraViews>,
    mut ctx: RenderContext,
) {
    let (entity, settings, resources, prepass, extracted) = view.into_inner();
    let Some(depth) = prepass.depth_view() else {
        return;
    };
    let depth: &wgpu::TextureView = depth;
    let device = device.wgpu_device();
    let queue: &wgpu::Queue = &queue.0;
    let options = settings.options();
    let state = &mut *state;
    let view_ao = match state.views.get_mut(&entity) {
        Some(v) if v.options == options => v,
        _ => match obscura::Ao::new(device, options) {
            Ok(ao) => {
                let view = ViewAo {
                    options,
                    ao,
                    view_from_world: None,
                };
                state.views.insert(entity, view);
                state.views.get_mut(&entity).expect("inserted")
            }
            Err(e) => {
                error_once!("obscura: {e}");
                return;
            }
        },
    };
    let convention = obscura::DepthConvention::ReversedZInfinite;
    let projection = match obscura::Projection::from_matrix(
        extracted.clip_from_view.to_cols_array_2d(),
        convention,
    ) {
        Ok(p) => p,
        Err(e) => {
            error_once!("obscura: {e}");
            return;
        }
    };
    let world_from_view = extracted.world_from_view.to_matrix();
    let view_from_world = world_from_view.inverse();
    // The camera's motion since the last frame, as obscura's history reprojects it:
    // previous view-from-world times this frame's world-from-view.
    let motion = match view_ao.view_from_world.replace(view_from_world) {
        None => obscura::CameraMotion::Cut,
        Some(previous) if previous == view_from_world => obscura::CameraMotion::Still,
        Some(previous) => obscura::CameraMotion::Moved {
            previous_from_current: (previous * world_from_view).to_cols_array_2d(),
        },
    };
    // The rotation that takes the prepass's world normals to view space.
    let view_from_world = Mat3::from_mat4(view_from_world).to_cols_array_2d();
    let normals = prepass
        .normal_view()
        .filter(|_| settings.prepass_normals)
        .map(|n| {
            let n: &wgpu::TextureView = n;
            (n, obscura::NormalEncoding::WorldUnorm { view_from_world })
        });
    let target = &resources.screen_space_ambient_occlusion_texture;
    let input = obscura::AoInput {
        depth,
        convention,
        projection,
        normals,
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    };
    // Bevy's GPU timestamps around obscura's passes and the copy, as around its own SSAO:
    // `render/obscura/elapsed_gpu` with its `RenderDiagnosticsPlugin`.
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let span = diagnostics.time_span(ctx.command_encoder(), "obscura");
    let encoder = ctx.command_encoder();
    let written = view_ao
        .ao
        .record(
            device,
            queue,
            encoder,
            &input,
            &obscura::AoParams {
                motion,
                ..settings.params()
            },
        )
        .map_err(|e| e.to_string())
        .and_then(|()| {
            let ao = view_ao.ao.output_view().ok_or("no output")?;
            copy_into(device, encoder, &mut state.copies, ao, target)
        });
    span.end(ctx.command_encoder());
    if let Err(e) = written {
        error_once!("obscura: {e}");
    }
}

/// Copies obscura's AO (`ao`) into Bevy's AO texture (`target`).
fn copy_into(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    copies: &mut HashMap<wgpu::TextureFormat, (wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
    ao: &wgpu::TextureView,
    target: &bevy::render::texture::CachedTexture,
) -> Result<(), String> {
    let format = target.texture.format();
    let (layout, pipeline) = match copies.entry(format) {
        Entry::Occupied(e) => e.into_mut(),
        Entry::Vacant(v) => v.insert(copy_pipeline(device, format).ok_or(format!(
            "Bevy's AO texture is {format:?}; expected R16Float or R32Float"
        ))?),
    };
    let dst: &wgpu::TextureView = &target.default_view;
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("obscura-bevy copy"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(ao),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(dst),
            },
        ],
    });
    let size = target.texture.size();
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("obscura-bevy copy"),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind, &[]);
    pass.dispatch_workgroups(size.width.div_ceil(8), size.height.div_ceil(8), 1);
    Ok(())
}

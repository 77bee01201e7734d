//! Headless frames for tests, tools and measurements: an app without a window whose
//! camera renders to a linear float image, surfaces of a near-black rough albedo lit by
//! ambient light alone. Bevy occludes only ambient and indirect light, and at this albedo
//! its multi-bounce fit is the identity (to 1e-5; peers/bevy), so a frame over the same
//! frame without AO is the AO that reached the lighting.

use crate::ObscuraPlugin;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::light::GlobalAmbientLight;
use bevy::prelude::*;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::texture::GpuImage;
use bevy::render::view::Msaa;
use bevy::render::{RenderApp, RenderPlugin};
use obscura::wgpu;
use std::time::Instant;

/// The surfaces' albedo: near black, where Bevy's multi-bounce fit is the identity.
pub const ALBEDO: f32 = 0.001;

/// A windowless app with [`ObscuraPlugin`], pipelines compiled at once (so a frame after
/// the first is complete), ambient light alone, a black clear colour.
pub fn app() -> App {
    let mut app = App::new();
    let plugins = DefaultPlugins.set(RenderPlugin {
        synchronous_pipeline_compilation: true,
        ..default()
    });
    // With the viewer's window features on, still no window and no event loop.
    #[cfg(feature = "viewer")]
    let plugins = plugins
        .set(bevy::window::WindowPlugin {
            primary_window: None,
            exit_condition: bevy::window::ExitCondition::DontExit,
            ..default()
        })
        .disable::<bevy::winit::WinitPlugin>();
    app.add_plugins(plugins)
        .add_plugins(ObscuraPlugin)
        .insert_resource(GlobalAmbientLight {
            color: Color::WHITE,
            brightness: 500.0 / ALBEDO,
            ..default()
        })
        .insert_resource(ClearColor(Color::BLACK));
    app.finish();
    app.cleanup();
    app
}

/// The rough, non-reflective material of [`ALBEDO`].
pub fn matte(world: &mut World) -> Handle<StandardMaterial> {
    world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::linear_rgb(ALBEDO, ALBEDO, ALBEDO),
            perceptual_roughness: 1.0,
            metallic: 0.0,
            reflectance: 0.0,
            ..default()
        })
}

/// A `width` × `height` `Rgba32Float` image to render into, readable by [`read_image`].
pub fn target(world: &mut World, width: u32, height: u32) -> Handle<Image> {
    let mut image = Image::new_target_texture(width, height, TextureFormat::Rgba32Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    world.resource_mut::<Assets<Image>>().add(image)
}

/// A camera that renders linearly into `target`: HDR, no tonemapping, no dithering, no
/// MSAA (Bevy's AO texture needs it off).
pub fn camera(target: &Handle<Image>) -> impl Bundle {
    (
        Camera3d::default(),
        RenderTarget::Image(target.clone().into()),
        Hdr,
        Tonemapping::None,
        DebandDither::Disabled,
        Msaa::Off,
    )
}

/// One frame: update, then wait for the device. Its wall time in ms.
pub fn frame(app: &mut App) -> f64 {
    let start = Instant::now();
    app.update();
    let device = app.sub_app(RenderApp).world().resource::<RenderDevice>();
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    start.elapsed().as_secs_f64() * 1e3
}

/// The red channel of `image` (a [`target`]) after the last frame, top row first.
pub fn read_image(app: &App, image: &Handle<Image>) -> Option<Vec<f32>> {
    let world = app.sub_app(RenderApp).world();
    let gpu = world.resource::<RenderAssets<GpuImage>>().get(image.id())?;
    Some(read_texture(world, &gpu.texture, 16))
}

/// The first channel of each texel of `texture` (one 2D layer of a 32-bit float format,
/// `texel` bytes a texel: 4 for `R32Float`, 16 for `Rgba32Float`; `COPY_SRC` usage), top row
/// first, read back on the render world's device: for tests, tools and screenshots.
pub fn read_texture(render_world: &World, texture: &wgpu::Texture, texel: u32) -> Vec<f32> {
    let device = render_world.resource::<RenderDevice>().wgpu_device();
    let queue: &wgpu::Queue = &render_world.resource::<RenderQueue>().0;
    let (w, h) = (texture.width(), texture.height());
    let row = (w * texel).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("obscura-bevy readback"),
        size: u64::from(row * h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    let data = buffer.slice(..).get_mapped_range();
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let at = y * row as usize + x * texel as usize;
            out.push(f32::from_le_bytes([
                data[at],
                data[at + 1],
                data[at + 2],
                data[at + 3],
            ]));
        }
    }
    out
}

//! Bevy's SSAO (`ScreenSpaceAmbientOcclusion`) and obscura through its Bevy plugin
//! (`obscura_bevy::ObscuraAo`) in one app, on the same prepasses and frames of obscura's
//! shared views, for `obscura eval --score-images`.
//!
//! ```sh
//! obscura-peer-bevy VIEWS_JSON OUT_ROOT [--qualities low,medium,high,ultra]
//!                   [--obscura low,medium,high,ultra|none] [--runs 5] [--times times.json]
//! ```
//!
//! VIEWS_JSON comes from `obscura eval --all --export-views` (each view's scene, camera and
//! AO radius). Every surface is rough and non-reflective, and lit by ambient light only:
//! Bevy applies its SSAO to the ambient term alone, so the frame with SSAO divided by the
//! same frame without it, per pixel, is Bevy's AO.
//!
//! **Albedo.** Bevy brightens its AO by a multi-bounce fit that grows with the albedo
//! (Jimenez et al. 2016, "Practical Realtime Strategies for Accurate Indirect Occlusion",
//! ssao_utils.wgsl): at white, a visibility of 0.5 is shown as 0.90. The ray-traced truth is
//! visibility without bounces, so the surfaces are nearly black ([`ALBEDO`]), where the fit
//! is the identity to within 1e-5, and the ambient light is bright in proportion. Writes
//! `OUT_ROOT/bevy-QUALITY/VIEW.png` and `OUT_ROOT/obscura-bevy-PRESET/VIEW.png` (16-bit
//! grey, white = unoccluded) and the timing (`--times`, beside the images). obscura's AO
//! reaches the frame the way Bevy's does (the plugin writes Bevy's AO texture), so the same
//! ratio of frames is obscura's AO as the lighting sees it.
//!
//! **Radius.** Bevy's SSAO has no radius setting: its shader fixes it at 0.5 × 1.457 world
//! units (XeGTAO's default radius and multiplier). Each view's world (mesh and camera) is
//! therefore scaled uniformly by that radius ÷ the view's AO radius; the picture is the same
//! and Bevy's radius is obscura's. Bevy's own thickness (0.25 units) scales with it, so it is
//! 0.34 × the radius on every view.
//!
//! **Time.** Bevy's own GPU timestamps around its SSAO (`render/ssao/elapsed_gpu` of its
//! `RenderDiagnosticsPlugin`: the depth mips, the AO and the spatial denoiser) and around
//! obscura's passes (`render/obscura/elapsed_gpu`: every pass of its frame and the copy
//! into Bevy's texture), the median over the frames with AO. Beside it, as a check, the median wall time of a frame
//! (`App::update` and a wait on the device) with SSAO minus that of one without it,
//! alternated after a warm-up; both keep the depth and normal prepasses that Bevy's SSAO
//! needs, and the prepasses' own wall cost is recorded apart. Where the adapter has no
//! timestamp queries the wall difference is the time.
//!
//! MSAA is off (Bevy's SSAO requires it) and tonemapping too, so the frame is linear.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use bevy::asset::RenderAssetUsages;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::prepass::{DepthPrepass, NormalPrepass};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::diagnostic::{DiagnosticPath, DiagnosticsStore};
use bevy::light::GlobalAmbientLight;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel};
use bevy::prelude::*;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::TextureUsages;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::texture::GpuImage;
use bevy::render::view::Msaa;
use bevy::render::{RenderApp, RenderPlugin};
use obscura_bevy::{obscura, ObscuraAo, ObscuraPlugin};

/// The AO radius Bevy's shader fixes, in world units (ssao.wgsl: `effect_radius`).
const BEVY_RADIUS: f32 = 0.5 * 1.457;
/// The surfaces' albedo: Bevy's multi-bounce fit `max(x, ((a x + b) x + c) x)` is x to
/// within 1e-5 here (it is exactly x at 0).
const ALBEDO: f32 = 0.001;
/// Bevy's default near plane (`PerspectiveProjection::default().near`, world units). Its
/// SSAO adds 1e-5 to the reverse-Z depth of the pixel it shades (ssao.wgsl, "avoid depth
/// precision issues"), which is `near / z`: with obscura's views' near planes (the far ÷
/// 10,000), 1e-5 moves a pixel 40 radii away by 3 of them towards the camera and its AO
/// vanishes. So each view is rendered at Bevy's default near plane, as its users have it
/// (the further of the two), and the pixels that it clips are counted.
const BEVY_NEAR: f32 = 0.1;
/// The ambient light, in proportion to 1 / [`ALBEDO`] so that a lit frame is near 0.5 after
/// Bevy's default exposure.
const AMBIENT: f32 = 1000.0 / ALBEDO;
/// The target's format: linear and exact enough for a ratio of two frames.
const TARGET_FORMAT: bevy::render::render_resource::TextureFormat =
    bevy::render::render_resource::TextureFormat::Rgba32Float;

struct View {
    name: String,
    scene: PathBuf,
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fov_y_deg: f32,
    near: f32,
    far: f32,
    radius: f32,
    width: u32,
    height: u32,
}

struct Args {
    views: PathBuf,
    out: PathBuf,
    qualities: Vec<String>,
    presets: Vec<String>,
    runs: usize,
    times: String,
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn parse_args() -> Result<Args, String> {
    let mut positional = Vec::new();
    let mut qualities = "low,medium,high,ultra".to_string();
    let mut presets = "low,medium,high,ultra".to_string();
    let mut runs = 5usize;
    let mut times = "times.json".to_string();
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--qualities" => qualities = value("--qualities")?,
            "--obscura" => presets = value("--obscura")?,
            "--runs" => {
                runs = value("--runs")?
                    .parse()
                    .map_err(|_| "--runs takes a whole number".to_string())?;
                if runs == 0 {
                    return Err("--runs must be at least 1".into());
                }
            }
            "--times" => times = value("--times")?,
            "-h" | "--help" => {
                println!("obscura-peer-bevy VIEWS_JSON OUT_ROOT [--qualities low,medium,high,ultra] [--obscura low,medium,high,ultra|none] [--runs 5] [--times times.json]");
                std::process::exit(0);
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            _ => positional.push(PathBuf::from(a)),
        }
    }
    let [views, out]: [PathBuf; 2] = positional
        .try_into()
        .map_err(|_| "expected VIEWS_JSON OUT_ROOT (see --help)".to_string())?;
    let qualities: Vec<String> = qualities.split(',').map(str::to_string).collect();
    for q in &qualities {
        quality(q)?;
    }
    let presets: Vec<String> = match presets.as_str() {
        "none" => Vec::new(),
        p => p.split(',').map(str::to_string).collect(),
    };
    for p in &presets {
        preset(p)?;
    }
    Ok(Args {
        views,
        out,
        qualities,
        presets,
        runs,
        times,
    })
}

fn quality(name: &str) -> Result<ScreenSpaceAmbientOcclusionQualityLevel, String> {
    use ScreenSpaceAmbientOcclusionQualityLevel as Q;
    Ok(match name {
        "low" => Q::Low,
        "medium" => Q::Medium,
        "high" => Q::High,
        "ultra" => Q::Ultra,
        _ => {
            return Err(format!(
                "unknown quality `{name}` (low, medium, high, ultra)"
            ))
        }
    })
}

fn preset(name: &str) -> Result<obscura::Preset, String> {
    use obscura::Preset as P;
    Ok(match name {
        "low" => P::Low,
        "medium" => P::Medium,
        "high" => P::High,
        "ultra" => P::Ultra,
        _ => {
            return Err(format!(
                "unknown obscura preset `{name}` (low, medium, high, ultra, or none)"
            ))
        }
    })
}

/// One AO on the camera: Bevy's SSAO at a quality, or obscura's plugin at a preset.
#[derive(Clone)]
enum Variant {
    Bevy(ScreenSpaceAmbientOcclusion),
    Obscura(ObscuraAo),
}

impl Variant {
    /// Bevy's diagnostic path of the variant's GPU time span.
    fn gpu_path(&self) -> &'static str {
        match self {
            Variant::Bevy(_) => "render/ssao/elapsed_gpu",
            Variant::Obscura(_) => "render/obscura/elapsed_gpu",
        }
    }

    fn insert(&self, camera: &mut EntityWorldMut) {
        match self {
            Variant::Bevy(s) => camera.insert(s.clone()),
            Variant::Obscura(o) => camera.insert(o.clone()),
        };
    }

    /// Takes any AO off the camera (`ObscuraAo` requires Bevy's component: both go).
    fn remove(camera: &mut EntityWorldMut) {
        camera.remove::<(ObscuraAo, ScreenSpaceAmbientOcclusion)>();
    }
}

fn read_views(path: &Path) -> Result<Vec<View>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = |what: &str| format!("{}: {what}", path.display());
    let views = json["views"].as_array().ok_or(bad("no `views` list"))?;
    let f = |v: &serde_json::Value, k: &str| {
        v[k].as_f64()
            .map(|x| x as f32)
            .ok_or(bad(&format!("a view lacks `{k}`")))
    };
    let v3 = |v: &serde_json::Value, k: &str| -> Result<Vec3, String> {
        let a = v[k].as_array().filter(|a| a.len() == 3);
        let a = a.ok_or(bad(&format!("a view's `{k}` is not 3 numbers")))?;
        let n: Vec<f32> = a
            .iter()
            .filter_map(|x| x.as_f64())
            .map(|x| x as f32)
            .collect();
        (n.len() == 3)
            .then(|| Vec3::new(n[0], n[1], n[2]))
            .ok_or(bad(&format!("a view's `{k}` is not 3 numbers")))
    };
    views
        .iter()
        .map(|v| {
            Ok(View {
                name: v["name"].as_str().ok_or(bad("a view lacks `name`"))?.into(),
                scene: v["scene"]
                    .as_str()
                    .ok_or(bad("a view lacks `scene`"))?
                    .into(),
                eye: v3(v, "eye")?,
                target: v3(v, "target")?,
                up: v3(v, "up")?,
                fov_y_deg: f(v, "fov_y_deg")?,
                near: f(v, "near")?,
                far: f(v, "far")?,
                radius: f(v, "radius")?,
                width: f(v, "width")? as u32,
                height: f(v, "height")? as u32,
            })
        })
        .collect()
}

/// obscura-scene's mesh (the geometry obscura and its ray tracer see) as a Bevy mesh with
/// flat normals: obscura's G-buffer has face normals, and Bevy's SSAO reads the normals.
fn bevy_mesh(path: &Path) -> Result<Mesh, String> {
    let m = obscura_scene::Mesh::load(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, m.positions)
    .with_inserted_indices(Indices::U32(m.indices));
    mesh.duplicate_vertices();
    mesh.compute_flat_normals();
    Ok(mesh)
}

/// A frame: update the app, then wait until the device is idle. Its wall time in ms.
fn frame(app: &mut App) -> f64 {
    let start = Instant::now();
    app.update();
    let device = app.sub_app(RenderApp).world().resource::<RenderDevice>();
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    start.elapsed().as_secs_f64() * 1e3
}

/// The red channel of the camera's target, top row first.
fn read_target(app: &mut App, image: &Handle<Image>, width: u32, height: u32) -> Vec<f32> {
    let world = app.sub_app(RenderApp).world();
    let device = world.resource::<RenderDevice>().wgpu_device();
    let queue = world.resource::<RenderQueue>();
    let gpu = world
        .resource::<RenderAssets<GpuImage>>()
        .get(image.id())
        .expect("the camera's target is on the GPU after a frame");
    let row = (width * 16).div_ceil(256) * 256;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(row * height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        gpu.texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    buffer
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    let data = buffer.slice(..).get_mapped_range();
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height as usize {
        for x in 0..width as usize {
            let at = y * row as usize + x * 16;
            out.push(f32::from_le_bytes(data[at..at + 4].try_into().unwrap()));
        }
    }
    out
}

/// The GPU time of a diagnostic span (`path`) in each frame since the last call, in ms.
fn gpu_ms(app: &mut App, path: &'static str) -> Vec<f64> {
    let path = DiagnosticPath::new(path);
    let mut store = app.world_mut().resource_mut::<DiagnosticsStore>();
    let Some(d) = store.get_mut(&path) else {
        return Vec::new();
    };
    let v = d.values().copied().collect();
    d.clear_history();
    v
}

/// The view's perspective in the world scaled by `scale`, with its near plane at `near`.
fn projection(v: &View, scale: f32, near: f32) -> Projection {
    Projection::Perspective(PerspectiveProjection {
        fov: v.fov_y_deg.to_radians(),
        aspect_ratio: v.width as f32 / v.height as f32,
        near,
        far: v.far * scale,
        // Bevy clips at this plane, not at `near`: it must follow it.
        near_clip_plane: Vec4::new(0.0, 0.0, -1.0, -near),
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn write_png(path: &Path, width: u32, height: u32, ao: &[f32]) -> Result<(), String> {
    let px: Vec<u16> = ao
        .iter()
        .map(|a| (a.clamp(0.0, 1.0) * 65535.0).round() as u16)
        .collect();
    let img = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(width, height, px)
        .ok_or("image size")?;
    // Written beside, then renamed: never a half-written picture.
    let tmp = path.with_extension("png.tmp");
    img.save_with_format(&tmp, image::ImageFormat::Png)
        .map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let views = read_views(&args.views)?;
    if views.is_empty() {
        return Err(format!("{}: no views", args.views.display()));
    }
    for v in &views {
        if !(v.radius > 0.0 && v.near > 0.0 && v.far > v.near && v.width > 0 && v.height > 0) {
            return Err(format!("view {}: bad radius, clip planes or size", v.name));
        }
    }
    // Bevy's qualities, then obscura's presets: (folder, AO, label for the log and JSON).
    let mut variants: Vec<(PathBuf, Variant, String)> = Vec::new();
    for q in &args.qualities {
        let ssao = ScreenSpaceAmbientOcclusion {
            quality_level: quality(q)?,
            ..default()
        };
        variants.push((
            args.out.join(format!("bevy-{q}")),
            Variant::Bevy(ssao),
            q.clone(),
        ));
    }
    for p in &args.presets {
        // The world is scaled so that Bevy's fixed radius is the view's: obscura's is the
        // same number of world units. Every other setting is obscura's default.
        let ao = ObscuraAo {
            radius: BEVY_RADIUS,
            preset: preset(p)?,
            ..default()
        };
        let dir = args.out.join(format!("obscura-bevy-{p}"));
        variants.push((dir, Variant::Obscura(ao), format!("obscura {p}")));
    }
    let dirs: Vec<PathBuf> = variants.iter().map(|v| v.0.clone()).collect();
    for d in &dirs {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }

    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(RenderPlugin {
        synchronous_pipeline_compilation: true,
        ..default()
    }))
    .add_plugins((RenderDiagnosticsPlugin, ObscuraPlugin))
    .insert_resource(GlobalAmbientLight {
        color: Color::WHITE,
        brightness: AMBIENT,
        ..default()
    })
    .insert_resource(ClearColor(Color::BLACK));
    app.finish();
    app.cleanup();

    let material = app
        .world_mut()
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::linear_rgb(ALBEDO, ALBEDO, ALBEDO),
            perceptual_roughness: 1.0,
            metallic: 0.0,
            reflectance: 0.0,
            double_sided: true,
            cull_mode: None,
            ..default()
        });

    let mut loaded: HashMap<PathBuf, Handle<Mesh>> = HashMap::new();
    let mut times: Vec<serde_json::Map<String, serde_json::Value>> =
        vec![Default::default(); dirs.len()];
    for v in &views {
        let mesh = match loaded.get(&v.scene) {
            Some(h) => h.clone(),
            None => {
                eprintln!("{}: loading {}", v.name, v.scene.display());
                let m = bevy_mesh(&v.scene)?;
                let h = app.world_mut().resource_mut::<Assets<Mesh>>().add(m);
                loaded.insert(v.scene.clone(), h.clone());
                h
            }
        };
        let scale = BEVY_RADIUS / v.radius;
        let mut target = Image::new_target_texture(v.width, v.height, TARGET_FORMAT, None);
        target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        let target = app.world_mut().resource_mut::<Assets<Image>>().add(target);
        let object = app
            .world_mut()
            .spawn((
                Mesh3d(mesh),
                MeshMaterial3d(material.clone()),
                Transform::from_scale(Vec3::splat(scale)),
            ))
            .id();
        let camera = app
            .world_mut()
            .spawn((
                Camera3d::default(),
                RenderTarget::Image(target.clone().into()),
                Hdr,
                Tonemapping::None,
                DebandDither::Disabled,
                Msaa::Off,
                DepthPrepass,
                NormalPrepass,
                projection(v, scale, v.near * scale),
                Transform::from_translation(v.eye * scale).looking_at(v.target * scale, v.up),
            ))
            .id();

        // The view's own near plane, then Bevy's: what the latter clips is counted.
        for _ in 0..3 {
            frame(&mut app);
        }
        let lit = |frame: &[f32]| frame.iter().filter(|&&p| p > 1e-6).count();
        let lit_at_view_near = lit(&read_target(&mut app, &target, v.width, v.height));
        let near = BEVY_NEAR.max(v.near * scale);
        app.world_mut()
            .entity_mut(camera)
            .insert(projection(v, scale, near));
        for _ in 0..3 {
            frame(&mut app);
        }
        let plain = read_target(&mut app, &target, v.width, v.height);
        let clipped = lit_at_view_near.saturating_sub(lit(&plain));
        if clipped > 0 {
            eprintln!(
                "{}: warning: Bevy's near plane clips {clipped} pixels the view sees",
                v.name
            );
        }
        let mut with_prepass = Vec::new();
        let mut without_prepass = Vec::new();
        for _ in 0..args.runs {
            with_prepass.push(frame(&mut app));
        }
        app.world_mut()
            .entity_mut(camera)
            .remove::<(DepthPrepass, NormalPrepass)>();
        for _ in 0..2 {
            frame(&mut app);
        }
        for _ in 0..args.runs {
            without_prepass.push(frame(&mut app));
        }
        app.world_mut()
            .entity_mut(camera)
            .insert((DepthPrepass, NormalPrepass));
        let prepass_ms = median(with_prepass) - median(without_prepass);

        for (qi, (_, variant, q)) in variants.iter().enumerate() {
            let mut on = Vec::new();
            let mut off = Vec::new();
            // Bevy's timings reach its store a frame or two late: settle with this variant,
            // then drop what came before.
            variant.insert(&mut app.world_mut().entity_mut(camera));
            frame(&mut app);
            frame(&mut app);
            gpu_ms(&mut app, variant.gpu_path());
            for run in 0..args.runs + 2 {
                for with in [false, true] {
                    let mut e = app.world_mut().entity_mut(camera);
                    if with {
                        variant.insert(&mut e);
                    } else {
                        Variant::remove(&mut e);
                    }
                    // A frame to settle the change (pipelines, textures), then the timed one.
                    frame(&mut app);
                    let ms = frame(&mut app);
                    if run >= 2 {
                        if with { &mut on } else { &mut off }.push(ms);
                    }
                }
            }
            // The last frame had SSAO. Two more, with it, sync the GPU times into the store.
            let occluded = read_target(&mut app, &target, v.width, v.height);
            frame(&mut app);
            frame(&mut app);
            let gpu = gpu_ms(&mut app, variant.gpu_path());
            let ao: Vec<f32> = occluded
                .iter()
                .zip(&plain)
                .map(|(&o, &p)| if p > 1e-6 { o / p } else { 1.0 })
                .collect();
            let (on_ms, off_ms) = (median(on), median(off));
            let wall_ms = on_ms - off_ms;
            let gpu_frames = gpu.len();
            let gpu_ms = (gpu_frames > 0).then(|| median(gpu));
            write_png(
                &dirs[qi].join(format!("{}.png", v.name)),
                v.width,
                v.height,
                &ao,
            )?;
            eprintln!(
                "{} {q}: AO {} ms on the GPU over {} frames; wall: frame {on_ms:.1} ms, without {off_ms:.1}, prepasses {prepass_ms:.1}",
                v.name,
                gpu_ms.map_or("(no timestamps)".into(), |g| format!("{g:.1}")),
                gpu_frames
            );
            times[qi].insert(
                v.name.clone(),
                serde_json::json!({
                    "ssao_ms": gpu_ms.unwrap_or(wall_ms),
                    "ssao_gpu_ms": gpu_ms,
                    "ssao_wall_ms": wall_ms,
                    "frame_ms": on_ms,
                    "plain_ms": off_ms,
                    "prepass_ms": prepass_ms,
                    "near_clipped_pixels": clipped,
                }),
            );
            Variant::remove(&mut app.world_mut().entity_mut(camera));
        }
        app.world_mut().despawn(camera);
        app.world_mut().despawn(object);
        app.world_mut()
            .resource_mut::<Assets<Image>>()
            .remove(&target);
    }
    for (qi, d) in dirs.iter().enumerate() {
        let json = match &variants[qi].1 {
            Variant::Bevy(_) => serde_json::json!({
                "peer": "bevy",
                "bevy": "0.19.1",
                "quality": args.qualities[qi],
                "views": times[qi],
            }),
            Variant::Obscura(o) => serde_json::json!({
                "peer": "obscura-bevy",
                "bevy": "0.19.1",
                "preset": format!("{:?}", o.preset).to_lowercase(),
                "views": times[qi],
            }),
        };
        let path = d.join(&args.times);
        std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap())
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

//! An interactive viewer: a scene, an orbiting camera, and keys that switch between no AO,
//! Bevy's SSAO and obscura, with the frame time and the AO's GPU time on screen.
//!
//!     cargo run --release --example viewer --features viewer [-- SCENE.glb|.gltf|.obj]
//!         [--screenshots DIR]
//!
//! The scene is the file given, else Sponza when the shared scenes are beside the
//! repository (`../shared/scenes/sponza_dabrovic`), else obscura's built-in courtyard. It
//! is scaled so that obscura's default radius for it (3% of its bounding diagonal) is
//! Bevy's fixed SSAO radius (0.5 × 1.457 units): both AOs reach the same distance.
//!
//! Keys: `1` no AO, `2` Bevy's SSAO, `3` obscura, `Space` the next of the three; `Q` the
//! next quality (Bevy's levels, obscura's presets: low, medium, high, ultra); `O` stops and
//! starts the orbit; `Esc` quits.
//!
//! `--screenshots DIR` stops the orbit, saves the window with each of the three (at high)
//! as `DIR/none.png`, `DIR/bevy.png`, `DIR/obscura.png`, and quits: the pictures in the
//! docs come from it (under `xvfb-run` on a machine without a display).

use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::prepass::{DepthPrepass, NormalPrepass};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::diagnostic::{DiagnosticPath, DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel as Q};
use bevy::prelude::*;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use bevy::render::view::screenshot::{save_to_disk, Screenshot};
use bevy::render::view::Msaa;
use bevy::window::{PresentMode, WindowResolution};
use obscura_bevy::{ObscuraAo, ObscuraPlugin};
use std::path::PathBuf;
use std::process::ExitCode;

/// Bevy's SSAO radius, fixed by its shader (0.5 × 1.457 world units; peers/bevy).
const BEVY_RADIUS: f32 = 0.5 * 1.457;
/// obscura's CLI's default radius for a scene: this fraction of its bounding diagonal.
const RADIUS_OF_DIAGONAL: f32 = 0.03;
/// The surfaces' albedo (times the file's colours). Bevy shows AO through a multi-bounce
/// fit that brightens it with the albedo (Jimenez et al. 2016): at white a visibility of 0.5
/// is shown as 0.90, at this grey as 0.60.
const ALBEDO: f32 = 0.3;
/// Seconds per turn of the orbit.
const ORBIT_SECONDS: f32 = 60.0;
/// Frames each picture of `--screenshots` waits for after a switch (pipelines, timings).
const SETTLE_FRAMES: u32 = 30;

#[derive(Clone, Copy, PartialEq, Debug)]
enum Ao {
    None,
    Bevy,
    Obscura,
}

/// What the viewer shows: the AO, its quality (0 low … 3 ultra), the orbit.
#[derive(Resource)]
struct Viewer {
    ao: Ao,
    quality: usize,
    orbit: bool,
    angle: f32,
    /// The orbit's centre, its half-axes (x, z) and the eye's height above the centre.
    centre: Vec3,
    axes: Vec2,
    height: f32,
    screenshots: Option<Screenshots>,
}

/// `--screenshots`: the folder, the pictures still to take, frames since the last switch.
struct Screenshots {
    dir: PathBuf,
    left: Vec<Ao>,
    frames: u32,
}

#[derive(Component)]
struct Label;

const QUALITIES: [&str; 4] = ["low", "medium", "high", "ultra"];

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut scene: Option<PathBuf> = None;
    let mut screenshots = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--screenshots" => {
                let dir = PathBuf::from(args.next().ok_or("--screenshots needs a folder")?);
                std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
                screenshots = Some(Screenshots {
                    dir,
                    left: vec![Ao::None, Ao::Bevy, Ao::Obscura],
                    frames: 0,
                });
            }
            "-h" | "--help" => {
                println!("viewer [SCENE.glb|.gltf|.obj] [--screenshots DIR]");
                return Ok(());
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            s if scene.is_none() => scene = Some(s.into()),
            s => return Err(format!("one scene at most (`{s}` is a second)")),
        }
    }
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/sponza_dabrovic/sponza_dabrovic.glb");
    let scene = scene.or_else(|| shared.exists().then_some(shared));
    let mesh = match &scene {
        Some(path) => obscura_scene::Mesh::load(path).map_err(|e| e.to_string())?,
        None => obscura_scene::default_scene::mesh(),
    };
    let bounds = mesh.bounds().ok_or("the scene has no triangles")?;
    let (min, max) = (
        Vec3::from_array(bounds.min.to_array()),
        Vec3::from_array(bounds.max.to_array()),
    );
    let scale = BEVY_RADIUS / (RADIUS_OF_DIAGONAL * bounds.diagonal());
    let (min, max) = (min * scale, max * scale);
    let size = max - min;
    eprintln!(
        "{}: {} triangles; keys: 1 no AO, 2 Bevy's SSAO, 3 obscura, Space next, Q quality, O orbit, Esc quit",
        scene
            .as_ref()
            .map_or("the built-in courtyard".into(), |p| p.display().to_string()),
        mesh.triangle_count()
    );
    let viewer = Viewer {
        ao: Ao::Obscura,
        quality: 2,
        orbit: screenshots.is_none(),
        // A view along the long axis, a little off it, for the pictures.
        angle: 0.6,
        centre: (min + max) * 0.5 - Vec3::Y * size.y * 0.2,
        axes: Vec2::new(size.x, size.z) * 0.3,
        height: size.y * 0.15,
        screenshots,
    };

    App::new()
        .add_plugins(DefaultPlugins.set(WindowPlugin {
            primary_window: Some(Window {
                title: "obscura in Bevy".into(),
                resolution: WindowResolution::new(1280, 720),
                present_mode: PresentMode::AutoNoVsync,
                ..default()
            }),
            ..default()
        }))
        .add_plugins((
            ObscuraPlugin,
            RenderDiagnosticsPlugin,
            FrameTimeDiagnosticsPlugin::default(),
        ))
        .insert_resource(GlobalAmbientLight {
            color: Color::WHITE,
            brightness: 500.0 / ALBEDO,
            ..default()
        })
        .insert_resource(viewer)
        .insert_resource(SceneMesh(Some((mesh, scale))))
        .add_systems(Startup, setup)
        .add_systems(
            Update,
            (keys, take_screenshots, orbit, apply_ao, label).chain(),
        )
        .run();
    Ok(())
}

#[derive(Resource)]
struct SceneMesh(Option<(obscura_scene::Mesh, f32)>);

/// The scene as one Bevy mesh (flat normals, the file's colours), a dim sun, the camera,
/// the label.
fn setup(
    mut commands: Commands,
    mut scene: ResMut<SceneMesh>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let Some((m, scale)) = scene.0.take() else {
        return;
    };
    let colours: Vec<[f32; 4]> = m
        .vertex_colours()
        .iter()
        .map(|c| [c[0], c[1], c[2], 1.0])
        .collect();
    let mut mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, m.positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours)
    .with_inserted_indices(Indices::U32(m.indices));
    mesh.duplicate_vertices();
    mesh.compute_flat_normals();
    commands.spawn((
        Mesh3d(meshes.add(mesh)),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::linear_rgb(ALBEDO, ALBEDO, ALBEDO),
            perceptual_roughness: 0.9,
            reflectance: 0.1,
            double_sided: true,
            cull_mode: None,
            ..default()
        })),
        Transform::from_scale(Vec3::splat(scale)),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 250.0 / ALBEDO,
            ..default()
        },
        Transform::from_xyz(0.3, 1.0, 0.2).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // Bevy's SSAO and obscura both need the camera's MSAA off (Bevy 0.19 makes its AO
    // texture only then) and the depth and normal prepasses. ACES needs no lookup tables
    // (Bevy's default tonemapper does: its feature `tonemapping_luts`).
    commands.spawn((
        Camera3d::default(),
        Tonemapping::AcesFitted,
        Msaa::Off,
        DepthPrepass,
        NormalPrepass,
        Transform::default(),
    ));
    commands.spawn((
        Label,
        Text::new(""),
        TextFont {
            font_size: FontSize::Px(18.0),
            ..default()
        },
        Node {
            position_type: PositionType::Absolute,
            top: Val::Px(8.0),
            left: Val::Px(8.0),
            padding: UiRect::all(Val::Px(6.0)),
            ..default()
        },
        BackgroundColor(Color::srgba(0.0, 0.0, 0.0, 0.6)),
    ));
}

fn keys(
    input: Res<ButtonInput<KeyCode>>,
    mut viewer: ResMut<Viewer>,
    mut exit: MessageWriter<AppExit>,
) {
    if input.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
    for (key, ao) in [
        (KeyCode::Digit1, Ao::None),
        (KeyCode::Digit2, Ao::Bevy),
        (KeyCode::Digit3, Ao::Obscura),
    ] {
        if input.just_pressed(key) {
            viewer.ao = ao;
        }
    }
    if input.just_pressed(KeyCode::Space) {
        viewer.ao = match viewer.ao {
            Ao::None => Ao::Bevy,
            Ao::Bevy => Ao::Obscura,
            Ao::Obscura => Ao::None,
        };
    }
    if input.just_pressed(KeyCode::KeyQ) {
        viewer.quality = (viewer.quality + 1) % QUALITIES.len();
    }
    if input.just_pressed(KeyCode::KeyO) {
        viewer.orbit = !viewer.orbit;
    }
}

/// `--screenshots`: each AO in turn, a picture after it settles, then quit.
fn take_screenshots(
    mut commands: Commands,
    mut viewer: ResMut<Viewer>,
    mut exit: MessageWriter<AppExit>,
) {
    let Some(shots) = viewer.screenshots.as_mut() else {
        return;
    };
    shots.frames += 1;
    let Some(&ao) = shots.left.first() else {
        // The last picture is written a few frames after its request.
        if shots.frames > SETTLE_FRAMES {
            exit.write(AppExit::Success);
        }
        return;
    };
    if shots.frames == SETTLE_FRAMES {
        let path = shots.dir.join(format!("{ao:?}.png").to_lowercase());
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path));
    }
    // The switch waits until the picture's frame has rendered.
    if shots.frames == SETTLE_FRAMES + 3 {
        shots.left.remove(0);
        shots.frames = 0;
    }
    viewer.ao = shots.left.first().copied().unwrap_or(ao);
}

fn orbit(
    time: Res<Time>,
    mut viewer: ResMut<Viewer>,
    mut camera: Query<&mut Transform, With<Camera3d>>,
) {
    if viewer.orbit {
        viewer.angle += time.delta_secs() * std::f32::consts::TAU / ORBIT_SECONDS;
    }
    let (s, c) = viewer.angle.sin_cos();
    let eye = viewer.centre + Vec3::new(viewer.axes.x * c, viewer.height, viewer.axes.y * s);
    for mut t in &mut camera {
        *t = Transform::from_translation(eye).looking_at(viewer.centre, Vec3::Y);
    }
}

/// Puts the chosen AO on the camera when it changed.
fn apply_ao(
    mut commands: Commands,
    viewer: Res<Viewer>,
    camera: Query<Entity, With<Camera3d>>,
    mut shown: Local<Option<(Ao, usize)>>,
) {
    if *shown == Some((viewer.ao, viewer.quality)) {
        return;
    }
    *shown = Some((viewer.ao, viewer.quality));
    for entity in &camera {
        let mut e = commands.entity(entity);
        // obscura's component requires Bevy's: both go, then the chosen one comes back.
        e.remove::<(ObscuraAo, ScreenSpaceAmbientOcclusion)>();
        match viewer.ao {
            Ao::None => {}
            Ao::Bevy => {
                let quality_level = [Q::Low, Q::Medium, Q::High, Q::Ultra][viewer.quality];
                e.insert(ScreenSpaceAmbientOcclusion {
                    quality_level,
                    ..default()
                });
            }
            Ao::Obscura => {
                e.insert(ObscuraAo {
                    radius: BEVY_RADIUS,
                    preset: obscura_bevy::obscura::Preset::ALL[viewer.quality],
                    ..default()
                });
            }
        }
    }
}

/// The label: what is shown, the smoothed frame time and the AO's GPU time.
fn label(
    viewer: Res<Viewer>,
    store: Res<DiagnosticsStore>,
    mut text: Query<&mut Text, With<Label>>,
) {
    let smoothed = |path: &DiagnosticPath| store.get(path).and_then(|d| d.smoothed());
    let frame = smoothed(&FrameTimeDiagnosticsPlugin::FRAME_TIME);
    let gpu = match viewer.ao {
        Ao::None => None,
        Ao::Bevy => smoothed(&DiagnosticPath::const_new("render/ssao/elapsed_gpu")),
        Ao::Obscura => smoothed(&DiagnosticPath::const_new("render/obscura/elapsed_gpu")),
    };
    let what = match viewer.ao {
        Ao::None => "no AO".to_string(),
        Ao::Bevy => format!("Bevy's SSAO, {}", QUALITIES[viewer.quality]),
        Ao::Obscura => format!("obscura, {}", QUALITIES[viewer.quality]),
    };
    let ms = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.2} ms"));
    for mut t in &mut text {
        t.0 = format!(
            "{what}\nframe {}   AO on the GPU {}\n1 none  2 Bevy  3 obscura  Q quality  O orbit",
            ms(frame),
            ms(gpu)
        );
    }
}

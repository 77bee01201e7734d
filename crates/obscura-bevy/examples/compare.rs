//! The same frame with Bevy's SSAO and with obscura, in one headless app: a courtyard of
//! Bevy primitives lit by ambient light alone, rendered without AO, with Bevy's
//! `ScreenSpaceAmbientOcclusion` (each quality level) and with [`ObscuraAo`] (each of
//! obscura's presets, High its default, at Bevy's fixed radius). Writes the AO each applied (the frame over the frame
//! without AO; a near-black albedo keeps Bevy's multi-bounce fit the identity) side by
//! side as an 8-bit PNG, and prints each mode's wall-clock frame time against no AO.
//!
//!     cargo run --release --example compare -- OUT.png [--frames 20]

use bevy::core_pipeline::prepass::{DepthPrepass, NormalPrepass};
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel as Q};
use bevy::prelude::*;
use obscura_bevy::headless::{self, frame};
use obscura_bevy::ObscuraAo;

const WIDTH: u32 = 640;
const HEIGHT: u32 = 400;
/// Bevy's SSAO radius, fixed by its shader (0.5 × 1.457 world units; peers/bevy).
const BEVY_RADIUS: f32 = 0.5 * 1.457;

#[derive(Clone, Copy)]
enum Mode {
    None,
    Bevy(Q),
    Obscura(obscura::Preset),
}

impl Mode {
    fn name(self) -> String {
        match self {
            Mode::None => "no AO".into(),
            Mode::Bevy(q) => format!("Bevy SSAO {q:?}").to_lowercase(),
            Mode::Obscura(p) => format!("obscura {p:?}").to_lowercase(),
        }
    }
}

fn courtyard(world: &mut World) {
    let material = headless::matte(world);
    let mut meshes = world.resource_mut::<Assets<Mesh>>();
    let floor = meshes.add(Plane3d::default().mesh().size(12.0, 12.0));
    let wall = meshes.add(Cuboid::new(12.0, 3.0, 0.4));
    let side = meshes.add(Cuboid::new(0.4, 3.0, 12.0));
    let crate_ = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    let column = meshes.add(Cylinder::new(0.3, 3.0));
    let ball = meshes.add(Sphere::new(0.8).mesh().uv(48, 24));
    let mut put = |mesh: &Handle<Mesh>, at: Vec3| {
        world.spawn((
            Mesh3d(mesh.clone()),
            MeshMaterial3d(material.clone()),
            Transform::from_translation(at),
        ));
    };
    put(&floor, Vec3::ZERO);
    put(&wall, Vec3::new(0.0, 1.5, -6.0));
    put(&side, Vec3::new(-6.0, 1.5, 0.0));
    put(&side, Vec3::new(6.0, 1.5, 0.0));
    for (x, z) in [(-4.0, -4.0), (-2.5, -4.5), (3.5, -3.0)] {
        put(&crate_, Vec3::new(x, 0.5, z));
    }
    put(&crate_, Vec3::new(-4.0, 1.5, -4.0));
    for x in [-3.0, 0.0, 3.0] {
        put(&column, Vec3::new(x, 1.5, -2.0));
    }
    put(&ball, Vec3::new(0.5, 0.8, 1.0));
}

fn set_mode(app: &mut App, camera: Entity, mode: Mode) {
    let mut e = app.world_mut().entity_mut(camera);
    e.remove::<(ObscuraAo, ScreenSpaceAmbientOcclusion)>();
    match mode {
        Mode::None => {}
        Mode::Bevy(quality_level) => {
            e.insert(ScreenSpaceAmbientOcclusion {
                quality_level,
                ..default()
            });
        }
        Mode::Obscura(preset) => {
            e.insert(ObscuraAo {
                radius: BEVY_RADIUS,
                preset,
                ..default()
            });
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (out, frames) = match args.as_slice() {
        [out] => (out.clone(), 20),
        [out, flag, n] if flag == "--frames" => (
            out.clone(),
            n.parse::<usize>()
                .ok()
                .filter(|&n| n > 0)
                .ok_or("--frames takes a whole number above 0")?,
        ),
        _ => return Err("usage: compare OUT.png [--frames N]".into()),
    };
    if !out.ends_with(".png") {
        return Err(format!("{out}: expected a .png path"));
    }
    let mut app = headless::app();
    courtyard(app.world_mut());
    let target = headless::target(app.world_mut(), WIDTH, HEIGHT);
    let camera = app
        .world_mut()
        .spawn((
            headless::camera(&target),
            DepthPrepass,
            NormalPrepass,
            Transform::from_xyz(4.0, 3.5, 7.0).looking_at(Vec3::new(-0.5, 0.5, -2.0), Vec3::Y),
        ))
        .id();

    let modes = [
        Mode::None,
        Mode::Bevy(Q::Low),
        Mode::Bevy(Q::Medium),
        Mode::Bevy(Q::High),
        Mode::Bevy(Q::Ultra),
        Mode::Obscura(obscura::Preset::Low),
        Mode::Obscura(obscura::Preset::Medium),
        Mode::Obscura(obscura::Preset::High),
        Mode::Obscura(obscura::Preset::Ultra),
    ];
    let mut lit = Vec::new();
    let mut times = vec![Vec::new(); modes.len()];
    for (i, &mode) in modes.iter().enumerate() {
        set_mode(&mut app, camera, mode);
        for _ in 0..3 {
            frame(&mut app); // warm-up: pipelines, textures
        }
        lit.push(
            headless::read_image(&app, &target).ok_or("the camera's target is not on the GPU")?,
        );
        times[i].push(frame(&mut app));
    }
    // Timed rounds, the modes interleaved.
    for _ in 1..frames {
        for (i, &mode) in modes.iter().enumerate() {
            set_mode(&mut app, camera, mode);
            frame(&mut app);
            times[i].push(frame(&mut app));
        }
    }
    let none = median(times[0].clone());
    println!("| mode | frame, ms (median of {frames}) | over no AO, ms |");
    println!("|---|---|---|");
    for (i, mode) in modes.iter().enumerate() {
        let t = median(times[i].clone());
        println!("| {} | {t:.1} | {:+.1} |", mode.name(), t - none);
    }
    // The AO each applied: Bevy's high and obscura's, side by side, 8-bit grey.
    let ao = |frame: &[f32]| -> Vec<u8> {
        frame
            .iter()
            .zip(&lit[0])
            .map(|(&a, &b)| {
                let r = if b > 1e-3 { a / b } else { 1.0 };
                (r.clamp(0.0, 1.0) * 255.0).round() as u8
            })
            .collect()
    };
    let (bevy, ours) = (ao(&lit[3]), ao(&lit[7]));
    let w = WIDTH as usize;
    let mut strip = Vec::with_capacity(2 * bevy.len());
    for y in 0..HEIGHT as usize {
        strip.extend_from_slice(&bevy[y * w..(y + 1) * w]);
        strip.extend_from_slice(&ours[y * w..(y + 1) * w]);
    }
    let img = image::ImageBuffer::<image::Luma<u8>, _>::from_raw(2 * WIDTH, HEIGHT, strip)
        .ok_or("image size")?;
    let tmp = format!("{out}.tmp");
    img.save_with_format(&tmp, image::ImageFormat::Png)
        .map_err(|e| format!("{tmp}: {e}"))?;
    std::fs::rename(&tmp, &out).map_err(|e| format!("{out}: {e}"))?;
    println!("wrote {out}: Bevy's SSAO (high) left, obscura's default right");
    Ok(())
}

//! The plugin in a headless Bevy app (lavapipe where there is no GPU): a box on a floor,
//! lit by ambient light alone, rendered with [`ObscuraAo`] on the camera and without it.
//! Bevy occludes only ambient and indirect light, and with a near-black albedo its
//! multi-bounce fit is the identity (to 1e-5; peers/bevy), so the ratio of the two frames
//! is the AO that reached the lighting. It must darken where the box meets the floor,
//! brighten nowhere, and equal obscura's own output for the frame's depth.

use bevy::pbr::ScreenSpaceAmbientOcclusion;
use bevy::prelude::*;
use bevy::render::sync_world::RenderEntity;
use bevy::render::RenderApp;
use obscura_bevy::headless::{self, read_texture};
use obscura_bevy::{ao_texture, ObscuraAo};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// A few frames: the last is complete (pipelines compile at once).
fn frames(app: &mut App) {
    for _ in 0..4 {
        headless::frame(app);
    }
}

/// A box on a floor, both of the matte material.
fn box_on_floor(world: &mut World) {
    let material = headless::matte(world);
    let mut meshes = world.resource_mut::<Assets<Mesh>>();
    let floor = meshes.add(Plane3d::default().mesh().size(8.0, 8.0));
    let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    world.spawn((Mesh3d(floor), MeshMaterial3d(material.clone())));
    world.spawn((
        Mesh3d(cube),
        MeshMaterial3d(material),
        Transform::from_xyz(0.0, 0.5, 0.0),
    ));
}

/// The camera's view of the box from `eye`.
fn pose(eye: Vec3) -> Transform {
    Transform::from_translation(eye).looking_at(Vec3::new(0.0, 0.3, 0.0), Vec3::Y)
}

/// obscura's AO of the camera's last frame, read back.
fn obscura_ao(app: &App, camera: Entity) -> Vec<f32> {
    let render_view = app
        .world()
        .get::<RenderEntity>(camera)
        .expect("the camera is synced to the render world")
        .id();
    let world = app.sub_app(RenderApp).world();
    let texture = ao_texture(world, render_view).expect("obscura ran for the camera");
    assert_eq!((texture.width(), texture.height()), (WIDTH, HEIGHT));
    read_texture(world, texture, 4)
}

fn mean_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f32>() / a.len() as f32
}

#[test]
fn obscura_occludes_bevys_ambient_light() {
    let mut app = headless::app();
    let world = app.world_mut();
    box_on_floor(world);
    let target = headless::target(world, WIDTH, HEIGHT);
    let camera = world
        .spawn((
            headless::camera(&target),
            pose(Vec3::new(2.5, 2.0, 3.0)),
            ObscuraAo {
                radius: 0.5,
                ..default()
            },
        ))
        .id();

    frames(&mut app);
    let lit = headless::read_image(&app, &target).expect("the target is on the GPU");
    let ao = obscura_ao(&app, camera);

    // The same frame without AO: the prepasses kept, Bevy's SSAO off.
    app.world_mut()
        .entity_mut(camera)
        .remove::<(ObscuraAo, ScreenSpaceAmbientOcclusion)>();
    frames(&mut app);
    let plain = headless::read_image(&app, &target).expect("the target is on the GPU");

    let (mut worst, mut sum, mut n) = (0.0f32, 0.0f32, 0);
    let mut darkest = 1.0f32;
    for i in 0..lit.len() {
        if plain[i] <= 1e-3 {
            continue; // sky
        }
        let ratio = lit[i] / plain[i];
        assert!(ratio <= 1.0 + 2e-3, "pixel {i} brightened: {ratio}");
        // R16Float rounding (1e-3) and Bevy's fit (1e-5): within 0.01 everywhere.
        worst = worst.max((ratio - ao[i]).abs());
        sum += (ratio - ao[i]).abs();
        darkest = darkest.min(ratio);
        n += 1;
    }
    eprintln!(
        "{n} lit pixels; the lighting's AO against obscura's: up to {worst}, mean {}; darkest {darkest}",
        sum / n.max(1) as f32
    );
    assert!(n > (WIDTH * HEIGHT / 2) as usize, "{n} lit pixels");
    assert!(
        worst <= 0.01,
        "the lighting's AO differs from obscura's by up to {worst} (mean {})",
        sum / n as f32
    );
    assert!(
        darkest < 0.6,
        "nothing darkened: the darkest ratio is {darkest}"
    );
    // Open floor, far from the box (the bottom corners of the image), stays lit.
    for &(x, y) in &[(4u32, HEIGHT - 4), (WIDTH - 4, HEIGHT - 4)] {
        let i = (y * WIDTH + x) as usize;
        assert!(
            lit[i] / plain[i] > 0.97,
            "open floor at ({x}, {y}): {}",
            lit[i] / plain[i]
        );
    }
}

/// With a temporal history the plugin passes the camera's motion to obscura, which
/// reprojects the history: the first frame after a move is close to the history settled at
/// the new pose. A history left where the camera was (`CameraMotion::Still`) carries the
/// old pose's AO into the new one. Measured on the shaded pixels (lavapipe): the first
/// frame is 0.13 of the move's change from the settled AO with the motion, 0.51 without.
#[test]
fn the_history_follows_the_camera() {
    let mut app = headless::app();
    let world = app.world_mut();
    box_on_floor(world);
    let target = headless::target(world, WIDTH, HEIGHT);
    let (from, to) = (Vec3::new(2.5, 2.0, 3.0), Vec3::new(3.1, 1.8, 2.3));
    let camera = world
        .spawn((
            headless::camera(&target),
            pose(from),
            ObscuraAo {
                radius: 0.5,
                history: 8,
                ..default()
            },
        ))
        .id();
    let settle = |app: &mut App| {
        for _ in 0..12 {
            headless::frame(app);
        }
    };
    settle(&mut app);
    let before = obscura_ao(&app, camera);
    app.world_mut().entity_mut(camera).insert(pose(to));
    headless::frame(&mut app);
    let moved = obscura_ao(&app, camera);
    settle(&mut app);
    let after = obscura_ao(&app, camera);
    // Where either pose's settled AO is occluded: open floor is 1 at both.
    let shaded = |a: &[f32]| -> Vec<f32> {
        (0..a.len())
            .filter(|&i| before[i].min(after[i]) < 0.95)
            .map(|i| a[i])
            .collect()
    };
    let (moved, before, after) = (shaded(&moved), shaded(&before), shaded(&after));
    let (moved_err, motion) = (
        mean_abs_diff(&moved, &after),
        mean_abs_diff(&before, &after),
    );
    eprintln!(
        "{} shaded pixels; after the move: {moved_err} from the settled history; the move changed the AO by {motion}",
        moved.len()
    );
    assert!(motion > 0.01, "the move changed little: {motion}");
    assert!(
        moved_err < 0.25 * motion,
        "the first frame after the move is {moved_err} from the settled AO, the move {motion}"
    );
}

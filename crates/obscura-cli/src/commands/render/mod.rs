//! `obscura render`: scene → G-buffer → AO → PNG (`scene`), or a captured depth map → AO
//! (`depth_map`), with the arguments both share (`args`) and their timed AO run (`record`);
//! `--orbit` turns the camera (`orbit`), and `--budget-ms` holds a frame time (`budget`).

mod args;
mod budget;
mod depth_map;
mod orbit;
mod prepared;
mod record;
mod scene;

pub use args::{apply_layered, RenderArgs};

/// `obscura render`: the arguments checked, then a depth map (`--depth` with
/// `--intrinsics`) or a scene.
pub fn run(a: &RenderArgs) -> anyhow::Result<()> {
    // A depth map and a scene are two sources of the same AO input: depth_map.rs and
    // scene.rs share args.rs's arguments and record.rs's timing.
    args::check_args(a).and_then(|()| match (&a.depth, &a.intrinsics) {
        (Some(depth), Some(intrinsics)) => depth_map::run(a, depth, intrinsics),
        _ => scene::run(a),
    })
}

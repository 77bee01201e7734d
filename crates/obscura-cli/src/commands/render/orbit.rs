//! `render --orbit` without a budget: the camera turns about its target over the frames,
//! each frame's AO recorded with the camera motion and written as a PNG; and the turn at
//! each frame, which the budgeted orbit shares.

use super::args::RenderArgs;
use crate::options::NormalSource;
use crate::output::save_ao;
use crate::progress::progress;
use crate::timing::median;
use anyhow::{Context, Result};
use obscura::{Ao, AoParams, CameraMotion, GpuContext};
use obscura_scene::{Camera, GBufferRenderer};
use std::time::Instant;

/// `render --orbit`: the camera turns `degrees` about the vertical axis through its target
/// over `--frames` frames; each frame's G-buffer is rasterized, its AO recorded with the
/// camera motion (temporal accumulation reprojects the history) and written as a PNG.
#[allow(clippy::too_many_arguments)]
pub(super) fn orbit(
    a: &RenderArgs,
    ctx: &GpuContext,
    raster: &GBufferRenderer,
    mesh: &obscura_scene::GpuMesh,
    cam: &Camera,
    ao: &mut Ao,
    params: &AoParams,
    degrees: f32,
    dir: &std::path::Path,
    t0: Instant,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create `{}`", dir.display()))?;
    let n = a.frames;
    let mut times = Vec::with_capacity(n as usize);
    let mut previous: Option<Camera> = None;
    for k in 0..n {
        let c = cam.orbit(orbit_turn(degrees, k, n));
        let g = raster.render(ctx, mesh, &c, a.width, a.height)?;
        let input = g.ao_input(&c, a.normals == NormalSource::Gbuffer);
        let p = AoParams {
            motion: previous.map_or(CameraMotion::Cut, |prev| c.motion_since(&prev)),
            ..*params
        };
        let t = Instant::now();
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
        let values = ctx.read_f32(ao.output().context("AO output missing after a run")?)?;
        let path = dir.join(format!("frame_{k:04}.png"));
        save_ao(&path, &values, a.width, a.height, a.bits)?;
        previous = Some(c);
        progress(k + 1, n, &path);
    }
    eprintln!();
    eprintln!(
        "ao: {n} frames orbiting {degrees}°, median {:.2} ms per frame (the first includes \
         shader compilation); wrote {}",
        median(times),
        dir.display()
    );
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// The camera's turn in degrees at frame `k` of `n` of an orbit of `degrees`: evenly from 0
/// at the first frame to `degrees` at the last.
pub(super) fn orbit_turn(degrees: f32, k: u32, n: u32) -> f32 {
    if n > 1 {
        degrees * k as f32 / (n - 1) as f32
    } else {
        0.0
    }
}

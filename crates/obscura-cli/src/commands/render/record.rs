//! The timed AO run of `render`, shared by its scene and depth-map paths: a warm-up frame,
//! then `--runs` timed single frames or `--frames` accumulated ones, and their times.

use super::args::RenderArgs;
use crate::output::fmt_ms;
use crate::timing::{median, pass_medians, warm_up};
use anyhow::{Context, Result};
use obscura::{Ao, AoParams, GpuContext, Timing};
use std::time::Instant;

/// Records one warm-up frame (shader compilation), then `--runs` timed single frames or
/// `--frames` accumulated frames, prints the times, and returns the AO output. Shared by
/// the scene and the depth-map paths.
pub(crate) fn record_timed(
    a: &RenderArgs,
    ctx: &GpuContext,
    ao: &mut Ao,
    input: &obscura::AoInput<'_>,
    params: &AoParams,
) -> Result<Vec<f32>> {
    let mut times = Vec::new();
    let first = Instant::now();
    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, input, params))?;
    eprintln!(
        "ao: first run {:.1} ms (includes shader compilation)",
        first.elapsed().as_secs_f64() * 1e3
    );
    // With temporal accumulation the warm-up frame is not part of the image, and the frames
    // sample as an `obscura::depth_map::Renderer` call's do.
    ao.restart();
    let timed = if a.frames > 1 { a.frames } else { a.runs };
    let total = Instant::now();
    for _ in 0..timed {
        let t = Instant::now();
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, input, params))?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    if a.frames > 1 {
        eprintln!(
            "ao: {} accumulated frames (history {}), median {:.2} ms per frame, {:.1} ms in all",
            a.frames,
            ao.options().history,
            median(times),
            total.elapsed().as_secs_f64() * 1e3
        );
    } else {
        eprintln!(
            "ao: median {:.2} ms over {} runs (wall clock around submit + wait)",
            median(times),
            a.runs
        );
        gpu_time(a, ctx, ao, input, params)?;
    }
    let out = ao.output().context("AO output missing after a run")?;
    Ok(ctx.read_f32(out)?)
}

/// On hardware adapters, single frames are also timed by GPU timestamps, pass by pass,
/// after [`crate::timing::GPU_WARM_UP`]: the wall clock there adds submission and wake-up
/// latency (0.2–0.35 ms on an H200, BENCHMARKS.md). Nothing on CPU adapters, whose
/// timestamps do not bracket dispatches.
fn gpu_time(
    a: &RenderArgs,
    ctx: &GpuContext,
    ao: &mut Ao,
    input: &obscura::AoInput<'_>,
    params: &AoParams,
) -> Result<()> {
    let timing = Timing::best_for(ctx);
    if timing != Timing::Timestamps {
        return Ok(());
    }
    warm_up(timing, || {
        ao.run_timed(ctx, input, params, timing)?;
        Ok(())
    })?;
    let runs = (0..a.runs)
        .map(|_| ao.run_timed(ctx, input, params, timing))
        .collect::<Result<Vec<_>, _>>()?;
    let (total, passes) = pass_medians(&runs);
    let passes: Vec<String> = passes
        .iter()
        .map(|(label, ms)| format!("{label} {}", fmt_ms(*ms)))
        .collect();
    eprintln!(
        "ao: median {} ms of GPU time over {} runs (timestamps: {})",
        fmt_ms(total),
        a.runs,
        passes.join(", ")
    );
    Ok(())
}

//! Timing AO frames: one frame's milliseconds by the adapter's best clock, and the median
//! of repeated runs.

use anyhow::Result;
use obscura::{Ao, AoInput, AoParams, GpuContext, Timing};
use std::time::Instant;

/// One AO frame, run and timed: the sum of its passes' GPU timestamps on hardware adapters
/// (the AO's own GPU time, what a budget is about; the wall clock there adds submission and
/// wake-up latency of about half a millisecond, measured on an H100), else the wall clock
/// around submit + wait (lavapipe, whose timestamps do not bracket dispatches).
pub(crate) fn frame_ms(
    ctx: &GpuContext,
    ao: &mut Ao,
    input: &AoInput<'_>,
    params: &AoParams,
    timing: Timing,
) -> Result<f64> {
    Ok(match timing {
        Timing::Timestamps => ao
            .run_timed(ctx, input, params, timing)?
            .iter()
            .map(|p| p.1)
            .sum(),
        Timing::WallClock => {
            let t = Instant::now();
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, input, params))?;
            t.elapsed().as_secs_f64() * 1e3
        }
    })
}

/// The median of `v` (the upper middle value of an even count).
pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

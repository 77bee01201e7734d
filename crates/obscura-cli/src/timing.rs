//! Timing AO frames: one frame's milliseconds by the adapter's best clock, and the median
//! of repeated runs.

use anyhow::Result;
use obscura::{Ao, AoInput, AoParams, GpuContext, Timing};
use std::time::{Duration, Instant};

/// How long untimed frames keep a hardware GPU busy before timed ones. A GPU lowers its
/// clocks while it idles (the CPU tracing a reference or loading a scene), and a few frames
/// do not raise them again: on an H200 (2026-11-27, b560942) `eval`'s 720p frontier at `--runs 5`
/// after each view's reference took 0.23–0.73 ms a view for the default frame, and
/// 0.09–0.14 ms with this warm-up first.
pub(crate) const GPU_WARM_UP: Duration = Duration::from_secs(1);

/// Untimed rounds before the timed ones: one round (shader compilation, first-use
/// allocations), and on hardware adapters ([`Timing::Timestamps`]) more until
/// [`GPU_WARM_UP`] has passed.
pub(crate) fn warm_up(timing: Timing, round: impl FnMut() -> Result<()>) -> Result<()> {
    let start = Instant::now();
    warm_up_by(timing, || start.elapsed(), round)
}

/// [`warm_up`] on any clock: `elapsed` gives the time since the warm-up began.
fn warm_up_by(
    timing: Timing,
    mut elapsed: impl FnMut() -> Duration,
    mut round: impl FnMut() -> Result<()>,
) -> Result<()> {
    loop {
        round()?;
        if timing != Timing::Timestamps || elapsed() >= GPU_WARM_UP {
            return Ok(());
        }
    }
}

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

/// Frames timed pass by pass (each [`Ao::run_timed`]'s labels and milliseconds): the
/// median of their sums, and each pass's median (NaN and none without frames).
pub(crate) fn pass_medians(runs: &[Vec<(&'static str, f64)>]) -> (f64, Vec<(&'static str, f64)>) {
    let Some(first) = runs.first() else {
        return (f64::NAN, Vec::new());
    };
    let total = median(runs.iter().map(|p| p.iter().map(|x| x.1).sum()).collect());
    let passes = first
        .iter()
        .enumerate()
        .map(|(k, (label, _))| (*label, median(runs.iter().map(|p| p[k].1).collect())))
        .collect();
    (total, passes)
}

/// The median of `v` (the upper middle value of an even count).
pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_medians_are_medians_of_the_sums_and_of_each_pass() {
        // Three frames of two passes; the sums are 3, 12 and 6, so the median frame is 6
        // though no frame has both median passes (2 and 4).
        let runs = vec![
            vec![("a", 1.0), ("b", 2.0)],
            vec![("a", 2.0), ("b", 10.0)],
            vec![("a", 5.0), ("b", 1.0)],
        ];
        let (total, passes) = pass_medians(&runs);
        assert_eq!(total, 6.0);
        assert_eq!(passes, [("a", 2.0), ("b", 2.0)]);
        let (total, passes) = pass_medians(&[]);
        assert!(total.is_nan() && passes.is_empty());
    }

    #[test]
    fn warm_up_runs_once_on_cpu_adapters_and_a_second_on_gpus() {
        // A clock that each round moves on by 300 ms, so the count does not depend on how
        // long a sleep takes on a loaded machine.
        let clock = std::cell::Cell::new(Duration::ZERO);
        let mut rounds = 0;
        let round = |rounds: &mut u32| {
            *rounds += 1;
            clock.set(clock.get() + Duration::from_millis(300));
            Ok(())
        };
        warm_up_by(Timing::WallClock, || clock.get(), || round(&mut rounds)).unwrap();
        assert_eq!(
            rounds, 1,
            "lavapipe needs no clocks raised: one untimed round"
        );

        let mut rounds = 0;
        clock.set(Duration::ZERO);
        warm_up_by(Timing::Timestamps, || clock.get(), || round(&mut rounds)).unwrap();
        // 300, 600, 900 ms are short of GPU_WARM_UP (1 s); the fourth round reaches it.
        assert_eq!(rounds, 4, "rounds of 300 ms until a second has passed");
        assert!(clock.get() >= GPU_WARM_UP);

        let mut rounds = 0;
        let err = warm_up_by(
            Timing::Timestamps,
            || clock.get(),
            || {
                rounds += 1;
                anyhow::bail!("device lost")
            },
        );
        assert!(err.is_err() && rounds == 1, "an error ends the warm-up");
    }
}

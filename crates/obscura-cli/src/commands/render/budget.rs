//! `render --orbit ... --budget-ms X`: the orbit of `render --orbit`, each frame at the
//! working scale and sample count that `obscura::budget::JointController` chooses
//! (`--budget-control joint`), at the working scale alone that
//! `obscura::budget::ScaleController` chooses (`--budget-control scale`), or at the level
//! of a ladder of AO settings that `obscura::budget::BudgetController` chooses
//! (`--budget-control ladder`) to hold the budget; prints each frame's time and knob, and
//! writes `budget.csv` and `budget.svg` (time and knob per frame) beside the frames.

use anyhow::{Context, Result};
use obscura::budget::{BudgetController, JointController, Knob, ScaleController};
use obscura::{
    Ao, AoOptions, AoParams, CameraMotion, Denoise, GpuContext, Preset, Resolution, Timing,
    Upsampler,
};
use obscura_scene::{Camera, GBuffer, GBufferRenderer, GpuMesh};
use std::fmt::Write as _;
use std::path::Path;

use super::args::RenderArgs;
use super::orbit::orbit_turn;
use crate::options::NormalSource;
use crate::output::{fmt_ms, save_ao};
use crate::timing::frame_ms;

/// The ladder, from the most error to the least: working resolution and preset. The order
/// is measured, for GTAO in the default 2×2 layout with the spatial denoiser (mean RMSE
/// against ray-traced AO over the shared views; docs/frontier.md, docs/sample-reuse.md):
/// half low 0.1033, medium 0.1006, high 0.0915, ultra 0.0907; full low 0.0831, medium
/// 0.0704, high 0.0584 (3 × 5 crowded; 0.0605 with 4 × 4 before), ultra 0.0565. Full resolution at the low preset beats half at the
/// ultra one, so resolution comes before samples; quarter resolution (not in those tables)
/// goes below half. The levels' costs are measured on the first view, not assumed. The
/// order is GTAO's; other estimators take the same order by principle (resolution first,
/// then samples), not by measurement.
pub const LADDER: [(Resolution, Preset); 11] = [
    (Resolution::Quarter, Preset::Low),
    (Resolution::Quarter, Preset::Medium),
    (Resolution::Quarter, Preset::High),
    (Resolution::Half, Preset::Low),
    (Resolution::Half, Preset::Medium),
    (Resolution::Half, Preset::High),
    (Resolution::Half, Preset::Ultra),
    (Resolution::Full, Preset::Low),
    (Resolution::Full, Preset::Medium),
    (Resolution::Full, Preset::High),
    (Resolution::Full, Preset::Ultra),
];

fn preset_name(p: Preset) -> &'static str {
    match p {
        Preset::Low => "low",
        Preset::Medium => "medium",
        Preset::High => "high",
        Preset::Ultra => "ultra",
    }
}

/// One frame of the run: level, milliseconds.
type Frame = (usize, f64);

/// Runs the orbit under the budget; `base` carries the estimator, layout, denoiser and
/// history (resolution and preset come from the ladder).
pub fn orbit(mut orbit: Orbit, base: AoOptions, params: &AoParams, budget_ms: f64) -> Result<()> {
    let (a, ctx, cam, dir) = (orbit.a, orbit.ctx, orbit.cam, orbit.dir);
    // The ladder's resolutions are fixed: scale 1 whatever --scale says.
    let params = &AoParams {
        scale: 1.0,
        ..*params
    };
    // Every level is created and warmed up on the first view (shader compilation and its
    // textures), then timed there: those times are the controller's nominal costs, and no
    // GPU object is created during the orbit.
    let first = orbit.first_view()?;
    let input = first.ao_input(cam, a.normals == NormalSource::Gbuffer);
    let mut levels = Vec::with_capacity(LADDER.len());
    for (resolution, preset) in LADDER {
        let mut ao = ao_at(ctx, base, a.march_exponent, resolution, preset)?;
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, params))?;
        levels.push(ao);
    }
    // Median of three runs per level, interleaved (CPU adapters' times vary by ±20%).
    let mut runs = vec![Vec::new(); levels.len()];
    let timing = orbit.timing;
    for _ in 0..3 {
        for (ao, times) in levels.iter_mut().zip(&mut runs) {
            times.push(frame_ms(ctx, ao, &input, params, timing)?);
        }
    }
    let nominal = medians(runs);
    let name = |k: usize| format!("{} {}", LADDER[k].0.name(), preset_name(LADDER[k].1));
    eprintln!(
        "budget: {budget_ms} ms per frame; levels (measured on the first view): {}",
        (0..levels.len())
            .map(|k| format!("{k} {} {} ms", name(k), fmt_ms(nominal[k])))
            .collect::<Vec<_>>()
            .join(", ")
    );
    // A level that costs at least as much as some better level is dominated: on a GPU the
    // full-resolution passes set a floor, so half ultra costs more than full low
    // (BENCHMARKS.md, "On a hardware GPU"); on lavapipe timing noise can invert a close
    // pair. The controller steps over the levels cheaper than every level above them.
    let kept = undominated(&nominal);
    if kept.len() < nominal.len() {
        eprintln!(
            "budget: skipping dominated levels (a better level costs no more): {}",
            (0..nominal.len())
                .filter(|k| !kept.contains(k))
                .map(|k| format!("{k} {}", name(k)))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let costs: Vec<f64> = kept.iter().map(|&k| nominal[k]).collect();
    let mut control = BudgetController::new(budget_ms, &costs).with_context(|| {
        format!("no controller for a {budget_ms} ms budget over the measured level costs {costs:?}")
    })?;
    let n = a.frames;
    let mut frames: Vec<Frame> = Vec::with_capacity(n as usize);
    let mut floor = Floor::default();
    for k in 0..n {
        let level = kept[control.level()];
        // A level's history is from the last frame it ran, not the previous one: restart it.
        let ms = orbit.frame(k, &mut levels[level], level, 1.0, params)?;
        floor.frame(
            (level == kept[0]).then(|| name(level)).as_deref(),
            ms,
            budget_ms,
        );
        control.update(ms);
        frames.push((level, ms));
        eprintln!(
            "frame {k:4}: level {level} ({}) {:>6} ms ({:+.0}% of the budget)",
            name(level),
            fmt_ms(ms),
            (ms / budget_ms - 1.0) * 100.0
        );
    }
    let dearest = frames
        .iter()
        .filter(|f| f.0 == kept[kept.len() - 1] && f.1 < 0.85 * budget_ms)
        .count();
    eprintln!(
        "budget: {}, {} level changes; {dearest} frames under it at the dearest level",
        summary(&frames.iter().map(|f| f.1).collect::<Vec<_>>(), budget_ms),
        frames.windows(2).filter(|w| w[0].0 != w[1].0).count()
    );
    let mut csv = String::from("frame,level,resolution,preset,ms\n");
    for (k, (level, ms)) in frames.iter().enumerate() {
        let _ = writeln!(
            csv,
            "{k},{level},{},{},{ms:.4}",
            LADDER[*level].0.name(),
            preset_name(LADDER[*level].1)
        );
    }
    let levels = LADDER.len() as f64;
    let knob: Vec<f64> = frames.iter().map(|f| (f.0 as f64 + 0.5) / levels).collect();
    let labels: Vec<(f64, String)> = (0..LADDER.len())
        .map(|l| ((l as f64 + 0.5) / levels, format!("{l} {}", name(l))))
        .collect();
    let times: Vec<f64> = frames.iter().map(|f| f.1).collect();
    write_outputs(dir, &csv, &plot(&times, &knob, &labels, "level", budget_ms))
}

/// A budgeted orbit's setting, and its frames: each renders its view's G-buffer, runs one
/// of the run's `Ao`s on it (timed) and saves the AO as `frame_NNNN.png` in `dir` (which
/// the caller has created).
pub struct Orbit<'a> {
    pub a: &'a RenderArgs,
    pub ctx: &'a GpuContext,
    pub raster: &'a GBufferRenderer,
    pub mesh: &'a GpuMesh,
    /// The first view; the orbit turns about its target.
    pub cam: &'a Camera,
    pub degrees: f32,
    pub dir: &'a Path,
    pub timing: Timing,
    /// The previous frame's camera and the id of the `Ao` that ran it.
    pub previous: Option<(Camera, usize)>,
}

impl Orbit<'_> {
    /// The G-buffer of the first view.
    fn first_view(&self) -> Result<GBuffer> {
        let a = self.a;
        Ok(self
            .raster
            .render(self.ctx, self.mesh, self.cam, a.width, a.height)?)
    }

    /// Frame `k`, run by `ao` (the caller's `id` for it) at working scale `scale`; returns
    /// its time in ms. An `Ao` that did not run the previous frame restarts its history
    /// (its history is from the last frame it ran).
    fn frame(
        &mut self,
        k: u32,
        ao: &mut Ao,
        id: usize,
        scale: f32,
        params: &AoParams,
    ) -> Result<f64> {
        let (a, ctx) = (self.a, self.ctx);
        let c = self.cam.orbit(orbit_turn(self.degrees, k, a.frames));
        let g = self.raster.render(ctx, self.mesh, &c, a.width, a.height)?;
        let input = g.ao_input(&c, a.normals == NormalSource::Gbuffer);
        let motion = match &self.previous {
            Some((prev, p)) if *p == id => c.motion_since(prev),
            Some(_) => {
                ao.restart();
                CameraMotion::Cut
            }
            None => CameraMotion::Cut,
        };
        let p = AoParams {
            motion,
            scale,
            ..*params
        };
        let ms = frame_ms(ctx, ao, &input, &p, self.timing)?;
        let values = ctx.read_f32(ao.output().context("AO output missing after a run")?)?;
        let path = self.dir.join(format!("frame_{k:04}.png"));
        save_ao(&path, &values, a.width, a.height, a.bits)?;
        self.previous = Some((c, id));
        Ok(ms)
    }
}

/// Says once that the budget is below what the view costs: on the third frame in a row
/// more than 15% over it at the cheapest setting the controller has.
#[derive(Debug, Default)]
struct Floor {
    over: u32,
    said: bool,
}

impl Floor {
    fn frame(&mut self, cheapest: Option<&str>, ms: f64, budget_ms: f64) {
        self.over = match cheapest {
            Some(_) if ms > 1.15 * budget_ms => self.over + 1,
            _ => 0,
        };
        if let (3, false, Some(setting)) = (self.over, self.said, cheapest) {
            self.said = true;
            eprintln!(
                "budget: {budget_ms} ms cannot be held on this view: its cheapest setting \
                 ({setting}) takes {} ms, and the orbit runs on there (a smaller --width and \
                 --height, or a larger --budget-ms, can be held)",
                fmt_ms(ms)
            );
        }
    }
}

/// `frames within ±15% of the budget; median`, for the last line of a run.
fn summary(times: &[f64], budget_ms: f64) -> String {
    let within = times
        .iter()
        .filter(|t| (*t / budget_ms - 1.0).abs() <= 0.15)
        .count();
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    format!(
        "{within} of {} frames within ±15% of {budget_ms} ms; median {} ms",
        times.len(),
        fmt_ms(sorted[sorted.len() / 2])
    )
}

/// Writes `budget.csv` and `budget.svg` to `dir`.
fn write_outputs(dir: &Path, csv: &str, svg: &str) -> Result<()> {
    let csv_path = dir.join("budget.csv");
    std::fs::write(&csv_path, csv)
        .with_context(|| format!("cannot write `{}`", csv_path.display()))?;
    let svg_path = dir.join("budget.svg");
    std::fs::write(&svg_path, svg)
        .with_context(|| format!("cannot write `{}`", svg_path.display()))?;
    eprintln!("wrote {}, {}", csv_path.display(), svg_path.display());
    Ok(())
}

/// The scale the orbit starts at: half resolution's.
const START_SCALE: f32 = 0.5;

/// Runs the orbit under the budget with one `Ao` at `Resolution::Scaled`, whose working
/// scale `ScaleController` sets every frame; `base` carries the estimator, preset, layout,
/// denoiser and history (the upsampler is the bilateral one, the only one at any scale).
pub fn orbit_scaled(
    mut orbit: Orbit,
    base: AoOptions,
    params: &AoParams,
    budget_ms: f64,
) -> Result<()> {
    let (a, ctx, cam, dir) = (orbit.a, orbit.ctx, orbit.cam, orbit.dir);
    let options = scaled_options(a, base);
    let mut ao = Ao::new(&ctx.device, options)?;
    // Compiled and its textures (those of scale 1 serve every scale) created before the
    // first timed frame: nothing is created during the orbit.
    let first = orbit.first_view()?;
    let input = first.ao_input(cam, a.normals == NormalSource::Gbuffer);
    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, params))?;
    let mut control = ScaleController::new(budget_ms, START_SCALE)
        .with_context(|| format!("no controller for a {budget_ms} ms budget"))?;
    eprintln!(
        "budget: {budget_ms} ms per frame; continuous scale from {START_SCALE}, {} {}×{}, \
         denoise {}",
        options.estimator.name(),
        options.directions,
        options.steps,
        options.denoise.name()
    );
    let n = a.frames;
    let mut frames: Vec<(f32, f64)> = Vec::with_capacity(n as usize);
    let mut floor = Floor::default();
    for k in 0..n {
        let scale = control.scale();
        // The history is on the working grid; the temporal pass reprojects it into last
        // frame's grid, so it carries over a change of scale.
        let ms = orbit.frame(k, &mut ao, 0, scale, params)?;
        let cheapest = scale <= obscura::MIN_SCALE + 1e-4;
        floor.frame(cheapest.then_some("scale 0.25"), ms, budget_ms);
        control.update(ms);
        frames.push((scale, ms));
        eprintln!(
            "frame {k:4}: scale {scale:.3} {:>6} ms ({:+.0}% of the budget)",
            fmt_ms(ms),
            (ms / budget_ms - 1.0) * 100.0
        );
    }
    let times: Vec<f64> = frames.iter().map(|f| f.1).collect();
    eprintln!("budget: {}", summary(&times, budget_ms));
    let mut csv = String::from("frame,scale,ms\n");
    for (k, (scale, ms)) in frames.iter().enumerate() {
        let _ = writeln!(csv, "{k},{scale:.4},{ms:.4}");
    }
    // The right axis: scale 0.25 at the bottom, 1 at the top.
    let axis = |s: f64| (s - f64::from(obscura::MIN_SCALE)) / (1.0 - f64::from(obscura::MIN_SCALE));
    let knob: Vec<f64> = frames.iter().map(|f| axis(f64::from(f.0))).collect();
    let labels: Vec<(f64, String)> = [0.25, 0.5, 0.75, 1.0]
        .iter()
        .map(|&s| (axis(s), format!("scale {s}")))
        .collect();
    write_outputs(dir, &csv, &plot(&times, &knob, &labels, "scale", budget_ms))
}

/// The full-resolution rungs of `--budget-control joint`, above the scaled AO at the
/// preset given. Measured in one interleaved run over the nine shared views (GTAO, spatial
/// denoiser, 640×400, lavapipe; docs/budget.md "Both knobs"): at equal time a
/// full-resolution frame at the low preset is no better than the scaled high one in the
/// 2×2 layout (0.0830 at 18.4 ms against 0.0915 at scale 0.5, 16.7 ms, and 0.0748 at 0.7,
/// 21.9 ms) and worse in the randomized one (0.0790 at 24.4 ms against 0.0682 at 0.7, 24.2
/// ms), while from the medium preset up full resolution wins (2×2 0.0704 at 20.6 ms,
/// randomized 0.0623 at 26.0 ms). So the scale runs the preset given, and full resolution
/// starts at medium. Between the presets, rungs of more slices and steps keep each rung
/// within about 15% of the next one's cost (on lavapipe a frame costs a fixed part and
/// about 0.8 ms per sample at 640×400), so that a budget between two presets is held
/// rather than undershot: with the presets alone a budget between high and ultra ran
/// high, 17% under it (38 of 100 frames within ±15% of 100 ms on the built-in scene at
/// 640×400, 2026-11-29, lavapipe).
pub fn joint_rungs(e: obscura::Estimator) -> Vec<Rung> {
    use Rung::{Preset as P, Samples as S};
    if matches!(e, obscura::Estimator::Gtao | obscura::Estimator::Bitmask) {
        vec![
            P(Preset::Medium),
            P(Preset::High),
            S(4, 5, obscura::HIGH_MARCH_EXPONENT),
            S(4, 6, obscura::HIGH_MARCH_EXPONENT),
            S(4, 8, obscura::HIGH_MARCH_EXPONENT),
            S(6, 7, obscura::HIGH_MARCH_EXPONENT),
            P(Preset::Ultra),
        ]
    } else {
        let even = obscura::EVEN_MARCH_EXPONENT;
        vec![
            P(Preset::Medium),
            P(Preset::High),
            S(8, 5, even),
            S(10, 5, even),
            S(12, 5, even),
            S(14, 6, even),
            P(Preset::Ultra),
        ]
    }
}

/// A full-resolution rung of the joint controller: a preset's samples, or directions
/// (slices) × steps at a march exponent between two presets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rung {
    Preset(Preset),
    Samples(u32, u32, f32),
}

impl Rung {
    fn name(self) -> String {
        match self {
            Rung::Preset(p) => preset_name(p).into(),
            Rung::Samples(d, s, _) => format!("{d}×{s}"),
        }
    }

    /// `base` at full resolution with this rung's samples (an explicit march exponent
    /// kept).
    fn options(self, base: AoOptions, exponent: Option<f32>) -> AoOptions {
        let full = AoOptions {
            resolution: Resolution::Full,
            ..base
        };
        let o = match self {
            Rung::Preset(p) => full.with_preset(p),
            Rung::Samples(directions, steps, march_exponent) => AoOptions {
                directions,
                steps,
                march_exponent,
                ..full
            },
        };
        AoOptions {
            march_exponent: exponent.unwrap_or(o.march_exponent),
            ..o
        }
    }
}

/// Scales at which the scaled AO is timed on the first view, to fit `floor + c × s²`.
const FIT_SCALES: [f32; 4] = [0.25, 0.5, 0.75, 1.0];

/// Least-squares `(floor, c)` of `ms = floor + c × s²` over `(s, ms)` points; the floor at
/// least 0 and c at least a microsecond, so the top scale is defined.
fn fit_affine_in_area(points: &[(f32, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let x: Vec<f64> = points.iter().map(|p| f64::from(p.0).powi(2)).collect();
    let mx = x.iter().sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = x
        .iter()
        .zip(points)
        .map(|(v, p)| (v - mx) * (p.1 - my))
        .sum();
    let c = if sxx > 0.0 { sxy / sxx } else { 0.0 }.max(1e-3);
    ((my - c * mx).max(0.0), c)
}

/// Runs the orbit under the budget with both knobs (`JointController`): one `Ao` at
/// `Resolution::Scaled` at the preset given, below the scale where it costs what the
/// cheapest full-resolution rung does, and full-resolution `Ao`s at the `joint_rungs`
/// presets above it. `base` carries the estimator, preset, layout, denoiser and history.
pub fn orbit_joint(
    mut orbit: Orbit,
    base: AoOptions,
    params: &AoParams,
    budget_ms: f64,
) -> Result<()> {
    let (a, ctx, cam, dir) = (orbit.a, orbit.ctx, orbit.cam, orbit.dir);
    let mut scaled = Ao::new(&ctx.device, scaled_options(a, base))?;
    let ladder = joint_rungs(base.estimator);
    let mut rungs = Vec::with_capacity(ladder.len());
    for rung in &ladder {
        rungs.push(Ao::new(&ctx.device, rung.options(base, a.march_exponent))?);
    }
    // Everything compiled and its textures created on the first view, then timed there
    // (median of three interleaved runs): the rungs' costs and the scaled AO's cost over
    // its scale. No GPU object is created during the orbit.
    let first = orbit.first_view()?;
    let input = first.ao_input(cam, a.normals == NormalSource::Gbuffer);
    let at = |scale: f32| AoParams { scale, ..*params };
    ctx.run(|enc| scaled.record(&ctx.device, &ctx.queue, enc, &input, &at(1.0)))?;
    for ao in &mut rungs {
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &at(1.0)))?;
    }
    let timing = orbit.timing;
    let mut runs = vec![Vec::new(); FIT_SCALES.len() + rungs.len()];
    for _ in 0..3 {
        for (i, &s) in FIT_SCALES.iter().enumerate() {
            runs[i].push(frame_ms(ctx, &mut scaled, &input, &at(s), timing)?);
        }
        for (j, ao) in rungs.iter_mut().enumerate() {
            runs[FIT_SCALES.len() + j].push(frame_ms(ctx, ao, &input, &at(1.0), timing)?);
        }
    }
    let medians = medians(runs);
    let (floor, c) = fit_affine_in_area(
        &FIT_SCALES
            .iter()
            .zip(&medians)
            .map(|(&s, &ms)| (s, ms))
            .collect::<Vec<_>>(),
    );
    let nominal = &medians[FIT_SCALES.len()..];
    let name = |k: usize| format!("full {}", ladder[k].name());
    // Rungs undercut by a dearer one are skipped, as in the ladder.
    let kept = undominated(nominal);
    let costs: Vec<f64> = kept.iter().map(|&k| nominal[k]).collect();
    let min_area = f64::from(obscura::MIN_SCALE).powi(2);
    let top_area = ((costs[0] - floor) / c).clamp(min_area, 1.0);
    let top = top_area.sqrt() as f32;
    let handover = costs[0] / (floor + c * top_area);
    eprintln!(
        "budget: {budget_ms} ms per frame; measured on the first view: scaled {} {}×{} \
         {} + {} × scale² ms, {}; top scale {top:.3} (handover {handover:.2})",
        base.estimator.name(),
        base.directions,
        base.steps,
        fmt_ms(floor),
        fmt_ms(c),
        (0..nominal.len())
            .map(|k| {
                let skipped = if kept.contains(&k) {
                    ""
                } else {
                    " (skipped: a dearer rung costs no more)"
                };
                format!("{} {} ms{skipped}", name(k), fmt_ms(nominal[k]))
            })
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut control = JointController::new(budget_ms, START_SCALE.min(top), top, &costs, handover)
        .with_context(|| {
            format!("no controller for a {budget_ms} ms budget over the measured costs {costs:?}")
        })?;
    let n = a.frames;
    let mut frames: Vec<(Knob, f64)> = Vec::with_capacity(n as usize);
    let mut floor = Floor::default();
    for k in 0..n {
        let knob = control.knob();
        let (which, scale) = match knob {
            Knob::Scale(s) => (None, s),
            Knob::Level(l) => (Some(kept[l]), 1.0),
        };
        // The scaled history carries over a change of scale; an `Ao` that did not run the
        // previous frame restarts its history. Ids: 0 the scaled `Ao`, 1 + r rung r.
        let (ao, id) = match which {
            None => (&mut scaled, 0),
            Some(r) => (&mut rungs[r], 1 + r),
        };
        let ms = orbit.frame(k, ao, id, scale, params)?;
        let cheapest = which.is_none() && scale <= obscura::MIN_SCALE + 1e-4;
        floor.frame(cheapest.then_some("scale 0.25"), ms, budget_ms);
        control.update(ms);
        frames.push((knob, ms));
        let label = match which {
            None => format!("scale {scale:.3}"),
            Some(r) => name(r),
        };
        eprintln!(
            "frame {k:4}: {label:<12} {:>6} ms ({:+.0}% of the budget)",
            fmt_ms(ms),
            (ms / budget_ms - 1.0) * 100.0
        );
    }
    let times: Vec<f64> = frames.iter().map(|f| f.1).collect();
    let on_rungs = frames
        .iter()
        .filter(|f| matches!(f.0, Knob::Level(_)))
        .count();
    // A budget above the dearest rung's cost cannot be filled: those frames run the best
    // setting there is.
    let dearest = frames
        .iter()
        .filter(|f| f.0 == Knob::Level(kept.len() - 1) && f.1 < 0.85 * budget_ms)
        .count();
    eprintln!(
        "budget: {}; {on_rungs} frames at full resolution, {dearest} of them under it at the \
         dearest rung",
        summary(&times, budget_ms)
    );
    let mut csv = String::from("frame,resolution,scale,preset,ms\n");
    let base_preset = |o: &AoOptions| {
        Preset::ALL
            .into_iter()
            .find(|&p| {
                let q = o.with_preset(p);
                (q.directions, q.steps, q.march_exponent)
                    == (o.directions, o.steps, o.march_exponent)
            })
            .map_or_else(
                || format!("{}x{}", o.directions, o.steps),
                |p| preset_name(p).into(),
            )
    };
    for (k, (knob, ms)) in frames.iter().enumerate() {
        let _ = match knob {
            Knob::Scale(s) => writeln!(
                csv,
                "{k},scaled,{s:.4},{},{ms:.4}",
                base_preset(scaled.options())
            ),
            Knob::Level(l) => writeln!(csv, "{k},full,1,{},{ms:.4}", ladder[kept[*l]].name()),
        };
    }
    // The right axis: the scale from 0.25 to the top over the lower half, the kept rungs
    // evenly over the upper half.
    let lo = f64::from(obscura::MIN_SCALE);
    let scale_axis = |s: f64| {
        if f64::from(top) > lo {
            0.5 * (s - lo) / (f64::from(top) - lo)
        } else {
            0.25
        }
    };
    let rung_axis = |l: usize| 0.5 + 0.5 * (l as f64 + 0.5) / kept.len() as f64;
    let knob: Vec<f64> = frames
        .iter()
        .map(|f| match f.0 {
            Knob::Scale(s) => scale_axis(f64::from(s)),
            Knob::Level(l) => rung_axis(l),
        })
        .collect();
    let mut labels: Vec<(f64, String)> = vec![
        (scale_axis(lo), format!("scale {lo}")),
        (scale_axis(f64::from(top)), format!("scale {top:.2}")),
    ];
    labels.extend((0..kept.len()).map(|l| (rung_axis(l), name(kept[l]))));
    write_outputs(dir, &csv, &plot(&times, &knob, &labels, "knob", budget_ms))
}

/// An `Ao` with `base`'s settings at `resolution` and `preset`'s slices, steps and march
/// exponent there (`exponent`, --march-exponent, when given).
fn ao_at(
    ctx: &GpuContext,
    base: AoOptions,
    exponent: Option<f32>,
    resolution: Resolution,
    preset: Preset,
) -> Result<Ao> {
    let o = AoOptions { resolution, ..base }.with_preset(preset);
    let o = AoOptions {
        march_exponent: exponent.unwrap_or(o.march_exponent),
        ..o
    };
    Ok(Ao::new(&ctx.device, o)?)
}

/// The median of each variant's three timed runs.
fn medians(runs: Vec<Vec<f64>>) -> Vec<f64> {
    runs.into_iter()
        .map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        })
        .collect()
}

/// The indices of the costs (cheapest level first) that every dearer level's cost exceeds:
/// a level that a better one undercuts is dominated (on lavapipe timing noise can invert a
/// close pair; on a GPU the full-resolution passes set a floor).
fn undominated(costs: &[f64]) -> Vec<usize> {
    (0..costs.len())
        .filter(|&k| costs[k + 1..].iter().all(|&c| costs[k] < c))
        .collect()
}

/// The options of the scaled `Ao` that the orbit's scale knobs turn: `a`'s samples at
/// `Resolution::Scaled`, the bilateral upsampler (the only one at any scale), denoise none
/// or spatial, no bent normals.
fn scaled_options(a: &RenderArgs, base: AoOptions) -> AoOptions {
    let samples = super::args::options_at(a, Resolution::Scaled);
    AoOptions {
        directions: samples.directions,
        steps: samples.steps,
        march_exponent: samples.march_exponent,
        resolution: Resolution::Scaled,
        upsample: Upsampler::Bilateral,
        denoise: match base.denoise {
            Denoise::None => Denoise::None,
            _ => Denoise::Spatial,
        },
        bent_normals: false,
        ..base
    }
}

/// Time per frame (line, left axis, with the budget and its ±15% band) and the knob per
/// frame (steps, right axis; `knob` as fractions of the axis height, `labels` placed the same
/// way).
fn plot(
    times: &[f64],
    knob: &[f64],
    labels: &[(f64, String)],
    knob_name: &str,
    budget_ms: f64,
) -> String {
    let (w, h, left, top) = (640.0, 300.0, 60.0, 20.0);
    let n = times.len().max(2) as f64;
    let tmax = times.iter().copied().fold(budget_ms * 1.3, f64::max) * 1.05;
    let x = |k: f64| left + k / (n - 1.0) * w;
    let yt = |t: f64| top + h - t / tmax * h;
    let yl = |f: f64| top + h - f * h;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        w + left + 170.0,
        h + top + 45.0
    );
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{:.1}\" width=\"{w}\" height=\"{:.1}\" fill=\"#2ca02c\" opacity=\"0.12\"/>",
        yt(budget_ms * 1.15),
        yt(budget_ms * 0.85) - yt(budget_ms * 1.15)
    );
    let _ = writeln!(
        s,
        "<line x1=\"{left}\" x2=\"{0}\" y1=\"{1:.1}\" y2=\"{1:.1}\" stroke=\"#2ca02c\" stroke-dasharray=\"6 4\"/>\n<text x=\"{2}\" y=\"{3:.1}\" fill=\"#2ca02c\">budget {budget_ms} ms ± 15%</text>",
        left + w,
        yt(budget_ms),
        left + 6.0,
        yt(budget_ms * 1.15) - 4.0
    );
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{w}\" height=\"{h}\" fill=\"none\" stroke=\"#999\"/>"
    );
    for k in 0..=4 {
        let t = tmax * k as f64 / 4.0;
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            left - 4.0,
            yt(t) + 4.0,
            fmt_ms(t)
        );
    }
    for (f, label) in labels {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{:.1}\" fill=\"#1f77b4\">{label}</text>",
            left + w + 6.0,
            yl(*f) + 4.0,
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">frame ({} in all)</text>\n<text x=\"14\" y=\"{2}\" transform=\"rotate(-90 14 {2})\" text-anchor=\"middle\">ms per frame (black); {knob_name} (blue)</text>",
        left + w / 2.0,
        top + h + 32.0,
        times.len()
    );
    let steps: Vec<String> = knob
        .iter()
        .enumerate()
        .flat_map(|(k, f)| {
            let y = yl(*f);
            [
                format!("{:.1},{y:.1}", x(k as f64 - 0.5).max(left)),
                format!("{:.1},{y:.1}", x(k as f64 + 0.5).min(left + w)),
            ]
        })
        .collect();
    let _ = writeln!(
        s,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"#1f77b4\" stroke-width=\"2\" opacity=\"0.7\"/>",
        steps.join(" ")
    );
    let line: Vec<String> = times
        .iter()
        .enumerate()
        .map(|(k, t)| format!("{:.1},{:.1}", x(k as f64), yt(*t)))
        .collect();
    let _ = writeln!(
        s,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>",
        line.join(" ")
    );
    s.push_str("</svg>\n");
    s
}

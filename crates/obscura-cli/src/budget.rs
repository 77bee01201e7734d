//! `render --orbit ... --budget-ms X`: the orbit of `render --orbit`, each frame at the
//! working scale that `obscura::budget::ScaleController` chooses (`--budget-control scale`,
//! the default) or at the level of a ladder of AO settings that
//! `obscura::budget::BudgetController` chooses (`--budget-control ladder`) to hold the
//! budget; prints each frame's time and scale or level, and writes `budget.csv` and
//! `budget.svg` (time and knob per frame) beside the frames.

use anyhow::{Context, Result};
use obscura::budget::{BudgetController, ScaleController};
use obscura::{
    Ao, AoOptions, AoParams, CameraMotion, Denoise, GpuContext, Preset, Resolution, Timing,
    Upsampler,
};
use obscura_scene::{Camera, GBufferRenderer, GpuMesh};
use std::fmt::Write as _;
use std::path::Path;

use crate::bench::frame_ms;
use crate::output::{fmt_ms, save_ao};
use crate::render::{orbit_turn, NormalSource, RenderArgs};

/// The ladder, from the most error to the least: working resolution and preset. The order
/// is measured, for GTAO in the default 2×2 layout with the spatial denoiser (mean RMSE
/// against ray-traced AO over the shared views; docs/frontier.md, docs/sample-reuse.md):
/// half low 0.1033, medium 0.1006, high 0.0915, ultra 0.0907; full low 0.0831, medium
/// 0.0704, high 0.0605, ultra 0.0565. Full resolution at the low preset beats half at the
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
#[allow(clippy::too_many_arguments)]
pub fn orbit(
    a: &RenderArgs,
    ctx: &GpuContext,
    raster: &GBufferRenderer,
    mesh: &GpuMesh,
    cam: &Camera,
    base: AoOptions,
    params: &AoParams,
    (degrees, budget_ms): (f32, f64),
    dir: &Path,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create `{}`", dir.display()))?;
    // The ladder's resolutions are fixed: scale 1 whatever --scale says.
    let params = &AoParams {
        scale: 1.0,
        ..*params
    };
    // Every level is created and warmed up on the first view (shader compilation and its
    // textures), then timed there: those times are the controller's nominal costs, and no
    // GPU object is created during the orbit.
    let first = raster.render(ctx, mesh, cam, a.width, a.height)?;
    let input = first.ao_input(cam, a.normals == NormalSource::Gbuffer);
    let mut levels = Vec::with_capacity(LADDER.len());
    for (resolution, preset) in LADDER {
        let o = AoOptions {
            resolution,
            ..AoOptions::preset(base.estimator, preset)
        };
        let mut ao = Ao::new(
            &ctx.device,
            AoOptions {
                resolution,
                directions: o.directions,
                steps: o.steps,
                ..base
            },
        )?;
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, params))?;
        levels.push(ao);
    }
    // Median of three runs per level, interleaved (CPU adapters' times vary by ±20%).
    let mut runs = vec![Vec::new(); levels.len()];
    let timing = Timing::best_for(ctx);
    for _ in 0..3 {
        for (ao, times) in levels.iter_mut().zip(&mut runs) {
            times.push(frame_ms(ctx, ao, &input, params, timing)?);
        }
    }
    let nominal: Vec<f64> = runs
        .into_iter()
        .map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[1]
        })
        .collect();
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
    let kept: Vec<usize> = (0..nominal.len())
        .filter(|&k| nominal[k + 1..].iter().all(|&c| nominal[k] < c))
        .collect();
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
    let mut previous: Option<(Camera, usize)> = None;
    for k in 0..n {
        let c = cam.orbit(orbit_turn(degrees, k, n));
        let g = raster.render(ctx, mesh, &c, a.width, a.height)?;
        let input = g.ao_input(&c, a.normals == NormalSource::Gbuffer);
        let level = kept[control.level()];
        let ao = &mut levels[level];
        // A level's history is from the last frame it ran, not the previous one: restart it.
        let motion = match previous {
            Some((prev, l)) if l == level => c.motion_since(&prev),
            Some(_) => {
                ao.restart();
                CameraMotion::Cut
            }
            None => CameraMotion::Cut,
        };
        let p = AoParams { motion, ..*params };
        let ms = frame_ms(ctx, ao, &input, &p, timing)?;
        control.update(ms);
        frames.push((level, ms));
        let values = ctx.read_f32(ao.output().context("AO output missing after a run")?)?;
        let path = dir.join(format!("frame_{k:04}.png"));
        save_ao(&path, &values, a.width, a.height, a.bits)?;
        eprintln!(
            "frame {k:4}: level {level} ({}) {:>6} ms ({:+.0}% of the budget)",
            name(level),
            fmt_ms(ms),
            (ms / budget_ms - 1.0) * 100.0
        );
        previous = Some((c, level));
    }
    eprintln!(
        "budget: {}, {} level changes",
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
#[allow(clippy::too_many_arguments)]
pub fn orbit_scaled(
    a: &RenderArgs,
    ctx: &GpuContext,
    raster: &GBufferRenderer,
    mesh: &GpuMesh,
    cam: &Camera,
    base: AoOptions,
    params: &AoParams,
    (degrees, budget_ms): (f32, f64),
    dir: &Path,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create `{}`", dir.display()))?;
    let options = AoOptions {
        resolution: Resolution::Scaled,
        upsample: Upsampler::Bilateral,
        denoise: match base.denoise {
            Denoise::None => Denoise::None,
            _ => Denoise::Spatial,
        },
        bent_normals: false,
        ..base
    };
    let mut ao = Ao::new(&ctx.device, options)?;
    // Compiled and its textures (those of scale 1 serve every scale) created before the
    // first timed frame: nothing is created during the orbit.
    let first = raster.render(ctx, mesh, cam, a.width, a.height)?;
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
    let timing = Timing::best_for(ctx);
    let n = a.frames;
    let mut frames: Vec<(f32, f64)> = Vec::with_capacity(n as usize);
    let mut previous: Option<Camera> = None;
    for k in 0..n {
        let c = cam.orbit(orbit_turn(degrees, k, n));
        let g = raster.render(ctx, mesh, &c, a.width, a.height)?;
        let input = g.ao_input(&c, a.normals == NormalSource::Gbuffer);
        let scale = control.scale();
        // The history is on the working grid; the temporal pass reprojects it into last
        // frame's grid, so it carries over a change of scale.
        let motion = previous.map_or(CameraMotion::Cut, |p| c.motion_since(&p));
        let p = AoParams {
            motion,
            scale,
            ..*params
        };
        let ms = frame_ms(ctx, &mut ao, &input, &p, timing)?;
        control.update(ms);
        frames.push((scale, ms));
        let values = ctx.read_f32(ao.output().context("AO output missing after a run")?)?;
        let path = dir.join(format!("frame_{k:04}.png"));
        save_ao(&path, &values, a.width, a.height, a.bits)?;
        eprintln!(
            "frame {k:4}: scale {scale:.3} {:>6} ms ({:+.0}% of the budget)",
            fmt_ms(ms),
            (ms / budget_ms - 1.0) * 100.0
        );
        previous = Some(c);
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

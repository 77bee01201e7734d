//! `obscura cost`: the cost model of a frame's passes (obscura::frame::cost), counted from
//! the plan, no adapter needed: per pass the invocations, each one's texel fetches,
//! special-function operations and other arithmetic, the bytes it binds, and the time each
//! device's peaks allow (the H200's roofline, lavapipe's measured rates).

use crate::options::{parse_denoise, parse_resolution, ModeArg, NormalSource, QualityArgs};
use anyhow::{bail, Result};
use clap::Args;
use obscura::frame::cost::{frame_cost, Device, PassCost, H200, LAVAPIPE};
use obscura::{AoOptions, Denoise, Resolution};
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct CostArgs {
    /// Frame width in pixels.
    #[arg(long, default_value_t = 1920)]
    pub width: u32,
    /// Frame height in pixels.
    #[arg(long, default_value_t = 1080)]
    pub height: u32,
    /// Pass layout.
    #[arg(long, value_enum, default_value_t = ModeArg::Deinterleaved2)]
    pub mode: ModeArg,
    #[command(flatten)]
    pub quality: QualityArgs,
    /// AO resolution: full, half or quarter.
    #[arg(long, value_parser = parse_resolution, default_value = "full")]
    pub resolution: Resolution,
    /// Filtering at the working resolution: none, spatial, box, tent.
    #[arg(long, value_parser = parse_denoise, default_value = "spatial")]
    pub denoise: Denoise,
    /// March exponent (1: even steps; the presets' own by default).
    #[arg(long)]
    pub march_exponent: Option<f32>,
    /// A second depth layer (the bitmask).
    #[arg(long)]
    pub second_layer: bool,
    /// Normals given by the renderer, or reconstructed from the depth in the prepare pass.
    #[arg(long, value_enum, default_value_t = NormalSource::Gbuffer)]
    pub normals: NormalSource,
    /// Also write the table as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

pub fn run(a: &CostArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 {
        bail!("--width and --height must be at least 1");
    }
    if let Some(p) = &a.json {
        crate::output::check_folder(p)?;
    }
    let mut o = a.quality.samples.apply(AoOptions {
        estimator: a.quality.estimator.into(),
        mode: a.mode.into(),
        resolution: a.resolution,
        denoise: a.denoise,
        second_layer: a.second_layer,
        ..AoOptions::default()
    });
    if let Some(e) = a.march_exponent {
        o.march_exponent = e;
    }
    o.validate()?;
    let passes = frame_cost(&o, [a.width, a.height], a.normals == NormalSource::Gbuffer);
    println!(
        "{} {} {} × {} steps (exponent {}), {} resolution, denoise {}, {}×{}{}",
        o.estimator.name(),
        o.mode.name(),
        o.directions,
        o.steps,
        o.march_exponent,
        o.resolution.name(),
        o.denoise.name(),
        a.width,
        a.height,
        if o.second_layer { ", second layer" } else { "" }
    );
    println!();
    println!(
        "| pass | invocations | fetches | special | other ops | MB bound | {} | {} |",
        H200.name, LAVAPIPE.name
    );
    println!("|---|---|---|---|---|---|---|---|");
    for p in &passes {
        let w = p.per_invocation;
        let count = |f: fn(&obscura::frame::cost::Work) -> f64| {
            w.map_or("–".into(), |w| format!("{:.0}", f(&w)))
        };
        println!(
            "| {} | {:.2} M | {} | {} | {} | {:.1} | {} | {} |",
            p.label,
            p.invocations as f64 / 1e6,
            count(|w| w.fetches),
            count(|w| w.special),
            count(|w| w.alu),
            p.bytes as f64 / 1e6,
            time(&H200, p, 1e6, "µs"),
            time(&LAVAPIPE, p, 1e3, "ms"),
        );
    }
    let total = |d: &Device, scale: f64| -> Option<f64> {
        passes.iter().map(|p| d.time(p).map(|t| t.0 * scale)).sum()
    };
    let show = |t: Option<f64>, unit: &str| {
        t.map_or("– (a pass is not counted)".into(), |t| {
            format!("{t:.1} {unit}")
        })
    };
    println!(
        "| frame | | | | | {:.1} | {} | {} |",
        passes.iter().map(|p| p.bytes).sum::<u64>() as f64 / 1e6,
        show(total(&H200, 1e6), "µs"),
        show(total(&LAVAPIPE, 1e3), "ms"),
    );
    if let Some(p) = &a.json {
        crate::output::write_text(p, &to_json(&o, a, &passes))?;
    }
    println!();
    println!(
        "Counted per invocation (fetches exact where every sample lands on a surface on screen; \
         arithmetic a hand count of the WGSL, good to about a fifth). Times are at the device's \
         peaks: the H200's roofline takes each pass's slowest unit (named), lavapipe the sum of \
         every kind of work; a measured time above them is what latency, cache misses and \
         divergence cost."
    );
    Ok(())
}

fn time(d: &Device, p: &PassCost, scale: f64, unit: &str) -> String {
    match d.time(p) {
        Some((t, bound)) if d.overlapped => format!("{:.1} {unit} ({})", t * scale, bound.name()),
        Some((t, _)) => format!("{:.1} {unit}", t * scale),
        None => "–".into(),
    }
}

fn to_json(o: &AoOptions, a: &CostArgs, passes: &[PassCost]) -> String {
    let device = |d: &Device, p: &PassCost| {
        d.time(p)
            .map(|(t, b)| json!({ "seconds": t, "bound": b.name() }))
    };
    let rows: Vec<_> = passes
        .iter()
        .map(|p| {
            json!({
                "pass": p.label,
                "invocations": p.invocations,
                "fetches": p.per_invocation.map(|w| w.fetches),
                "special": p.per_invocation.map(|w| w.special),
                "other_ops": p.per_invocation.map(|w| w.alu),
                "bytes": p.bytes,
                "h200": device(&H200, p),
                "lavapipe": device(&LAVAPIPE, p),
            })
        })
        .collect();
    let doc = json!({
        "estimator": o.estimator.name(),
        "mode": o.mode.name(),
        "directions": o.directions,
        "steps": o.steps,
        "march_exponent": (o.march_exponent as f64 * 1e4).round() / 1e4,
        "resolution": o.resolution.name(),
        "denoise": o.denoise.name(),
        "second_layer": o.second_layer,
        "normals_given": a.normals == NormalSource::Gbuffer,
        "width": a.width,
        "height": a.height,
        "passes": rows,
    });
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}

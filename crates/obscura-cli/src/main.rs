//! `obscura`: screen-space ambient occlusion from the command line.

mod commands;
mod options;
mod output;
mod progress;
mod readback;
mod ssdo_shading;
mod timing;
mod views;

use clap::parser::ValueSource;
use clap::{CommandFactory, FromArgMatches, Subcommand};
use commands::{bench, cost, eval, lights, render};
use std::process::ExitCode;

/// Screen-space ambient occlusion on any GPU wgpu reaches, or on the CPU through Mesa's
/// lavapipe. Set OBSCURA_ADAPTER=cpu|gpu|<name substring> to force the adapter.
#[derive(Debug, clap::Parser)]
#[command(name = "obscura", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render a scene's G-buffer and compute its ambient occlusion, written as PNG.
    Render(render::RenderArgs),
    /// Time the AO pass layouts (randomized, deinterleaved 2×2 and 4×4, fused or not)
    /// against each other over radius and resolution, on the built-in scene.
    Bench(bench::BenchArgs),
    /// Compare the AO of each pass layout with ray-traced ground truth (RMSE, bias, SSIM,
    /// error near depth discontinuities, time), on a scene or the shared standard views.
    Eval(eval::EvalArgs),
    /// Interleaved many-light shading against shading every light: virtual point lights
    /// on the built-in scene (or a scene file, or the shared views), time and error.
    Lights(lights::LightsArgs),
    /// The cost model of a frame's passes, counted from the plan (no adapter): invocations,
    /// texel fetches, special-function and other operations, bytes, and the time at an
    /// H200's peaks and at lavapipe's measured rates.
    Cost(cost::CostArgs),
}

fn main() -> ExitCode {
    // Mesa's Vulkan device-select layer probes for a display server and prints
    // "XDG_RUNTIME_DIR is invalid" on headless machines; obscura chooses adapters itself.
    // OBSCURA_DEVICE_SELECT keeps it. Set before any thread exists.
    if obscura::context::quiet_device_select() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
    let matches = Cli::command().get_matches();
    let mut cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    // Which flags the command line gave (not their defaults): a command refuses a flag
    // that would do nothing for its input.
    let given = |name: &str| -> options::Given {
        let Some(m) = matches.subcommand_matches(name) else {
            return Default::default();
        };
        m.ids()
            .filter(|id| m.value_source(id.as_str()) == Some(ValueSource::CommandLine))
            .map(|id| id.to_string())
            .collect()
    };
    match &mut cli.command {
        Command::Render(a) => {
            a.given = given("render");
            // A depth map alone takes the library's estimator for depth maps unless the
            // command line names one.
            if a.depth.is_some() && !a.given.contains("estimator") {
                a.quality.estimator = options::EstimatorArg::of(obscura::DEPTH_MAP_ESTIMATOR);
            }
            if a.layered {
                render::apply_layered(a);
            }
        }
        Command::Eval(a) => a.given = given("eval"),
        Command::Bench(_) | Command::Lights(_) | Command::Cost(_) => {}
    }
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Lights(args) => lights::run(&args),
        Command::Cost(args) => cost::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

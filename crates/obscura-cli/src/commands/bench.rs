//! `obscura bench`: the AO pass layouts compared in one process, interleaved
//! (A B C … A B C …) after warm-up, over on-screen radius × resolution. GPU timestamps per
//! pass on hardware adapters; on CPU adapters (lavapipe, whose timestamps do not bracket
//! dispatches) the wall clock around submit + wait of each pass. Medians and ratios to the
//! first variant (the randomized single pass, or full resolution with `--compare resolutions`).

use crate::options::{ModeArg, NormalSource, QualityArgs, ResolutionArgs};
use crate::output::{check_png_path, fmt_ms, write_text};
use crate::timing::{pass_medians, warm_up};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use obscura::{
    Ao, AoMode, AoOptions, AoParams, Denoise, Estimator, GpuContext, Resolution, Timing,
};
use obscura_scene::{default_scene, DepthLayer, GBuffer, GBufferRenderer, GpuMesh};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What the variants of a benchmark differ in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Compare {
    /// Pass layouts: randomized, 2×2 and 4×4 deinterleaved, fused and not (the first is
    /// the baseline of the ratios).
    Layouts,
    /// AO resolution full, half, quarter in the default layout, with the --downsample,
    /// --upsample and --denoise choices (full is the baseline).
    Resolutions,
    /// Sample reuse in the chosen layout and resolution: no denoising (the baseline), the
    /// spatial denoiser, and the denoiser with temporal accumulation (history 16).
    Reuse,
    /// Depth beyond one layer, in the chosen layout and resolution: one layer (the
    /// baseline) and a guard band of --guard-band pixels; with `--estimator bitmask` (the
    /// estimator that reads one) also a second depth layer peeled at the thickness prior
    /// behind the first (`AoOptions::second_layer`), alone and with the band. The peel
    /// itself is the renderer's and is not timed.
    Layers,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// What the variants differ in.
    #[arg(long, value_enum, default_value_t = Compare::Layouts)]
    pub compare: Compare,
    #[command(flatten)]
    pub resolution: ResolutionArgs,
    /// With --compare resolutions: the pass layout every resolution runs in.
    #[arg(long, value_enum, default_value_t = ModeArg::Deinterleaved2)]
    pub mode: ModeArg,
    /// Resolutions as WxH, comma-separated.
    #[arg(long, default_value = "1280x720,1920x1080,3840x2160")]
    pub resolutions: String,
    /// On-screen AO radii in pixels, comma-separated. Every pixel gets exactly this radius
    /// (view-space radius unbounded, clamped by max_radius_px).
    #[arg(long, default_value = "8,32,128,256")]
    pub radii: String,
    /// Timed rounds after one warm-up round; each round runs every variant once.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub runs: u32,
    #[command(flatten)]
    pub quality: QualityArgs,
    /// Where the AO normals come from (the G-buffer's, or reconstructed from depth).
    #[arg(long, value_enum, default_value_t = NormalSource::Gbuffer)]
    pub normals: NormalSource,
    /// Rasterize depth alone with 4× MSAA and time obscura's resolve with the rest (normals
    /// are then reconstructed, whatever --normals says).
    #[arg(long)]
    pub msaa: bool,
    /// With --compare layers: the guard band's width in pixels on each side.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub guard_band: u32,
    /// Write machine-readable results here (one record per variant, resolution and radius).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write a plot of time versus radius per variant (SVG).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// One measured cell.
struct Record {
    variant: String,
    width: u32,
    height: u32,
    radius_px: f32,
    median_ms: f64,
    passes: Vec<(&'static str, f64)>,
    ratio: f64,
}

/// The G-buffers `--compare layers` times, in its variants' order: the view alone, the
/// view with a guard band, and each with its second layer peeled behind it.
struct LayerInputs {
    camera: obscura_scene::Camera,
    plain: GBuffer,
    guarded: GBuffer,
    plain_second: DepthLayer,
    guarded_second: DepthLayer,
}

impl LayerInputs {
    fn render(
        ctx: &GpuContext,
        raster: &GBufferRenderer,
        mesh: &GpuMesh,
        size: (u32, u32),
        band: u32,
        separation: f32,
    ) -> Result<Self> {
        let camera = default_scene::camera();
        let plain = raster.render_guarded(ctx, mesh, &camera, size, 0)?;
        let guarded = raster.render_guarded(ctx, mesh, &camera, size, band)?;
        let plain_second = raster.peel(ctx, mesh, &camera, &plain, separation)?;
        let guarded_second = raster.peel(ctx, mesh, &camera, &guarded, separation)?;
        Ok(Self {
            camera,
            plain,
            guarded,
            plain_second,
            guarded_second,
        })
    }

    fn inputs(&self, with_normals: bool) -> Vec<obscura::AoInput<'_>> {
        let plain = self.plain.ao_input(&self.camera, with_normals);
        let guarded = self.guarded.ao_input(&self.camera, with_normals);
        vec![
            plain,
            guarded,
            obscura::AoInput {
                second_layer: Some(&self.plain_second.view),
                ..plain
            },
            obscura::AoInput {
                second_layer: Some(&self.guarded_second.view),
                ..guarded
            },
        ]
    }
}

fn variants(base: AoOptions, compare: Compare) -> Vec<(String, AoOptions)> {
    let mut v = Vec::new();
    if compare == Compare::Reuse {
        for (name, denoise, history) in [
            ("none", Denoise::None, 0),
            ("spatial", Denoise::Spatial, 0),
            ("spatial+temporal", Denoise::Spatial, 16),
        ] {
            v.push((
                name.to_string(),
                AoOptions {
                    denoise,
                    history,
                    ..base
                },
            ));
        }
        return v;
    }
    if compare == Compare::Layers {
        for (name, second_layer) in [
            ("one-layer", false),
            ("guard-band", false),
            ("second-layer", true),
            ("second-layer+guard-band", true),
        ] {
            if second_layer && base.estimator != Estimator::Bitmask {
                continue;
            }
            v.push((
                name.to_string(),
                AoOptions {
                    second_layer,
                    ..base
                },
            ));
        }
        return v;
    }
    if compare == Compare::Resolutions {
        for resolution in Resolution::ALL {
            v.push((
                resolution.name().to_string(),
                AoOptions { resolution, ..base },
            ));
        }
        return v;
    }
    for mode in AoMode::ALL {
        for fused in [true, false] {
            if mode == AoMode::Randomized && !fused {
                continue;
            }
            let name = format!("{}{}", mode.name(), if fused { "" } else { "-unfused" });
            v.push((
                name,
                AoOptions {
                    mode,
                    fused,
                    ..base
                },
            ));
        }
    }
    v
}

fn parse_list<T: std::str::FromStr>(s: &str, what: &str) -> Result<Vec<T>> {
    s.split(',')
        .map(|t| t.trim().parse::<T>().ok())
        .collect::<Option<Vec<T>>>()
        .with_context(|| format!("{what} `{s}` is not a comma-separated list"))
}

pub fn run(a: &BenchArgs) -> Result<()> {
    let resolutions: Vec<(u32, u32)> = a
        .resolutions
        .split(',')
        .map(|r| {
            let (w, h) = r
                .trim()
                .split_once('x')
                .with_context(|| format!("resolution `{r}` is not WxH"))?;
            Ok((w.parse()?, h.parse()?))
        })
        .collect::<Result<_>>()
        .with_context(|| format!("--resolutions `{}`", a.resolutions))?;
    let radii: Vec<f32> = parse_list(&a.radii, "--radii")?;
    if resolutions.iter().any(|&(w, h)| w == 0 || h == 0) {
        bail!("resolutions must be at least 1x1");
    }
    if radii.iter().any(|r| !(1.0..=4096.0).contains(r)) {
        bail!("radii must be pixels in [1, 4096]");
    }
    if a.runs == 0 || a.runs > 100 {
        bail!("--runs must be in 1..=100");
    }
    if a.resolution.scale != 1.0 && a.resolution.resolution != Resolution::Scaled {
        bail!(
            "--scale {} needs --resolution scaled (the other resolutions have fixed scales)",
            a.resolution.scale
        );
    }
    if let Some(p) = &a.json {
        crate::output::check_folder(p)?;
    }
    if let Some(p) = &a.plot {
        check_svg_path(p)?;
    }
    if a.msaa && a.compare == Compare::Layers {
        bail!("--compare layers rasterizes its own layers: it does not take --msaa");
    }
    // Every compared layout and resolution takes the base's samples.
    let base = a.quality.samples.apply(a.resolution.apply(AoOptions {
        estimator: a.quality.estimator.into(),
        mode: a.mode.into(),
        ..AoOptions::default()
    }));
    let variants = variants(base, a.compare);
    for (_, o) in &variants {
        o.validate()?;
    }

    let ctx = GpuContext::new()?;
    let timing = Timing::best_for(&ctx);
    eprintln!("adapter: {}; timing: {timing:?}", ctx.describe());
    let raster = GBufferRenderer::new(&ctx.device);
    let scene = default_scene::mesh();
    let mesh = raster.upload(&ctx, &scene)?;
    // --compare layers peels at the default thickness prior times `render`'s default radius
    // (3% of the scene's diagonal): the second layer a renderer would hand over for the
    // scene. The AO itself runs at the fixed on-screen radius of every bench cell, so its
    // thickness prior need not match the peel's: the layer's cost, not its AO, is measured.
    let separation =
        AoParams::default().thickness * 0.03 * scene.bounds().map_or(1.0, |b| b.diagonal());
    let cam = default_scene::camera();
    let mut aos: Vec<Ao> = variants
        .iter()
        .map(|(_, o)| Ao::new(&ctx.device, *o))
        .collect::<Result<_, _>>()?;
    let mut records = Vec::new();
    let total = resolutions.len() * radii.len();
    let mut cell = 0;
    for &(w, h) in &resolutions {
        let (g, ms, layers);
        let mut inputs = Vec::new();
        if a.msaa {
            ms = raster.render_msaa_depth(&ctx, &mesh, &cam, w, h)?;
            inputs.push(ms.ao_input(&cam));
        } else if a.compare == Compare::Layers {
            layers = LayerInputs::render(&ctx, &raster, &mesh, (w, h), a.guard_band, separation)?;
            inputs = layers.inputs(a.normals == NormalSource::Gbuffer);
        } else {
            g = raster.render(&ctx, &mesh, &cam, w, h)?;
            inputs.push(g.ao_input(&cam, a.normals == NormalSource::Gbuffer));
        }
        for &r in &radii {
            cell += 1;
            let params = AoParams {
                radius: 1e6,
                max_radius_px: r,
                scale: a.resolution.scale,
                ..Default::default()
            };
            // One round of every variant, timed per pass.
            let round = |aos: &mut [Ao]| -> Result<Vec<Vec<(&'static str, f64)>>> {
                let mut t = Vec::with_capacity(aos.len());
                for (i, ao) in aos.iter_mut().enumerate() {
                    // `--compare resolutions` runs the fixed resolutions, at scale 1.
                    let scaled = ao.options().resolution == Resolution::Scaled;
                    let params = AoParams {
                        scale: if scaled { params.scale } else { 1.0 },
                        ..params
                    };
                    // One input for all variants, or one each (--compare layers).
                    let input = &inputs[i.min(inputs.len() - 1)];
                    t.push(ao.run_timed(&ctx, input, &params, timing)?);
                }
                Ok(t)
            };
            warm_up(timing, || round(&mut aos).map(drop))?;
            let mut times: Vec<Vec<Vec<(&'static str, f64)>>> = vec![Vec::new(); aos.len()];
            for _ in 0..a.runs {
                for (i, t) in round(&mut aos)?.into_iter().enumerate() {
                    times[i].push(t);
                }
            }
            let summaries: Vec<_> = times.iter().map(|runs| pass_medians(runs)).collect();
            let base = summaries[0].0;
            let mut line = format!("[{cell}/{total}] {w}x{h} radius {r} px:");
            for ((name, _), (median_ms, passes)) in variants.iter().zip(summaries) {
                let _ = write!(
                    line,
                    " {name} {} ms ({:.2}x)",
                    fmt_ms(median_ms),
                    base / median_ms
                );
                records.push(Record {
                    variant: name.clone(),
                    width: w,
                    height: h,
                    radius_px: r,
                    median_ms,
                    passes,
                    ratio: median_ms / base,
                });
            }
            eprintln!("{line}");
        }
    }
    print!("{}", table(&records, &variants));
    if let Some(p) = &a.json {
        write_text(p, &json(&records, &ctx, a, &base))?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &a.plot {
        write_text(p, &svg(&records, &variants, &resolutions))?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

fn check_svg_path(p: &Path) -> Result<()> {
    // Same folder rules as PNG output; only the extension differs.
    let as_png = p.with_extension("png");
    check_png_path(&as_png)?;
    if p.extension().and_then(|e| e.to_str()) != Some("svg") {
        bail!("--plot `{}` must end in .svg", p.display());
    }
    Ok(())
}

/// Markdown: one row per resolution and radius; each variant's median and ratio
/// (baseline time / variant time, > 1 = faster than the first variant).
fn table(records: &[Record], variants: &[(String, AoOptions)]) -> String {
    let mut s = String::from("| resolution | radius px |");
    for (name, _) in variants {
        let _ = write!(s, " {name} ms (speed-up) |");
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---|".repeat(variants.len()));
    s.push('\n');
    for row in records.chunks(variants.len()) {
        let _ = write!(
            s,
            "| {}×{} | {} |",
            row[0].width, row[0].height, row[0].radius_px
        );
        for r in row {
            let _ = write!(s, " {} ({:.2}×) |", fmt_ms(r.median_ms), 1.0 / r.ratio);
        }
        s.push('\n');
    }
    s.push_str("\nPer pass (median ms):\n\n| resolution | radius px | variant | passes |\n|---|---|---|---|\n");
    for r in records {
        let passes: Vec<String> = r
            .passes
            .iter()
            .map(|(l, t)| format!("{l} {}", fmt_ms(*t)))
            .collect();
        let _ = writeln!(
            s,
            "| {}×{} | {} | {} | {} |",
            r.width,
            r.height,
            r.radius_px,
            r.variant,
            passes.join(", ")
        );
    }
    s
}

fn json(records: &[Record], ctx: &GpuContext, a: &BenchArgs, base: &AoOptions) -> String {
    let esc = |t: &str| t.replace('\\', "\\\\").replace('"', "\\\"");
    let mut s = format!(
        "{{\n  \"adapter\": \"{}\",\n  \"estimator\": \"{}\",\n  \"directions\": {},\n  \"steps\": {},\n  \"march_exponent\": {},\n  \"runs\": {},\n  \"records\": [\n",
        esc(&ctx.describe()),
        base.estimator.name(),
        base.directions,
        base.steps,
        base.march_exponent,
        a.runs
    );
    for (i, r) in records.iter().enumerate() {
        let passes: Vec<String> = r
            .passes
            .iter()
            .map(|(l, t)| format!("\"{l}\": {t:.4}"))
            .collect();
        let _ = writeln!(
            s,
            "    {{\"variant\": \"{}\", \"width\": {}, \"height\": {}, \"radius_px\": {}, \"median_ms\": {:.4}, \"ratio_to_baseline\": {:.4}, \"passes_ms\": {{{}}}}}{}",
            r.variant,
            r.width,
            r.height,
            r.radius_px,
            r.median_ms,
            r.ratio,
            passes.join(", "),
            if i + 1 == records.len() { "" } else { "," }
        );
    }
    s.push_str("  ]\n}\n");
    s
}

/// One panel per resolution: time (ms, from 0) against radius (px, log scale), a line per variant.
fn svg(records: &[Record], variants: &[(String, AoOptions)], resolutions: &[(u32, u32)]) -> String {
    // Colour by split factor where that tells the variants apart (--compare layouts), else
    // by variant; unfused variants dashed.
    let by_split = {
        let mut keys: Vec<(u32, bool)> = variants
            .iter()
            .map(|v| (v.1.mode.split(), v.1.fused))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        keys.len() == variants.len()
    };
    const PALETTE: [&str; 4] = ["#222222", "#1f77b4", "#e6730f", "#2ca02c"];
    let style = |vi: usize, o: &AoOptions| {
        let color = if by_split {
            match o.mode.split() {
                1 => PALETTE[0],
                2 => PALETTE[1],
                _ => PALETTE[2],
            }
        } else {
            PALETTE[vi % PALETTE.len()]
        };
        let dash = if o.fused {
            ""
        } else {
            " stroke-dasharray=\"6 4\""
        };
        format!("stroke=\"{color}\"{dash}")
    };
    let (pw, ph, m) = (360.0, 260.0, 50.0);
    let width = m + resolutions.len() as f64 * (pw + m);
    let height = ph + 2.0 * m + 20.0 * variants.len() as f64;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let radii: Vec<f64> = {
        let mut r: Vec<f64> = records.iter().map(|r| r.radius_px as f64).collect();
        r.sort_by(f64::total_cmp);
        r.dedup();
        r
    };
    let (rmin, rmax) = (
        radii[0].log2(),
        radii[radii.len() - 1].log2().max(radii[0].log2() + 1.0),
    );
    for (pi, &(w, h)) in resolutions.iter().enumerate() {
        let x0 = m + pi as f64 * (pw + m);
        let cells: Vec<&Record> = records
            .iter()
            .filter(|r| r.width == w && r.height == h)
            .collect();
        let tmax = cells.iter().map(|r| r.median_ms).fold(1e-9, f64::max) * 1.1;
        let px = |r: f64| x0 + (r.log2() - rmin) / (rmax - rmin) * pw;
        let py = |t: f64| m + ph - t / tmax * ph;
        let _ = writeln!(s, "<rect x=\"{x0}\" y=\"{m}\" width=\"{pw}\" height=\"{ph}\" fill=\"none\" stroke=\"#999\"/>");
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{w}×{h}</text>",
            x0 + pw / 2.0,
            m - 10.0
        );
        for &r in &radii {
            let _ = writeln!(
                s,
                "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{r}</text>",
                px(r),
                m + ph + 15.0
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">radius (px, log scale)</text>",
            x0 + pw / 2.0,
            m + ph + 32.0
        );
        for k in 0..=4 {
            let t = tmax * k as f64 / 4.0;
            let _ = writeln!(
                s,
                "<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{t:.0}</text>",
                x0 - 4.0,
                py(t) + 4.0
            );
        }
        for (vi, (name, o)) in variants.iter().enumerate() {
            let pts: Vec<String> = cells
                .iter()
                .filter(|r| &r.variant == name)
                .map(|r| format!("{:.1},{:.1}", px(r.radius_px as f64), py(r.median_ms)))
                .collect();
            let _ = writeln!(
                s,
                "<polyline points=\"{}\" fill=\"none\" {} stroke-width=\"2\"/>",
                pts.join(" "),
                style(vi, o)
            );
        }
    }
    let _ = writeln!(
        s,
        "<text x=\"10\" y=\"{}\" transform=\"rotate(-90 10 {})\">median ms per frame</text>",
        m + ph / 2.0,
        m + ph / 2.0
    );
    for (vi, (name, o)) in variants.iter().enumerate() {
        let y = m + ph + 50.0 + 18.0 * vi as f64;
        let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" {} stroke-width=\"3\"/><text x=\"{}\" y=\"{}\">{name}</text>", m + 30.0, style(vi, o), m + 38.0, y + 4.0);
    }
    s.push_str("</svg>\n");
    s
}

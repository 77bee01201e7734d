//! `eval --ssdo`: screen-space directional occlusion judged against the ray tracer
//! extended to the same lighting (`obscura_eval::trace_ssdo_view`: the environment within
//! the radius and one diffuse bounce), beside the usual `AO × E(n)` and no occlusion at
//! all, in each layout, with each variant's cost timed interleaved (wall clock around
//! submit + wait, after a warm-up, median).

use super::args::EvalArgs;
use super::pictures::shrink;
use crate::output::{fmt_ms, write_text};
use crate::progress::tenths;
use crate::ssdo_shading::{inputs, lighting, parse_env, read_rgba, save_radiance};
use crate::timing::median;
use crate::views::{camera_for, Job};
use anyhow::{Context, Result};
use obscura::{
    Ao, AoOptions, AoParams, Environment, Estimator, GpuContext, IrradianceSh, Ssdo, SsdoOptions,
};
use obscura_eval::cache::{self, Fnv};
use obscura_eval::{Bvh, Falloff, PixelSampling, ReferenceSsdo, TraceSettings};
use obscura_scene::{Camera, GBufferRenderer, Mesh};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// The environment's identity for the reference cache.
fn env_hash(env: &Environment, f: &mut Fnv) {
    match env {
        Environment::Constant(c) => f.bytes(b"c").f32s(c),
        Environment::Gradient { sky, ground } => f.bytes(b"g").f32s(sky).f32s(ground),
        Environment::Map(m) => {
            f.bytes(b"m").bytes(&m.width.to_le_bytes());
            for t in &m.texels {
                f.f32s(t);
            }
            f
        }
    };
}

/// The SSDO reference of one view, from the cache or traced (with progress).
#[allow(clippy::too_many_arguments)]
fn reference(
    a: &EvalArgs,
    env: &Environment,
    irradiance: &IrradianceSh,
    scene_bytes: &[u8],
    mesh: &Mesh,
    cam: &Camera,
    settings: &TraceSettings,
    name: &str,
) -> Result<ReferenceSsdo> {
    let (w, h) = (a.width, a.height);
    let mut f = Fnv::default();
    f.bytes(&cache::key(scene_bytes, cam, w, h, settings).to_le_bytes())
        .bytes(b"ssdo1");
    env_hash(env, &mut f);
    for c in mesh.triangle_colours() {
        f.f32s(&c);
    }
    let path = a.cache.join(format!("ssdo-{:016x}.bin", f.finish()));
    let n = (w * h) as usize;
    if let Some(v) = cache::load_floats(&path, w, h, 7 * n) {
        eprintln!("  reference: cached ({})", path.display());
        let rgb = |k: usize| -> Vec<[f32; 3]> {
            v[k..k + 3 * n]
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect()
        };
        return Ok(ReferenceSsdo {
            width: w,
            height: h,
            radiance: rgb(0),
            albedo: rgb(3 * n),
            depth: v[6 * n..].to_vec(),
        });
    }
    let t = Instant::now();
    let bvh = Bvh::new(obscura_eval::triangles(mesh));
    let colours = mesh.triangle_colours();
    let label = format!("{name} reference");
    let r = obscura_eval::trace_ssdo_view(
        &bvh,
        &colours,
        (env, irradiance),
        cam,
        (w, h),
        settings,
        &tenths(&label, t),
    );
    eprintln!(
        "  reference: {w}x{h} × {} rays in {:.1} s",
        settings.rays,
        t.elapsed().as_secs_f64()
    );
    let floats: Vec<f32> = r
        .radiance
        .iter()
        .flatten()
        .chain(r.albedo.iter().flatten())
        .chain(&r.depth)
        .copied()
        .collect();
    if let Err(e) = cache::store_floats(&path, w, h, &floats) {
        eprintln!("  warning: could not cache the reference: {e}");
    }
    Ok(r)
}

/// One variant of the lighting, as `eval --ssdo` compares them.
#[derive(Clone, Copy, Debug)]
enum Variant {
    /// Albedo × E(n): the environment with no occlusion.
    Open,
    /// Albedo × AO × E(n): AO multiplied onto the environment's light.
    AoTimesE,
    /// Albedo × AO × E(bent normal).
    Directional,
    /// Directional, plus the bounce of `directions` slices per pixel interleaved over
    /// `period`.
    Bounce { period: u32, directions: u32 },
}

impl Variant {
    fn label(self) -> String {
        match self {
            Variant::Open => "no occlusion: E(n)".into(),
            Variant::AoTimesE => "AO × E(n)".into(),
            Variant::Directional => "SSDO direct: AO × E(bent)".into(),
            Variant::Bounce {
                period: 1,
                directions: d,
            } => format!("SSDO + bounce, {d} slices, the same at every pixel"),
            Variant::Bounce {
                period: n,
                directions: d,
            } => format!("SSDO + bounce, {d} slices, {n}×{n} interleaved + merge"),
        }
    }

    fn options(self) -> SsdoOptions {
        let base = SsdoOptions::default();
        match self {
            Variant::Bounce { period, directions } => SsdoOptions {
                period,
                directions,
                ..base
            },
            _ => SsdoOptions {
                bounce: false,
                ..base
            },
        }
    }

    fn file(self) -> String {
        match self {
            Variant::Open => "open".into(),
            Variant::AoTimesE => "ao".into(),
            Variant::Directional => "direct".into(),
            Variant::Bounce {
                period: 2,
                directions: 2,
            } => "bounce".into(),
            Variant::Bounce { period, directions } => format!("bounce-p{period}-d{directions}"),
        }
    }
}

struct Row {
    view: String,
    mode: String,
    variant: String,
    rmse: f64,
    bias: f64,
    ms: f64,
}

/// Root-mean-square and mean difference over the channels of `mask`ed pixels.
fn errors(got: &[[f32; 3]], want: &[[f32; 3]], mask: &[bool]) -> (f64, f64) {
    let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for ((g, w), &m) in got.iter().zip(want).zip(mask) {
        if m {
            for k in 0..3 {
                let d = (g[k] - w[k]) as f64;
                se += d * d;
                sum += d;
                n += 1.0;
            }
        }
    }
    if n == 0.0 {
        return (0.0, 0.0);
    }
    ((se / n).sqrt(), sum / n)
}

/// `eval --ssdo`: every view, every `--modes` layout (GTAO with bent normals at the preset,
/// the library's default denoiser), the variants of [`Variant`] against the traced
/// reference.
pub(super) fn evaluate(a: &EvalArgs, jobs: &[Job]) -> Result<()> {
    let env = parse_env(&a.env)?;
    let irradiance = env.irradiance_sh();
    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let raster = GBufferRenderer::new(&ctx.device);
    let (w, h) = (a.width, a.height);
    let mut rows = Vec::new();
    let mut pictures = Vec::new();
    if let Some(dir) = &a.report {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
    }
    for job in jobs {
        let bytes = std::fs::read(&job.file)
            .with_context(|| format!("cannot read scene `{}`", job.file.display()))?;
        let mut mesh = Mesh::load(&job.file)
            .with_context(|| format!("cannot load scene `{}`", job.file.display()))?;
        mesh.colours = mesh
            .vertex_colours()
            .into_iter()
            .map(|c| c.map(|v| v * a.albedo_scale))
            .collect();
        let cam = camera_for(job, &mesh)?;
        let bounds = mesh.bounds().context("the scene has no triangles")?;
        let radius = super::view_radius(a, &bounds);
        let settings = TraceSettings {
            radius,
            rays: a.rays,
            falloff: Falloff::None,
            sampling: PixelSampling::Centre,
        };
        eprintln!(
            "{}: {} triangles, radius {radius:.3}",
            job.name,
            mesh.triangle_count()
        );
        let truth = reference(
            a,
            &env,
            &irradiance,
            &bytes,
            &mesh,
            &cam,
            &settings,
            &job.name,
        )?;
        let gpu_mesh = raster.upload(&ctx, &mesh)?;
        let g = raster.render(&ctx, &gpu_mesh, &cam, w, h)?;
        let input = g.ao_input(&cam, true);
        let params = AoParams {
            radius,
            ..Default::default()
        };
        let light = lighting(&irradiance, &cam);
        let ones = ctx.upload_r32("ones", &vec![1.0; (w * h) as usize], w, h);
        for (m, &mode) in a.modes.iter().enumerate() {
            let options = a.samples.apply(AoOptions {
                estimator: Estimator::Gtao,
                mode: mode.into(),
                bent_normals: true,
                ..AoOptions::default()
            });
            let mut ao = Ao::new(&ctx.device, options)?;
            let frame = ao.validate(&input, &params)?;
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
            let bounce = |period, directions| Variant::Bounce { period, directions };
            let mut variants = vec![
                Variant::AoTimesE,
                Variant::Directional,
                bounce(2, 2),
                bounce(2, 1),
                bounce(2, 4),
                bounce(4, 2),
                bounce(1, 2),
            ];
            if m == 0 {
                variants.insert(0, Variant::Open);
            }
            let mut passes = variants
                .iter()
                .map(|v| Ok(Ssdo::new(&ctx.device, v.options())?))
                .collect::<Result<Vec<_>>>()?;
            // The AO's own frame, timed with the variants, interleaved.
            let mut times = vec![Vec::new(); passes.len() + 1];
            for round in 0..=a.runs {
                let t = Instant::now();
                ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
                if round > 0 {
                    times[0].push(t.elapsed().as_secs_f64() * 1e3);
                }
                for (i, (s, v)) in passes.iter_mut().zip(&variants).enumerate() {
                    let mut inputs = inputs(&ao, &g)?;
                    // Open: AO 1 and the normal; AO × E(n): the plan's AO and the normal.
                    if matches!(v, Variant::Open) {
                        inputs.ao = &ones;
                    }
                    if matches!(v, Variant::Open | Variant::AoTimesE) {
                        inputs.bent = None;
                    }
                    let t = Instant::now();
                    ctx.run(|enc| s.record(&ctx.device, &ctx.queue, enc, inputs, &frame, &light))?;
                    if round > 0 {
                        times[i + 1].push(t.elapsed().as_secs_f64() * 1e3);
                    }
                }
            }
            let mode_name = obscura::AoMode::from(mode).name().to_string();
            let ao_ms = median(std::mem::take(&mut times[0]));
            rows.push(Row {
                view: job.name.clone(),
                mode: mode_name.clone(),
                variant: "GTAO + bent normals (the AO frame)".into(),
                rmse: f64::NAN,
                bias: f64::NAN,
                ms: ao_ms,
            });
            for (i, (s, v)) in passes.iter().zip(&variants).enumerate() {
                let (img, surface) = read_rgba(&ctx, s.output().context("no SSDO output")?)?;
                // Pixels both the rasterizer and the tracer see a surface at.
                let mask: Vec<bool> = surface
                    .iter()
                    .zip(&truth.depth)
                    .map(|(&a, &b)| a && b > 0.0)
                    .collect();
                let (rmse, bias) = errors(&img, &truth.radiance, &mask);
                rows.push(Row {
                    view: job.name.clone(),
                    mode: mode_name.clone(),
                    variant: v.label(),
                    rmse,
                    bias,
                    ms: median(std::mem::take(&mut times[i + 1])),
                });
                if let (Some(dir), 0) = (&a.report, m) {
                    let path = dir.join(format!("{}-{}.png", job.name, v.file()));
                    save_scaled(&path, &img, w, h, a.picture_scale)?;
                    pictures.push((format!("{}: {}", job.name, v.label()), path));
                }
            }
            eprintln!("  {mode_name}: done");
        }
        if let Some(dir) = &a.report {
            let path = dir.join(format!("{}-truth.png", job.name));
            save_scaled(&path, &truth.radiance, w, h, a.picture_scale)?;
            pictures.push((format!("{}: ray-traced truth", job.name), path));
        }
    }
    let table = table(&rows);
    print!("{table}");
    if let Some(dir) = &a.report {
        let md_path = a.markdown.clone().unwrap_or_else(|| dir.join("index.md"));
        let mut md = format!(
            "# Screen-space directional occlusion against the ray tracer\n\nCommand: `obscura {}`\n\nAdapter: {}\n\n{table}",
            std::env::args().skip(1).collect::<Vec<_>>().join(" "),
            ctx.describe()
        );
        for (title, file) in &pictures {
            let base = md_path.parent().unwrap_or(Path::new(""));
            let link = file
                .strip_prefix(base)
                .unwrap_or(file)
                .display()
                .to_string();
            let _ = write!(md, "\n![{title}]({link})\n");
        }
        write_text(&md_path, &md)?;
        eprintln!("wrote {}", md_path.display());
    }
    Ok(())
}

/// Writes `rgb` (w × h) as an sRGB PNG shrunk by `scale` (box filter).
fn save_scaled(path: &Path, rgb: &[[f32; 3]], w: u32, h: u32, scale: f32) -> Result<()> {
    let (small, sw, sh) = shrink(rgb, w, h, scale);
    save_radiance(path, &small, sw, sh)
}

/// The rows as a markdown table, then the mean over views per layout and variant.
fn table(rows: &[Row]) -> String {
    let mut s =
        String::from("| view | layout | variant | RMSE | bias | ms |\n|---|---|---|---|---|---|\n");
    let num = |v: f64| {
        if v.is_nan() {
            "–".to_string()
        } else {
            format!("{v:+.4}")
        }
    };
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.view,
            r.mode,
            r.variant,
            num(r.rmse).trim_start_matches('+'),
            num(r.bias),
            fmt_ms(r.ms)
        );
    }
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in rows {
        let k = (r.mode.clone(), r.variant.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    s.push_str(
        "\nMean over views:\n\n| layout | variant | RMSE | bias | ms |\n|---|---|---|---|---|\n",
    );
    for (mode, variant) in keys {
        let sel: Vec<&Row> = rows
            .iter()
            .filter(|r| r.mode == mode && r.variant == variant)
            .collect();
        let mean = |f: fn(&Row) -> f64| sel.iter().map(|r| f(r)).sum::<f64>() / sel.len() as f64;
        let _ = writeln!(
            s,
            "| {mode} | {variant} | {} | {} | {} |",
            num(mean(|r| r.rmse)).trim_start_matches('+'),
            num(mean(|r| r.bias)),
            fmt_ms(mean(|r| r.ms))
        );
    }
    s
}

//! `obscura lights`: interleaved many-light shading (obscura's `Lights`) against shading
//! every light at every pixel, on the built-in scene, a scene file or the shared views.
//! Virtual point lights are scattered over the scene's surfaces; each variant is timed
//! interleaved with the others (wall clock around submit + wait, after a warm-up, median)
//! and its error is stated against the all-lights image. Writes pictures and a markdown
//! table when asked.

use crate::output::{fmt_ms, save_png, write_text};
use crate::readback::read_rgb;
use crate::timing::median;
use crate::views::{camera_for, Job, ViewArgs};
use anyhow::{bail, Context, Result};
use clap::Args;
use glam::Vec3;
use obscura::lights::LIGHTS_MAX;
use obscura::{Ao, AoMode, AoOptions, AoParams, GpuContext, Lights, LightsOptions, PointLight};
use obscura_scene::{default_scene, GBufferRenderer, Mesh};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct LightsArgs {
    /// The views (default: the built-in scene).
    #[command(flatten)]
    pub views: ViewArgs,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: u32,
    /// Virtual point lights scattered over the scene's surfaces.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=obscura::lights::LIGHTS_MAX as i64))]
    pub count: u32,
    /// Read the lights from a JSON file instead of scattering them: an array (or
    /// `{"lights": [...]}`) of `{"position": [x, y, z], "colour": [r, g, b], "range": r}`
    /// in the scene's world space and units, colour the irradiance at unit distance.
    #[arg(long, value_name = "FILE", conflicts_with = "count")]
    pub lights_file: Option<PathBuf>,
    /// Interleaving periods N to compare with every light (comma-separated; each pixel of
    /// an N×N tile shades 1/N² of the lights): 2, 4 or 8.
    #[arg(long, value_delimiter = ',', default_value = "2,4", value_parser = clap::value_parser!(u32).range(2..=8))]
    pub periods: Vec<u32>,
    /// Timed runs per variant after a warm-up, interleaved across variants; the median is
    /// reported.
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Seed of the light placement.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Folder for pictures (VIEW-all.png, VIEW-NxN.png, VIEW-NxN-raw.png); created if
    /// missing.
    #[arg(long, value_name = "DIR")]
    pub out_dir: Option<PathBuf>,
    /// Write the table as markdown to FILE (pictures linked relative to it).
    #[arg(long, value_name = "FILE")]
    pub markdown: Option<PathBuf>,
}

/// One variant's measurements on one view.
struct Row {
    view: String,
    variant: Variant,
    ms: f64,
    /// RMS of the difference from the all-lights image over its mean (lit pixels).
    error: f64,
    /// RMS difference of the tone-mapped images in [0, 1] (what a viewer sees; HDR
    /// peaks near lights dominate `error`).
    display: f64,
}

/// How one image is shaded: every light (period 1), or interleaved over `period` × `period`
/// tiles, on the pixel grid or `layered` (one dispatch layer per class), merged or raw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Variant {
    period: u32,
    merge: bool,
    layered: bool,
}

impl Variant {
    fn label(self) -> String {
        let n = self.period;
        match (n, self.layered, self.merge) {
            (1, ..) => "every light".into(),
            (_, false, true) => format!("{n}×{n} interleaved + merge"),
            (_, true, true) => format!("{n}×{n} layered + merge"),
            (_, false, false) => format!("{n}×{n} interleaved, no merge"),
            (_, true, false) => format!("{n}×{n} layered, no merge"),
        }
    }

    fn file(self, view: &str) -> String {
        let n = self.period;
        match (n, self.layered, self.merge) {
            (1, ..) => format!("{view}-all.png"),
            (_, false, true) => format!("{view}-{n}x{n}.png"),
            (_, true, true) => format!("{view}-{n}x{n}-layered.png"),
            (_, false, false) => format!("{view}-{n}x{n}-raw.png"),
            (_, true, false) => format!("{view}-{n}x{n}-layered-raw.png"),
        }
    }
}

fn check(a: &LightsArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 8192 || a.height > 8192 {
        bail!(
            "--width and --height must be 1 to 8192, got {}x{}",
            a.width,
            a.height
        );
    }
    if a.count == 0 || a.count > LIGHTS_MAX {
        bail!("--count must be 1 to {LIGHTS_MAX}, got {}", a.count);
    }
    if let Some(p) = a.periods.iter().find(|p| ![2, 4, 8].contains(*p)) {
        bail!("--periods takes 2, 4 or 8 (1, every light, always runs), got {p}");
    }
    if a.runs == 0 || a.runs > 1000 {
        bail!("--runs must be 1 to 1000, got {}", a.runs);
    }
    Ok(())
}

pub fn run(a: &LightsArgs) -> Result<()> {
    check(a)?;
    let jobs = a.views.jobs()?;
    let file_lights = a.lights_file.as_deref().map(read_lights).transpose()?;
    if let Some(p) = &a.markdown {
        crate::output::check_folder(p)?;
    }
    // The pictures' folder once every input has been read.
    if let Some(dir) = &a.out_dir {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
    }
    let count = file_lights.as_ref().map_or(a.count as usize, Vec::len);
    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let raster = GBufferRenderer::new(&ctx.device);
    let mut rows = Vec::new();
    let mut pictures = Vec::new();
    match jobs {
        Some(jobs) => {
            for job in &jobs {
                let mesh = Mesh::load(&job.file)
                    .with_context(|| format!("cannot load scene `{}`", job.file.display()))?;
                view(
                    a,
                    &ctx,
                    &raster,
                    job,
                    &mesh,
                    file_lights.as_deref(),
                    &mut rows,
                    &mut pictures,
                )?;
            }
        }
        None => {
            let job = Job {
                name: "courtyard".into(),
                file: PathBuf::new(),
                camera: None,
            };
            view(
                a,
                &ctx,
                &raster,
                &job,
                &default_scene::mesh(),
                file_lights.as_deref(),
                &mut rows,
                &mut pictures,
            )?;
        }
    }
    let table = table(a, count, &rows);
    print!("{table}");
    if let Some(path) = &a.markdown {
        let mut md = format!(
            "# Interleaved many-light shading\n\nCommand: `obscura {}`\n\nAdapter: {}\n\n{table}",
            std::env::args().skip(1).collect::<Vec<_>>().join(" "),
            ctx.describe()
        );
        for (title, file) in &pictures {
            let link = relative(file, path);
            let _ = write!(md, "\n![{title}]({link})\n");
        }
        write_text(path, &md)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// `file` as a link from the markdown file `md` (its folder-relative path when below it).
fn relative(file: &Path, md: &Path) -> String {
    let base = md.parent().unwrap_or(Path::new(""));
    file.strip_prefix(base)
        .unwrap_or(file)
        .display()
        .to_string()
}

#[allow(
    clippy::too_many_arguments,
    reason = "one view's run, every input spelled out at its only call sites"
)]
fn view(
    a: &LightsArgs,
    ctx: &GpuContext,
    raster: &GBufferRenderer,
    job: &Job,
    mesh: &Mesh,
    file_lights: Option<&[PointLight]>,
    rows: &mut Vec<Row>,
    pictures: &mut Vec<(String, PathBuf)>,
) -> Result<()> {
    let cam = if job.file.as_os_str().is_empty() {
        default_scene::camera()
    } else {
        camera_for(job, mesh)?
    };
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let gpu_mesh = raster.upload(ctx, mesh)?;
    let gbuffer = raster.render(ctx, &gpu_mesh, &cam, a.width, a.height)?;
    let input = gbuffer.ao_input(&cam, true);
    // Only the AO's prepare matters here (linear depth and the rasterised normals at full
    // resolution); the randomized layout keeps that buffer.
    let options = AoOptions {
        mode: AoMode::Randomized,
        ..AoOptions::default()
    };
    let mut ao = Ao::new(&ctx.device, options)?;
    let params = AoParams {
        radius: 0.03 * bounds.diagonal(),
        ..AoParams::default()
    };
    let frame = ao.validate(&input, &params)?;
    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
    let prepared = ao
        .prepared()
        .context("the AO plan keeps no prepared buffer")?;

    let world = match file_lights {
        Some(l) => l.to_vec(),
        None => virtual_lights(mesh, a.count, a.seed, bounds.diagonal()),
    };
    let to_view = cam.view_matrix();
    let lights: Vec<PointLight> = world
        .iter()
        .map(|l| PointLight {
            position: to_view.transform_point3(Vec3::from(l.position)).to_array(),
            ..*l
        })
        .collect();

    // Every light (the reference), then each period on the pixel grid and layered, merged,
    // and on the grid without the merge (its cost and its error apart).
    let variant = |period, layered, merge| Variant {
        period,
        merge,
        layered,
    };
    let mut variants = vec![variant(1, false, false)];
    for &n in &a.periods {
        variants.extend([
            variant(n, false, true),
            variant(n, true, true),
            variant(n, false, false),
        ]);
    }
    let mut passes = variants
        .iter()
        .map(|v| {
            let options = LightsOptions {
                period: v.period,
                layered: v.layered,
                merge: v.merge,
            };
            Ok(Lights::new(&ctx.device, options)?)
        })
        .collect::<Result<Vec<_>>>()?;
    let mut times = vec![Vec::new(); passes.len()];
    for round in 0..=a.runs {
        for (l, t) in passes.iter_mut().zip(&mut times) {
            let start = Instant::now();
            ctx.run(|enc| l.record(&ctx.device, &ctx.queue, enc, prepared, &frame, &lights))?;
            if round > 0 {
                t.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        eprint!("\r{}: round {round}/{}", job.name, a.runs);
    }
    eprintln!();
    let images = passes
        .iter()
        .map(|l| read_rgb(ctx, l.output().context("no output")?))
        .collect::<Result<Vec<_>>>()?;
    let lit: Vec<bool> = read_rgb(ctx, prepared)?
        .iter()
        .map(|p| p[0] > 0.0)
        .collect();
    let exposure = exposure(&images[0], &lit);
    for (i, &v) in variants.iter().enumerate() {
        let ms = median(std::mem::take(&mut times[i]));
        let error = relative_rms(&images[i], &images[0], &lit);
        let display = display_rms(&images[i], &images[0], exposure, &lit);
        rows.push(Row {
            view: job.name.clone(),
            variant: v,
            ms,
            error,
            display,
        });
        // Layered shading gives the grid's image: one picture each.
        if let (Some(dir), false) = (&a.out_dir, v.layered) {
            let path = dir.join(v.file(&job.name));
            let rgb = tonemap(&images[i], exposure);
            save_png(
                &path,
                &rgb,
                a.width,
                a.height,
                image::ExtendedColorType::Rgb8,
            )?;
            pictures.push((format!("{} {}", job.name, v.label()), path));
        }
    }
    Ok(())
}

/// Lights from a JSON file (see [`LightsArgs::lights_file`]), checked entry by entry.
pub(crate) fn read_lights(path: &Path) -> Result<Vec<PointLight>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read lights file `{}`", path.display()))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("lights file `{}` is not JSON", path.display()))?;
    let list = match value.get("lights").unwrap_or(&value) {
        serde_json::Value::Array(list) => list,
        _ => bail!(
            "lights file `{}`: expected an array of lights or {{\"lights\": [...]}}",
            path.display()
        ),
    };
    if list.is_empty() || list.len() > LIGHTS_MAX as usize {
        bail!(
            "lights file `{}`: {} lights; expected 1 to {LIGHTS_MAX}",
            path.display(),
            list.len()
        );
    }
    let vector = |light: &serde_json::Value, i: usize, key: &str| -> Result<[f32; 3]> {
        let v: Option<Vec<f32>> = light.get(key).and_then(|v| v.as_array()).and_then(|a| {
            a.iter()
                .map(|x| x.as_f64().map(|x| x as f32).filter(|x| x.is_finite()))
                .collect()
        });
        match v.as_deref() {
            Some(&[x, y, z]) => Ok([x, y, z]),
            _ => bail!(
                "lights file `{}`, light {i}: `{key}` must be three finite numbers",
                path.display()
            ),
        }
    };
    list.iter()
        .enumerate()
        .map(|(i, light)| {
            let position = vector(light, i, "position")?;
            let colour = vector(light, i, "colour")?;
            let Some(range) = light.get("range").and_then(|r| r.as_f64()) else {
                bail!(
                    "lights file `{}`, light {i}: `range` must be a number",
                    path.display()
                );
            };
            let light = PointLight {
                position,
                colour,
                range: range as f32,
            };
            light
                .validate(i)
                .with_context(|| format!("lights file `{}`", path.display()))?;
            Ok(light)
        })
        .collect()
}

/// `count` virtual point lights on the mesh's surfaces: triangles chosen by area (a
/// fixed-seed generator), a uniform point on each, raised 1% of the scene diagonal along
/// the face normal; range 20% of the diagonal, colours of random hue whose total power
/// does not depend on the count. In world space.
fn virtual_lights(mesh: &Mesh, count: u32, seed: u32, diagonal: f32) -> Vec<PointLight> {
    let tri = |t: usize| {
        let i = &mesh.indices[3 * t..3 * t + 3];
        [0, 1, 2].map(|k| Vec3::from(mesh.positions[i[k] as usize]))
    };
    let mut cumulative = Vec::with_capacity(mesh.triangle_count());
    let mut total = 0.0f64;
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = tri(t);
        total += 0.5 * (b - a).cross(c - a).length() as f64;
        cumulative.push(total);
    }
    let mut state = seed as u64 ^ 0x9e37_79b9_7f4a_7c15;
    let mut next = move || {
        // SplitMix64 (Steele, Lea & Flood 2014): a uniform float in [0, 1).
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    };
    let range = 0.2 * diagonal;
    let power = range * range * 16.0 / count as f32;
    (0..count)
        .map(|_| {
            let pick = next() as f64 * total;
            let t = cumulative
                .partition_point(|&c| c <= pick)
                .min(cumulative.len() - 1);
            let [a, b, c] = tri(t);
            let (mut u, mut v) = (next(), next());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let n = (b - a).cross(c - a).normalize_or_zero();
            let position = a + (b - a) * u + (c - a) * v + n * (0.01 * diagonal);
            // A random hue: each channel a raised cosine of the hue angle, a third apart.
            let hue = next() * std::f32::consts::TAU;
            let colour = [0.0f32, 1.0, 2.0]
                .map(|k| 0.3 + 0.35 * (1.0 + (hue - k * std::f32::consts::TAU / 3.0).cos()));
            PointLight {
                position: position.to_array(),
                colour: colour.map(|c| c * power),
                range,
            }
        })
        .collect()
}

/// RMS of the rgb difference over the mean rgb magnitude of `want`, over `mask`.
fn relative_rms(got: &[[f32; 4]], want: &[[f32; 4]], mask: &[bool]) -> f64 {
    let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for ((g, w), &m) in got.iter().zip(want).zip(mask) {
        if m {
            let (g, w) = (Vec3::new(g[0], g[1], g[2]), Vec3::new(w[0], w[1], w[2]));
            se += (g - w).length_squared() as f64;
            sum += w.length() as f64;
            n += 1.0;
        }
    }
    if n == 0.0 || sum == 0.0 {
        return 0.0;
    }
    (se / n).sqrt() / (sum / n)
}

/// RMS difference of `got` and `want` after the tone curve of [`tonemap`] (before the
/// sRGB curve), over `mask`.
fn display_rms(got: &[[f32; 4]], want: &[[f32; 4]], k: f32, mask: &[bool]) -> f64 {
    let tone = |c: f32| 1.0 - (-k * c.max(0.0)).exp();
    let (mut se, mut n) = (0.0f64, 0.0f64);
    for ((g, w), &m) in got.iter().zip(want).zip(mask) {
        if m {
            se += (0..3)
                .map(|c| ((tone(g[c]) - tone(w[c])) as f64).powi(2))
                .sum::<f64>()
                / 3.0;
            n += 1.0;
        }
    }
    if n == 0.0 {
        0.0
    } else {
        (se / n).sqrt()
    }
}

/// Exposure putting the mean lit luminance of `image` at 0.5 before the tone curve.
fn exposure(image: &[[f32; 4]], mask: &[bool]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0.0f64);
    for (p, &m) in image.iter().zip(mask) {
        if m {
            sum += (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64;
            n += 1.0;
        }
    }
    if sum > 0.0 {
        (0.5 * n / sum) as f32
    } else {
        1.0
    }
}

/// `1 − exp(−k·E)` per channel, then the sRGB curve, 8 bits.
fn tonemap(image: &[[f32; 4]], k: f32) -> Vec<u8> {
    image
        .iter()
        .flat_map(|p| {
            [p[0], p[1], p[2]].map(|c| {
                let x = 1.0 - (-k * c.max(0.0)).exp();
                let s = if x <= 0.003_130_8 {
                    12.92 * x
                } else {
                    1.055 * x.powf(1.0 / 2.4) - 0.055
                };
                (s.clamp(0.0, 1.0) * 255.0).round() as u8
            })
        })
        .collect()
}

fn table(a: &LightsArgs, count: usize, rows: &[Row]) -> String {
    let mut s = format!(
        "{} lights, {}x{}; error: RMS difference from every light's image over its mean, \
         display: RMS difference of the tone-mapped images (0 to 1), both over lit pixels\n\n\
         | view | variant | ms | speed-up | error | display |\n|---|---|---|---|---|---|\n",
        count, a.width, a.height
    );
    let mut all_ms = 0.0;
    for r in rows {
        if r.variant.period == 1 {
            all_ms = r.ms;
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2}× | {} | {} |",
            r.view,
            r.variant.label(),
            fmt_ms(r.ms),
            all_ms / r.ms,
            error_cell(r.variant, r.error),
            error_cell(r.variant, r.display)
        );
    }
    let views = rows.iter().filter(|r| r.variant.period == 1).count();
    if views > 1 {
        s.push_str(
            "\nMeans over the views (speed-up: every light's mean ms over the variant's):\n\n\
             | variant | ms | speed-up | error | display |\n|---|---|---|---|---|\n",
        );
        let mut variants: Vec<Variant> = rows.iter().map(|r| r.variant).collect();
        variants.sort_unstable();
        variants.dedup();
        let all_mean = mean(rows.iter().filter(|r| r.variant.period == 1).map(|r| r.ms));
        for v in variants {
            let sel = || rows.iter().filter(move |r| r.variant == v);
            let t = mean(sel().map(|r| r.ms));
            let _ = writeln!(
                s,
                "| {} | {} | {:.2}× | {} | {} |",
                v.label(),
                fmt_ms(t),
                all_mean / t,
                error_cell(v, mean(sel().map(|r| r.error))),
                error_cell(v, mean(sel().map(|r| r.display)))
            );
        }
    }
    s
}

fn error_cell(v: Variant, error: f64) -> String {
    if v.period == 1 {
        "(reference)".to_string()
    } else {
        format!("{error:.4}")
    }
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n): (f64, f64) = v.fold((0.0, 0.0), |(s, n), x| (s + x, n + 1.0));
    s / n.max(1.0)
}

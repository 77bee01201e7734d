//! `obscura eval`: AO from each pass layout against ray-traced ground truth, on a scene
//! file or the standard views of the shared scenes. Writes a markdown report with
//! pictures (AO, reference, signed error) and a quality-versus-time plot, and JSON.

use crate::bench::frame_ms;
use crate::output::{check_png_path, fmt_ms, save_png, write_text};
use crate::render::{
    parse_denoise, parse_downsample, parse_floats, parse_resolution, parse_upsampler, EstimatorArg,
    ModeArg, NormalSource, PresetArg, SampleArgs,
};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use glam::Vec3;
use obscura::{
    Ao, AoMode, AoOptions, AoParams, Denoise, DepthDownsample, Estimator, GpuContext, Resolution,
    Timing, Upsampler,
};
use obscura_eval::{cache, metrics, sensor, views, Bvh, Falloff, PixelSampling, TraceSettings};
use obscura_scene::{Camera, CameraProjection, GBufferRenderer, Mesh};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FalloffArg {
    /// Any hit within the radius occludes (the usual definition of AO).
    None,
    /// A hit at distance t occludes by 1 − t²/R² (HBAO's weight).
    Quadratic,
}

/// Which views to work on: a scene file, standard views by name, or all of them.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Scene file (with --camera, or framed from its bounds).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["view", "all"])]
    pub scene: Option<PathBuf>,
    /// Camera as EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z[,FOV_Y_DEG] (with --scene).
    #[arg(long, allow_hyphen_values = true, requires = "scene")]
    pub camera: Option<String>,
    /// A standard view by name (repeatable): sponza, cornell, house5, house6, etoile,
    /// munich, bunny, teapot, dragon.
    #[arg(long)]
    pub view: Vec<String>,
    /// Every standard view.
    #[arg(long)]
    pub all: bool,
    /// The shared scenes folder holding the standard views' files.
    #[arg(long, default_value = "../shared/scenes")]
    pub scenes_dir: PathBuf,
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    #[command(flatten)]
    pub views: ViewArgs,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 400)]
    pub height: u32,
    /// AO radius in scene units. Default: 3% of the scene's bounding-box diagonal.
    #[arg(long)]
    pub radius: Option<f32>,
    /// Rays per pixel of the ray-traced reference.
    #[arg(long, default_value_t = 256)]
    pub rays: u32,
    /// How the reference weighs a hit within the radius.
    #[arg(long, value_enum, default_value_t = FalloffArg::None)]
    pub falloff: FalloffArg,
    /// Estimators to evaluate (comma-separated).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "gtao,hbao,vo,vao,sao,vo-area"
    )]
    pub estimators: Vec<EstimatorArg>,
    #[command(flatten)]
    pub samples: SampleArgs,
    /// Sample splits to compare in one run, timed interleaved (comma-separated
    /// DIRECTIONSxSTEPS, e.g. 4x4,4x8,2x8); each runs with every estimator, mode, resolution
    /// and denoiser. Overrides --preset, --directions and --steps.
    #[arg(long, value_parser = parse_split, value_delimiter = ',')]
    pub splits: Vec<(u32, u32)>,
    /// Quality presets to compare in one run (comma-separated, e.g. low,medium,high,ultra);
    /// each runs with every estimator, mode, resolution and denoiser, and the report's
    /// frontier shows which choices give the least error for their time. Overrides
    /// --preset, --directions and --steps.
    #[arg(long, value_enum, value_delimiter = ',', conflicts_with = "splits")]
    pub presets: Vec<PresetArg>,
    /// Pass layouts to evaluate (comma-separated); every estimator runs in every mode.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "randomized,deinterleaved2,deinterleaved4"
    )]
    pub modes: Vec<ModeArg>,
    /// AO resolutions (comma-separated); below full, every downsample rule × upsampler ×
    /// denoise choice listed runs.
    #[arg(long, value_parser = parse_resolution, value_delimiter = ',', default_value = "full")]
    pub resolutions: Vec<Resolution>,
    /// Working scales of the continuous resolution (`Resolution::Scaled`, comma-separated,
    /// each in [0.25, 1]): each runs as a variant "… scaled S" with the bilateral upsampler
    /// and the --denoise choices it takes (none, spatial); estimators with depth mips (SAO,
    /// VO's area integral) are left out.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub scales: Vec<f32>,
    /// Depth downsampling rules for the low resolutions (comma-separated).
    #[arg(long, value_parser = parse_downsample, value_delimiter = ',', default_value = "checkerboard")]
    pub downsamples: Vec<DepthDownsample>,
    /// Upsamplers for the low resolutions (comma-separated).
    #[arg(long, value_parser = parse_upsampler, value_delimiter = ',', default_value = "bilateral")]
    pub upsamplers: Vec<Upsampler>,
    /// Denoise choices (comma-separated; at full resolution too).
    #[arg(long, value_parser = parse_denoise, value_delimiter = ',', default_value = "none")]
    pub denoise: Vec<Denoise>,
    /// Leave the per-view picture sections out of the report (tables and plot only).
    #[arg(long)]
    pub no_pictures: bool,
    /// Where the estimator's normals come from. Default: the G-buffer's, or reconstructed
    /// from the depth with --sensor (a depth camera gives none). `--sensor S --normals
    /// gbuffer` gives the sensor-like depth the G-buffer's exact normals: what the noise
    /// costs when the normals come from elsewhere (a dataset's, or `render --normals-file`).
    #[arg(long, value_enum)]
    pub normals: Option<NormalSource>,
    /// Timed runs per mode after a warm-up (interleaved across modes); the median is reported.
    #[arg(long, default_value_t = 5)]
    pub runs: u32,
    /// Folder for the report's pictures; created if missing.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// The report's markdown file (default: DIR/index.md). Pictures are linked relative to it.
    #[arg(long, value_name = "FILE", requires = "report")]
    pub markdown: Option<PathBuf>,
    /// Pictures are written at this fraction of the evaluated size (box filter).
    #[arg(long, default_value_t = 0.5)]
    pub picture_scale: f32,
    /// Machine-readable results: one record per view and mode.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Skip the screen-space references (each estimator's integral brute-forced with 64 × 64
    /// samples and no jitter; slow on a CPU adapter).
    #[arg(long)]
    pub no_screen_reference: bool,
    /// Cache folder for ray-traced references.
    #[arg(long, default_value = ".obscura-cache")]
    pub cache: PathBuf,
    /// Also score the bent normals of GTAO and HBAO (their single-frame variants, run once more with bent
    /// normals on, untimed; not after box/tent below full resolution) against the ray tracer's: the mean angle to the
    /// traced bent normal, over all pixels and over occluded ones (traced AO < 0.9), beside
    /// the surface normal's angle to it (what a renderer without bent normals uses).
    #[arg(long)]
    pub bent_normals: bool,
    /// Temporal accumulation (comma-separated counts, timed interleaved: `1,8` puts single
    /// frames and 8 accumulated frames in one frontier): each count N runs every variant; for
    /// N > 1 with a history (--history), scored after N frames of a still camera;
    /// also reported: the mean absolute frame-to-frame change after them, and an orbit of N
    /// frames (--orbit-step degrees apart) ending at the view, scored by how long each
    /// pixel has been visible. The frontier ranks an accumulated variant by the worse of its
    /// still and orbit RMSE.
    #[arg(long, value_delimiter = ',', default_value = "1")]
    pub frames: Vec<u32>,
    /// Most frames the temporal history averages (with --frames > 1), 2..=256.
    #[arg(long, default_value_t = 16)]
    pub history: u32,
    /// Evaluate on sensor-like depth made from each view's clean depth (the view scaled so
    /// its farthest surface is 5 m; see obscura_eval::sensor), with normals reconstructed
    /// from it unless --normals says otherwise; the truth is the clean scene's.
    #[arg(long, value_enum, default_value_t = SensorArg::None)]
    pub sensor: SensorArg,
    /// Scales the --sensor's random noise (0: its quantisation alone), not the model that
    /// `--depth-noise known` gives: with 0 and `known`, what the noise treatment costs on
    /// depth without noise.
    #[arg(long, default_value_t = 1.0)]
    pub sensor_noise: f32,
    /// The depth noise model obscura is given: `auto` estimates it from --sensor depth (as
    /// `render --depth` does by default) and gives none for rendered depth (as a renderer
    /// passing its own depth buffer does); `estimate` estimates it from either.
    #[arg(long, value_enum, default_value_t = NoiseArg::Auto)]
    pub depth_noise: NoiseArg,
    /// Degrees the orbit turns per frame (with --frames > 1).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub orbit_step: f32,
    /// Give obscura the view's depth rasterized with 4× MSAA (resolved by obscura; normals
    /// reconstructed from it) instead of single-sampled depth. Single frames only.
    #[arg(long, conflicts_with = "sensor")]
    pub msaa: bool,
    /// Where the reference's primary rays go: `centre` (the pixel centre, where single-
    /// sampled depth is taken) or `msaa4` (the four 4× MSAA sample positions, a quarter of
    /// the rays each, averaged: the AO a 4× MSAA image resolves to; judges --msaa and
    /// single-sampled depth against the same truth).
    #[arg(long, value_enum, default_value_t = TruthArg::Centre)]
    pub truth: TruthArg,
    /// Evaluate screen-space directional occlusion instead of AO: GTAO with bent normals
    /// in each --modes layout (the library's default denoiser), then the environment
    /// through the bent cone with and without the one-bounce pass, beside AO × E(n) and no
    /// occlusion, against the ray tracer extended to --env and one diffuse bounce (albedo
    /// from the scene's materials). RMSE of linear radiance; each variant timed. Runs GTAO
    /// at --preset (or --directions/--steps) with the library's default denoiser at full
    /// resolution: --estimators, --resolutions and --denoise do not apply.
    #[arg(long, conflicts_with_all = ["sensor", "msaa", "bent_normals"])]
    pub ssdo: bool,
    /// The environment of --ssdo: sky (a daylight gradient), white, constant:R,G,B,
    /// gradient:R,G,B:R,G,B (zenith, nadir), or an equirectangular .hdr or .exr file (row 0
    /// the zenith, +y; the left edge facing +x, columns turning toward +z).
    #[arg(long, default_value = "sky", requires = "ssdo")]
    pub env: String,
    /// --ssdo: multiply every surface's albedo by this (0..=1). The shared scenes name no
    /// materials, so their surfaces are white (glTF's default); 0.5 is closer to real ones.
    #[arg(long, default_value_t = 1.0, requires = "ssdo")]
    pub albedo_scale: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TruthArg {
    /// Primary rays through pixel centres.
    Centre,
    /// Primary rays through the 4× MSAA sample positions, averaged.
    Msaa4,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SensorArg {
    /// The clean rendered depth.
    None,
    /// Axial noise σ = 1.5 mm · z², millimetre steps.
    Kinect,
    /// Stereo disparity noise and quantisation.
    Stereo,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NoiseArg {
    /// Estimated from --sensor depth; none for rendered depth.
    Auto,
    /// Estimated from the depth (obscura::DepthNoise::estimate).
    Estimate,
    /// None: obscura treats the depth as clean.
    None,
    /// The simulated sensor's own σ(z) (with --sensor).
    Known,
}

/// One evaluated view: what to load and how to look at it.
pub(crate) struct Job {
    pub(crate) name: String,
    pub(crate) file: PathBuf,
    pub(crate) camera: Option<([f32; 3], [f32; 3], f32)>,
}

struct Row {
    view: String,
    variant: String,
    /// Estimator name ("none" for the white baseline) and mode ("" for the baseline,
    /// "screen-reference" for the screen-space reference).
    estimator: String,
    mode: String,
    rmse: f32,
    bias: f32,
    ssim: f32,
    band_rmse: f32,
    /// RMSE against the estimator's own screen-space reference: its sampling error.
    screen_rmse: Option<f32>,
    /// Mean difference from the estimator's own screen-space reference: the sampling's
    /// bias (a maximum over a few steps reads horizons low, so GTAO's is positive).
    screen_bias: Option<f32>,
    /// Below full resolution (or with denoising): RMSE over the image and over the band
    /// against the same estimator and mode at full resolution.
    full_rmse: Option<(f32, f32)>,
    ms: Option<f64>,
    /// With --frames: the temporal figures.
    temporal: Option<TemporalFigures>,
    /// With --bent-normals: the bent normals' angles to the traced ones.
    bent: Option<BentError>,
}

/// Mean angles (degrees) to the ray-traced bent normal, over the compared pixels and over
/// the occluded ones (traced AO < [`OCCLUDED`]): of the estimate's bent normal, and of the
/// surface normal the estimate used.
#[derive(Clone, Copy, Debug)]
struct BentError {
    bent: f32,
    bent_occluded: f32,
    normal: f32,
    normal_occluded: f32,
}

/// Traced AO below which a pixel counts as occluded for [`BentError`].
const OCCLUDED: f32 = 0.9;

/// [`BentError`] of `bent` (rgba per pixel) and the prepared normals (`vec4(d, n)` per
/// pixel) against `truth`'s bent normals, where `mask` holds and both are defined.
fn bent_error(
    bent: &[f32],
    prepared: &[f32],
    truth: &obscura_eval::ReferenceAo,
    mask: &[bool],
) -> BentError {
    use glam::Vec3;
    let angle = |a: Vec3, b: Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees() as f64;
    // Sums of (bent angle, normal angle, count), all pixels and occluded ones.
    let (mut all, mut occ) = ([0.0f64; 3], [0.0f64; 3]);
    for (i, m) in mask.iter().enumerate() {
        let t = Vec3::from(truth.bent[i]);
        let g = Vec3::from_slice(&bent[4 * i..4 * i + 3]);
        let n = Vec3::from_slice(&prepared[4 * i + 1..4 * i + 4]);
        if !m || t.length_squared() < 0.25 || g.length_squared() < 0.25 {
            continue;
        }
        let (b, nn) = (angle(g, t), angle(n.normalize_or_zero(), t));
        for (acc, on) in [(&mut all, true), (&mut occ, truth.ao[i] < OCCLUDED)] {
            if on {
                acc[0] += b;
                acc[1] += nn;
                acc[2] += 1.0;
            }
        }
    }
    let mean = |acc: [f64; 3], k: usize| (acc[k] / acc[2].max(1.0)) as f32;
    BentError {
        bent: mean(all, 0),
        bent_occluded: mean(occ, 0),
        normal: mean(all, 1),
        normal_occluded: mean(occ, 1),
    }
}

/// How temporal accumulation behaves on one view (`eval --frames N`).
#[derive(Clone, Copy, Debug)]
struct TemporalFigures {
    /// N: frames of the still camera and of the orbit.
    frames: u32,
    /// Mean |AO(frame N+1) − AO(frame N)| of a still camera.
    flicker: f32,
    /// RMSE of the last frame of the orbit.
    orbit_rmse: f32,
    /// Pixels of the orbit's last frame that became visible 4 frames before it (history of
    /// 5 frames): their RMSE after the orbit, their RMSE in the still camera's converged
    /// image, and how many there are.
    disoccluded: Option<(f32, f32, usize)>,
}

/// How one group of variants chooses its sample counts.
#[derive(Clone, Copy)]
enum SampleChoice {
    Given,
    Split((u32, u32)),
    Preset(PresetArg),
}

/// A G-buffer's depth as linear view depth (0 for the sky).
fn linear_depth(
    ctx: &GpuContext,
    g: &obscura_scene::GBuffer,
    input: &obscura::AoInput<'_>,
) -> Result<Vec<f32>> {
    let lin = input.projection.linearize(input.convention)?;
    Ok(ctx
        .read_f32(&g.depth)?
        .into_iter()
        .map(|z| lin.apply(z).unwrap_or(0.0))
        .collect())
}

/// Sensor-like linear depth made from a G-buffer's depth ([`sensor_depth`]).
struct SensorDepth {
    depth: Vec<f32>,
    /// Keeps `view`'s texture alive.
    _texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// The sensor's σ(z) in view units.
    known: obscura::DepthNoise,
    /// The step of its integer encoding in view units, if it has one.
    quantum: Option<f32>,
}

/// Sensor-like linear depth from a G-buffer's depth (obscura_eval::sensor).
fn sensor_depth(
    ctx: &GpuContext,
    g: &obscura_scene::GBuffer,
    input: &obscura::AoInput<'_>,
    s: sensor::Sensor,
    noise_scale: f32,
) -> Result<SensorDepth> {
    let clean = linear_depth(ctx, g, input)?;
    let focal_px = match input.projection {
        obscura::Projection::Perspective { fov_y, .. } => {
            0.5 * g.height as f32 / (0.5 * fov_y).tan()
        }
        _ => bail!("--sensor needs a perspective view"),
    };
    let (noisy, map) = sensor::simulate(&clean, focal_px, s, noise_scale, 0x5eed);
    eprintln!(
        "  {} depth: the view's depth range mapped onto {}..{} m",
        s.name(),
        sensor::NEAR_M,
        sensor::FAR_M
    );
    let texture = ctx.upload_r32("sensor depth", &noisy, g.width, g.height);
    let view = texture.create_view(&Default::default());
    let (constant, linear, quadratic) = map.sigma_in_depth(s.sigma_m(focal_px));
    let noise = obscura::DepthNoise {
        constant,
        linear,
        quadratic,
        // The sensor's noise dithers its millimetre terraces away beyond 0.58 m (σ of
        // half a step): no terraces to model.
        ..obscura::DepthNoise::NONE
    };
    // Kinect-like depth is stored as integer millimetres: its unit in view units.
    let quantum = match s {
        sensor::Sensor::Kinect => Some(0.001 / map.scale),
        sensor::Sensor::Stereo => None,
    };
    Ok(SensorDepth {
        depth: noisy,
        _texture: texture,
        view,
        known: noise,
        quantum,
    })
}

/// Parses a sample split `DIRECTIONSxSTEPS` (`4x8`); the ranges are checked by `Ao::new`.
fn parse_split(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected DIRECTIONSxSTEPS such as 4x8, got `{s}`");
    let (d, st) = s.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    Ok((
        d.trim().parse().map_err(|_| bad())?,
        st.trim().parse().map_err(|_| bad())?,
    ))
}

fn jobs(a: &EvalArgs) -> Result<Vec<Job>> {
    a.views
        .jobs()?
        .context("choose what to evaluate: --scene FILE, --view NAME or --all")
}

impl ViewArgs {
    /// The views named (`None` if none is given).
    pub(crate) fn jobs(&self) -> Result<Option<Vec<Job>>> {
        jobs_for(
            self.scene.as_deref(),
            self.camera.as_deref(),
            self.all,
            &self.view,
            &self.scenes_dir,
        )
    }
}

fn jobs_for(
    scene: Option<&Path>,
    camera: Option<&str>,
    all: bool,
    view: &[String],
    scenes_dir: &Path,
) -> Result<Option<Vec<Job>>> {
    if let Some(f) = scene {
        let camera = match camera {
            Some(c) => {
                let v = parse_floats(c, "--camera")?;
                if !(v.len() == 6 || v.len() == 7) {
                    bail!("--camera needs 6 or 7 numbers (eye, target, optional fov)");
                }
                Some((
                    [v[0], v[1], v[2]],
                    [v[3], v[4], v[5]],
                    v.get(6).copied().unwrap_or(60.0),
                ))
            }
            None => None,
        };
        let name = f
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene")
            .to_string();
        return Ok(Some(vec![Job {
            name,
            file: f.to_path_buf(),
            camera,
        }]));
    }
    let chosen: Vec<&views::StandardView> = if all {
        views::STANDARD_VIEWS.iter().collect()
    } else if view.is_empty() {
        return Ok(None);
    } else {
        view.iter()
            .map(|n| {
                views::find(n).with_context(|| {
                    let names: Vec<&str> = views::STANDARD_VIEWS.iter().map(|v| v.name).collect();
                    format!(
                        "unknown view `{n}`; the standard views are {}",
                        names.join(", ")
                    )
                })
            })
            .collect::<Result<_>>()?
    };
    Ok(Some(
        chosen
            .into_iter()
            .map(|v| Job {
                name: v.name.to_string(),
                file: scenes_dir.join(v.file),
                camera: v.camera,
            })
            .collect(),
    ))
}

pub(crate) fn camera_for(job: &Job, mesh: &Mesh) -> Result<Camera> {
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let mut cam = match job.camera {
        Some((eye, target, fov)) => Camera {
            eye: Vec3::from(eye),
            target: Vec3::from(target),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: fov },
            near: 0.0,
            far: 0.0,
        },
        None => Camera::framing(&bounds, CameraProjection::Perspective { fov_y_deg: 50.0 }),
    };
    cam.fit_clip_planes(&bounds);
    cam.validate()?;
    Ok(cam)
}

pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

impl EvalArgs {
    /// `--normals`, or its default: the G-buffer's, reconstructed with `--sensor`.
    fn normal_source(&self) -> NormalSource {
        self.normals.unwrap_or(match self.sensor {
            SensorArg::None => NormalSource::Gbuffer,
            _ => NormalSource::Reconstruct,
        })
    }
}

pub fn run(a: &EvalArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 8192 || a.height > 8192 {
        bail!(
            "--width and --height must be in 1..=8192 (got {}x{})",
            a.width,
            a.height
        );
    }
    if a.rays == 0 || a.rays > 65536 {
        bail!("--rays must be in 1..=65536 (got {})", a.rays);
    }
    if a.truth == TruthArg::Msaa4 && !a.rays.is_multiple_of(4) {
        bail!(
            "--truth msaa4 traces a quarter of the rays through each of 4 sample positions: \
             --rays must be a multiple of 4 (got {})",
            a.rays
        );
    }
    if a.runs == 0 || a.runs > 1000 {
        bail!("--runs must be in 1..=1000");
    }
    if !(a.picture_scale > 0.0 && a.picture_scale <= 1.0) {
        bail!("--picture-scale must be in (0, 1]");
    }
    if let Some(r) = a.radius {
        if !(r.is_finite() && r > 0.0) {
            bail!("--radius must be a finite number > 0 (got {r})");
        }
    }
    if !(0.0..=10.0).contains(&a.sensor_noise) {
        bail!("--sensor-noise must be in 0..=10 (got {})", a.sensor_noise);
    }
    if a.sensor_noise != 1.0 && a.sensor == SensorArg::None {
        bail!("--sensor-noise needs --sensor");
    }
    if let Some(f) = a.frames.iter().find(|f| !(1..=1000).contains(*f)) {
        bail!("--frames must each be in 1..=1000 (got {f})");
    }
    if a.frames.is_empty() {
        bail!("--frames needs at least one count");
    }
    let temporal_run = a.frames.iter().any(|&f| f > 1);
    if temporal_run && !(2..=256).contains(&a.history) {
        bail!("--history must be in 2..=256 (got {})", a.history);
    }
    if a.sensor != SensorArg::None && temporal_run {
        bail!(
            "--sensor evaluates single frames (its noise is drawn once, and the orbit \
             rasterizes clean depth)"
        );
    }
    if a.msaa && temporal_run {
        bail!("--msaa evaluates single frames (the orbit rasterizes single-sampled depth)");
    }
    if !a.orbit_step.is_finite() || a.orbit_step.abs() > 90.0 {
        bail!(
            "--orbit-step must be degrees within ±90 (got {})",
            a.orbit_step
        );
    }
    if a.modes.is_empty() || a.estimators.is_empty() {
        bail!("--modes and --estimators need at least one value each");
    }
    if let Some(s) = a
        .scales
        .iter()
        .find(|s| !(obscura::MIN_SCALE..=1.0).contains(*s))
    {
        bail!("--scales must each be in [0.25, 1] (got {s})");
    }
    let jobs = jobs(a)?;
    if a.ssdo {
        if temporal_run || a.falloff != FalloffArg::None || a.truth != TruthArg::Centre {
            bail!("--ssdo evaluates single frames against centre-sampled truth without falloff");
        }
        if !(0.0..=1.0).contains(&a.albedo_scale) {
            bail!("--albedo-scale must be in 0..=1 (got {})", a.albedo_scale);
        }
        return crate::ssdo::evaluate(a, &jobs);
    }
    if let Some(dir) = &a.report {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
    }
    let md_path = a
        .report
        .as_ref()
        .map(|d| a.markdown.clone().unwrap_or_else(|| d.join("index.md")));
    if let Some(p) = &md_path {
        check_png_path(&p.with_extension("png"))?;
    }

    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let raster = GBufferRenderer::new(&ctx.device);
    let mut variants: Vec<(String, AoOptions)> = Vec::new();
    // Each variant's `AoParams::scale` (1 but for the scaled ones).
    let mut scales: Vec<f32> = Vec::new();
    // The sample choices crossed with everything else: explicit splits, presets, or the
    // one choice of --preset / --directions / --steps (no label suffix).
    let choices: Vec<SampleChoice> = if !a.splits.is_empty() {
        a.splits.iter().map(|&s| SampleChoice::Split(s)).collect()
    } else if !a.presets.is_empty() {
        a.presets.iter().map(|&p| SampleChoice::Preset(p)).collect()
    } else {
        vec![SampleChoice::Given]
    };
    for &e in &a.estimators {
        for (&m, choice) in a
            .modes
            .iter()
            .flat_map(|m| choices.iter().map(move |c| (m, c)))
        {
            let (estimator, mode): (Estimator, AoMode) = (e.into(), m.into());
            let mut base = AoOptions {
                mode,
                ..a.samples.options(estimator)
            };
            let mut name = format!("{} {}", estimator.name(), mode.name());
            match *choice {
                SampleChoice::Given => {}
                SampleChoice::Split((directions, steps)) => {
                    base.directions = directions;
                    base.steps = steps;
                    name = format!("{name} {directions}×{steps}");
                }
                SampleChoice::Preset(p) => {
                    let o = AoOptions::preset(estimator, p.into());
                    (base.directions, base.steps) = (o.directions, o.steps);
                    let label = p.to_possible_value().map(|v| v.get_name().to_owned());
                    name = format!("{name} {}", label.unwrap_or_default());
                }
            }
            for &resolution in &a.resolutions {
                for &denoise in &a.denoise {
                    if resolution == Resolution::Full {
                        let label = match denoise {
                            Denoise::None => name.clone(),
                            d => format!("{name} full {}", d.name()),
                        };
                        let o = AoOptions { denoise, ..base };
                        variants.push((label, o));
                        scales.push(1.0);
                        continue;
                    }
                    for &downsample in &a.downsamples {
                        for &upsample in &a.upsamplers {
                            let o = AoOptions {
                                resolution,
                                downsample,
                                upsample,
                                denoise,
                                ..base
                            };
                            let mut label = format!(
                                "{name} {} {} {}",
                                resolution.name(),
                                downsample.name(),
                                upsample.name()
                            );
                            if denoise != Denoise::None {
                                label = format!("{label} {}", denoise.name());
                            }
                            variants.push((label, o));
                            scales.push(1.0);
                        }
                    }
                }
            }
            for &scale in &a.scales {
                if estimator.uses_pyramid() || estimator.uses_moments() {
                    break;
                }
                for &denoise in &a.denoise {
                    if !matches!(denoise, Denoise::None | Denoise::Spatial) {
                        continue;
                    }
                    let o = AoOptions {
                        resolution: Resolution::Scaled,
                        upsample: Upsampler::Bilateral,
                        denoise,
                        ..base
                    };
                    let mut label = format!("{name} scaled {scale}");
                    if denoise != Denoise::None {
                        label = format!("{label} {}", denoise.name());
                    }
                    variants.push((label, o));
                    scales.push(scale);
                }
            }
        }
    }
    if variants.is_empty() {
        bail!("no variant to evaluate");
    }
    // Each frame count crossed with the variants above: N > 1 keeps a history and is
    // labelled ×N. `frames_of[i]`: variant i's frame count.
    let mut counts: Vec<u32> = Vec::new();
    for &f in &a.frames {
        if !counts.contains(&f) {
            counts.push(f);
        }
    }
    let single = std::mem::take(&mut variants);
    let single_scales = std::mem::take(&mut scales);
    let mut frames_of: Vec<u32> = Vec::new();
    for &f in &counts {
        for ((label, o), &scale) in single.iter().zip(&single_scales) {
            let (mut label, mut o) = (label.clone(), *o);
            if f > 1 {
                o.history = a.history;
                label = format!("{label} ×{f}");
            }
            variants.push((label, o));
            scales.push(scale);
            frames_of.push(f);
        }
    }
    let orbit_frames = counts.iter().copied().max().unwrap_or(1);
    let mut aos: Vec<Ao> = variants
        .iter()
        .map(|(_, o)| Ao::new(&ctx.device, *o))
        .collect::<Result<_, _>>()?;
    let mut estimators: Vec<Estimator> = Vec::new();
    for &e in &a.estimators {
        if !estimators.contains(&e.into()) {
            estimators.push(e.into());
        }
    }
    let mut screen_aos: Vec<(Estimator, Ao)> = if a.no_screen_reference {
        Vec::new()
    } else {
        estimators
            .iter()
            .map(|&e| Ok((e, Ao::new(&ctx.device, AoOptions::screen_reference(e))?)))
            .collect::<Result<_, obscura::Error>>()?
    };
    let (w, h) = (a.width, a.height);
    let mut rows = Vec::new();
    let mut sections = String::new();
    let mut info = Vec::new();
    for job in &jobs {
        let t0 = Instant::now();
        let bytes = std::fs::read(&job.file)
            .with_context(|| format!("cannot read scene `{}`", job.file.display()))?;
        let mesh = Mesh::load(&job.file)
            .with_context(|| format!("cannot load scene `{}`", job.file.display()))?;
        let cam = camera_for(job, &mesh)?;
        let bounds = mesh.bounds().context("the scene has no triangles")?;
        let radius = a.radius.unwrap_or(0.03 * bounds.diagonal());
        let settings = TraceSettings {
            radius,
            rays: a.rays,
            falloff: match a.falloff {
                FalloffArg::None => Falloff::None,
                FalloffArg::Quadratic => Falloff::Quadratic,
            },
            sampling: match a.truth {
                TruthArg::Centre => PixelSampling::Centre,
                TruthArg::Msaa4 => PixelSampling::Msaa4,
            },
        };
        eprintln!(
            "{}: {} triangles, radius {radius:.3}",
            job.name,
            mesh.triangle_count()
        );

        // Ground truth, cached.
        let key = cache::key(&bytes, &cam, w, h, &settings);
        let cpath = cache::path(&a.cache, key);
        let reference = match cache::load(&cpath, w, h) {
            Some(r) => {
                eprintln!("  reference: cached ({})", cpath.display());
                r
            }
            None => {
                let t = Instant::now();
                let bvh = Bvh::new(obscura_eval::triangles(&mesh));
                let r =
                    obscura_eval::trace_view(&bvh, &cam, w, h, &settings, &tenths("reference", t));
                eprintln!(
                    "  reference: {}x{} × {} rays in {:.1} s, mean standard error {:.4}",
                    w,
                    h,
                    a.rays,
                    t.elapsed().as_secs_f64(),
                    r.mean_std_error
                );
                if let Err(e) = cache::store(&cpath, &r) {
                    eprintln!("  warning: could not cache the reference: {e}");
                }
                r
            }
        };
        info.push((
            job.name.clone(),
            radius,
            reference.mean_std_error,
            mesh.triangle_count(),
        ));

        // Screen-space AO in each mode, timed interleaved.
        let gpu_mesh = raster.upload(&ctx, &mesh)?;
        let g = raster.render(&ctx, &gpu_mesh, &cam, w, h)?;
        let msaa = if a.msaa {
            Some(raster.render_msaa_depth(&ctx, &gpu_mesh, &cam, w, h)?)
        } else {
            None
        };
        let mut input = match &msaa {
            Some(m) => m.ao_input(&cam),
            None => g.ao_input(&cam, a.normal_source() == NormalSource::Gbuffer),
        };
        let noisy = match a.sensor {
            SensorArg::None => None,
            SensorArg::Kinect => Some(sensor::Sensor::Kinect),
            SensorArg::Stereo => Some(sensor::Sensor::Stereo),
        }
        .map(|s| sensor_depth(&ctx, &g, &input, s, a.sensor_noise))
        .transpose()?;
        let mut params = AoParams {
            radius,
            ..Default::default()
        };
        if let Some(s) = &noisy {
            input.depth = &s.view;
            input.convention = obscura::DepthConvention::LinearView;
            if a.depth_noise == NoiseArg::Known {
                params.depth_noise = s.known;
            }
        }
        if a.depth_noise == NoiseArg::Estimate
            || (a.depth_noise == NoiseArg::Auto && noisy.is_some())
        {
            let depth = match &noisy {
                Some(s) => std::borrow::Cow::Borrowed(&s.depth),
                None => std::borrow::Cow::Owned(linear_depth(&ctx, &g, &input)?),
            };
            // An integer encoding (Kinect-like millimetres) is known to the estimate, as
            // `render --depth` knows it of a 16-bit PNG.
            let quantum = noisy.as_ref().and_then(|s| s.quantum);
            let e = obscura::DepthNoise::estimate(&depth, w, h, &input.projection, quantum)?;
            params.depth_noise = e.model;
            eprintln!(
                "  depth noise: estimated {} (σ up to {:.3} px){}",
                crate::depthmap::describe_noise(&e.model),
                e.sigma_px,
                match &noisy {
                    Some(s) => format!(
                        "; the sensor's {}",
                        crate::depthmap::describe_noise(&s.known)
                    ),
                    None => String::new(),
                }
            );
        }
        let mut times = vec![Vec::new(); aos.len()];
        let timing = Timing::best_for(&ctx);
        for round in 0..=a.runs {
            for (i, ao) in aos.iter_mut().enumerate() {
                let p = AoParams {
                    scale: scales[i],
                    ..params
                };
                let ms = frame_ms(&ctx, ao, &input, &p, timing)?;
                if round > 0 {
                    times[i].push(ms);
                }
            }
        }
        let gpu_depth = ctx.read_f32(&g.depth)?;
        // Compare where both see a surface.
        let mask: Vec<bool> = reference
            .depth
            .iter()
            .zip(&gpu_depth)
            .map(|(r, g)| *r > 0.0 && *g < 1.0)
            .collect();
        let band: Vec<bool> =
            metrics::discontinuity_band(&reference.depth, w as usize, h as usize, 0.05, 2)
                .into_iter()
                .zip(&mask)
                .map(|(b, m)| b && *m)
                .collect();
        // Temporal accumulation: N frames of the still camera, one more for the flicker,
        // then an orbit of N frames ending at this camera.
        let mut temporal: Vec<Option<TemporalFigures>> = vec![None; aos.len()];
        let mut still_images: Vec<Option<Vec<f32>>> = vec![None; aos.len()];
        let mut orbit_images: Vec<Option<(Vec<f32>, Vec<f32>)>> = vec![None; aos.len()];
        if orbit_frames > 1 {
            for (i, ao) in aos.iter_mut().enumerate() {
                if frames_of[i] == 1 {
                    continue;
                }
                ao.reset_history();
                let p = AoParams {
                    scale: scales[i],
                    ..params
                };
                for _ in 0..frames_of[i] {
                    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
                }
                let still = ctx.read_f32(ao.output().context("AO output missing")?)?;
                ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
                let next = ctx.read_f32(ao.output().context("AO output missing")?)?;
                let flicker = metrics::mean_abs_diff(&still, &next, &mask);
                temporal[i] = Some(TemporalFigures {
                    frames: frames_of[i],
                    flicker,
                    orbit_rmse: 0.0,
                    disoccluded: None,
                });
                still_images[i] = Some(still);
            }
            // One orbit of the longest count, rasterized once; a variant of N frames joins
            // it N frames before its end, with a cut.
            let mut previous: Option<Camera> = None;
            for k in 0..orbit_frames {
                let c = cam.orbit(a.orbit_step * (k as f32 - (orbit_frames - 1) as f32));
                let gk = raster.render(&ctx, &gpu_mesh, &c, w, h)?;
                let ik = gk.ao_input(&c, a.normal_source() == NormalSource::Gbuffer);
                for (i, ao) in aos.iter_mut().enumerate() {
                    let first = orbit_frames - frames_of[i];
                    if frames_of[i] == 1 || k < first {
                        continue;
                    }
                    let motion = match previous {
                        Some(p) if k > first => c.motion_since(&p),
                        _ => obscura::CameraMotion::Cut,
                    };
                    let p = AoParams {
                        scale: scales[i],
                        motion,
                        ..params
                    };
                    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &ik, &p))?;
                }
                previous = Some(c);
            }
            for (i, ao) in aos.iter().enumerate().filter(|(i, _)| frames_of[*i] > 1) {
                let out = ctx.read_f32(ao.output().context("AO output missing")?)?;
                // The history's frame counts at full resolution (the working texel whose
                // footprint holds the pixel). A scaled history is on the working grid of
                // a texture created at full size.
                let hist = ctx.read_f32(ao.history().context("history missing")?)?;
                let scaled = ao.options().resolution == Resolution::Scaled;
                let f = ao.options().resolution.factor();
                let hw = w.div_ceil(f);
                let texel = |c: u32| {
                    if scaled {
                        ((c as f32 + 0.5) * scales[i]) as u32
                    } else {
                        c / f
                    }
                };
                let frames: Vec<f32> = (0..(w * h))
                    .map(|p| {
                        let (x, y) = (texel(p % w), texel(p / w));
                        hist[((y * hw + x) * 4 + 1) as usize]
                    })
                    .collect();
                orbit_images[i] = Some((out, frames));
            }
        }
        let mut screen = Vec::new();
        for (e, ao) in screen_aos.iter_mut() {
            let t = Instant::now();
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
            let out = ctx.read_f32(ao.output().context("AO output missing")?)?;
            eprintln!(
                "  {} screen-space reference: {:.1} s",
                e.name(),
                t.elapsed().as_secs_f64()
            );
            screen.push((*e, out));
        }
        let screen_of = |e: Estimator| screen.iter().find(|s| s.0 == e).map(|s| &s.1);
        let white = vec![1.0f32; (w * h) as usize];
        // (label, estimator, mode, image, time, options)
        type Result5 = (
            String,
            String,
            String,
            Vec<f32>,
            Option<f64>,
            Option<AoOptions>,
        );
        let mut results: Vec<Result5> = vec![(
            "white (no AO)".into(),
            "none".into(),
            String::new(),
            white,
            None,
            None,
        )];
        for (e, img) in &screen {
            results.push((
                format!("{} screen-space reference", e.name()),
                e.name().into(),
                "screen-reference".into(),
                img.clone(),
                None,
                None,
            ));
        }
        for (i, ao) in aos.iter().enumerate() {
            let out = match still_images[i].take() {
                Some(img) => img,
                None => ctx.read_f32(ao.output().context("AO output missing")?)?,
            };
            if let (Some(t), Some((orbit, frames))) = (temporal[i].as_mut(), &orbit_images[i]) {
                t.orbit_rmse = metrics::rmse(orbit, &reference.ao, &mask);
                // Visible for 4 frames before the last: a history of 5 frames.
                let young: Vec<bool> = frames
                    .iter()
                    .zip(&mask)
                    .map(|(f, m)| *m && (*f - 5.0).abs() < 0.5)
                    .collect();
                let count = young.iter().filter(|y| **y).count();
                // Only an orbit longer than 5 frames (and a history longer than 5) tells
                // those pixels from the ones seen since its first frame.
                if count > 0 && t.frames > 5 && a.history > 5 {
                    t.disoccluded = Some((
                        metrics::rmse(orbit, &reference.ao, &young),
                        metrics::rmse(&out, &reference.ao, &young),
                        count,
                    ));
                }
            }
            let o = variants[i].1;
            results.push((
                variants[i].0.clone(),
                o.estimator.name().into(),
                o.mode.name().into(),
                out,
                Some(median(times[i].clone())),
                Some(o),
            ));
        }
        // Bent normals of GTAO's and HBAO's single-frame variants (untimed; unfused, which is the same
        // work, so that the prepared normals can be read back), where they come out at full
        // resolution (not after box/tent filtering below it).
        let mut bent_of = std::collections::HashMap::new();
        for (label, o) in variants.iter().filter(|(_, o)| {
            a.bent_normals
                && o.estimator.has_bent_normals()
                && (o.resolution == obscura::Resolution::Full || !o.denoise.downsamples())
                && o.resolution != obscura::Resolution::Scaled
                && o.history == 0
        }) {
            let mut b = Ao::new(
                &ctx.device,
                AoOptions {
                    bent_normals: true,
                    fused: false,
                    ..*o
                },
            )?;
            ctx.run(|enc| b.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
            let bent = ctx.read_f32(b.bent_normals().context("bent normals missing")?)?;
            let prepared = b.prepared_view().context("prepared buffer missing")?;
            let prepared = ctx.read_f32(prepared.texture())?;
            let e = bent_error(&bent, &prepared, &reference, &mask);
            eprintln!(
                "  {label}: bent normals {:.1}° from the traced ones ({:.1}° where occluded), \
                 the surface normal {:.1}° ({:.1}°)",
                e.bent, e.bent_occluded, e.normal, e.normal_occluded
            );
            bent_of.insert(label.clone(), e);
        }
        let r = &reference.ao;
        // The full-resolution result of the same estimator, mode and samples, if evaluated.
        let full_of = |o: &AoOptions| {
            results.iter().find_map(|r| {
                r.5.filter(|f| {
                    f.direct()
                        && f.estimator == o.estimator
                        && f.mode == o.mode
                        && (f.directions, f.steps) == (o.directions, o.steps)
                })
                .map(|_| &r.3)
            })
        };
        for (name, estimator, mode, img, ms, options) in &results {
            let full_rmse = options.filter(|o| !o.direct()).and_then(|o| {
                full_of(&o).map(|f| (metrics::rmse(img, f, &mask), metrics::rmse(img, f, &band)))
            });
            let screen = ms
                .and(Estimator::ALL.into_iter().find(|e| e.name() == estimator))
                .and_then(screen_of);
            rows.push(Row {
                view: job.name.clone(),
                variant: name.clone(),
                estimator: estimator.clone(),
                mode: mode.clone(),
                rmse: metrics::rmse(img, r, &mask),
                bias: metrics::bias(img, r, &mask),
                ssim: metrics::ssim(img, r, w as usize, h as usize, &mask),
                band_rmse: metrics::rmse(img, r, &band),
                screen_rmse: screen.map(|s| metrics::rmse(img, s, &mask)),
                screen_bias: screen.map(|s| metrics::bias(img, s, &mask)),
                full_rmse,
                ms: *ms,
                temporal: variants
                    .iter()
                    .position(|v| &v.0 == name)
                    .and_then(|i| temporal[i]),
                bent: bent_of.get(name).copied(),
            });
        }
        for row in rows.iter().filter(|x| x.view == job.name) {
            eprintln!(
                "  {:<30} RMSE {:.4}  bias {:+.4}  SSIM {:.3}  band RMSE {:.4}  {}{}",
                row.variant,
                row.rmse,
                row.bias,
                row.ssim,
                row.band_rmse,
                row.screen_rmse
                    .zip(row.screen_bias)
                    .map_or(String::new(), |(m, b)| format!(
                        "vs screen ref {m:.4} (bias {b:+.4})  "
                    )),
                row.ms
                    .map_or(String::new(), |m| format!("{} ms", fmt_ms(m)))
            );
        }

        if let (Some(dir), Some(md), false) = (&a.report, &md_path, a.no_pictures) {
            let rel = relative_dir(dir, md);
            let pic = |stem: &str| format!("{}-{}.png", job.name, stem.replace(' ', "-"));
            write_gray(&dir.join(pic("reference")), r, w, h, a.picture_scale)?;
            let _ = write!(
                sections,
                "\n### {}\n\n`{}`, {} triangles, radius {radius:.3}, reference {} rays/pixel (mean standard error {:.4}), eval {}×{}; evaluated in {:.0} s.\n\n| reference | {} |\n|---|{}\n| ![]({rel}{}) |",
                job.name,
                job.file.display(),
                mesh.triangle_count(),
                a.rays,
                reference.mean_std_error,
                w,
                h,
                t0.elapsed().as_secs_f64(),
                variants.iter().map(|v| v.0.as_str()).collect::<Vec<_>>().join(" | "),
                "---|".repeat(variants.len()),
                pic("reference"),
            );
            for (name, _, _, img, _, _) in results.iter().skip(1 + screen.len()) {
                write_gray(&dir.join(pic(name)), img, w, h, a.picture_scale)?;
                write_error(
                    &dir.join(pic(&format!("{name}-error"))),
                    img,
                    r,
                    &mask,
                    w,
                    h,
                    a.picture_scale,
                )?;
                let _ = write!(sections, " ![]({rel}{}) |", pic(name));
            }
            let _ = write!(
                sections,
                "\n| signed error (red: too bright, blue: too dark, ±0.5) |"
            );
            for (name, _, _, _, _, _) in results.iter().skip(1 + screen.len()) {
                let _ = write!(sections, " ![]({rel}{}) |", pic(&format!("{name}-error")));
            }
            sections.push('\n');
        }
    }

    let means = variant_means(&rows);
    let table = format!(
        "{}{}{}{}{}{}",
        mixed_summary(&rows),
        frontier_table(&means),
        sampling_bias_table(&rows),
        bent_table(&rows),
        summary_table(&rows),
        temporal_table(&rows, a)
    );
    print!("{table}");
    if let (Some(dir), Some(md)) = (&a.report, &md_path) {
        let rel = relative_dir(dir, md);
        write_text(&dir.join("quality-vs-time.svg"), &scatter(&rows, &variants))?;
        if means.len() > 1 {
            write_text(&dir.join("frontier.svg"), &frontier_plot(&means))?;
        }
        // The mixed-resolution introduction only when some variant runs below full
        // resolution (a denoiser alone also gets the full-resolution comparison columns).
        let title = if variants
            .iter()
            .any(|(_, o)| o.resolution != Resolution::Full)
        {
            &format!("# Mixed resolution against ray-traced ground truth\n\nAO computed at half or quarter resolution (depth downsampled 2×2 → 1 by a rule, picks recentred on their tangent plane) or at a continuous scale *s* (`scaled s`: each working texel one of the full-resolution pixels it covers, by the same rule among the 2×2 nearest its centre, recentred; temporal accumulation, when on, on the working grid), upsampled to full resolution, compared with ray-traced AO and with the same estimator at full resolution. The evaluation size is {w}×{h} (half resolution is a {}×{} AO){}; speed-ups at 1920×1080 and 3840×2160, and what the numbers mean, are in BENCHMARKS.md (`obscura bench --compare resolutions`). *Speed-up* here is the mean over the views of full-resolution time / variant time at {w}×{h}, where the full-resolution prepare and upsample passes weigh most.", w.div_ceil(2), h.div_ceil(2), if w * h <= 640 * 400 { ", small: the harshest case for low resolutions" } else { "" })
        } else {
            "# Quality against ray-traced ground truth"
        };
        let mut doc = format!(
            "{title}\n\nGenerated by `{}`.\n\nReference: CPU ray tracing of the scene triangles, cosine-weighted hemisphere, {} rays per pixel{}, hits within the radius {} (see `crates/obscura-eval`). Metrics over pixels where both the reference and the G-buffer see a surface; the band is the pixels within 2 px of a depth discontinuity (> 5% relative). Bias = mean(estimate − reference): positive means too bright. Each estimator's *screen-space reference* is its own integral brute-forced (64 × 64 samples, no jitter, `AoOptions::screen_reference`): its error against the ray tracer is what one depth layer allows that estimator, and *RMSE vs screen ref* and *bias vs screen ref* are an estimate's sampling error and sampling bias (for vo-area, whose 64 × 64 samples each cover under 4 px², the reference is the line integral's, so it is the area integral's distance from it). Times: median {} on {}.\n\n",
            std::env::args().collect::<Vec<_>>().join(" "),
            a.rays,
            match a.truth {
                TruthArg::Centre => "",
                TruthArg::Msaa4 =>
                    " (a quarter through each of the four 4× MSAA sample positions, averaged; sky samples unoccluded)",
            },
            match a.falloff {
                FalloffArg::None => "occlude fully",
                FalloffArg::Quadratic => "occlude by 1 − t²/R²",
            },
            match Timing::best_for(&ctx) {
                Timing::Timestamps => "GPU time of the whole AO frame (the sum of its passes' timestamps)",
                Timing::WallClock => "wall clock of the whole AO frame (every pass, submit to completion)",
            },
            ctx.describe()
        );
        doc.push_str(&table);
        let _ = write!(doc, "\n![quality versus time]({rel}quality-vs-time.svg)\n");
        if means.len() > 1 {
            let _ = write!(
                doc,
                "\n![the quality-versus-time frontier]({rel}frontier.svg)\n"
            );
        }
        doc.push_str("\n## Views\n");
        doc.push_str(&sections);
        write_text(md, &doc)?;
        eprintln!("wrote {}", md.display());
    }
    if let Some(p) = &a.json {
        write_text(p, &json(&rows, &info))?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// `dir` as seen from the markdown file's folder, with a trailing slash ("" if the same).
fn relative_dir(dir: &Path, md: &Path) -> String {
    let base = md.parent().unwrap_or(Path::new(""));
    match dir.strip_prefix(base) {
        Ok(r) if r.as_os_str().is_empty() => String::new(),
        Ok(r) => format!("{}/", r.display()),
        Err(_) => format!("{}/", dir.display()),
    }
}

/// A tracer's progress callback: prints `  LABEL: N% (T s)` at each tenth of the rows,
/// T counted from `start`.
pub(crate) fn tenths(label: &str, start: Instant) -> impl Fn(usize, usize) + Sync + '_ {
    let last = std::sync::atomic::AtomicUsize::new(0);
    move |done, total| {
        let pct = done * 10 / total;
        if last.fetch_max(pct, std::sync::atomic::Ordering::Relaxed) < pct {
            eprintln!(
                "  {label}: {}% ({:.0} s)",
                pct * 10,
                start.elapsed().as_secs_f64()
            );
        }
    }
}

/// Box-filters `img` by `scale` (1/scale rounded to an integer factor).
pub(crate) fn shrink(img: &[[f32; 3]], w: u32, h: u32, scale: f32) -> (Vec<[f32; 3]>, u32, u32) {
    let f = (1.0 / scale).round().max(1.0) as u32;
    let (ow, oh) = ((w / f).max(1), (h / f).max(1));
    let mut out = vec![[0.0; 3]; (ow * oh) as usize];
    for y in 0..oh {
        for x in 0..ow {
            let mut acc = [0.0; 3];
            for dy in 0..f {
                for dx in 0..f {
                    let p = img[((y * f + dy).min(h - 1) * w + (x * f + dx).min(w - 1)) as usize];
                    for c in 0..3 {
                        acc[c] += p[c];
                    }
                }
            }
            out[(y * ow + x) as usize] = acc.map(|v| v / (f * f) as f32);
        }
    }
    (out, ow, oh)
}

fn to8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn write_gray(path: &Path, img: &[f32], w: u32, h: u32, scale: f32) -> Result<()> {
    let rgb: Vec<[f32; 3]> = img.iter().map(|v| [*v; 3]).collect();
    let (s, sw, sh) = shrink(&rgb, w, h, scale);
    let px: Vec<u8> = s.iter().map(|p| to8(p[0])).collect();
    save_png(path, &px, sw, sh, image::ExtendedColorType::L8)
}

/// Signed error heat map: white = exact, red = too bright, blue = too dark (±0.5 saturates),
/// grey = not compared.
fn write_error(
    path: &Path,
    img: &[f32],
    reference: &[f32],
    mask: &[bool],
    w: u32,
    h: u32,
    scale: f32,
) -> Result<()> {
    let rgb: Vec<[f32; 3]> = img
        .iter()
        .zip(reference)
        .zip(mask)
        .map(|((a, b), m)| {
            if !m {
                return [0.5; 3];
            }
            let e = ((a - b) / 0.5).clamp(-1.0, 1.0);
            if e >= 0.0 {
                [1.0, 1.0 - e, 1.0 - e]
            } else {
                [1.0 + e, 1.0 + e, 1.0]
            }
        })
        .collect();
    let (s, sw, sh) = shrink(&rgb, w, h, scale);
    let px: Vec<u8> = s.iter().flat_map(|p| p.map(to8)).collect();
    save_png(path, &px, sw, sh, image::ExtendedColorType::Rgb8)
}

/// Below full resolution: each variant's errors averaged over the views, and its speed-up
/// over the full-resolution run of the same estimator and mode (mean of per-view ratios).
fn mixed_summary(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.ms.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if !rows.iter().any(|r| r.full_rmse.is_some()) {
        return String::new();
    }
    let mut s = String::from("Mean over the views. *Band ratio*: band RMSE against ray-traced AO divided by that of the same estimator and mode at full resolution (issue 5 asks ≤ 1.25). An accumulated variant (×N) is compared with the single full-resolution frame of its estimator, mode and samples.\n\n| variant | RMSE | band RMSE | band ratio | RMSE vs full res | band RMSE vs full res | speed-up over full res |\n|---|---|---|---|---|---|---|\n");
    for name in names {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.variant == name).collect();
        let n = mine.len() as f32;
        let mean = |f: &dyn Fn(&Row) -> f32| mine.iter().map(|r| f(r)).sum::<f32>() / n;
        // The same estimator, mode and samples at full resolution without denoising on the
        // same view: this variant itself if it is one, else the timed variant whose name,
        // plus a space, begins this one's (the longest, so "gtao randomized high" and not
        // "gtao randomized" for a preset).
        let full_of = |r: &Row| {
            rows.iter()
                .filter(|f| {
                    f.view == r.view
                        && f.estimator == r.estimator
                        && f.mode == r.mode
                        && f.ms.is_some()
                        && f.full_rmse.is_none()
                        && (r.variant == f.variant
                            || r.variant.starts_with(&format!("{} ", f.variant)))
                })
                .max_by_key(|f| f.variant.len())
        };
        let speedups: Vec<f64> = mine
            .iter()
            .filter_map(|r| Some(full_of(r)?.ms? / r.ms?))
            .collect();
        let speedup = if speedups.is_empty() {
            "–".to_string()
        } else {
            format!(
                "{:.2}×",
                speedups.iter().sum::<f64>() / speedups.len() as f64
            )
        };
        let full_band: Vec<f32> = mine
            .iter()
            .filter_map(|r| full_of(r).map(|f| f.band_rmse))
            .collect();
        let band_ratio = if full_band.len() == mine.len() {
            format!(
                "{:.2}",
                mean(&|r| r.band_rmse) / (full_band.iter().sum::<f32>() / n)
            )
        } else {
            "–".into()
        };
        let full = mine.iter().all(|r| r.full_rmse.is_some());
        let _ = writeln!(
            s,
            "| {name} | {:.4} | {:.4} | {band_ratio} | {} | {} | {speedup} |",
            mean(&|r| r.rmse),
            mean(&|r| r.band_rmse),
            if full {
                format!("{:.4}", mean(&|r| r.full_rmse.map_or(0.0, |f| f.0)))
            } else {
                "–".into()
            },
            if full {
                format!("{:.4}", mean(&|r| r.full_rmse.map_or(0.0, |f| f.1)))
            } else {
                "–".into()
            },
        );
    }
    s.push('\n');
    s
}

/// Per variant, the mean and the largest (in magnitude) over the views of its bias minus
/// that of its estimator's screen-space reference: how far sampling moves the mean AO from
/// the integral it samples (issue 10 asks GTAO's within ±0.01 on every view). Empty
/// without screen-space references.
fn sampling_bias_table(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.screen_bias.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if names.is_empty() {
        return String::new();
    }
    let mut s = String::from("\n### Sampling bias\n\nBias minus the bias of the estimator's own screen-space reference (= mean(estimate − screen ref)), over the views: positive means sampling leaves the image brighter than the integral it samples.\n\n| variant | mean | largest | on |\n|---|---|---|---|\n");
    for name in names {
        let mine: Vec<(&str, f32)> = rows
            .iter()
            .filter(|r| r.variant == name)
            .filter_map(|r| Some((r.view.as_str(), r.screen_bias?)))
            .collect();
        let mean = mine.iter().map(|m| m.1).sum::<f32>() / mine.len() as f32;
        let (view, largest) = mine
            .iter()
            .copied()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap_or(("–", 0.0));
        let _ = writeln!(s, "| {name} | {mean:+.4} | {largest:+.4} | {view} |");
    }
    s.push('\n');
    s
}

fn bent_table(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.bent.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if names.is_empty() {
        return String::new();
    }
    let mut s = format!("\n### Bent normals\n\nMean angle to the ray tracer's bent normal (the mean direction of its unoccluded cosine-weighted rays), over the views: of the estimator's bent normals (GTAO, HBAO), and of the surface normal it was given or reconstructed (what a renderer uses without bent normals); *occluded*: pixels whose traced AO is below {OCCLUDED}, where the two differ most.\n\n| variant | bent normals | surface normal | bent normals, occluded | surface normal, occluded |\n|---|---|---|---|---|\n");
    for name in names {
        let mine: Vec<BentError> = rows
            .iter()
            .filter(|r| r.variant == name)
            .filter_map(|r| r.bent)
            .collect();
        let mean = |f: fn(&BentError) -> f32| mine.iter().map(f).sum::<f32>() / mine.len() as f32;
        let _ = writeln!(
            s,
            "| {name} | {:.1}° | {:.1}° | {:.1}° | {:.1}° |",
            mean(|e| e.bent),
            mean(|e| e.normal),
            mean(|e| e.bent_occluded),
            mean(|e| e.normal_occluded)
        );
    }
    s.push('\n');
    s
}

fn summary_table(rows: &[Row]) -> String {
    let mixed = rows.iter().any(|r| r.full_rmse.is_some());
    let mut s = String::from(
        "| view | estimator / mode | RMSE | bias | SSIM | band RMSE | RMSE vs screen ref | bias vs screen ref |",
    );
    s.push_str(if mixed {
        " RMSE vs full res | band RMSE vs full res | ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n"
    } else {
        " ms |\n|---|---|---|---|---|---|---|---|---|\n"
    });
    for r in rows {
        let full = match (mixed, r.full_rmse) {
            (false, _) => String::new(),
            (true, None) => " – | – |".into(),
            (true, Some((a, b))) => format!(" {a:.4} | {b:.4} |"),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {:+.4} | {:.3} | {:.4} | {} | {} |{full} {} |",
            r.view,
            r.variant,
            r.rmse,
            r.bias,
            r.ssim,
            r.band_rmse,
            r.screen_rmse.map_or("–".to_string(), |m| format!("{m:.4}")),
            r.screen_bias
                .map_or("–".to_string(), |b| format!("{b:+.4}")),
            r.ms.map_or("–".to_string(), fmt_ms)
        );
    }
    s
}

/// The temporal figures of `eval --frames N`, per view and variant, and their means.
fn temporal_table(rows: &[Row], a: &EvalArgs) -> String {
    let t: Vec<(&Row, TemporalFigures)> = rows
        .iter()
        .filter_map(|r| r.temporal.map(|t| (r, t)))
        .collect();
    if t.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n### Temporal accumulation (history {})\n\n*×N*: scored after N frames of a still camera. *Flicker*: mean |AO(frame N+1) − AO(frame N)| of the still camera. *Orbit*: N frames {}° apart about the vertical axis through the target, ending at the view; RMSE of its last frame. *Disoccluded*: pixels of that frame that became visible 4 frames earlier (history of 5 frames): their RMSE after the orbit, against the same pixels in the still camera's N-frame image (ratio: the issue asks ≤ 1.5).\n\n| view | variant | RMSE (still, N frames) | flicker | orbit RMSE | disoccluded pixels | their RMSE | same pixels still | ratio |\n|---|---|---|---|---|---|---|---|---|\n",
        a.history, a.orbit_step
    );
    for (r, f) in &t {
        let d = f
            .disoccluded
            .map_or(" – | – | – | – |".to_string(), |(o, st, n)| {
                format!(" {n} | {o:.4} | {st:.4} | {:.2} |", o / st.max(1e-6))
            });
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {:.4} | {:.4} |{d}",
            r.view, r.variant, r.rmse, f.flicker, f.orbit_rmse
        );
    }
    let mut variants: Vec<&str> = t.iter().map(|(r, _)| r.variant.as_str()).collect();
    variants.dedup();
    variants.sort();
    variants.dedup();
    for v in variants {
        let of: Vec<&(&Row, TemporalFigures)> = t.iter().filter(|(r, _)| r.variant == v).collect();
        let n = of.len() as f32;
        let mean =
            |f: &dyn Fn(&(&Row, TemporalFigures)) -> f32| of.iter().map(|x| f(x)).sum::<f32>() / n;
        let (o, st): (f32, f32) = of
            .iter()
            .filter_map(|(_, f)| f.disoccluded)
            .fold((0.0, 0.0), |acc, (o, st, _)| {
                (acc.0 + o * o, acc.1 + st * st)
            });
        // An orbit shorter than 5 frames has no pixel with a 5-frame history.
        let pooled = if st > 0.0 {
            format!("{:.2} (pooled)", (o / st).sqrt())
        } else {
            "–".to_string()
        };
        let _ = writeln!(
            s,
            "| **mean** | {v} | {:.4} | {:.4} | {:.4} | | | | {pooled} |",
            mean(&|x| x.0.rmse),
            mean(&|x| x.1.flicker),
            mean(&|x| x.1.orbit_rmse),
        );
    }
    s
}

fn json(rows: &[Row], info: &[(String, f32, f32, usize)]) -> String {
    let mut s = String::from("{\n  \"views\": [\n");
    for (i, (name, radius, se, tris)) in info.iter().enumerate() {
        let _ = writeln!(
            s,
            "    {{\"view\": \"{name}\", \"radius\": {radius}, \"reference_mean_std_error\": {se}, \"triangles\": {tris}}}{}",
            if i + 1 == info.len() { "" } else { "," }
        );
    }
    s.push_str("  ],\n  \"records\": [\n");
    for (i, r) in rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "    {{\"view\": \"{}\", \"variant\": \"{}\", \"estimator\": \"{}\", \"mode\": \"{}\", \"rmse\": {:.5}, \"bias\": {:.5}, \"ssim\": {:.5}, \"band_rmse\": {:.5}, \"screen_rmse\": {}, \"screen_bias\": {}, \"full_rmse\": {}, \"full_band_rmse\": {}, \"median_ms\": {}, \"frames\": {}, \"flicker\": {}, \"orbit_rmse\": {}, \"disoccluded_rmse\": {}, \"disoccluded_still_rmse\": {}, \"bent_deg\": {}, \"bent_occluded_deg\": {}, \"normal_deg\": {}, \"normal_occluded_deg\": {}}}{}",
            r.view,
            r.variant,
            r.estimator,
            r.mode,
            r.rmse,
            r.bias,
            r.ssim,
            r.band_rmse,
            r.screen_rmse.map_or("null".to_string(), |m| format!("{m:.5}")),
            r.screen_bias.map_or("null".to_string(), |b| format!("{b:.5}")),
            r.full_rmse.map_or("null".to_string(), |m| format!("{:.5}", m.0)),
            r.full_rmse.map_or("null".to_string(), |m| format!("{:.5}", m.1)),
            r.ms.map_or("null".to_string(), |m| format!("{m:.4}")),
            r.temporal.map_or(1, |t| t.frames),
            r.temporal.map_or("null".to_string(), |t| format!("{:.5}", t.flicker)),
            r.temporal.map_or("null".to_string(), |t| format!("{:.5}", t.orbit_rmse)),
            r.temporal
                .and_then(|t| t.disoccluded)
                .map_or("null".to_string(), |d| format!("{:.5}", d.0)),
            r.temporal
                .and_then(|t| t.disoccluded)
                .map_or("null".to_string(), |d| format!("{:.5}", d.1)),
            r.bent.map_or("null".to_string(), |e| format!("{:.3}", e.bent)),
            r.bent.map_or("null".to_string(), |e| format!("{:.3}", e.bent_occluded)),
            r.bent.map_or("null".to_string(), |e| format!("{:.3}", e.normal)),
            r.bent.map_or("null".to_string(), |e| format!("{:.3}", e.normal_occluded)),
            if i + 1 == rows.len() { "" } else { "," }
        );
    }
    s.push_str("  ]\n}\n");
    s
}

/// One timed variant averaged over the evaluated views.
struct VariantMean {
    variant: String,
    estimator: String,
    rmse: f64,
    bias: f64,
    ms: f64,
    /// An accumulated variant's mean orbit RMSE (a moving camera's error).
    moving: Option<f64>,
    /// The variant that beats it (`pareto`), or `None` on the frontier.
    beaten_by: Option<usize>,
}

impl VariantMean {
    /// The error the frontier ranks by: the RMSE, or for an accumulated variant the worse
    /// of the still camera's and the orbit's (a still camera alone flatters it).
    fn error(&self) -> f64 {
        self.moving.map_or(self.rmse, |m| m.max(self.rmse))
    }
}

/// Every timed variant's mean RMSE, bias and time over the views, in evaluation order.
fn variant_means(rows: &[Row]) -> Vec<VariantMean> {
    let mut out: Vec<VariantMean> = Vec::new();
    for r in rows.iter().filter(|r| r.ms.is_some()) {
        if out.iter().any(|m| m.variant == r.variant) {
            continue;
        }
        let mine: Vec<&Row> = rows.iter().filter(|x| x.variant == r.variant).collect();
        let n = mine.len() as f64;
        out.push(VariantMean {
            variant: r.variant.clone(),
            estimator: r.estimator.clone(),
            rmse: mine.iter().map(|x| x.rmse as f64).sum::<f64>() / n,
            bias: mine.iter().map(|x| x.bias as f64).sum::<f64>() / n,
            ms: mine.iter().filter_map(|x| x.ms).sum::<f64>() / n,
            moving: r.temporal.map(|_| {
                mine.iter()
                    .filter_map(|x| x.temporal)
                    .map(|t| t.orbit_rmse as f64)
                    .sum::<f64>()
                    / n
            }),
            beaten_by: None,
        });
    }
    let beaten = pareto(&out.iter().map(|m| (m.ms, m.error())).collect::<Vec<_>>());
    for (m, b) in out.iter_mut().zip(beaten) {
        m.beaten_by = b;
    }
    out
}

/// For each point (time, error), the index of the point that dominates it, or `None` when
/// it is on the Pareto frontier: no other point is at most as slow and strictly more
/// accurate, or as accurate and strictly faster. The dominating point named is the most
/// accurate of those at most as slow (itself on the frontier).
fn pareto(points: &[(f64, f64)]) -> Vec<Option<usize>> {
    points
        .iter()
        .enumerate()
        .map(|(i, &(t, e))| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, &(tj, ej))| {
                    j != i && tj <= t && ej <= e && (tj < t || ej < e || j < i)
                })
                .min_by(|a, b| {
                    (a.1 .1, a.1 .0)
                        .partial_cmp(&(b.1 .1, b.1 .0))
                        .unwrap_or(std::cmp::Ordering::Equal)
                })
                .map(|(j, _)| j)
        })
        .collect()
}

/// The quality-versus-time frontier: every timed variant by mean time, marked when no other
/// variant is both at most as slow and more accurate.
fn frontier_table(means: &[VariantMean]) -> String {
    if means.len() < 2 {
        return String::new();
    }
    let mut order: Vec<usize> = (0..means.len()).collect();
    order.sort_by(|&a, &b| means[a].ms.total_cmp(&means[b].ms));
    let moving = means.iter().any(|m| m.moving.is_some());
    let mut s = String::from("\n### Quality-versus-time frontier\n\nMean over the views of RMSE against ray-traced AO and of the frame time, every variant by time. **frontier**: no other variant is at most as slow and more accurate; the others name the faster-or-equal variant that beats them. Pick the row that fits your budget.");
    if moving {
        s.push_str(" *×N*: N accumulated frames (a history), timed per frame; *RMSE* is the still camera's after N frames, *moving* the last frame of an orbit of N frames (`--orbit-step`), and the frontier ranks these by the worse of the two.\n\n| variant | RMSE | moving | bias | ms | |\n|---|---|---|---|---|---|\n");
    } else {
        s.push_str("\n\n| variant | RMSE | bias | ms | |\n|---|---|---|---|---|\n");
    }
    for i in order {
        let m = &means[i];
        let mark = match m.beaten_by {
            None => "**frontier**".to_string(),
            Some(j) => format!("beaten by {}", means[j].variant),
        };
        let mov = match (moving, m.moving) {
            (false, _) => String::new(),
            (true, None) => " – |".to_string(),
            (true, Some(o)) => format!(" {o:.4} |"),
        };
        let _ = writeln!(
            s,
            "| {} | {:.4} |{mov} {:+.4} | {} | {mark} |",
            m.variant,
            m.rmse,
            m.bias,
            fmt_ms(m.ms)
        );
    }
    s.push('\n');
    s
}

/// The frontier as a picture: one point per variant (mean time, mean RMSE), coloured by
/// estimator; frontier points filled, labelled and joined.
fn frontier_plot(means: &[VariantMean]) -> String {
    let (w, h, m, right) = (640.0, 400.0, 60.0, 440.0);
    let tmax = means.iter().map(|v| v.ms).fold(1e-9, f64::max) * 1.05;
    let emax = means.iter().map(|v| v.error()).fold(1e-9, f64::max) * 1.05;
    let px = |t: f64| m + t / tmax * w;
    let py = |e: f64| 20.0 + h - e / emax * h;
    let estimators = ["gtao", "hbao", "vo", "vao", "sao", "vo-area"];
    let colors = [
        "#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#e6730f", "#17becf",
    ];
    let color = |e: &str| {
        estimators
            .iter()
            .position(|x| *x == e)
            .map_or("#222222", |i| colors[i])
    };
    let mut s = plot_axes(
        w + m + right,
        (w, h, m),
        (tmax, emax),
        (
            "mean ms per frame (every pass)",
            if means.iter().any(|v| v.moving.is_some()) {
                "mean RMSE vs ray-traced (×N: the worse of still and moving)"
            } else {
                "mean RMSE vs ray-traced"
            },
        ),
    );
    let mut front: Vec<usize> = (0..means.len())
        .filter(|&i| means[i].beaten_by.is_none())
        .collect();
    front.sort_by(|&a, &b| means[a].ms.total_cmp(&means[b].ms));
    let line: Vec<String> = front
        .iter()
        .map(|&i| format!("{:.1},{:.1}", px(means[i].ms), py(means[i].error())))
        .collect();
    let _ = writeln!(
        s,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"#555\" stroke-dasharray=\"4 3\"/>",
        line.join(" ")
    );
    for v in means {
        let c = color(&v.estimator);
        let fill = if v.beaten_by.is_none() { c } else { "none" };
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{fill}\" stroke=\"{c}\"><title>{}: {:.4}, {:.1} ms</title></circle>",
            px(v.ms),
            py(v.error()),
            v.variant,
            v.error(),
            v.ms
        );
    }
    // Frontier labels in a column on the right, joined to their points.
    for (k, &i) in front.iter().enumerate() {
        let v = &means[i];
        let y = 30.0 + 16.0 * k as f64;
        let _ = writeln!(
            s,
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{}\" y2=\"{}\" stroke=\"#ccc\"/>\n<text x=\"{}\" y=\"{}\" fill=\"{}\">{} ({:.4}, {:.0} ms)</text>",
            px(v.ms),
            py(v.error()),
            m + w + 8.0,
            y - 4.0,
            m + w + 10.0,
            y,
            color(&v.estimator),
            v.variant,
            v.error(),
            v.ms
        );
    }
    s.push_str("</svg>\n");
    s
}

/// An SVG plot up to its points: a `width`-wide canvas, the w × h frame at (m, 20), five
/// tick labels per axis from 0 to `tmax` ms and `emax` RMSE, and the two axis titles.
fn plot_axes(
    width: f64,
    (w, h, m): (f64, f64, f64),
    (tmax, emax): (f64, f64),
    (xlabel, ylabel): (&str, &str),
) -> String {
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<rect x=\"{m}\" y=\"20\" width=\"{w}\" height=\"{h}\" fill=\"none\" stroke=\"#999\"/>\n",
        h + m + 30.0
    );
    for k in 0..=4 {
        let (t, e) = (tmax * k as f64 / 4.0, emax * k as f64 / 4.0);
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{t:.0}</text>\n<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{e:.3}</text>",
            m + t / tmax * w,
            20.0 + h + 15.0,
            m - 4.0,
            20.0 + h - e / emax * h + 4.0
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{xlabel}</text>\n<text x=\"14\" y=\"{2}\" transform=\"rotate(-90 14 {2})\" text-anchor=\"middle\">{ylabel}</text>",
        m + w / 2.0,
        20.0 + h + 32.0,
        20.0 + h / 2.0
    );
    s
}

/// Quality (RMSE) against time, one point per view and mode.
fn scatter(rows: &[Row], variants: &[(String, AoOptions)]) -> String {
    let pts: Vec<&Row> = rows.iter().filter(|r| r.ms.is_some()).collect();
    let (w, h, m) = (560.0, 360.0, 60.0);
    let tmax = pts.iter().filter_map(|r| r.ms).fold(1e-9, f64::max) * 1.1;
    let emax = pts.iter().map(|r| r.rmse as f64).fold(1e-9, f64::max) * 1.1;
    let colors = ["#222222", "#1f77b4", "#e6730f", "#2ca02c", "#9467bd"];
    let mut s = plot_axes(
        w + 2.0 * m + 140.0,
        (w, h, m),
        (tmax, emax),
        ("median ms (prepare + AO)", "RMSE vs ray-traced"),
    );
    let px = |t: f64| m + t / tmax * w;
    let py = |e: f64| 20.0 + h - e / emax * h;
    for (vi, (name, _)) in variants.iter().enumerate() {
        let c = colors[vi % colors.len()];
        for r in pts.iter().filter(|r| &r.variant == name) {
            let _ = writeln!(
                s,
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{c}\"><title>{} {}</title></circle>",
                px(r.ms.unwrap_or(0.0)),
                py(r.rmse as f64),
                r.view,
                name
            );
        }
        let y = 30.0 + 18.0 * vi as f64;
        let _ = writeln!(s, "<circle cx=\"{}\" cy=\"{y}\" r=\"4\" fill=\"{c}\"/><text x=\"{}\" y=\"{}\">{name}</text>", m + w + 15.0, m + w + 25.0, y + 4.0);
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::{mixed_summary, pareto, parse_split, Row};

    /// A row of one view with only what the mixed summary reads.
    fn row(variant: &str, ms: f64, full_rmse: Option<(f32, f32)>) -> Row {
        let words: Vec<&str> = variant.split(' ').collect();
        Row {
            view: "v".into(),
            variant: variant.into(),
            estimator: words[0].into(),
            mode: words[1].into(),
            rmse: 0.05,
            bias: 0.0,
            ssim: 1.0,
            band_rmse: 0.1,
            screen_rmse: None,
            screen_bias: None,
            full_rmse,
            ms: Some(ms),
            temporal: None,
            bent: None,
        }
    }

    /// With several presets, a denoised or low-resolution variant's speed-up is over the
    /// full-resolution variant of its own preset ("gtao randomized high"), not of another
    /// one nor of none; a variant that is its own full-resolution one reads 1.00×.
    #[test]
    fn the_mixed_summary_compares_each_preset_with_its_own_full_resolution() {
        let rows = [
            row("gtao randomized low", 10.0, None),
            row("gtao randomized high", 20.0, None),
            row(
                "gtao randomized high full spatial",
                40.0,
                Some((0.01, 0.01)),
            ),
            row(
                "gtao randomized low half bilateral",
                5.0,
                Some((0.02, 0.02)),
            ),
        ];
        let s = mixed_summary(&rows);
        let speedup = |name: &str| {
            let line = s
                .lines()
                .find(|l| l.starts_with(&format!("| {name} |")))
                .unwrap_or_else(|| panic!("{name} missing: {s}"));
            line.rsplit('|').nth(1).unwrap().trim().to_string()
        };
        assert_eq!(speedup("gtao randomized high full spatial"), "0.50×", "{s}");
        assert_eq!(
            speedup("gtao randomized low half bilateral"),
            "2.00×",
            "{s}"
        );
        assert_eq!(speedup("gtao randomized high"), "1.00×", "{s}");
    }

    #[test]
    fn the_frontier_keeps_exactly_the_undominated_points() {
        // (ms, rmse). 0, 1 and 3 trade time for error; 2 is slower and worse than 1; 4 ties
        // 1's time with more error; 5 duplicates 3 (the first of equal points stays).
        let p = [
            (10.0, 0.08),
            (20.0, 0.06),
            (25.0, 0.07),
            (40.0, 0.05),
            (20.0, 0.065),
            (40.0, 0.05),
        ];
        let d = pareto(&p);
        assert_eq!(d, vec![None, None, Some(1), None, Some(1), Some(3)]);
        // Equal error and more time is beaten too; a single point is its own frontier.
        assert_eq!(pareto(&[(1.0, 0.1), (2.0, 0.1)]), vec![None, Some(0)]);
        assert_eq!(pareto(&[(3.0, 0.2)]), vec![None]);
    }

    #[test]
    fn splits_parse_and_refuse_what_is_not_a_split() {
        assert_eq!(parse_split("4x8"), Ok((4, 8)));
        assert_eq!(parse_split("2×16"), Ok((2, 16)));
        for bad in ["4", "x8", "4x", "ax8", "4x8x2", "-1x4"] {
            assert!(parse_split(bad).is_err(), "`{bad}` parsed");
        }
    }
}

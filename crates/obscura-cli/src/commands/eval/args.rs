//! The arguments of `obscura eval` (`EvalArgs`, with the choices of falloff, truth, sensor
//! and depth noise), the sample-split parser, and the checks that need no file or GPU.

use crate::options::{
    parse_denoise, parse_downsample, parse_resolution, parse_thickness, parse_upsampler,
    refuse_unused, EstimatorArg, Given, ModeArg, NormalSource, PresetArg, SampleArgs,
};
use crate::views::ViewArgs;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use obscura::{Denoise, DepthDownsample, Resolution, Upsampler};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FalloffArg {
    /// Any hit within the radius occludes (the usual definition of AO).
    None,
    /// A hit at distance t occludes by 1 − t²/R² (HBAO's weight).
    Quadratic,
}

impl EvalArgs {
    /// The thickness priors to run: --thickness, or the library's default.
    pub fn priors(&self) -> Vec<f32> {
        if self.thickness.is_empty() {
            vec![obscura::DEFAULT_THICKNESS]
        } else {
            self.thickness.clone()
        }
    }

    /// The guard bands to run, each once: --guard-bands in order.
    pub fn guards(&self) -> Vec<u32> {
        let mut v: Vec<u32> = Vec::new();
        for &g in &self.guard_bands {
            if !v.contains(&g) {
                v.push(g);
            }
        }
        v
    }

    /// Whether variants carry a guard-band label ("gN"): some band is above 0.
    pub fn guard_labels(&self) -> bool {
        self.guard_bands.iter().any(|&g| g > 0)
    }

    /// The march exponents to run: --march-exponents, or `None` for each variant's own
    /// (its preset's; even with --splits, --directions or --steps).
    pub fn exponents(&self) -> Option<Vec<f32>> {
        (!self.march_exponents.is_empty()).then(|| self.march_exponents.clone())
    }
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    #[command(flatten)]
    pub views: ViewArgs,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 400, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub height: u32,
    /// AO radius in scene units. Default: 3% of the scene's bounding-box diagonal.
    #[arg(long)]
    pub radius: Option<f32>,
    /// Rays per pixel of the ray-traced reference.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub rays: u32,
    /// How the reference weighs a hit within the radius.
    #[arg(long, value_enum, default_value_t = FalloffArg::None)]
    pub falloff: FalloffArg,
    /// Estimators to evaluate (comma-separated).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "gtao,hbao,vo,vao,sao,vo-area,bitmask"
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
    /// Thickness priors of the bitmask estimator (comma-separated, times the radius, or
    /// `inf`): with more than one, each bitmask variant runs with each, labelled "tT", and
    /// so does its screen-space reference. Other estimators ignore it. Default: the
    /// library's (`obscura::DEFAULT_THICKNESS`).
    #[arg(long, value_parser = parse_thickness, value_delimiter = ',')]
    pub thickness: Vec<f32>,
    /// March exponents of GTAO and the bitmask estimator (comma-separated, each in [1, 4];
    /// see `obscura::AoOptions::march_exponent`): with more than one, each of their variants
    /// runs with each, labelled "eE". Default: each variant's preset's (1.3 for high
    /// where the layout samples every 1 or 2 pixels), 1 with --splits, --directions or
    /// --steps.
    #[arg(long, value_delimiter = ',')]
    pub march_exponents: Vec<f32>,
    /// Guard bands, pixels on each side (comma-separated, 0 = none): each variant runs
    /// with each band, labelled "gN" when one is above 0, and so do the screen-space
    /// references. All of them, 0 included, read one raster of the view and the widest
    /// band (obscura-scene's `GBufferRenderer::render_guarded`, same pixel size), so that
    /// the bands differ by what they see, not by depth rounding (the orbit of --frames too).
    /// The truth and the pictures stay the view's. A renderer's clean depth, single-sampled
    /// or with --msaa (the multisampled depth then rasterized with the widest band).
    #[arg(long, value_delimiter = ',', default_value = "0", value_parser = clap::value_parser!(u32).range(0..=1024))]
    pub guard_bands: Vec<u32>,
    /// Also run each full-resolution bitmask variant with a finite --thickness with a
    /// second depth layer (`AoOptions::second_layer`), peeled from the view's raster at its
    /// prior (times the radius) behind the first (obscura-scene's `GBufferRenderer::peel`),
    /// labelled "L2", beside its one-layer twin; the bitmask's screen-space references
    /// likewise. The peel's own time is printed apart (a renderer's cost, not the AO's).
    /// With --frames, every frame of the orbit is peeled too. Clean single-sampled depth.
    #[arg(long)]
    pub second_layer: bool,
    /// Also score the bitmask estimator's screen-space limit with renderer layers,
    /// computed on the CPU from ray-traced layers (obscura-eval's `layers`): one layer
    /// infinitely thick, with the thickness prior (the first --thickness), with back-face
    /// thickness bounded by the prior, and two layers with the prior or so; each also with
    /// the largest --guard-bands band; march exponent 1. Rows
    /// "limit …", untimed; DIRECTIONSxSTEPS samples a pixel, no jitter (16x16 takes
    /// seconds a view and representation).
    #[arg(long, value_parser = parse_split, value_name = "DIRECTIONSxSTEPS")]
    pub layer_limits: Option<(u32, u32)>,
    /// --layer-limits with each pixel's directions jittered as the randomized layout's
    /// (its 4 × 4 patterns): what the bitmask estimator at those counts gives with each
    /// representation before a denoiser.
    #[arg(long, requires = "layer_limits")]
    pub layer_jitter: bool,
    /// Depth downsampling rules for the low resolutions (comma-separated).
    #[arg(long, value_parser = parse_downsample, value_delimiter = ',', default_value = "checkerboard")]
    pub downsamples: Vec<DepthDownsample>,
    /// Upsamplers for the low resolutions (comma-separated).
    #[arg(long, value_parser = parse_upsampler, value_delimiter = ',', default_value = "bilateral")]
    pub upsamplers: Vec<Upsampler>,
    /// Denoise choices (comma-separated; at full resolution too).
    #[arg(long, value_parser = parse_denoise, value_delimiter = ',', default_value = "none")]
    pub denoise: Vec<Denoise>,
    /// Write the views' cameras and AO radii to this JSON file and stop (no tracing, no
    /// AO): what another library needs to render the same views for --score-images. Per
    /// view: name, scene (path), eye, target, up, fov_y_deg, near, far, radius, width,
    /// height; world units are the scene file's.
    #[arg(long)]
    pub export_views: Option<std::path::PathBuf>,
    /// Folders of AO made elsewhere (another library, an older build), scored beside the
    /// variants against the same truth (comma-separated): each holds one image per view,
    /// `VIEW.png` (8- or 16-bit grey, 1 = white = unoccluded) or `VIEW.exr`, at --width ×
    /// --height. Each folder is a row "image NAME" (untimed; no screen-space reference).
    #[arg(long, value_delimiter = ',')]
    pub score_images: Vec<std::path::PathBuf>,
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
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
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
    /// Also score the bent normals of GTAO, HBAO and the bitmask (their single-frame variants, run once more with bent
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
    #[arg(long, value_delimiter = ',', default_value = "1", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub frames: Vec<u32>,
    /// Most frames the temporal history averages (with --frames > 1), 2..=256.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(2..=256))]
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
    /// Give obscura the ray tracer's depth (each pixel centre's exact linear depth, as
    /// `R32Float`) instead of the rasterized Depth32Float: what the depth format's
    /// precision costs each variant and reference. With obscura-scene's reversed-Z raster
    /// almost nothing (0.0001 on the standard views); the standard convention's steps,
    /// and the pixels where its depth test kept a hidden surface, cost 0.002–0.006
    /// (docs/thickness.md, "The depth buffer: reversed-Z"). Normals are the G-buffer's unless --normals reconstructs
    /// them (then from the traced depth). Single frames, without --sensor, --msaa,
    /// --second-layer, guard bands, --ssdo or --truth msaa4.
    #[arg(long, conflicts_with_all = ["sensor", "msaa", "second_layer", "ssdo"])]
    pub traced_depth: bool,
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
    /// The flags the command line gave (filled in after parsing).
    #[arg(skip)]
    pub given: Given,
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

/// Parses a sample split `DIRECTIONSxSTEPS` (`4x8`); the ranges are checked by `Ao::new`.
pub(super) fn parse_split(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected DIRECTIONSxSTEPS such as 4x8, got `{s}`");
    let (d, st) = s.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    Ok((
        d.trim().parse().map_err(|_| bad())?,
        st.trim().parse().map_err(|_| bad())?,
    ))
}

impl EvalArgs {
    /// `--normals`, or its default: the G-buffer's, reconstructed with `--sensor`.
    pub(super) fn normal_source(&self) -> NormalSource {
        self.normals.unwrap_or(match self.sensor {
            SensorArg::None => NormalSource::Gbuffer,
            _ => NormalSource::Reconstruct,
        })
    }

    /// Whether some `--frames` count accumulates (is above 1).
    /// The library's default frame for this run's input: a depth map's user (normals
    /// reconstructed from the depth) gets `DEPTH_MAP_ESTIMATOR`, a renderer's the default.
    pub(super) fn default_frame(&self) -> obscura::AoOptions {
        obscura::AoOptions {
            estimator: match self.normal_source() {
                NormalSource::Reconstruct => obscura::DEPTH_MAP_ESTIMATOR,
                NormalSource::Gbuffer => obscura::Estimator::default(),
            },
            ..Default::default()
        }
    }

    pub(super) fn temporal_run(&self) -> bool {
        self.frames.iter().any(|&f| f > 1)
    }
}

/// Validates the arguments that need no file or GPU (those of --ssdo are checked once the
/// views are known).
/// Each flag that would do nothing in this run, with the reason: refused, so that a flag
/// that is accepted does its job.
fn check_unused(a: &EvalArgs) -> Result<()> {
    let has = |e: EstimatorArg| a.estimators.contains(&e);
    let bitmask = has(EstimatorArg::Bitmask);
    let marching = bitmask || has(EstimatorArg::Gtao);
    let bent = marching || has(EstimatorArg::Hbao);
    let low = a.resolutions.iter().any(|r| *r != Resolution::Full) || !a.scales.is_empty();
    let accumulates = a.frames.iter().any(|&f| f > 1);
    let counts = !a.presets.is_empty() || !a.splits.is_empty();
    let pictures = a.report.is_some() && !a.no_pictures;
    let ssdo = "--ssdo runs GTAO at full resolution with the library's denoiser";
    refuse_unused(
        &a.given,
        &[
            (
                "thickness",
                !bitmask,
                "it is the bitmask's thickness prior (--estimators)",
            ),
            (
                "second_layer",
                !bitmask,
                "only the bitmask reads a second layer (--estimators)",
            ),
            (
                "march_exponents",
                !marching,
                "only gtao and the bitmask march their steps",
            ),
            (
                "downsamples",
                !low,
                "they apply below full resolution (--resolutions, --scales)",
            ),
            (
                "upsamplers",
                !low,
                "they apply below full resolution (--resolutions, --scales)",
            ),
            (
                "bent_normals",
                !bent,
                "only gtao, hbao and the bitmask have bent normals",
            ),
            (
                "history",
                !accumulates,
                "it is the length of an accumulation (--frames above 1)",
            ),
            (
                "orbit_step",
                !accumulates,
                "the orbit scores accumulated frames (--frames above 1)",
            ),
            (
                "sensor_noise",
                a.sensor == SensorArg::None,
                "it scales --sensor's noise",
            ),
            (
                "normals",
                a.msaa && a.normals == Some(NormalSource::Gbuffer),
                "--msaa reconstructs the normals from the resolved depth",
            ),
            ("preset", counts, "--presets or --splits give the samples"),
            (
                "directions",
                counts,
                "--presets or --splits give the samples",
            ),
            ("steps", counts, "--presets or --splits give the samples"),
            (
                "no_pictures",
                a.report.is_none(),
                "it leaves the pictures out of --report",
            ),
            ("picture_scale", !pictures, "it sizes --report's pictures"),
            ("estimators", a.ssdo, ssdo),
            ("resolutions", a.ssdo, ssdo),
            ("denoise", a.ssdo, ssdo),
        ],
    )
}

pub(super) fn check(a: &EvalArgs) -> Result<()> {
    check_unused(a)?;
    if a.width == 0 || a.height == 0 || a.width > 8192 || a.height > 8192 {
        bail!(
            "--width and --height must be in 1..=8192 (got {}x{})",
            a.width,
            a.height
        );
    }
    if a.traced_depth
        && (a.temporal_run() || a.guards().iter().any(|&g| g > 0) || a.truth != TruthArg::Centre)
    {
        bail!(
            "--traced-depth replaces the single-sampled raster of a still view: it takes \
             single frames, no guard band and --truth centre"
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
    if let Some(f) = a.frames.iter().find(|f| !(1..=1000).contains(*f)) {
        bail!("--frames must each be in 1..=1000 (got {f})");
    }
    if a.frames.is_empty() {
        bail!("--frames needs at least one count");
    }
    let temporal_run = a.temporal_run();
    if a.sensor != SensorArg::None && temporal_run {
        bail!(
            "--sensor evaluates single frames (its noise is drawn once, and the orbit \
             rasterizes clean depth)"
        );
    }
    if a.msaa && temporal_run {
        bail!("--msaa evaluates single frames (the orbit rasterizes single-sampled depth)");
    }
    if a.guard_bands.is_empty() {
        bail!("--guard-bands needs at least one value (0 for none)");
    }
    if a.guard_bands.iter().any(|&g| g > 0) && a.sensor != SensorArg::None {
        bail!(
            "--guard-bands evaluates a renderer's clean depth (not --sensor: a depth sensor sees nothing beyond its frame)"
        );
    }
    if a.second_layer && (a.msaa || a.sensor != SensorArg::None) {
        bail!("--second-layer evaluates clean single-sampled depth (not with --msaa or --sensor)");
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_split;

    #[test]
    fn splits_parse_and_refuse_what_is_not_a_split() {
        assert_eq!(parse_split("4x8"), Ok((4, 8)));
        assert_eq!(parse_split("2×16"), Ok((2, 16)));
        for bad in ["4", "x8", "4x", "ax8", "4x8x2", "-1x4"] {
            assert!(parse_split(bad).is_err(), "`{bad}` parsed");
        }
    }
}

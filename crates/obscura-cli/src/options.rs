//! Command-line option types shared by the subcommands (pass layout, estimator, preset and
//! sample counts, resolution, normal source) and their conversion to obscura's settings,
//! with the parsers of named and numeric option values.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use obscura::{
    AoMode, AoOptions, Denoise, DepthDownsample, Estimator, Preset, PyramidBuild, Resolution,
    Upsampler,
};

/// The AO pass layout (see `obscura::AoMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// One full-resolution pass, per-pixel patterns from a 4×4 table.
    Randomized,
    /// 2×2 deinterleaved layers, one pattern per layer.
    Deinterleaved2,
    /// 4×4 deinterleaved layers, one pattern per layer.
    Deinterleaved4,
}

impl From<ModeArg> for AoMode {
    fn from(m: ModeArg) -> Self {
        match m {
            ModeArg::Randomized => AoMode::Randomized,
            ModeArg::Deinterleaved2 => AoMode::Deinterleaved2,
            ModeArg::Deinterleaved4 => AoMode::Deinterleaved4,
        }
    }
}

/// The AO estimator (see `obscura::Estimator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EstimatorArg {
    /// Horizon-based AO (Bavoil et al. 2008).
    Hbao,
    /// Ground-Truth AO (Jimenez et al. 2016).
    Gtao,
    /// Volumetric Obscurance (Loos & Sloan 2010).
    Vo,
    /// Volumetric AO (Szirmay-Kalos et al. 2009).
    Vao,
    /// Scalable Ambient Obscurance (McGuire et al. 2012), depth-pyramid sampled.
    Sao,
    /// Volumetric Obscurance's area integral (Loos & Sloan 2010): depth mean and variance
    /// over each sample's share of the disk.
    VoArea,
    /// Visibility-bitmask AO (Therrien et al. 2023): GTAO's slices with sectors occluded
    /// between each sample's front and back (--thickness).
    Bitmask,
}

impl From<EstimatorArg> for Estimator {
    fn from(e: EstimatorArg) -> Self {
        match e {
            EstimatorArg::Hbao => Estimator::Hbao,
            EstimatorArg::Gtao => Estimator::Gtao,
            EstimatorArg::Vo => Estimator::Vo,
            EstimatorArg::Vao => Estimator::Vao,
            EstimatorArg::Sao => Estimator::Sao,
            EstimatorArg::VoArea => Estimator::VoArea,
            EstimatorArg::Bitmask => Estimator::Bitmask,
        }
    }
}

impl EstimatorArg {
    /// The argument naming `e` (every estimator has one; the default's if none did).
    pub fn of(e: Estimator) -> EstimatorArg {
        use clap::ValueEnum;
        EstimatorArg::value_variants()
            .iter()
            .copied()
            .find(|&a| Estimator::from(a) == e)
            .unwrap_or(EstimatorArg::Gtao)
    }
}

/// Quality presets (see `obscura::Preset`): samples per pixel 8, 16, 32, 96.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PresetArg {
    Low,
    Medium,
    High,
    Ultra,
}

impl From<PresetArg> for Preset {
    fn from(p: PresetArg) -> Self {
        match p {
            PresetArg::Low => Preset::Low,
            PresetArg::Medium => Preset::Medium,
            PresetArg::High => Preset::High,
            PresetArg::Ultra => Preset::Ultra,
        }
    }
}

/// The estimator and its sample counts, shared by `render` and `bench`.
#[derive(Debug, Args)]
pub struct QualityArgs {
    /// AO estimator. `render --depth` without this flag takes bitmask, the library's
    /// estimator for depth maps (obscura::DEPTH_MAP_ESTIMATOR).
    #[arg(long, value_enum, default_value_t = EstimatorArg::Gtao)]
    pub estimator: EstimatorArg,
    #[command(flatten)]
    pub samples: SampleArgs,
}

/// Preset and explicit sample counts, shared by every subcommand.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Quality preset: samples per pixel 8 (low), 16 (medium), 32 (high; GTAO and the bitmask
    /// 36 where the layout samples every 1 or 2 pixels: 3 slices × 6 steps crowded toward
    /// the centre), 96 (ultra). --directions and --steps override it, marching evenly.
    #[arg(long, value_enum, default_value_t = PresetArg::High)]
    pub preset: PresetArg,
    /// Directions (HBAO, VO, VAO, SAO) or slices (GTAO) per pixel (1..=64). Default: the preset's.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub directions: Option<u32>,
    /// Steps per direction (1..=64). Default: the preset's.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub steps: Option<u32>,
}

impl SampleArgs {
    /// `o` (its estimator, layout and resolution chosen) with the preset's directions,
    /// steps and march exponent for them (`AoOptions::with_preset`), then the explicit
    /// counts. Counts given by hand march evenly: the preset's exponent was chosen with
    /// its own counts (docs/thickness.md).
    pub fn apply(&self, o: AoOptions) -> AoOptions {
        let p = o.with_preset(self.preset.into());
        if self.directions.is_none() && self.steps.is_none() {
            return p;
        }
        AoOptions {
            directions: self.directions.unwrap_or(p.directions),
            steps: self.steps.unwrap_or(p.steps),
            march_exponent: obscura::EVEN_MARCH_EXPONENT,
            ..p
        }
    }
}

// One of the library's named choices (`T::ALL`, `T::name`), listing them on error.
use obscura::settings::by_name as named;

pub fn parse_resolution(s: &str) -> Result<Resolution, String> {
    named(&Resolution::ALL, Resolution::name, s)
}
/// A resolution, the continuous `scaled` included.
pub fn parse_resolution_or_scaled(s: &str) -> Result<Resolution, String> {
    let all = [
        Resolution::Full,
        Resolution::Half,
        Resolution::Quarter,
        Resolution::Scaled,
    ];
    named(&all, Resolution::name, s)
}
pub fn parse_downsample(s: &str) -> Result<DepthDownsample, String> {
    named(&DepthDownsample::ALL, DepthDownsample::name, s)
}
pub fn parse_upsampler(s: &str) -> Result<Upsampler, String> {
    named(&Upsampler::ALL, Upsampler::name, s)
}
pub fn parse_denoise(s: &str) -> Result<Denoise, String> {
    named(&Denoise::ALL, Denoise::name, s)
}

/// Mixed resolution (seeds 002, 004), shared by `render` and `bench`.
#[derive(Debug, Args)]
pub struct ResolutionArgs {
    /// AO resolution: full, half, quarter, or scaled (any --scale in [0.25, 1]; bilateral
    /// upsampling, denoise none or spatial).
    #[arg(long, value_parser = parse_resolution_or_scaled, default_value = "full")]
    pub resolution: Resolution,
    /// Working pixels per full-resolution pixel with --resolution scaled, in [0.25, 1].
    #[arg(long, default_value_t = 1.0)]
    pub scale: f32,
    /// Depth downsampling rule below full resolution: max, min, checkerboard, representative.
    #[arg(long, value_parser = parse_downsample, default_value = "checkerboard")]
    pub downsample: DepthDownsample,
    /// Upsampler below full resolution: bilinear, nearest-depth, classified, bilateral.
    #[arg(long, value_parser = parse_upsampler, default_value = "bilateral")]
    pub upsample: Upsampler,
    /// Filtering at the working resolution: none, spatial (edge-aware, one jitter period), box, tent.
    #[arg(long, value_parser = parse_denoise, default_value = "spatial")]
    pub denoise: Denoise,
    /// Depth pyramid (SAO, classified upsampler): auto (four levels per pass on GPUs, one
    /// on CPU adapters), one (one level per pass) or four (four levels per pass).
    #[arg(long, value_parser = parse_pyramid, default_value = "auto")]
    pub pyramid: PyramidBuild,
}

pub fn parse_pyramid(s: &str) -> Result<PyramidBuild, String> {
    named(
        &PyramidBuild::ALL,
        |p| match p {
            PyramidBuild::Auto => "auto",
            PyramidBuild::OneLevelPerPass => "one",
            PyramidBuild::FourLevelsPerPass => "four",
        },
        s,
    )
}

impl ResolutionArgs {
    /// `o` with these choices applied.
    pub fn apply(&self, o: AoOptions) -> AoOptions {
        AoOptions {
            resolution: self.resolution,
            downsample: self.downsample,
            upsample: self.upsample,
            denoise: self.denoise,
            pyramid: self.pyramid,
            ..o
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalSource {
    /// Use the G-buffer's geometric normals (what an engine would pass in).
    Gbuffer,
    /// Reconstruct normals from depth alone.
    Reconstruct,
}

/// Parses comma-separated finite numbers, naming the option `what` in errors.
pub fn parse_floats(s: &str, what: &str) -> Result<Vec<f32>> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{what} `{s}` is not a comma-separated list of numbers"))?;
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        bail!("{what} `{s}` contains {bad}; every value must be finite");
    }
    Ok(v)
}

/// A thickness prior (`obscura::AoParams::thickness`): a number > 0 (times the radius), or
/// `inf` (infinitely thick, GTAO's assumption).
pub fn parse_thickness(s: &str) -> std::result::Result<f32, String> {
    let t = match s.trim() {
        "inf" | "infinite" | "infinity" => f32::INFINITY,
        v => v
            .parse::<f32>()
            .map_err(|_| format!("`{v}` is not a number or `inf`"))?,
    };
    if t > 0.0 && !t.is_nan() {
        Ok(t)
    } else {
        Err(format!(
            "{s}: the thickness must be > 0 (times the radius) or `inf`"
        ))
    }
}

/// The flags given on the command line (clap ids, not defaults), filled in after parsing.
pub type Given = std::collections::BTreeSet<String>;

/// Refuses the first of `rules` (a flag's clap id, whether it does nothing for this input,
/// and why) whose flag was given: a flag that is accepted does its job.
pub fn refuse_unused(given: &Given, rules: &[(&str, bool, &str)]) -> anyhow::Result<()> {
    match rules
        .iter()
        .find(|(id, idle, _)| *idle && given.contains(*id))
    {
        Some((id, _, why)) => anyhow::bail!("--{} does nothing here: {why}", id.replace('_', "-")),
        None => Ok(()),
    }
}

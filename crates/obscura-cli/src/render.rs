//! `obscura render`: scene → G-buffer → AO → PNG.

use crate::output::{
    check_ao_path, check_png_path, check_vectors_path, save_ao, save_png, save_vectors,
};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use glam::Vec3;
use obscura::{
    layout, Ao, AoMode, AoOptions, AoParams, CameraMotion, Denoise, DepthDownsample, Estimator,
    GpuContext, Preset, PyramidBuild, Resolution, Upsampler,
};
use obscura_scene::{default_scene, Camera, CameraProjection, GBufferRenderer, Mesh};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProjectionKind {
    Perspective,
    Orthographic,
}

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
        }
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
    /// AO estimator.
    #[arg(long, value_enum, default_value_t = EstimatorArg::Gtao)]
    pub estimator: EstimatorArg,
    #[command(flatten)]
    pub samples: SampleArgs,
}

/// Preset and explicit sample counts, shared by every subcommand.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Quality preset: samples per pixel 8 (low), 16 (medium), 32 (high), 96 (ultra), the same
    /// for every estimator. --directions and --steps override it.
    #[arg(long, value_enum, default_value_t = PresetArg::High)]
    pub preset: PresetArg,
    /// Directions (HBAO, VO, VAO, SAO) or slices (GTAO) per pixel (1..=64). Default: the preset's.
    #[arg(long)]
    pub directions: Option<u32>,
    /// Steps per direction (1..=64). Default: the preset's.
    #[arg(long)]
    pub steps: Option<u32>,
}

impl SampleArgs {
    /// The preset's options for `estimator`, with explicit counts applied.
    pub fn options(&self, estimator: Estimator) -> AoOptions {
        let base = AoOptions::preset(estimator, self.preset.into());
        AoOptions {
            directions: self.directions.unwrap_or(base.directions),
            steps: self.steps.unwrap_or(base.steps),
            ..base
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

/// The axes of a normal map given with a depth map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalsFrame {
    /// The depth-camera convention of the intrinsics (OpenCV, Open3D, NYU, ScanNet, TUM):
    /// x right, y down, z into the scene; a surface facing the camera has z < 0.
    Opencv,
    /// obscura's view space (OpenGL): x right, y up, z towards the viewer; a surface facing
    /// the camera has z > 0.
    Opengl,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalSource {
    /// Use the G-buffer's geometric normals (what an engine would pass in).
    Gbuffer,
    /// Reconstruct normals from depth alone.
    Reconstruct,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (.glb, .gltf or .obj). Without it, the built-in courtyard scene is used.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Camera as EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z[,FOV_Y_DEG] in scene units.
    /// Default: the built-in scene's camera, or one that frames the whole file scene.
    #[arg(
        long,
        value_name = "EX,EY,EZ,TX,TY,TZ[,FOV]",
        allow_hyphen_values = true
    )]
    pub camera: Option<String>,
    /// Up vector X,Y,Z.
    #[arg(
        long,
        value_name = "X,Y,Z",
        default_value = "0,1,0",
        allow_hyphen_values = true
    )]
    pub up: String,
    /// Projection of the camera.
    #[arg(long, value_enum, default_value_t = ProjectionKind::Perspective)]
    pub projection: ProjectionKind,
    /// Vertical field of view in degrees (perspective), unless --camera gives one.
    #[arg(long, default_value_t = 60.0)]
    pub fov: f32,
    /// Height of the orthographic view volume in scene units. Default: fits the scene.
    #[arg(long)]
    pub ortho_height: Option<f32>,
    /// Near clip plane in scene units. Default: 1/10000 of the far plane.
    #[arg(long)]
    pub near: Option<f32>,
    /// Far clip plane in scene units. Default: just beyond the farthest scene corner.
    #[arg(long)]
    pub far: Option<f32>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// AO radius in scene units. Default: 3% of the scene's bounding-box diagonal.
    #[arg(long)]
    pub radius: Option<f32>,
    #[command(flatten)]
    pub quality: QualityArgs,
    /// AO pass layout: deinterleaved modes split the image into N×N layers (seed 000).
    #[arg(long, value_enum, default_value_t = ModeArg::Deinterleaved2)]
    pub mode: ModeArg,
    /// Deinterleaved modes: run the split and merge as separate full-resolution passes
    /// instead of fusing them into the prepare and AO passes (for measurement).
    #[arg(long)]
    pub unfused: bool,
    #[command(flatten)]
    pub resolution: ResolutionArgs,
    /// Tangent bias angle in degrees (0..60).
    #[arg(long, default_value_t = AoParams::default().bias_angle_deg)]
    pub bias: f32,
    /// Occlusion strength multiplier (0..=4).
    #[arg(long, default_value_t = AoParams::default().strength)]
    pub strength: f32,
    /// Clamp of the on-screen radius in pixels (1..=4096).
    #[arg(long, default_value_t = AoParams::default().max_radius_px)]
    pub max_radius_px: f32,
    /// Where the AO normals come from.
    #[arg(long, value_enum, default_value_t = NormalSource::Gbuffer)]
    pub normals: NormalSource,
    /// Rasterize the scene's depth with 4× MSAA and hand obscura the multisampled depth,
    /// which it resolves per pixel: the pixel-centre depth where all samples see one
    /// surface, the nearest sample on silhouettes. Normals are reconstructed from it.
    #[arg(long, conflicts_with = "depth")]
    pub msaa: bool,
    /// A captured depth map instead of a scene: 16-bit PNG or uint16 .npy (units set by the
    /// intrinsics' depth_scale, default millimetres), or float EXR / float16/32/64 .npy (scene
    /// units already: depth_scale is not applied), C or Fortran order. 0, NaN and infinite
    /// depths are missing data. Needs --intrinsics.
    #[arg(
        long,
        value_name = "FILE",
        requires = "intrinsics",
        conflicts_with = "scene"
    )]
    pub depth: Option<PathBuf>,
    /// The depth map's noise σ(z), which obscura fits planes over and does not read as
    /// occlusion: `auto` (estimated from the map's local plane-fit residuals, none when they
    /// are below 0.02 pixel footprints; integer maps at least their quantisation, step /
    /// √12, and the depth terraces they show, which the fit spans), `none`, `kinect`
    /// (structured light, 1.5 mm · z² with z in metres: use with depth in metres), or
    /// `C,L,Q` for σ = C + L·z + Q·z² in scene units. `kinect` and `C,L,Q` on an integer
    /// map also take its unit (the depth scale) as the terraces' step.
    #[arg(
        long,
        value_name = "MODEL",
        default_value = "auto",
        requires = "depth",
        allow_hyphen_values = true
    )]
    pub depth_noise: String,
    /// Normals for --depth instead of reconstructing them: unit view-space normals as a
    /// (height, width, 3 or 4) float .npy or an RGB(A) float EXR, in --normals-frame.
    /// Zero or non-finite normals are missing (view-space +z is used there).
    #[arg(long, value_name = "FILE", requires = "depth")]
    pub normals_file: Option<PathBuf>,
    /// The axes of --normals-file.
    #[arg(long, value_enum, default_value_t = NormalsFrame::Opencv, requires = "normals_file")]
    pub normals_frame: NormalsFrame,
    /// Pinhole intrinsics of --depth as JSON: fx, fy, cx, cy (pixels, OpenCV convention),
    /// width, height, and optionally depth_scale (scene units per stored unit; 0.001).
    #[arg(long, value_name = "JSON", requires = "depth")]
    pub intrinsics: Option<PathBuf>,
    /// Output AO: .png (8-bit grey) or .npy (float32, for computing with it); 1 / white =
    /// unoccluded.
    #[arg(long, default_value = "ao.png")]
    pub out: PathBuf,
    /// Bits per sample of a PNG --out: 8, or 16 for anyone who computes with the AO (.npy
    /// and .exr are float32).
    #[arg(long, default_value_t = 8, value_parser = parse_bits)]
    pub bits: u8,
    /// Also write a linear-depth visualization PNG (near = bright, sky = black).
    #[arg(long, value_name = "FILE")]
    pub depth_out: Option<PathBuf>,
    /// Also write a view-space normal visualization PNG (xyz * 0.5 + 0.5).
    #[arg(long, value_name = "FILE")]
    pub normals_out: Option<PathBuf>,
    /// Also write the bent normals of GTAO or HBAO (view space, unit, the cosine-weighted mean unoccluded
    /// direction; full resolution, or the working one with --denoise box|tent): .png (8-bit
    /// RGB of xyz * 0.5 + 0.5, black on sky), .npy (float32, height × width × 3) or .exr
    /// (float32 RGB = xyz).
    #[arg(long, value_name = "FILE")]
    pub bent_normals_out: Option<PathBuf>,
    /// Timed AO runs after one warm-up run; the median is reported (single frames).
    #[arg(long, default_value_t = 5)]
    pub runs: u32,
    /// Frames to record with temporal accumulation (1: a single frame, no history): a still
    /// camera, or the --orbit path. Per-frame and total times are reported.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Most frames the temporal history averages (with --frames > 1), 2..=256.
    #[arg(long, default_value_t = 16)]
    pub history: u32,
    /// Orbit the camera this many degrees about the vertical axis through its target over
    /// the frames, writing one PNG per frame to --out-dir.
    #[arg(
        long,
        value_name = "DEGREES",
        requires = "out_dir",
        allow_hyphen_values = true
    )]
    pub orbit: Option<f32>,
    /// Folder for the --orbit frames (frame_0000.png, ...); created if missing.
    #[arg(long, value_name = "DIR", requires = "orbit")]
    pub out_dir: Option<PathBuf>,
    /// Hold this many milliseconds per AO frame over the --orbit, by the --budget-control
    /// knob; overrides --resolution (and, with the ladder, the preset). Prints each frame's
    /// time and scale or level and writes budget.csv and budget.svg to --out-dir.
    #[arg(long, value_name = "MS", requires = "orbit")]
    pub budget_ms: Option<f64>,
    /// What --budget-ms turns: `joint`, the working scale in [0.25, top] at the preset
    /// given and above it full resolution at the medium, high and ultra presets
    /// (`obscura::budget::JointController`; the top is where the scaled AO costs what full
    /// medium does, measured on the first view); `scale`, the working scale alone in
    /// [0.25, 1] (`obscura::budget::ScaleController`, the preset as given); or `ladder`,
    /// eleven levels of resolution × preset, quarter low .. full ultra
    /// (`obscura::budget::BudgetController`).
    #[arg(long, value_enum, default_value_t = BudgetControl::Joint, requires = "budget_ms")]
    pub budget_control: BudgetControl,
    /// Also write screen-space directional occlusion with one diffuse bounce (obscura's
    /// `Ssdo`): the scene's albedo (glTF base colour factors, OBJ `Kd`) lit by --env
    /// through the AO's bent normals (GTAO, HBAO; the normal otherwise), plus the light
    /// its occluders bounce. .png (sRGB, clamped at 1) or .exr (linear float RGB).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["depth", "msaa", "orbit"])]
    pub ssdo: Option<PathBuf>,
    /// The environment of --ssdo: sky (a daylight gradient), white, constant:R,G,B,
    /// gradient:R,G,B:R,G,B (zenith, nadir), or an equirectangular .hdr or .exr file (row 0
    /// the zenith, +y; the left edge facing +x, columns turning toward +z).
    #[arg(long, default_value = "sky", requires = "ssdo")]
    pub env: String,
}

/// The knob of `render --budget-ms`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BudgetControl {
    Joint,
    Scale,
    Ladder,
}

fn parse_bits(s: &str) -> Result<u8, String> {
    match s.trim() {
        "8" => Ok(8),
        "16" => Ok(16),
        _ => Err(format!("expected 8 or 16, got `{s}`")),
    }
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

/// Validates every argument that needs no file or GPU.
pub(crate) fn check_args(a: &RenderArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 {
        bail!(
            "--width and --height must be at least 1 (got {}x{})",
            a.width,
            a.height
        );
    }
    if a.runs == 0 || a.runs > 1000 {
        bail!("--runs must be in 1..=1000 (got {})", a.runs);
    }
    if a.frames == 0 || a.frames > 100_000 {
        bail!("--frames must be in 1..=100000 (got {})", a.frames);
    }
    if let Some(d) = a.orbit {
        if !d.is_finite() || d.abs() > 36000.0 {
            bail!("--orbit must be a finite number of degrees within ±36000 (got {d})");
        }
        if a.depth.is_some() {
            bail!("--orbit needs a scene (a depth map has one camera)");
        }
        if a.msaa {
            bail!("--msaa renders a still camera; --orbit rasterizes single-sampled G-buffers");
        }
    }
    if let Some(b) = a.budget_ms {
        if !(b.is_finite() && b > 0.0 && b <= 1e6) {
            bail!("--budget-ms must be a number of milliseconds in (0, 1e6] (got {b})");
        }
    }
    check_ao_path(&a.out)?;
    for p in [&a.depth_out, &a.normals_out].into_iter().flatten() {
        check_png_path(p)?;
    }
    if let Some(p) = &a.bent_normals_out {
        if !Estimator::from(a.quality.estimator).has_bent_normals() {
            bail!(
                "--bent-normals-out needs --estimator gtao or hbao (bent normals come from their horizons)"
            );
        }
        if a.orbit.is_some() {
            bail!("--bent-normals-out writes one frame; it does not go with --orbit");
        }
        check_vectors_path(p)?;
    }
    if let Some(p) = &a.ssdo {
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("png" | "exr")) {
            bail!("--ssdo writes .png or .exr, got `{}`", p.display());
        }
        if a.resolution.resolution != obscura::Resolution::Full {
            bail!("--ssdo reads the AO's full-resolution depth and normals: use --resolution full");
        }
    }
    options(a).validate()?;
    params(a, 1.0).validate()?;
    if a.resolution.scale != 1.0 && a.resolution.resolution != Resolution::Scaled {
        bail!(
            "--scale {} needs --resolution scaled (the other resolutions have fixed scales)",
            a.resolution.scale
        );
    }
    if let Some(r) = a.radius {
        if !(r.is_finite() && r > 0.0) {
            bail!("--radius must be a finite number > 0 (got {r})");
        }
    }
    Ok(())
}

pub(crate) fn options(a: &RenderArgs) -> AoOptions {
    a.resolution.apply(AoOptions {
        mode: a.mode.into(),
        fused: !a.unfused,
        history: if a.frames > 1 || a.orbit.is_some() {
            a.history
        } else {
            0
        },
        bent_normals: a.bent_normals_out.is_some()
            || (a.ssdo.is_some() && Estimator::from(a.quality.estimator).has_bent_normals()),
        ..a.quality.samples.options(a.quality.estimator.into())
    })
}

pub(crate) fn params(a: &RenderArgs, radius: f32) -> AoParams {
    AoParams {
        radius,
        bias_angle_deg: a.bias,
        strength: a.strength,
        max_radius_px: a.max_radius_px,
        scale: a.resolution.scale,
        ..Default::default()
    }
}

/// The camera from the arguments, the built-in scene, or framing the bounds.
fn camera(a: &RenderArgs, builtin: bool, mesh: &Mesh) -> Result<Camera> {
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let up = parse_floats(&a.up, "--up")?;
    if up.len() != 3 {
        bail!("--up needs 3 numbers, got {}", up.len());
    }
    let mut fov = a.fov;
    let mut cam = match &a.camera {
        Some(s) => {
            let v = parse_floats(s, "--camera")?;
            if v.len() != 6 && v.len() != 7 {
                bail!(
                    "--camera needs 6 or 7 numbers (eye, target, optional fov), got {}",
                    v.len()
                );
            }
            if let Some(&f) = v.get(6) {
                fov = f;
            }
            let mut c = Camera {
                eye: Vec3::new(v[0], v[1], v[2]),
                target: Vec3::new(v[3], v[4], v[5]),
                up: Vec3::from_slice(&up),
                projection: CameraProjection::Perspective { fov_y_deg: fov },
                near: 0.0,
                far: 0.0,
            };
            c.fit_clip_planes(&bounds);
            c
        }
        None if builtin => default_scene::camera(),
        None => Camera::framing(&bounds, CameraProjection::Perspective { fov_y_deg: fov }),
    };
    cam.up = Vec3::from_slice(&up);
    cam.projection = match a.projection {
        ProjectionKind::Perspective => match (&a.camera, builtin) {
            (None, true) if a.fov == 60.0 => cam.projection,
            _ => CameraProjection::Perspective { fov_y_deg: fov },
        },
        ProjectionKind::Orthographic => CameraProjection::Orthographic {
            height: a.ortho_height.unwrap_or_else(|| {
                // Match the perspective view's extent at the target distance.
                2.0 * (cam.target - cam.eye).length() * (0.5 * fov.to_radians()).tan()
            }),
        },
    };
    if a.projection == ProjectionKind::Orthographic {
        // An orthographic camera sees everything in its slab: keep near small but positive.
        cam.fit_clip_planes(&bounds);
    }
    if let Some(n) = a.near {
        cam.near = n;
    }
    if let Some(f) = a.far {
        cam.far = f;
    }
    cam.validate()?;
    Ok(cam)
}

/// Records one warm-up frame (shader compilation), then `--runs` timed single frames or
/// `--frames` accumulated frames, prints the times, and returns the AO output. Shared by
/// the scene and the depth-map paths.
pub(crate) fn record_timed(
    a: &RenderArgs,
    ctx: &GpuContext,
    ao: &mut Ao,
    input: &obscura::AoInput<'_>,
    params: &AoParams,
) -> Result<Vec<f32>> {
    let mut times = Vec::new();
    let first = Instant::now();
    ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, input, params))?;
    eprintln!(
        "ao: first run {:.1} ms (includes shader compilation)",
        first.elapsed().as_secs_f64() * 1e3
    );
    // With temporal accumulation the warm-up frame is not part of the image, and the frames
    // sample as an `obscura::depth_map::Renderer` call's do.
    ao.restart();
    let timed = if a.frames > 1 { a.frames } else { a.runs };
    let total = Instant::now();
    for _ in 0..timed {
        let t = Instant::now();
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, input, params))?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    if a.frames > 1 {
        eprintln!(
            "ao: {} accumulated frames (history {}), median {:.2} ms per frame, {:.1} ms in all",
            a.frames,
            ao.options().history,
            median_ms(times),
            total.elapsed().as_secs_f64() * 1e3
        );
    } else {
        eprintln!(
            "ao: median {:.2} ms over {} runs (wall clock around submit + wait)",
            median_ms(times),
            a.runs
        );
    }
    let out = ao.output().context("AO output missing after a run")?;
    Ok(ctx.read_f32(out)?)
}

/// The last frame's bent normals and their size (full, or the AO's working resolution after
/// the box or tent filter).
pub(crate) fn read_bent_normals(ctx: &GpuContext, ao: &Ao) -> Result<(Vec<[f32; 3]>, u32, u32)> {
    let t = ao
        .bent_normals()
        .context("bent normals missing after a run")?;
    let v = ctx.read_f32(t)?;
    let bent = v.chunks_exact(4).map(|c| [c[0], c[1], c[2]]).collect();
    Ok((bent, t.width(), t.height()))
}

fn median_ms(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `obscura render` of a scene (the built-in one without --scene); arguments checked by
/// [`check_args`].
pub fn run(a: &RenderArgs) -> Result<()> {
    let t0 = Instant::now();
    // The environment first: a bad --env fails before any output is written.
    let env = a
        .ssdo
        .as_ref()
        .map(|_| crate::ssdo::parse_env(&a.env))
        .transpose()?;
    let (mesh, name) = match &a.scene {
        Some(p) => (
            Mesh::load(p).with_context(|| format!("cannot load scene `{}`", p.display()))?,
            p.display().to_string(),
        ),
        None => (default_scene::mesh(), "built-in courtyard".to_string()),
    };
    let cam = camera(a, a.scene.is_none(), &mesh)?;
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let radius = a.radius.unwrap_or(0.03 * bounds.diagonal());
    eprintln!(
        "scene: {name}: {} triangles, loaded in {:.0} ms",
        mesh.triangle_count(),
        t0.elapsed().as_secs_f64() * 1e3
    );

    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let t = Instant::now();
    let raster = GBufferRenderer::new(&ctx.device);
    let gpu_mesh = raster.upload(&ctx, &mesh)?;
    let (gbuffer, msaa_depth);
    let input = if a.msaa {
        msaa_depth = raster.render_msaa_depth(&ctx, &gpu_mesh, &cam, a.width, a.height)?;
        gbuffer = None;
        msaa_depth.ao_input(&cam)
    } else {
        gbuffer = Some(raster.render(&ctx, &gpu_mesh, &cam, a.width, a.height)?);
        let g = gbuffer.as_ref().context("no G-buffer")?;
        g.ao_input(&cam, a.normals == NormalSource::Gbuffer)
    };
    eprintln!(
        "g-buffer: {}x{}{} in {:.1} ms (includes pipeline creation)",
        a.width,
        a.height,
        if a.msaa {
            ", depth only, 4x MSAA (obscura resolves it; normals reconstructed)"
        } else {
            ""
        },
        t.elapsed().as_secs_f64() * 1e3
    );

    let options = options(a);
    let params = params(a, radius);
    let mut ao = Ao::new(&ctx.device, options)?;
    let frame = ao.validate(&input, &params)?;
    eprintln!(
        "ao: {} {} directions x {} steps ({} samples/pixel), {}{}, radius {radius:.3} scene units",
        options.estimator.name(),
        options.directions,
        options.steps,
        options.samples_per_pixel(),
        options.mode.name(),
        if options.fused { "" } else { " (unfused)" },
    );
    if !options.direct() {
        eprintln!(
            "ao: {} resolution, downsample {}, upsample {}, denoise {}",
            options.resolution.name(),
            options.downsample.name(),
            options.upsample.name(),
            options.denoise.name()
        );
    }
    if let (Some(degrees), Some(dir), Some(budget)) = (a.orbit, &a.out_dir, a.budget_ms) {
        let run = match a.budget_control {
            BudgetControl::Joint => crate::budget::orbit_joint,
            BudgetControl::Scale => crate::budget::orbit_scaled,
            BudgetControl::Ladder => crate::budget::orbit,
        };
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
        let orbit = crate::budget::Orbit {
            a,
            ctx: &ctx,
            raster: &raster,
            mesh: &gpu_mesh,
            cam: &cam,
            degrees,
            dir,
            timing: obscura::Timing::best_for(&ctx),
            previous: None,
        };
        return run(orbit, options, &params, budget);
    }
    if let (Some(degrees), Some(dir)) = (a.orbit, &a.out_dir) {
        return orbit(
            a, &ctx, &raster, &gpu_mesh, &cam, &mut ao, &params, degrees, dir, t0,
        );
    }
    let values = record_timed(a, &ctx, &mut ao, &input, &params)?;
    save_ao(&a.out, &values, a.width, a.height, a.bits)?;
    eprintln!("wrote {}", a.out.display());
    if let Some(path) = &a.bent_normals_out {
        let (bent, w, h) = read_bent_normals(&ctx, &ao)?;
        save_vectors(path, &bent, w, h)?;
        eprintln!("wrote {} ({w}x{h})", path.display());
    }
    if let (Some(path), Some(g), Some(env)) = (&a.ssdo, &gbuffer, &env) {
        let lighting = crate::ssdo::lighting(&env.irradiance_sh(), &cam);
        let options = obscura::SsdoOptions::default();
        let (rgb, ms) = crate::ssdo::shade(&ctx, &ao, g, &frame, &lighting, options, a.runs)?;
        eprintln!(
            "ssdo: env {}, bounce {} slices × {} steps per pixel over {}×{} pixel classes + merge: median {ms:.2} ms over {} runs (after the AO)",
            a.env,
            options.directions,
            options.steps,
            options.period,
            options.period,
            a.runs
        );
        crate::ssdo::save_radiance(path, &rgb, a.width, a.height)?;
        eprintln!("wrote {}", path.display());
    }

    if a.depth_out.is_some() || a.normals_out.is_some() {
        let prepared = read_prepared(&ctx, &ao, &input, &params, a.width, a.height)?;
        if let Some(path) = &a.depth_out {
            save_png(
                path,
                &depth_visual(&prepared),
                a.width,
                a.height,
                image::ExtendedColorType::L8,
            )?;
            eprintln!("wrote {}", path.display());
        }
        if let Some(path) = &a.normals_out {
            let rgb: Vec<u8> = prepared
                .chunks_exact(4)
                .flat_map(|p| {
                    let sky = p[0] <= 0.0;
                    [p[1], p[2], p[3]].map(|c| {
                        if sky {
                            0
                        } else {
                            ((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8
                        }
                    })
                })
                .collect();
            save_png(
                path,
                &rgb,
                a.width,
                a.height,
                image::ExtendedColorType::Rgb8,
            )?;
            eprintln!("wrote {}", path.display());
        }
    }
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// `render --orbit`: the camera turns `degrees` about the vertical axis through its target
/// over `--frames` frames; each frame's G-buffer is rasterized, its AO recorded with the
/// camera motion (temporal accumulation reprojects the history) and written as a PNG.
#[allow(clippy::too_many_arguments)]
fn orbit(
    a: &RenderArgs,
    ctx: &GpuContext,
    raster: &GBufferRenderer,
    mesh: &obscura_scene::GpuMesh,
    cam: &Camera,
    ao: &mut Ao,
    params: &AoParams,
    degrees: f32,
    dir: &std::path::Path,
    t0: Instant,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create `{}`", dir.display()))?;
    let n = a.frames;
    let mut times = Vec::with_capacity(n as usize);
    let mut previous: Option<Camera> = None;
    for k in 0..n {
        let c = cam.orbit(orbit_turn(degrees, k, n));
        let g = raster.render(ctx, mesh, &c, a.width, a.height)?;
        let input = g.ao_input(&c, a.normals == NormalSource::Gbuffer);
        let p = AoParams {
            motion: previous.map_or(CameraMotion::Cut, |prev| c.motion_since(&prev)),
            ..*params
        };
        let t = Instant::now();
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
        let values = ctx.read_f32(ao.output().context("AO output missing after a run")?)?;
        let path = dir.join(format!("frame_{k:04}.png"));
        save_ao(&path, &values, a.width, a.height, a.bits)?;
        previous = Some(c);
        progress(k + 1, n, &path);
    }
    eprintln!();
    eprintln!(
        "ao: {n} frames orbiting {degrees}°, median {:.2} ms per frame (the first includes \
         shader compilation); wrote {}",
        median_ms(times),
        dir.display()
    );
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// The camera's turn in degrees at frame `k` of `n` of an orbit of `degrees`: evenly from 0
/// at the first frame to `degrees` at the last.
pub(crate) fn orbit_turn(degrees: f32, k: u32, n: u32) -> f32 {
    if n > 1 {
        degrees * k as f32 / (n - 1) as f32
    } else {
        0.0
    }
}

/// One line of progress on stderr, redrawn in place: `[=====     ] 5/10 path`.
pub(crate) fn progress(done: u32, total: u32, what: &std::path::Path) {
    let width = 30;
    let filled = (done as usize * width) / total.max(1) as usize;
    eprint!(
        "\r[{}{}] {done}/{total} {}",
        "=".repeat(filled),
        " ".repeat(width - filled),
        what.display()
    );
}

/// AO in [0, 1] as 8-bit gray (white = unoccluded).
/// The prepared `vec4(depth, normal)` buffer at full resolution: read directly, or
/// re-interleaved on the CPU from the deinterleaved layers (fused modes keep no full copy),
/// or, below full resolution without a full-resolution copy, prepared once more by a
/// full-resolution single pass.
fn read_prepared(
    ctx: &GpuContext,
    ao: &Ao,
    input: &obscura::AoInput<'_>,
    params: &AoParams,
    w: u32,
    h: u32,
) -> Result<Vec<f32>> {
    if let Some(view) = ao.prepared_view() {
        return Ok(ctx.read_f32(view.texture())?);
    }
    if ao.options().resolution != Resolution::Full {
        let mut full = Ao::new(
            &ctx.device,
            AoOptions {
                mode: AoMode::Randomized,
                resolution: Resolution::Full,
                denoise: Denoise::None,
                ..*ao.options()
            },
        )?;
        ctx.run(|enc| full.record(&ctx.device, &ctx.queue, enc, input, params))?;
        let view = full
            .prepared_view()
            .context("full-resolution prepared buffer missing")?;
        return Ok(ctx.read_f32(view.texture())?);
    }
    let view = ao
        .prepared_layers_view()
        .context("prepared buffer missing")?;
    let layers = ctx.read_f32(view.texture())?;
    let n = ao.options().mode.split();
    let (lw, lh) = layout::layer_size(w, h, n);
    let mut out = vec![0.0; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            let (tx, ty) = layout::layer_texel(x, y, n);
            let src = (((layout::layer_of(x, y, n) * lh + ty) * lw + tx) * 4) as usize;
            let dst = ((y * w + x) * 4) as usize;
            out[dst..dst + 4].copy_from_slice(&layers[src..src + 4]);
        }
    }
    Ok(out)
}

/// Log-scaled linear depth: nearest surface white, farthest dark grey, sky black.
fn depth_visual(prepared: &[f32]) -> Vec<u8> {
    let depths = prepared.chunks_exact(4).map(|p| p[0]);
    let (lo, hi) = depths
        .clone()
        .filter(|d| *d > 0.0)
        .fold((f32::INFINITY, 0.0f32), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        });
    let span = (hi / lo).ln().max(1e-6);
    depths
        .map(|d| {
            if d <= 0.0 {
                0
            } else {
                (255.0 - 215.0 * ((d / lo).ln() / span)).round() as u8
            }
        })
        .collect()
}

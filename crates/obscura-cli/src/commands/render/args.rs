//! The arguments of `obscura render` (`RenderArgs`), their checks, and the AO options and
//! parameters they give; shared by the scene, depth-map and orbit paths.

use crate::options::{refuse_unused, Given, ModeArg, NormalSource, QualityArgs, ResolutionArgs};
use crate::output::{check_ao_path, check_png_path, check_vectors_path};
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use obscura::{AoOptions, AoParams, Estimator, Resolution};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProjectionKind {
    Perspective,
    Orthographic,
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
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=65536))]
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
    /// The bitmask estimator's thickness prior: how deep every surface is taken to be
    /// behind the depth seen, times the radius (> 0, or `inf`). Other estimators ignore it.
    #[arg(long, value_parser = crate::options::parse_thickness, default_value_t = AoParams::default().thickness)]
    pub thickness: f32,
    /// GTAO's and the bitmask estimator's march exponent (1..=4): 1 spaces steps evenly,
    /// 2 puts them closer near the centre. Other estimators ignore it. Default: the
    /// preset's (1.3 for high where the layout samples every 1 or 2 pixels), 1 with
    /// --directions or --steps.
    #[arg(long)]
    pub march_exponent: Option<f32>,
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
    /// Rasterize the scene this many pixels beyond each side of the image (same pixel size,
    /// a wider view) and let the AO read that depth: occluders just off-screen then darken
    /// the image's edges, as they do inside it. The output keeps --width × --height.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 0,
        value_parser = clap::value_parser!(u32).range(0..=1024),
        conflicts_with_all = ["depth", "orbit", "depth_out", "normals_out", "bent_normals_out"]
    )]
    pub guard_band: u32,
    /// Peel a second depth layer (the nearest front face at least --thickness × the radius
    /// behind the first) and let the bitmask estimator read it where the first layer hides
    /// it (`AoOptions::second_layer`): what stands behind a thin foreground object then
    /// occludes too. Needs `--estimator bitmask` at full resolution and a finite --thickness.
    #[arg(
        long,
        conflicts_with_all = ["depth", "msaa", "orbit", "ssdo"]
    )]
    pub second_layer: bool,
    /// The setting for a renderer that peels a second layer and draws a guard band
    /// (`obscura::AoOptions::layered`): `--estimator bitmask --second-layer --thickness 0.75
    /// --directions 3 --steps 7 --march-exponent 1.3 --guard-band 16`, each of them still
    /// yours to give.
    #[arg(
        long,
        conflicts_with_all = ["depth", "msaa", "orbit", "ssdo", "depth_out", "normals_out", "bent_normals_out"]
    )]
    pub layered: bool,
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
    /// Also write a linear-depth visualization PNG (near = bright, sky = black) of the depth
    /// the AO read: the scene's G-buffer, or the depth map (after its noise model's plane
    /// fits, if any).
    #[arg(long, value_name = "FILE")]
    pub depth_out: Option<PathBuf>,
    /// Also write a view-space normal visualization PNG (xyz * 0.5 + 0.5) of the normals the
    /// AO read: the G-buffer's, the --normals-file's, or those reconstructed from depth.
    #[arg(long, value_name = "FILE")]
    pub normals_out: Option<PathBuf>,
    /// Also write the bent normals of GTAO, HBAO or the bitmask (view space, unit, the cosine-weighted mean unoccluded
    /// direction; full resolution, or the working one with --denoise box|tent): .png (8-bit
    /// RGB of xyz * 0.5 + 0.5, black on sky), .npy (float32, height × width × 3) or .exr
    /// (float32 RGB = xyz).
    #[arg(long, value_name = "FILE")]
    pub bent_normals_out: Option<PathBuf>,
    /// Timed AO runs after one warm-up run; the median is reported (single frames).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Frames to record with temporal accumulation (1: a single frame, no history): a still
    /// camera, or the --orbit path. Per-frame and total times are reported.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100000))]
    pub frames: u32,
    /// Most frames the temporal history averages (with --frames > 1), 2..=256.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(2..=256))]
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
    /// given and above it full resolution from the medium preset to ultra, with rungs of
    /// more slices and steps between high and ultra
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
    /// The flags the command line gave (filled in after parsing).
    #[arg(skip)]
    pub given: Given,
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

/// `--layered`: `obscura::AoOptions::layered` and its prior and band, for each of its
/// flags the command line did not give (`a.given`). Samples only where no --preset,
/// --directions or --steps was given.
pub fn apply_layered(a: &mut RenderArgs) {
    let o = AoOptions::layered();
    let given = |id: &str| a.given.contains(id);
    if !given("estimator") {
        a.quality.estimator = crate::options::EstimatorArg::of(o.estimator);
    }
    a.second_layer = true;
    if !given("thickness") {
        a.thickness = obscura::LAYERED_THICKNESS;
    }
    if !(given("preset") || given("directions") || given("steps")) {
        a.quality.samples.directions = Some(o.directions);
        a.quality.samples.steps = Some(o.steps);
    }
    if !given("march_exponent") {
        a.march_exponent = Some(o.march_exponent);
    }
    if !given("guard_band") {
        a.guard_band = obscura::LAYERED_GUARD_BAND;
    }
}

/// Each flag that would do nothing for this input, with the reason: refused, so that a
/// flag that is accepted does its job.
fn check_unused(a: &RenderArgs) -> Result<()> {
    let e = Estimator::from(a.quality.estimator);
    let depth = a.depth.is_some();
    let full = a.resolution.resolution == Resolution::Full;
    let ortho = a.projection == ProjectionKind::Orthographic;
    let frames = a.frames > 1 || a.orbit.is_some();
    let camera_fov = a
        .camera
        .as_deref()
        .is_some_and(|c| c.split(',').count() == 7);
    let png = a
        .out
        .extension()
        .is_some_and(|x| x.eq_ignore_ascii_case("png"));
    let pyramid = e.uses_pyramid()
        || e.uses_moments()
        || (!full && a.resolution.upsample == obscura::Upsampler::Classified);
    let camera = "a depth map's camera is its --intrinsics";
    refuse_unused(
        &a.given,
        &[
            ("camera", depth, camera),
            ("up", depth, camera),
            ("projection", depth, camera),
            ("fov", depth, camera),
            ("ortho_height", depth, camera),
            ("near", depth, camera),
            ("far", depth, camera),
            ("width", depth, "a depth map's AO has the map's size"),
            ("height", depth, "a depth map's AO has the map's size"),
            ("normals", depth, "a depth map's normals are --normals-file's, or made from its depth"),
            ("normals", a.msaa && a.normals == NormalSource::Gbuffer, "--msaa reconstructs the normals from the resolved depth"),
            ("fov", ortho, "it is a perspective camera's; --ortho-height sizes an orthographic one"),
            ("fov", camera_fov, "--camera's seventh value gives the field of view"),
            ("ortho_height", !ortho, "it sizes an orthographic view (--projection orthographic)"),
            ("bias", !matches!(e, Estimator::Hbao | Estimator::Sao), "it is the tangent bias of hbao and sao"),
            ("thickness", e != Estimator::Bitmask, "it is the bitmask's thickness prior"),
            ("march_exponent", !matches!(e, Estimator::Gtao | Estimator::Bitmask), "only gtao and the bitmask march their steps"),
            ("pyramid", !pyramid, "only sao, vo-area and the classified upsampler read a depth pyramid"),
            ("downsample", full, "it applies below full resolution (--resolution)"),
            ("upsample", full, "it applies below full resolution (--resolution)"),
            ("unfused", a.mode == ModeArg::Randomized && full, "at full resolution the randomized layout has no split, merge or downsample to fuse"),
            ("history", !frames, "it is the length of --frames' or --orbit's accumulation"),
            ("runs", frames, "--frames and --orbit time each of their own frames"),
            ("bits", !png, "it sets a PNG's bit depth; .npy and .exr are float32"),
            ("normals_frame", a.normals_file.is_none(), "it gives the axes of --normals-file"),
            ("env", a.ssdo.is_none(), "it is the environment --ssdo lights the scene with"),
            ("out_dir", a.orbit.is_none(), "it holds --orbit's frames"),
            ("depth_out", a.orbit.is_some(), "it writes one frame; --orbit writes its frames alone"),
            ("normals_out", a.orbit.is_some(), "it writes one frame; --orbit writes its frames alone"),
        ],
    )
}

/// Validates every argument that needs no file or GPU.
pub(crate) fn check_args(a: &RenderArgs) -> Result<()> {
    check_unused(a)?;
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
    if a.second_layer && !a.thickness.is_finite() {
        bail!(
            "--second-layer is peeled --thickness radii behind the first layer and is a solid \
             that deep: it needs a finite --thickness (got {})",
            a.thickness
        );
    }
    check_ao_path(&a.out)?;
    for p in [&a.depth_out, &a.normals_out].into_iter().flatten() {
        check_png_path(p)?;
    }
    if let Some(p) = &a.bent_normals_out {
        if !Estimator::from(a.quality.estimator).has_bent_normals() {
            bail!(
                "--bent-normals-out needs --estimator gtao, hbao or bitmask (bent normals come from their horizons)"
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
    options_at(a, a.resolution.resolution)
}

/// The options of `a` at `resolution` instead of its own, with the samples the preset
/// gives there (the frame budget's scaled AO).
pub(crate) fn options_at(a: &RenderArgs, resolution: Resolution) -> AoOptions {
    let chosen = AoOptions {
        resolution,
        ..a.resolution.apply(AoOptions::default())
    };
    let o = a.quality.samples.apply(AoOptions {
        estimator: a.quality.estimator.into(),
        mode: a.mode.into(),
        fused: !a.unfused,
        history: if a.frames > 1 || a.orbit.is_some() {
            a.history
        } else {
            0
        },
        bent_normals: a.bent_normals_out.is_some()
            || (a.ssdo.is_some() && Estimator::from(a.quality.estimator).has_bent_normals()),
        second_layer: a.second_layer,
        ..chosen
    });
    AoOptions {
        march_exponent: a.march_exponent.unwrap_or(o.march_exponent),
        ..o
    }
}

pub(crate) fn params(a: &RenderArgs, radius: f32) -> AoParams {
    AoParams {
        radius,
        bias_angle_deg: a.bias,
        strength: a.strength,
        max_radius_px: a.max_radius_px,
        scale: a.resolution.scale,
        thickness: a.thickness,
        ..Default::default()
    }
}

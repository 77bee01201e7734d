//! What every front end of depth maps shares beyond the map itself: normals given with a
//! map, the `.npy` files AO is written to, and the names of the noise models.

use super::{invalid, Framed};
use crate::{DepthNoise, Result};

/// The axes of normals given with a depth map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalsFrame {
    /// The depth camera's (OpenCV, Open3D, NYU, ScanNet, TUM): x right, y down, z into the
    /// scene; a surface facing the camera has z < 0.
    OpenCv,
    /// obscura's view space (OpenGL): x right, y up, z towards the viewer.
    OpenGl,
}

/// Normals given with a depth map (`channels` = 3 or 4 floats per pixel, row-major, in
/// `frame`) as obscura's view-space RGBA rows for [`Renderer::render`] (before
/// [`Framed::pad`]): zero where a normal is missing, zero or not finite. Also returns the
/// fraction of the given normals that face away from the camera, a sign that `frame` is
/// wrong. Normals of which none is a finite non-zero vector (all NaN, all zero) are an
/// error: they are a broken file or array, not a request for normals from depth (for
/// which a caller gives none).
pub fn view_normals(
    values: &[f32],
    channels: usize,
    frame: NormalsFrame,
) -> Result<(Vec<[f32; 4]>, f32)> {
    let flip = match frame {
        NormalsFrame::OpenCv => -1.0,
        NormalsFrame::OpenGl => 1.0,
    };
    let (mut given, mut away) = (0usize, 0usize);
    let normals = values
        .chunks_exact(channels.max(3))
        .map(|c| {
            let n = [c[0], flip * c[1], flip * c[2]];
            if !n.iter().all(|v| v.is_finite()) || n == [0.0; 3] {
                return [0.0; 4];
            }
            given += 1;
            away += usize::from(n[2] < 0.0);
            [n[0], n[1], n[2], 0.0]
        })
        .collect();
    if given == 0 && !values.is_empty() {
        return Err(invalid(
            "normals: not one is a finite, non-zero vector (all NaN, infinite or zero); \
             give none to derive normals from the depth"
                .into(),
        ));
    }
    Ok((normals, away as f32 / given as f32))
}

/// A version-1 `.npy` file of little-endian float32 `values` of `shape`, C order (NumPy's
/// format, NEP 1): magic, version, header length, the header padded so the data starts at a
/// multiple of 64 bytes, the data. The AO files the CLI and the Python package write.
pub fn npy_f32(values: &[f32], shape: &[u32]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(u32::to_string).collect();
    let mut header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({}), }}",
        dims.join(", ")
    );
    // Magic (6) + version (2) + length (2) + header + '\n' is a multiple of 64.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend(values.iter().flat_map(|v| v.to_le_bytes()));
    out
}

/// The warning a front end prints when more than half the given normals face away from
/// the camera ([`view_normals`]'s fraction `away`), or `None`.
pub fn normals_warning(away: f32) -> Option<String> {
    (away > 0.5).then(|| {
        format!(
            "{:.0}% of the normals face away from the camera: are the axes the other \
             normals frame (OpenCV or OpenGL)?",
            100.0 * away
        )
    })
}

/// A depth noise model as a front end names it (the CLI's `--depth-noise`, the Python
/// package's `depth_noise`), checked before any map is read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoiseSpec {
    /// Estimated from each map ([`Framed::estimate_noise`]).
    Auto,
    /// Clean depth.
    None,
    /// σ = 1.5 mm·z² in metres (a structured-light sensor), plus an integer map's terraces.
    Kinect,
    /// σ = C + L·z + Q·z² in scene units, plus an integer map's terraces.
    Given([f32; 3]),
}

impl NoiseSpec {
    /// `auto`, `none`, `kinect` or `C,L,Q` (three finite numbers ≥ 0).
    pub fn parse(spec: &str) -> Result<Self> {
        Ok(match spec.trim() {
            "auto" => NoiseSpec::Auto,
            "none" => NoiseSpec::None,
            "kinect" => NoiseSpec::Kinect,
            other => {
                let expected = "expected auto, none, kinect or C,L,Q (σ = C + L·z + Q·z²)";
                let v: Vec<f32> = other
                    .split(',')
                    .map(|t| t.trim().parse::<f32>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| invalid(format!("depth noise `{other}`: {expected}")))?;
                let [constant, linear, quadratic] = v[..] else {
                    return Err(invalid(format!(
                        "depth noise `{other}` needs 3 numbers C,L,Q (σ = C + L·z + Q·z²), got {}",
                        v.len()
                    )));
                };
                crate::AoParams {
                    depth_noise: DepthNoise {
                        constant,
                        linear,
                        quadratic,
                        ..DepthNoise::NONE
                    },
                    ..Default::default()
                }
                .validate()?;
                NoiseSpec::Given([constant, linear, quadratic])
            }
        })
    }
}

/// The depth noise model a front end names for `framed` ([`NoiseSpec::parse`]), and a
/// description for the user:
/// - `auto`: estimated from the map ([`Framed::estimate_noise`]);
/// - `none`: clean depth;
/// - `kinect`: σ = 1.5 mm·z² in metres (a structured-light sensor), plus the encoding's
///   terraces for an integer map;
/// - `C,L,Q`: σ = C + L·z + Q·z² in scene units, plus the terraces for an integer map.
pub fn noise_model(spec: &str, framed: &Framed) -> Result<(DepthNoise, String)> {
    let step = framed.quantum.unwrap_or(0.0);
    let model = match NoiseSpec::parse(spec)? {
        NoiseSpec::Auto => {
            let e = framed.estimate_noise()?;
            let found = if e.model.is_none() {
                format!(
                    "none (estimated: σ at most {:.3} pixel footprints)",
                    e.sigma_px
                )
            } else {
                format!(
                    "{} (estimated from {} depth bins; σ up to {:.2} pixel footprints)",
                    describe_noise(&e.model),
                    e.bins.len(),
                    e.sigma_px
                )
            };
            return Ok((e.model, found));
        }
        NoiseSpec::None => DepthNoise::NONE,
        NoiseSpec::Kinect => DepthNoise {
            quadratic: 0.0015,
            // An integer encoding's quantisation: σ = step / √12 and its terraces.
            constant: step / 12f32.sqrt(),
            step_constant: step,
            ..DepthNoise::NONE
        },
        NoiseSpec::Given([constant, linear, quadratic]) => DepthNoise {
            constant,
            linear,
            quadratic,
            step_constant: step,
            step_quadratic: 0.0,
        },
    };
    Ok((model, format!("{} ({spec})", describe_noise(&model))))
}

/// A noise model as the user reads it.
pub fn describe_noise(model: &DepthNoise) -> String {
    if model.is_none() {
        "none (clean depth)".to_string()
    } else {
        let steps = match (model.step_constant > 0.0, model.step_quadratic > 0.0) {
            (_, true) => format!(
                ", terraces of max({:.3e}, {:.3e}·z²)",
                model.step_constant, model.step_quadratic
            ),
            (true, false) => format!(", terraces of {:.3e}", model.step_constant),
            _ => String::new(),
        };
        format!(
            "σ = {:.3e} + {:.3e}·z + {:.3e}·z²{steps}",
            model.constant, model.linear, model.quadratic
        )
    }
}

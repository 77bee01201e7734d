//! Real captured depth maps as input (`obscura render --depth FILE --intrinsics JSON`):
//! 16-bit PNG, 32-bit float EXR or `.npy` (float16/32/64 or uint16, C or Fortran order),
//! pinhole intrinsics in JSON. Depth 0, NaN and ±inf are missing data: sky, never a near
//! occluder. The intrinsics' depth scale applies to integer maps (16-bit PNG, uint16);
//! float maps are in scene units already (Open3D's convention), so one intrinsics file
//! serves both encodings of the same data.
//!
//! This file decodes files; the rules (scale, missing data, padding to centre the
//! principal point, the default radius) are the library's one depth-map path,
//! `obscura::depth_map`.

use super::args::{options, params, NormalsFrame, RenderArgs};
use super::prepared::write_prepared;
use super::record::record_timed;
use crate::readback::read_bent_normals;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Pinhole intrinsics as the JSON file gives them: the camera and the depth scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    pub camera: obscura::Intrinsics,
    /// Scene units (metres) per stored depth unit, e.g. 0.001 for millimetres.
    pub depth_scale: f32,
}

use obscura::depth_map::MAX_SIDE;

impl Intrinsics {
    /// Parses `{"fx":…, "fy":…, "cx":…, "cy":…, "width":…, "height":…, "depth_scale":…}`;
    /// `depth_scale` defaults to 0.001 (millimetres); other keys are ignored.
    pub fn parse(text: &str) -> Result<Self> {
        let v: serde_json::Value = serde_json::from_str(text).context("intrinsics are not JSON")?;
        let num = |k: &str| -> Result<f64> {
            v.get(k)
                .with_context(|| format!("intrinsics lack `{k}`"))?
                .as_f64()
                .with_context(|| format!("intrinsics `{k}` is not a number"))
        };
        let dim = |k: &str| -> Result<u32> {
            let x = num(k)?;
            if !(x >= 1.0 && x <= MAX_SIDE as f64 && x.fract() == 0.0) {
                bail!("intrinsics `{k}` = {x} must be an integer in 1..={MAX_SIDE}");
            }
            Ok(x as u32)
        };
        let camera = obscura::Intrinsics {
            fx: num("fx")? as f32,
            fy: num("fy")? as f32,
            cx: num("cx")? as f32,
            cy: num("cy")? as f32,
            width: dim("width")?,
            height: dim("height")?,
        };
        camera.validate()?;
        let depth_scale = match v.get("depth_scale") {
            None => 0.001,
            Some(s) => s
                .as_f64()
                .context("intrinsics `depth_scale` is not a number")? as f32,
        };
        if !(depth_scale.is_finite() && depth_scale > 0.0) {
            bail!("intrinsics `depth_scale` = {depth_scale} must be finite and > 0");
        }
        Ok(Intrinsics {
            camera,
            depth_scale,
        })
    }
}

/// Decoded values before scaling: width, height, row-major values, stored as integers.
type Decoded = (u32, u32, Vec<f32>, bool);

/// A file's lower-case extension and its bytes (`what` names it in the error).
fn read_file(path: &Path, what: &str) -> Result<(String, Vec<u8>)> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let bytes =
        std::fs::read(path).with_context(|| format!("cannot read {what} `{}`", path.display()))?;
    Ok((ext, bytes))
}

/// Loads a depth map by extension (.png 16-bit, .exr, .npy); integer data is multiplied by
/// `scale`, float data is taken as scene units (`obscura::DepthMap`).
pub fn load(path: &Path, scale: f32) -> Result<obscura::DepthMap> {
    let (ext, bytes) = read_file(path, "depth")?;
    let (width, height, raw, integer) = match ext.as_str() {
        "png" | "exr" => decode_image(&bytes, &ext)?,
        "npy" => decode_npy(&bytes)?,
        _ => bail!(
            "depth `{}`: unsupported format (expected .png with 16-bit values, .exr or .npy)",
            path.display()
        ),
    };
    Ok(if integer {
        obscura::DepthMap::from_integer(width, height, raw, scale)?
    } else {
        obscura::DepthMap::from_float(width, height, raw)?
    })
}

fn decode_image(bytes: &[u8], ext: &str) -> Result<Decoded> {
    let format = if ext == "png" {
        image::ImageFormat::Png
    } else {
        image::ImageFormat::OpenExr
    };
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    reader.limits(limits);
    // The size is checked with the values (obscura::DepthMap).
    let img = reader.decode().context("cannot decode the depth image")?;
    let (w, h) = (img.width(), img.height());
    let (values, integer) = match img {
        image::DynamicImage::ImageLuma16(b) => {
            (b.into_raw().into_iter().map(f32::from).collect(), true)
        }
        image::DynamicImage::ImageRgb32F(b) => (b.pixels().map(|p| p.0[0]).collect(), false),
        image::DynamicImage::ImageRgba32F(b) => (b.pixels().map(|p| p.0[0]).collect(), false),
        other => bail!(
            "depth images must be 16-bit single-channel PNG or float EXR (got {:?}); 8-bit \
             images cannot hold depth",
            other.color()
        ),
    };
    Ok((w, h, values, integer))
}

/// A `.npy` array read as `f32`s in C order.
struct Npy {
    dims: Vec<usize>,
    values: Vec<f32>,
    integer: bool,
}

/// A 2-D `.npy` depth map (see [`read_npy`]).
fn decode_npy(bytes: &[u8]) -> Result<Decoded> {
    let a = read_npy(bytes)?;
    let [h, w] = a.dims[..] else {
        bail!(
            ".npy array has shape {:?}; a depth map is 2-D (height, width)",
            a.dims
        );
    };
    Ok((w as u32, h as u32, a.values, a.integer))
}

/// A `.npy` array (version 1–3 header): any dimensions, each in 1..=MAX_SIDE except a last
/// of 3 or 4 channels, C or Fortran order, little-endian float64, float32, float16 or
/// uint16.
fn read_npy(bytes: &[u8]) -> Result<Npy> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        bail!("not a .npy file (bad magic)");
    }
    let (header_len, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10usize),
        2 | 3 if bytes.len() >= 12 => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
        v => bail!(".npy version {v} is not supported"),
    };
    let header = bytes
        .get(start..start.saturating_add(header_len))
        .context(".npy header is truncated")?;
    let header = std::str::from_utf8(header).context(".npy header is not text")?;
    let field = |key: &str| -> Option<&str> {
        let i = header.find(key)? + key.len();
        let rest = header[i..].trim_start().strip_prefix(':')?.trim_start();
        Some(rest)
    };
    let descr = field("'descr'").context(".npy header lacks 'descr'")?;
    let (bytes_per, convert): (usize, fn(&[u8]) -> f32) = if descr.starts_with("'<f8'") {
        (8, |b| {
            f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) as f32
        })
    } else if descr.starts_with("'<f4'") {
        (4, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    } else if descr.starts_with("'<f2'") {
        (2, |b| half_to_f32(u16::from_le_bytes([b[0], b[1]])))
    } else if descr.starts_with("'<u2'") {
        (2, |b| u16::from_le_bytes([b[0], b[1]]) as f32)
    } else {
        bail!(
            ".npy dtype {} is not supported (little-endian float64, float32, float16 or uint16)",
            descr.split(',').next().unwrap_or("")
        );
    };
    let fortran = field("'fortran_order'").is_some_and(|f| f.starts_with("True"));
    let integer = descr.starts_with("'<u2'");
    let shape = field("'shape'").context(".npy header lacks 'shape'")?;
    let inner = shape
        .strip_prefix('(')
        .and_then(|s| s.split(')').next())
        .context(".npy shape is malformed")?;
    let dims: Vec<usize> = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<usize>())
        .collect::<Result<_, _>>()
        .context(".npy shape is malformed")?;
    if dims.is_empty()
        || dims.len() > 3
        || dims[..2.min(dims.len())]
            .iter()
            .any(|&d| d == 0 || d > MAX_SIDE as usize)
    {
        bail!(".npy array has shape {dims:?}; each image side must be in 1..={MAX_SIDE}");
    }
    let count: usize = dims.iter().product();
    let data = &bytes[start + header_len..];
    let need = count * bytes_per;
    if data.len() < need {
        bail!(".npy data is truncated ({} of {need} bytes)", data.len());
    }
    let stored: Vec<f32> = data[..need].chunks_exact(bytes_per).map(convert).collect();
    // Fortran order stores the first index fastest: element (i0, i1, …) at
    // i0 + d0 · (i1 + d1 · …).
    let values = if fortran {
        (0..count)
            .map(|c| {
                let (mut rest, mut at, mut stride) = (c, 0, 1);
                let mut index = vec![0; dims.len()];
                for (k, &d) in dims.iter().enumerate().rev() {
                    index[k] = rest % d;
                    rest /= d;
                }
                for (k, &d) in dims.iter().enumerate() {
                    at += index[k] * stride;
                    stride *= d;
                }
                stored[at]
            })
            .collect()
    } else {
        stored
    };
    Ok(Npy {
        dims,
        values,
        integer,
    })
}

/// IEEE half → f32 (subnormals, inf and NaN included).
fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = (h >> 10) & 0x1f;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 if frac == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + frac / 1024.0) * 2f32.powi(e as i32 - 15),
    }
}

/// `--normals-file`: a (height, width, 3 or 4) float `.npy` or an RGB(A) float EXR of
/// view-space normals in `frame`, `width` × `height`; returned in obscura's view space as
/// RGBA rows (zero where a normal is missing or not finite), with the fraction of the
/// given normals that face away from the camera (a sign that `frame` is wrong).
pub fn load_normals(
    path: &Path,
    width: u32,
    height: u32,
    frame: NormalsFrame,
) -> Result<(Vec<[f32; 4]>, f32)> {
    let (ext, bytes) = read_file(path, "normals")?;
    let (w, h, channels, values) = match ext.as_str() {
        "npy" => {
            let a = read_npy(&bytes)?;
            let [h, w, c @ (3 | 4)] = a.dims[..] else {
                bail!(
                    ".npy array has shape {:?}; normals are (height, width, 3) or (height, \
                     width, 4)",
                    a.dims
                );
            };
            if a.integer {
                bail!("normals must be float (float16/32/64), not uint16");
            }
            (w as u32, h as u32, c, a.values)
        }
        "exr" => {
            let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr)
                .context("cannot decode the normals EXR")?;
            let (w, h) = (img.width(), img.height());
            (w, h, 4, img.into_rgba32f().into_raw())
        }
        _ => bail!("unsupported format (expected a float .npy or .exr)"),
    };
    if (w, h) != (width, height) {
        bail!("the normals are {w}x{h} but the depth map is {width}x{height}");
    }
    let frame = match frame {
        NormalsFrame::Opencv => obscura::depth_map::NormalsFrame::OpenCv,
        NormalsFrame::Opengl => obscura::depth_map::NormalsFrame::OpenGl,
    };
    Ok(obscura::depth_map::view_normals(&values, channels, frame)?)
}

/// `obscura render --depth FILE --intrinsics JSON`.
pub fn run(a: &RenderArgs, depth_path: &Path, intrinsics: &Path) -> Result<()> {
    use obscura::{Ao, AoInput, DepthConvention, GpuContext};
    let t0 = std::time::Instant::now();
    let text = std::fs::read_to_string(intrinsics)
        .with_context(|| format!("cannot read intrinsics `{}`", intrinsics.display()))?;
    let k = Intrinsics::parse(&text)
        .with_context(|| format!("intrinsics `{}`", intrinsics.display()))?;
    let map = load(depth_path, k.depth_scale)
        .with_context(|| format!("depth `{}`", depth_path.display()))?;
    if !map.is_integer() && k.depth_scale != 1.0 {
        eprintln!(
            "depth: float values are taken as scene units; the intrinsics' depth_scale {} \
             applies to integer maps only",
            k.depth_scale
        );
    }
    let framed = map.frame(&k.camera)?;
    let radius = framed.radius(a.radius).context("--radius")?;
    let [pw, ph] = framed.padded_size;
    let [zmin, zmax] = framed.depth_range;
    let (depth_noise, noise_text) =
        obscura::depth_map::noise_model(&a.depth_noise, &framed).context("--depth-noise")?;
    eprintln!(
        "depth: {}x{} ({:.0}% valid), depth {:.3}..{:.3}, padded to {pw}x{ph} to centre the \
         principal point; loaded in {:.0} ms",
        map.width,
        map.height,
        100.0 * framed.valid as f64 / map.depth.len() as f64,
        zmin,
        zmax,
        t0.elapsed().as_secs_f64() * 1e3
    );

    let normals = match &a.normals_file {
        Some(path) => {
            let (n, away) = load_normals(path, map.width, map.height, a.normals_frame)
                .with_context(|| format!("normals `{}`", path.display()))?;
            eprintln!(
                "normals: {} ({:?} axes){}",
                path.display(),
                a.normals_frame,
                obscura::depth_map::normals_warning(away).map_or(String::new(), |w| format!(
                    "; warning: {w} (--normals-frame)"
                ))
            );
            Some(framed.pad(&n)?)
        }
        None => None,
    };
    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let tex = ctx.upload_r32("depth map", &framed.depth, pw, ph);
    let normal_tex = normals.map(|n| ctx.upload_rgba32("normal map", &n, pw, ph));
    let normal_view = normal_tex.map(|t| t.create_view(&Default::default()));
    let view = tex.create_view(&Default::default());
    let options = options(a);
    let params = obscura::AoParams {
        depth_noise,
        ..params(a, radius)
    };
    let mut ao = Ao::new(&ctx.device, options)?;
    let input = AoInput {
        depth: &view,
        convention: DepthConvention::LinearView,
        projection: framed.projection,
        normals: normal_view
            .as_ref()
            .map(|v| (v, obscura::NormalEncoding::ViewSigned)),
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    };
    ao.validate(&input, &params)?;
    eprintln!(
        "ao: {} ({} samples/pixel), radius {radius:.3}, depth noise {noise_text}",
        options.estimator.name(),
        options.samples_per_pixel(),
    );
    let out = record_timed(a, &ctx, &mut ao, &input, &params)?;
    let cropped = framed.crop(&out)?;
    crate::output::save_ao(&a.out, &cropped, map.width, map.height, a.bits)?;
    eprintln!("wrote {}", a.out.display());
    write_prepared(a, (&ctx, &ao), (&input, &params), (pw, ph), Some(&framed))?;
    if let Some(path) = &a.bent_normals_out {
        let (bent, w, h) = read_bent_normals(&ctx, &ao)?;
        // Cropped like the AO where they share its size; below full resolution as they are
        // (the padding then stays in, at the working resolution).
        let (bent, w, h) = if (w, h) == (pw, ph) {
            let channel = |k: usize| -> Result<Vec<f32>> {
                Ok(framed.crop(&bent.iter().map(|b| b[k]).collect::<Vec<_>>())?)
            };
            let (x, y, z) = (channel(0)?, channel(1)?, channel(2)?);
            let v = (0..x.len()).map(|i| [x[i], y[i], z[i]]).collect();
            (v, map.width, map.height)
        } else {
            (bent, w, h)
        };
        crate::output::save_vectors(path, &bent, w, h)?;
        eprintln!("wrote {} ({w}x{h})", path.display());
    }
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64*: a dependency-free PRNG for the mutation fuzzing below.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n.max(1) as u64) as usize
        }
    }

    /// Random edits of a valid input: byte flips, truncation, duplication, insertion.
    fn mutate(rng: &mut Rng, valid: &[u8]) -> Vec<u8> {
        let mut v = valid.to_vec();
        for _ in 0..1 + rng.below(4) {
            match rng.below(4) {
                0 if !v.is_empty() => {
                    let i = rng.below(v.len());
                    v[i] ^= 1 << rng.below(8);
                }
                1 => v.truncate(rng.below(v.len() + 1)),
                2 if !v.is_empty() => {
                    let i = rng.below(v.len());
                    let j = (i + rng.below(64)).min(v.len());
                    let chunk = v[i..j].to_vec();
                    v.splice(i..i, chunk);
                }
                _ => {
                    let i = rng.below(v.len() + 1);
                    v.insert(i, rng.next() as u8);
                }
            }
        }
        v
    }

    fn npy(w: u32, h: u32, values: &[f32]) -> Vec<u8> {
        crate::output::npy_f32(values, w, h)
    }

    /// A `.npy` with any dtype and order: `data` as stored.
    fn npy_raw(descr: &str, fortran: bool, h: u32, w: u32, data: &[u8]) -> Vec<u8> {
        let order = if fortran { "True" } else { "False" };
        let header =
            format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': ({h}, {w}), }}\n");
        let mut v = b"\x93NUMPY\x01\x00".to_vec();
        v.extend((header.len() as u16).to_le_bytes());
        v.extend(header.as_bytes());
        v.extend(data);
        v
    }

    #[test]
    fn npy_png_and_exr_decode_known_values() {
        let values = [1.5f32, 0.0, f32::NAN, 2.25, 1e3, -1.0];
        let (w, h, got, integer) = decode_npy(&npy(3, 2, &values)).unwrap();
        assert_eq!((w, h, integer), (3, 2, false));
        assert_eq!(got[0], 1.5);
        assert!(got[2].is_nan());
        let png16 = {
            let img = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(2, 1, vec![1234u16, 0])
                .unwrap();
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::Png).unwrap();
            out.into_inner()
        };
        assert_eq!(
            decode_image(&png16, "png").unwrap(),
            (2, 1, vec![1234.0, 0.0], true)
        );
        let exr = {
            let img =
                image::Rgb32FImage::from_raw(2, 1, vec![0.75, 0.0, 0.0, 3.5, 0.0, 0.0]).unwrap();
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::OpenExr).unwrap();
            out.into_inner()
        };
        assert_eq!(
            decode_image(&exr, "exr").unwrap(),
            (2, 1, vec![0.75, 3.5], false)
        );
        // 8-bit images cannot hold depth: a typed refusal.
        let png8 = {
            let img = image::GrayImage::from_raw(1, 1, vec![9]).unwrap();
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::Png).unwrap();
            out.into_inner()
        };
        assert!(decode_image(&png8, "png").is_err());
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0xc000), -2.0);
        assert_eq!(half_to_f32(0x7c00), f32::INFINITY);
        assert!(half_to_f32(0x7e00).is_nan());
    }

    /// numpy's default float64 and Fortran-ordered arrays (column after column) decode to
    /// the same row-major map as a C-ordered float32 copy.
    #[test]
    fn float64_and_fortran_order_npy_decode_row_major() {
        // value(y, x) = 10 y + x, 2 rows × 3 columns.
        let c_order: Vec<f32> = vec![0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        let f_order = [0.0f64, 10.0, 1.0, 11.0, 2.0, 12.0];
        let f8: Vec<u8> = f_order.iter().flat_map(|v| v.to_le_bytes()).collect();
        let got = decode_npy(&npy_raw("<f8", true, 2, 3, &f8)).unwrap();
        assert_eq!(got, (3, 2, c_order.clone(), false));
        let c8: Vec<u8> = c_order
            .iter()
            .flat_map(|&v| (v as f64).to_le_bytes())
            .collect();
        assert_eq!(
            decode_npy(&npy_raw("<f8", false, 2, 3, &c8)).unwrap().2,
            c_order
        );
        let u2: Vec<u8> = [0u16, 10, 1, 11, 2, 12]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        assert_eq!(
            decode_npy(&npy_raw("<u2", true, 2, 3, &u2)).unwrap(),
            (3, 2, c_order, true)
        );
        // Big-endian data is refused by name, not misread.
        let err = decode_npy(&npy_raw(">f8", false, 2, 3, &f8)).unwrap_err();
        assert!(err.to_string().contains(">f8"), "{err}");
    }

    /// The depth scale converts integer maps only: float maps are scene units already, so a
    /// float32 copy of millimetre data in metres loads to the same depths as the uint16 map.
    #[test]
    fn the_depth_scale_applies_to_integer_maps_only() {
        let dir = std::env::temp_dir().join(format!("obscura-scale-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mm = [1500u16, 0, 2250, 4000];
        let u2: Vec<u8> = mm.iter().flat_map(|v| v.to_le_bytes()).collect();
        let metres: Vec<f32> = mm.iter().map(|&v| v as f32 / 1000.0).collect();
        let (fu, ff) = (dir.join("mm.npy"), dir.join("m.npy"));
        std::fs::write(&fu, npy_raw("<u2", false, 2, 2, &u2)).unwrap();
        std::fs::write(&ff, npy(2, 2, &metres)).unwrap();
        let a = load(&fu, 0.001).unwrap();
        let b = load(&ff, 0.001).unwrap();
        assert!(a.is_integer() && !b.is_integer());
        for (x, y) in a.depth.iter().zip(&b.depth) {
            assert!((x - y).abs() <= 1e-6, "{:?} vs {:?}", a.depth, b.depth);
        }
        assert_eq!(b.depth[2], 2.25);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn intrinsics_parse_and_centre_the_principal_point() {
        let k = Intrinsics::parse(
            r#"{"fx": 500, "fy": 400, "cx": 99.5, "cy": 40, "width": 200, "height": 100}"#,
        )
        .unwrap();
        assert_eq!(k.depth_scale, 0.001);
        let ([l, t, r, b], p) = k.camera.centred(0.1, 10.0);
        // cx + 0.5 = 100 = width / 2: no horizontal padding; cy + 0.5 = 40.5 needs
        // 100 - 2 * 40.5 = 19 rows on top.
        assert_eq!((l, r, t, b), (0, 0, 19, 0));
        match p {
            obscura::Projection::Perspective { fov_y, aspect, .. } => {
                assert!((fov_y - 2.0 * (119.0f32 / 800.0).atan()).abs() < 1e-6);
                assert!((aspect - (200.0 / 1000.0) / (119.0 / 800.0)).abs() < 1e-5);
            }
            p => panic!("{p:?}"),
        }
        for bad in [
            "",
            "{}",
            r#"{"fx": -1, "fy": 1, "cx": 0, "cy": 0, "width": 2, "height": 2}"#,
            r#"{"fx": 1, "fy": 1, "cx": 50, "cy": 0, "width": 2, "height": 2}"#,
            r#"{"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 2.5, "height": 2}"#,
            r#"{"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 2, "height": 99999}"#,
            r#"{"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 2, "height": 2, "depth_scale": 0}"#,
        ] {
            assert!(Intrinsics::parse(bad).is_err(), "{bad} accepted");
        }
    }

    /// Mutated files never panic a loader: each answer is a value or a typed error. 3000
    /// cases or 15 s in CI ([`obscura::fuzz::Budget`] for a long run by hand).
    #[test]
    fn fuzz_depth_and_intrinsics_loaders() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let valid_npy = npy(4, 3, &[1.0; 12]);
        let valid_json = br#"{"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "width": 640, "height": 480, "depth_scale": 0.001}"#;
        let valid_png = {
            let img = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(4, 3, vec![700u16; 12])
                .unwrap();
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::Png).unwrap();
            out.into_inner()
        };
        let valid_exr = {
            let img = image::Rgb32FImage::from_raw(4, 3, vec![0.7; 36]).unwrap();
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::OpenExr).unwrap();
            out.into_inner()
        };
        let (mut ok, mut err) = (0, 0);
        let budget = obscura::fuzz::Budget::from_env(3000, 15);
        for _ in (0..).take_while(|&c| budget.more(c)) {
            let results = [
                decode_npy(&mutate(&mut rng, &valid_npy)).is_ok(),
                decode_image(&mutate(&mut rng, &valid_png), "png").is_ok(),
                decode_image(&mutate(&mut rng, &valid_exr), "exr").is_ok(),
                Intrinsics::parse(&String::from_utf8_lossy(&mutate(&mut rng, valid_json))).is_ok(),
            ];
            for r in results {
                if r {
                    ok += 1;
                } else {
                    err += 1;
                }
            }
        }
        // Both outcomes occur, so the mutations reach past the first check.
        eprintln!("fuzz depth maps and intrinsics: {ok} accepted, {err} refused, no panic");
        assert!(ok > 0 && err > 0, "{ok} accepted, {err} refused");
    }
}

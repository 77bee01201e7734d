//! Image output that never leaves a half-written file: write to a temporary file beside
//! the target, then rename over it.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// Checks up front that `path` can be written as a PNG (extension, existing folder).
pub fn check_png_path(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case("png") {
        bail!("output `{}` must end in .png", path.display());
    }
    check_folder(path)
}

/// Checks that the folder `path` would be written into exists: up front, for any output.
pub fn check_folder(path: &Path) -> Result<()> {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        bail!(
            "cannot write `{}`: folder `{}` does not exist",
            path.display(),
            parent.display()
        );
    }
    Ok(())
}

/// Checks up front that `path` can take an AO image: `.png` (8- or 16-bit grey), `.npy`
/// (float32) or `.exr` (float32), in an existing folder.
pub fn check_ao_path(path: &Path) -> Result<()> {
    check_image_path(path, "(8- or 16-bit grey, --bits)")
}

/// Checks up front that `path` can take vectors ([`save_vectors`]): `.png` (8-bit RGB),
/// `.npy` or `.exr` (float32), in an existing folder.
pub fn check_vectors_path(path: &Path) -> Result<()> {
    check_image_path(path, "(8-bit RGB of xyz · 0.5 + 0.5)")
}

/// `.png` (`png_kind`), `.npy` or `.exr`, in an existing folder.
fn check_image_path(path: &Path, png_kind: &str) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !["png", "npy", "exr"]
        .iter()
        .any(|e| ext.eq_ignore_ascii_case(e))
    {
        bail!(
            "output `{}` must end in .png {png_kind}, .npy or .exr (float32)",
            path.display()
        );
    }
    check_folder(path)
}

/// Writes AO values (`width` × `height`, row-major, 1 = unoccluded) to `path` atomically,
/// by extension: `.npy` as float32 (2-D, C order), `.exr` as float32 (grey in R, G and B,
/// the layout every EXR reader takes), anything else as a grey PNG of `bits` 8 or 16 per
/// sample.
pub fn save_ao(path: &Path, ao: &[f32], width: u32, height: u32, bits: u8) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "npy" => write_bytes(path, &npy_f32(ao, width, height)),
        "exr" => {
            let rgb: Vec<f32> = ao.iter().flat_map(|&v| [v; 3]).collect();
            save_exr_rgb(path, &rgb, width, height)
        }
        _ if bits == 16 => {
            let px: Vec<u8> = ao
                .iter()
                .flat_map(|v| ((v.clamp(0.0, 1.0) * 65535.0).round() as u16).to_ne_bytes())
                .collect();
            save_png(path, &px, width, height, image::ExtendedColorType::L16)
        }
        _ => {
            let px: Vec<u8> = ao
                .iter()
                .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect();
            save_png(path, &px, width, height, image::ExtendedColorType::L8)
        }
    }
}

/// Writes unit vectors (`width` × `height`, row-major; zero where there is none, as on sky)
/// to `path` atomically, by extension: `.npy` as float32 of shape (height, width, 3), `.exr`
/// as float32 RGB = xyz, anything else as an 8-bit RGB PNG of xyz · 0.5 + 0.5 (the usual
/// normal-map encoding; black where the vector is zero).
pub fn save_vectors(path: &Path, v: &[[f32; 3]], width: u32, height: u32) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let flat: Vec<f32> = v.iter().flatten().copied().collect();
    match ext.as_str() {
        "npy" => write_bytes(
            path,
            &obscura::depth_map::npy_f32(&flat, &[height, width, 3]),
        ),
        "exr" => save_exr_rgb(path, &flat, width, height),
        _ => {
            let rgb: Vec<u8> = v
                .iter()
                .flat_map(|n| {
                    let none = n.iter().all(|c| *c == 0.0);
                    n.map(|c| {
                        if none {
                            0
                        } else {
                            ((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8
                        }
                    })
                })
                .collect();
            save_png(path, &rgb, width, height, image::ExtendedColorType::Rgb8)
        }
    }
}

/// Float32 RGB (`rgb`: three values per pixel, row-major) as EXR into `path` atomically.
fn save_exr_rgb(path: &Path, rgb: &[f32], width: u32, height: u32) -> Result<()> {
    let bytes: Vec<u8> = rgb.iter().flat_map(|c| c.to_ne_bytes()).collect();
    save_image(
        path,
        &bytes,
        width,
        height,
        image::ExtendedColorType::Rgb32F,
        image::ImageFormat::OpenExr,
    )
}

/// A `.npy` file holding `values` as a float32 array of shape (height, width).
pub fn npy_f32(values: &[f32], width: u32, height: u32) -> Vec<u8> {
    obscura::depth_map::npy_f32(values, &[height, width])
}

/// Writes `bytes` to `path` atomically.
fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_path(path);
    let r = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r.with_context(|| format!("cannot write `{}`", path.display()))
}

/// A time in milliseconds to about three significant digits, so sub-millisecond GPU times
/// and lavapipe's hundreds of milliseconds both read: 0.0123, 0.456, 4.56, 45.6, 456.7.
pub fn fmt_ms(t: f64) -> String {
    let decimals = if t < 0.1 {
        4
    } else if t < 1.0 {
        3
    } else if t < 10.0 {
        2
    } else {
        1
    };
    format!("{t:.decimals$}")
}

/// Writes `text` to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_bytes(path, text.as_bytes())
}

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}", std::process::id()));
    path.with_file_name(name)
}

/// Encodes raw pixels (`color` layout, `width` × `height`) as PNG into `path` atomically.
pub fn save_png(
    path: &Path,
    pixels: &[u8],
    width: u32,
    height: u32,
    color: image::ExtendedColorType,
) -> Result<()> {
    save_image(path, pixels, width, height, color, image::ImageFormat::Png)
}

/// Encodes raw pixels as `format` into `path` atomically.
pub(crate) fn save_image(
    path: &Path,
    pixels: &[u8],
    width: u32,
    height: u32,
    color: image::ExtendedColorType,
    format: image::ImageFormat,
) -> Result<()> {
    let tmp = temp_path(path);
    let result = image::save_buffer_with_format(&tmp, pixels, width, height, color, format)
        .map_err(anyhow::Error::from)
        .and_then(|()| std::fs::rename(&tmp, path).map_err(anyhow::Error::from));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write `{}`", path.display()))
}

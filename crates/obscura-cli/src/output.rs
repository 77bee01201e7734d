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

/// Checks that the folder `path` would be written into exists.
fn check_folder(path: &Path) -> Result<()> {
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

/// Checks up front that `path` can take an AO image: `.png` (8-bit grey) or `.npy` (float32,
/// 1 = unoccluded, for anyone who computes with the AO), in an existing folder.
pub fn check_ao_path(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ext.eq_ignore_ascii_case("npy") {
        return check_folder(path);
    }
    if !ext.eq_ignore_ascii_case("png") {
        bail!(
            "output `{}` must end in .png (8-bit) or .npy (float32)",
            path.display()
        );
    }
    check_png_path(path)
}

/// Writes AO values (`width` × `height`, row-major) to `path` atomically: `.npy` as float32
/// (2-D, C order), anything else as an 8-bit grey PNG.
pub fn save_ao(path: &Path, ao: &[f32], width: u32, height: u32) -> Result<()> {
    let npy = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    if !npy {
        let px: Vec<u8> = ao
            .iter()
            .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect();
        return save_png(path, &px, width, height, image::ExtendedColorType::L8);
    }
    write_bytes(path, &npy_f32(ao, width, height))
}

/// A version-1 `.npy` file holding `values` as a little-endian float32 array of shape
/// (height, width) in C order (the NumPy format specification, NEP 1).
pub fn npy_f32(values: &[f32], width: u32, height: u32) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({height}, {width}), }}");
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

/// Writes `bytes` to `path` atomically.
fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_path(path);
    let r = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r.with_context(|| format!("cannot write `{}`", path.display()))
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
    let tmp = temp_path(path);
    let result =
        image::save_buffer_with_format(&tmp, pixels, width, height, color, image::ImageFormat::Png)
            .map_err(anyhow::Error::from)
            .and_then(|()| std::fs::rename(&tmp, path).map_err(anyhow::Error::from));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write `{}`", path.display()))
}

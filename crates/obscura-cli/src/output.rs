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

/// Writes `text` to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let tmp = temp_path(path);
    let r = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path));
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r.with_context(|| format!("cannot write `{}`", path.display()))
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

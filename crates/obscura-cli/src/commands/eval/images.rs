//! `eval --score-images DIR`: AO made elsewhere (another library, an earlier build), one
//! image per view, scored against the same ray-traced truth with the same metrics.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The extensions an AO image may have, in the order they are looked for.
const EXTENSIONS: [&str; 2] = ["png", "exr"];

/// A folder of AO images and its label in the report ("image NAME").
pub(super) struct ImageDir {
    pub(super) dir: PathBuf,
    pub(super) label: String,
}

/// The folders of `--score-images`, each checked to exist; labels must differ.
pub(super) fn image_dirs(dirs: &[PathBuf]) -> Result<Vec<ImageDir>> {
    let mut out: Vec<ImageDir> = Vec::new();
    for dir in dirs {
        if !dir.is_dir() {
            bail!("--score-images `{}` is not a folder", dir.display());
        }
        let name = dir
            .canonicalize()
            .ok()
            .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| dir.display().to_string());
        let label = format!("image {name}");
        if out.iter().any(|d| d.label == label) {
            bail!("--score-images: two folders are named `{name}`; their rows would share a label");
        }
        out.push(ImageDir {
            dir: dir.clone(),
            label,
        });
    }
    Ok(out)
}

/// The AO image of `view` in `dir` (`VIEW.png`, 8- or 16-bit grey, or `VIEW.exr`, float,
/// its luminance), as `width` × `height` values, 1 = unoccluded.
pub(super) fn load_view(dir: &Path, view: &str, width: u32, height: u32) -> Result<Vec<f32>> {
    let path = EXTENSIONS
        .iter()
        .map(|e| dir.join(format!("{view}.{e}")))
        .find(|p| p.exists())
        .with_context(|| {
            format!(
                "--score-images `{}` has no `{view}.png` or `{view}.exr`",
                dir.display()
            )
        })?;
    let img = image::open(&path).with_context(|| format!("cannot read `{}`", path.display()))?;
    if (img.width(), img.height()) != (width, height) {
        bail!(
            "`{}` is {}x{}; eval renders {width}x{height} (--width, --height)",
            path.display(),
            img.width(),
            img.height()
        );
    }
    let values: Vec<f32> = img.to_luma32f().into_raw();
    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
        bail!("`{}` holds {bad}; AO must be finite", path.display());
    }
    Ok(values)
}

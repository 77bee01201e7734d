//! `eval --score-images DIR`: AO made elsewhere (another library, an earlier build), one
//! image per view, scored against the same ray-traced truth with the same metrics.

use super::args::EvalArgs;
use crate::output::write_text;
use crate::views::{camera_for, Job};
use anyhow::{bail, Context, Result};
use obscura_scene::{CameraProjection, Mesh};
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

/// `eval --export-views FILE`: each view's scene, camera and AO radius (the rule eval uses:
/// `--radius`, else 3% of the bounds' diagonal) as JSON, for a peer to render the same.
pub(super) fn export_views(a: &EvalArgs, jobs: &[Job], path: &Path) -> Result<()> {
    let mut views = Vec::new();
    for job in jobs {
        let mesh = Mesh::load(&job.file)
            .with_context(|| format!("cannot load scene `{}`", job.file.display()))?;
        let cam = camera_for(job, &mesh)?;
        let bounds = mesh.bounds().context("the scene has no triangles")?;
        let CameraProjection::Perspective { fov_y_deg } = cam.projection else {
            bail!("view `{}`: only perspective views are exported", job.name);
        };
        views.push(serde_json::json!({
            "name": job.name,
            "scene": job.file.canonicalize().unwrap_or_else(|_| job.file.clone()),
            "eye": cam.eye.to_array(),
            "target": cam.target.to_array(),
            "up": cam.up.to_array(),
            "fov_y_deg": fov_y_deg,
            "near": cam.near,
            "far": cam.far,
            "radius": super::view_radius(a, &bounds),
            "width": a.width,
            "height": a.height,
        }));
    }
    let text = serde_json::to_string_pretty(&serde_json::json!({ "views": views }))?;
    write_text(path, &text)?;
    eprintln!("wrote {} ({} views)", path.display(), views.len());
    Ok(())
}

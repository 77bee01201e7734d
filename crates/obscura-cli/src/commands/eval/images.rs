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

/// The AO image of `view` in `dir` (`VIEW.png`, 8- or 16-bit grey, or `VIEW.exr`: one
/// channel such as Y, or the luminance of R, G and B), as `width` × `height` values in
/// [0, 1], 1 = unoccluded.
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
    let ((w, h), values) = if path.extension().is_some_and(|e| e == "exr") {
        read_exr(&path)?
    } else {
        let img =
            image::open(&path).with_context(|| format!("cannot read `{}`", path.display()))?;
        ((img.width(), img.height()), img.to_luma32f().into_raw())
    };
    if (w, h) != (width, height) {
        bail!(
            "`{}` is {w}x{h}; eval renders {width}x{height} (--width, --height)",
            path.display()
        );
    }
    if let Some(i) = values.iter().position(|v| !(0.0..=1.0).contains(v)) {
        bail!(
            "`{}` holds {} at pixel ({}, {}); AO must be in [0, 1] (1 = unoccluded)",
            path.display(),
            values[i],
            i as u32 % w,
            i as u32 / w
        );
    }
    Ok(values)
}

/// An EXR's size and grey values, row by row: its only channel (a Y image), else the
/// Rec. 709 luminance of its R, G and B channels (alpha ignored).
fn read_exr(path: &Path) -> Result<((u32, u32), Vec<f32>)> {
    let image = exr::prelude::read_first_flat_layer_from_file(path)
        .with_context(|| format!("cannot read `{}`", path.display()))?;
    let layer = image.layer_data;
    let size = (layer.size.width() as u32, layer.size.height() as u32);
    let channels = &layer.channel_data.list;
    let named = |n: &str| channels.iter().find(|c| c.name.to_string() == n);
    let values: Vec<f32> = match (channels.len(), named("R"), named("G"), named("B")) {
        (1, ..) => channels[0].sample_data.values_as_f32().collect(),
        (_, Some(r), Some(g), Some(b)) => r
            .sample_data
            .values_as_f32()
            .zip(g.sample_data.values_as_f32())
            .zip(b.sample_data.values_as_f32())
            .map(|((r, g), b)| 0.2126 * r + 0.7152 * g + 0.0722 * b)
            .collect(),
        _ => match named("Y") {
            Some(y) => y.sample_data.values_as_f32().collect(),
            None => bail!(
                "`{}` has channels {}; AO is one channel (Y) or R, G and B",
                path.display(),
                channels
                    .iter()
                    .map(|c| c.name.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        },
    };
    Ok((size, values))
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

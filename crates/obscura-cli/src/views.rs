//! The views a command works on (`--scene FILE [--camera ...]`, `--view NAME`, `--all`):
//! a scene file or the shared standard views, and the camera each is seen from.

use crate::options::parse_floats;
use anyhow::{bail, Context, Result};
use clap::Args;
use glam::Vec3;
use obscura_eval::views;
use obscura_scene::{Camera, CameraProjection, Mesh};
use std::path::{Path, PathBuf};

/// Which views to work on: a scene file, standard views by name, or all of them.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Scene file (with --camera, or framed from its bounds).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["view", "all"])]
    pub scene: Option<PathBuf>,
    /// Camera as EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z[,FOV_Y_DEG] (with --scene).
    #[arg(long, allow_hyphen_values = true, requires = "scene")]
    pub camera: Option<String>,
    /// A standard view by name (repeatable): sponza, cornell, house5, house6, etoile,
    /// munich, bunny, teapot, dragon.
    #[arg(long)]
    pub view: Vec<String>,
    /// Every standard view.
    #[arg(long)]
    pub all: bool,
    /// The shared scenes folder holding the standard views' files.
    #[arg(long, default_value = "../shared/scenes")]
    pub scenes_dir: PathBuf,
}

/// One evaluated view: what to load and how to look at it.
pub(crate) struct Job {
    pub(crate) name: String,
    pub(crate) file: PathBuf,
    pub(crate) camera: Option<([f32; 3], [f32; 3], f32)>,
}

impl ViewArgs {
    /// The views named (`None` if none is given).
    pub(crate) fn jobs(&self) -> Result<Option<Vec<Job>>> {
        jobs_for(
            self.scene.as_deref(),
            self.camera.as_deref(),
            self.all,
            &self.view,
            &self.scenes_dir,
        )
    }
}

fn jobs_for(
    scene: Option<&Path>,
    camera: Option<&str>,
    all: bool,
    view: &[String],
    scenes_dir: &Path,
) -> Result<Option<Vec<Job>>> {
    if let Some(f) = scene {
        let camera = match camera {
            Some(c) => {
                let v = parse_floats(c, "--camera")?;
                if !(v.len() == 6 || v.len() == 7) {
                    bail!("--camera needs 6 or 7 numbers (eye, target, optional fov)");
                }
                Some((
                    [v[0], v[1], v[2]],
                    [v[3], v[4], v[5]],
                    v.get(6).copied().unwrap_or(60.0),
                ))
            }
            None => None,
        };
        let name = f
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene")
            .to_string();
        return Ok(Some(vec![Job {
            name,
            file: f.to_path_buf(),
            camera,
        }]));
    }
    let chosen: Vec<&views::StandardView> = if all {
        views::STANDARD_VIEWS.iter().collect()
    } else if view.is_empty() {
        return Ok(None);
    } else {
        view.iter()
            .map(|n| {
                views::find(n).with_context(|| {
                    let names: Vec<&str> = views::STANDARD_VIEWS.iter().map(|v| v.name).collect();
                    format!(
                        "unknown view `{n}`; the standard views are {}",
                        names.join(", ")
                    )
                })
            })
            .collect::<Result<_>>()?
    };
    Ok(Some(
        chosen
            .into_iter()
            .map(|v| Job {
                name: v.name.to_string(),
                file: scenes_dir.join(v.file),
                camera: v.camera,
            })
            .collect(),
    ))
}

pub(crate) fn camera_for(job: &Job, mesh: &Mesh) -> Result<Camera> {
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let mut cam = match job.camera {
        Some((eye, target, fov)) => Camera {
            eye: Vec3::from(eye),
            target: Vec3::from(target),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: fov },
            near: 0.0,
            far: 0.0,
        },
        None => Camera::framing(&bounds, CameraProjection::Perspective { fov_y_deg: 50.0 }),
    };
    cam.fit_clip_planes(&bounds);
    cam.validate()?;
    Ok(cam)
}

//! `obscura render` of a scene (the built-in one without --scene): scene → G-buffer → AO →
//! PNG, with the optional depth, normal, bent-normal and SSDO pictures; `--orbit` and
//! `--budget-ms` hand over to `orbit` and `budget`.

use super::args::{options, params, BudgetControl, ProjectionKind, RenderArgs};
use super::orbit::orbit;
use super::prepared::write_prepared;
use super::record::record_timed;
use crate::options::{parse_floats, NormalSource};
use crate::output::{save_ao, save_vectors};
use crate::readback::read_bent_normals;
use anyhow::{bail, Context, Result};
use glam::Vec3;
use obscura::{Ao, GpuContext};
use obscura_scene::{default_scene, Camera, CameraProjection, GBufferRenderer, Mesh};
use std::time::Instant;

/// The camera from the arguments, the built-in scene, or framing the bounds.
fn camera(a: &RenderArgs, builtin: bool, mesh: &Mesh) -> Result<Camera> {
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let up = parse_floats(&a.up, "--up")?;
    if up.len() != 3 {
        bail!("--up needs 3 numbers, got {}", up.len());
    }
    let mut fov = a.fov;
    let mut cam = match &a.camera {
        Some(s) => {
            let v = parse_floats(s, "--camera")?;
            if v.len() != 6 && v.len() != 7 {
                bail!(
                    "--camera needs 6 or 7 numbers (eye, target, optional fov), got {}",
                    v.len()
                );
            }
            if let Some(&f) = v.get(6) {
                fov = f;
            }
            let mut c = Camera {
                eye: Vec3::new(v[0], v[1], v[2]),
                target: Vec3::new(v[3], v[4], v[5]),
                up: Vec3::from_slice(&up),
                projection: CameraProjection::Perspective { fov_y_deg: fov },
                near: 0.0,
                far: 0.0,
            };
            c.fit_clip_planes(&bounds);
            c
        }
        None if builtin => default_scene::camera(),
        None => Camera::framing(&bounds, CameraProjection::Perspective { fov_y_deg: fov }),
    };
    cam.up = Vec3::from_slice(&up);
    cam.projection = match a.projection {
        ProjectionKind::Perspective => match (&a.camera, builtin) {
            (None, true) if a.fov == 60.0 => cam.projection,
            _ => CameraProjection::Perspective { fov_y_deg: fov },
        },
        ProjectionKind::Orthographic => CameraProjection::Orthographic {
            height: a.ortho_height.unwrap_or_else(|| {
                // Match the perspective view's extent at the target distance.
                2.0 * (cam.target - cam.eye).length() * (0.5 * fov.to_radians()).tan()
            }),
        },
    };
    if a.projection == ProjectionKind::Orthographic {
        // An orthographic camera sees everything in its slab: keep near small but positive.
        cam.fit_clip_planes(&bounds);
    }
    if let Some(n) = a.near {
        cam.near = n;
    }
    if let Some(f) = a.far {
        cam.far = f;
    }
    cam.validate()?;
    Ok(cam)
}

/// `obscura render` of a scene (the built-in one without --scene); arguments checked by
/// [`check_args`](super::args::check_args).
pub fn run(a: &RenderArgs) -> Result<()> {
    let t0 = Instant::now();
    // The environment first: a bad --env fails before any output is written.
    let env = a
        .ssdo
        .as_ref()
        .map(|_| crate::ssdo_shading::parse_env(&a.env))
        .transpose()?;
    let (mesh, name) = match &a.scene {
        Some(p) => (
            Mesh::load(p).with_context(|| format!("cannot load scene `{}`", p.display()))?,
            p.display().to_string(),
        ),
        None => (default_scene::mesh(), "built-in courtyard".to_string()),
    };
    let cam = camera(a, a.scene.is_none(), &mesh)?;
    let bounds = mesh.bounds().context("the scene has no triangles")?;
    let radius = a.radius.unwrap_or(0.03 * bounds.diagonal());
    eprintln!(
        "scene: {name}: {} triangles, loaded in {:.0} ms",
        mesh.triangle_count(),
        t0.elapsed().as_secs_f64() * 1e3
    );

    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let t = Instant::now();
    let raster = GBufferRenderer::new(&ctx.device);
    let gpu_mesh = raster.upload(&ctx, &mesh)?;
    let (gbuffer, msaa_depth);
    let input = if a.msaa {
        let size = (a.width, a.height);
        msaa_depth = raster.render_msaa_depth_guarded(&ctx, &gpu_mesh, &cam, size, a.guard_band)?;
        gbuffer = None;
        msaa_depth.ao_input(&cam)
    } else {
        let size = (a.width, a.height);
        gbuffer = Some(raster.render_guarded(&ctx, &gpu_mesh, &cam, size, a.guard_band)?);
        let g = gbuffer.as_ref().context("no G-buffer")?;
        g.ao_input(&cam, a.normals == NormalSource::Gbuffer)
    };
    eprintln!(
        "g-buffer: {}x{}{} in {:.1} ms (includes pipeline creation)",
        a.width,
        a.height,
        if a.msaa {
            format!(
                ", depth only, 4x MSAA (obscura resolves it; normals reconstructed){}",
                if a.guard_band > 0 {
                    format!(", and a guard band of {} px", a.guard_band)
                } else {
                    String::new()
                }
            )
        } else if a.guard_band > 0 {
            format!(
                " and a guard band of {} px ({}x{} rasterized)",
                a.guard_band,
                a.width + 2 * a.guard_band,
                a.height + 2 * a.guard_band
            )
        } else {
            String::new()
        },
        t.elapsed().as_secs_f64() * 1e3
    );

    let options = options(a);
    let params = params(a, radius);
    // The second layer, peeled at the thickness prior behind the first.
    let second = match (a.second_layer, &gbuffer) {
        (true, Some(g)) => {
            let t = Instant::now();
            let separation = params.thickness * radius;
            let layer = raster.peel(&ctx, &gpu_mesh, &cam, g, separation)?;
            eprintln!(
                "second layer: peeled {separation:.3} scene units behind the first in {:.1} ms (includes the wait)",
                t.elapsed().as_secs_f64() * 1e3
            );
            Some(layer)
        }
        _ => None,
    };
    let input = obscura::AoInput {
        second_layer: second.as_ref().map(|l| &l.view),
        ..input
    };
    let mut ao = Ao::new(&ctx.device, options)?;
    let frame = ao.validate(&input, &params)?;
    let marches = matches!(
        options.estimator,
        obscura::Estimator::Gtao | obscura::Estimator::Bitmask
    );
    eprintln!(
        "ao: {} {} directions x {} steps ({} samples/pixel){}, {}{}, radius {radius:.3} scene units",
        options.estimator.name(),
        options.directions,
        options.steps,
        options.samples_per_pixel(),
        if marches && options.march_exponent != obscura::EVEN_MARCH_EXPONENT {
            format!(", march exponent {}", options.march_exponent)
        } else {
            String::new()
        },
        options.mode.name(),
        if options.fused { "" } else { " (unfused)" },
    );
    if !options.direct() {
        eprintln!(
            "ao: {} resolution, downsample {}, upsample {}, denoise {}",
            options.resolution.name(),
            options.downsample.name(),
            options.upsample.name(),
            options.denoise.name()
        );
    }
    if let (Some(degrees), Some(dir), Some(budget)) = (a.orbit, &a.out_dir, a.budget_ms) {
        let run = match a.budget_control {
            BudgetControl::Joint => super::budget::orbit_joint,
            BudgetControl::Scale => super::budget::orbit_scaled,
            BudgetControl::Ladder => super::budget::orbit,
        };
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
        let orbit = super::budget::Orbit {
            a,
            ctx: &ctx,
            raster: &raster,
            mesh: &gpu_mesh,
            cam: &cam,
            degrees,
            dir,
            timing: obscura::Timing::best_for(&ctx),
            previous: None,
        };
        return run(orbit, options, &params, budget);
    }
    if let (Some(degrees), Some(dir)) = (a.orbit, &a.out_dir) {
        return orbit(
            a, &ctx, &raster, &gpu_mesh, &cam, &mut ao, &params, degrees, dir, t0,
        );
    }
    let values = record_timed(a, &ctx, &mut ao, &input, &params)?;
    save_ao(&a.out, &values, a.width, a.height, a.bits)?;
    eprintln!("wrote {}", a.out.display());
    if let Some(path) = &a.bent_normals_out {
        let (bent, w, h) = read_bent_normals(&ctx, &ao)?;
        save_vectors(path, &bent, w, h)?;
        eprintln!("wrote {} ({w}x{h})", path.display());
    }
    if let (Some(path), Some(g), Some(env)) = (&a.ssdo, &gbuffer, &env) {
        let lighting = crate::ssdo_shading::lighting(&env.irradiance_sh(), &cam);
        let options = obscura::SsdoOptions::default();
        let (rgb, ms) =
            crate::ssdo_shading::shade(&ctx, &ao, g, &frame, &lighting, options, a.runs)?;
        eprintln!(
            "ssdo: env {}, bounce {} slices × {} steps per pixel over {}×{} pixel classes + merge: median {ms:.2} ms over {} runs (after the AO)",
            a.env,
            options.directions,
            options.steps,
            options.period,
            options.period,
            a.runs
        );
        crate::ssdo_shading::save_radiance(path, &rgb, a.width, a.height)?;
        eprintln!("wrote {}", path.display());
    }

    write_prepared(a, (&ctx, &ao), (&input, &params), (a.width, a.height), None)?;
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    Ok(())
}

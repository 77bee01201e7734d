//! Screen-space directional occlusion shading shared by `render --ssdo FILE --env ENV`
//! (which writes a colour image) and `eval --ssdo` (which judges it against the ray tracer):
//! the `--env` environment, the lighting, running obscura's `Ssdo`, and writing radiance.

use crate::options::parse_floats;
use crate::output::save_png;
use crate::readback;
use crate::timing::median;
use anyhow::{bail, Context, Result};
use glam::Mat3;
use obscura::{
    Ao, Environment, EnvironmentMap, GpuContext, IrradianceSh, Ssdo, SsdoInputs, SsdoLighting,
    SsdoOptions,
};
use obscura_scene::{Camera, GBuffer};
use std::path::Path;
use std::time::Instant;

/// Parses `--env`: `sky` (a daylight gradient, `obscura::Environment::SKY`), `white` (a
/// constant sky of 1), `gradient:R,G,B:R,G,B` (zenith, nadir), `constant:R,G,B`, or an
/// equirectangular `.hdr` / `.exr` file.
pub fn parse_env(s: &str) -> Result<Environment> {
    let colour = |t: &str| -> Result<[f32; 3]> {
        let v = parse_floats(t, "--env colour")?;
        match v.as_slice() {
            &[r, g, b] => Ok([r, g, b]),
            _ => bail!("--env colours need 3 numbers, got `{t}`"),
        }
    };
    let env = match s {
        "sky" => Environment::SKY,
        "white" => Environment::Constant([1.0; 3]),
        _ if s.starts_with("constant:") => Environment::Constant(colour(&s[9..])?),
        _ if s.starts_with("gradient:") => {
            let Some((sky, ground)) = s[9..].split_once(':') else {
                bail!("--env gradient:R,G,B:R,G,B needs two colours, got `{s}`");
            };
            Environment::Gradient {
                sky: colour(sky)?,
                ground: colour(ground)?,
            }
        }
        _ => Environment::Map(load_map(Path::new(s))?),
    };
    env.validate()?;
    Ok(env)
}

/// An equirectangular map from a Radiance `.hdr` or OpenEXR `.exr` file (row 0 at the
/// zenith, the left edge toward +x, columns turning toward +z; negative texels, which
/// filtered HDR images can hold, are clamped to 0).
fn load_map(path: &Path) -> Result<EnvironmentMap> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if ext != "hdr" && ext != "exr" {
        bail!(
            "--env `{}` is neither sky, white, constant:R,G,B, gradient:R,G,B:R,G,B nor a .hdr \
             or .exr equirectangular map",
            path.display()
        );
    }
    let image = image::open(path)
        .with_context(|| format!("cannot read the environment map `{}`", path.display()))?
        .into_rgb32f();
    let (w, h) = image.dimensions();
    let texels = image
        .pixels()
        .map(|p| p.0.map(|v| if v < 0.0 { 0.0 } else { v }))
        .collect();
    Ok(EnvironmentMap::new(w, h, texels)?)
}

/// The camera's view-to-world rotation and the environment's harmonics (computed once per
/// environment: `Environment::irradiance_sh`).
pub fn lighting(irradiance: &IrradianceSh, cam: &Camera) -> SsdoLighting {
    SsdoLighting {
        irradiance: *irradiance,
        view_to_world: Mat3::from_mat4(cam.view_matrix().inverse()).to_cols_array_2d(),
    }
}

/// Runs SSDO after `ao`'s last frame (full resolution) and returns its radiance (rgb).
#[allow(clippy::too_many_arguments)]
pub fn shade(
    ctx: &GpuContext,
    ao: &Ao,
    gbuffer: &GBuffer,
    frame: &obscura::uniforms::FrameUniforms,
    lighting: &SsdoLighting,
    options: SsdoOptions,
    runs: u32,
) -> Result<(Vec<[f32; 3]>, f64)> {
    let mut ssdo = Ssdo::new(&ctx.device, options)?;
    let inputs = inputs(ao, gbuffer)?;
    let mut times = Vec::new();
    for round in 0..=runs {
        let t = Instant::now();
        ctx.run(|enc| ssdo.record(&ctx.device, &ctx.queue, enc, inputs, frame, lighting))?;
        if round > 0 {
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    Ok((
        read_rgb(ctx, ssdo.output().context("no SSDO output")?)?,
        median(times),
    ))
}

/// SSDO's inputs from an AO plan at full resolution and the G-buffer's albedo.
pub(crate) fn inputs<'a>(ao: &'a Ao, gbuffer: &'a GBuffer) -> Result<SsdoInputs<'a>> {
    let prepared = ao
        .prepared_source()
        .context("SSDO reads the AO's full-resolution depth and normals: use --resolution full")?;
    Ok(SsdoInputs {
        prepared,
        albedo: &gbuffer.albedo,
        ao: ao.output().context("no AO output")?,
        bent: ao.bent_normals(),
    })
}

fn read_rgb(ctx: &GpuContext, t: &wgpu::Texture) -> Result<Vec<[f32; 3]>> {
    Ok(read_rgba(ctx, t)?.0)
}

/// The rgb of an SSDO output, and where its alpha marks a surface.
pub(crate) fn read_rgba(ctx: &GpuContext, t: &wgpu::Texture) -> Result<(Vec<[f32; 3]>, Vec<bool>)> {
    let v = readback::read_rgb(ctx, t)?;
    Ok((
        v.iter().map(|c| [c[0], c[1], c[2]]).collect(),
        v.iter().map(|c| c[3] > 0.0).collect(),
    ))
}

/// Linear radiance → 8-bit sRGB (clamped at 1; sky black).
pub fn srgb8(rgb: &[[f32; 3]]) -> Vec<u8> {
    rgb.iter()
        .flatten()
        .map(|&v| {
            let v = v.clamp(0.0, 1.0);
            let s = if v <= 0.003_130_8 {
                12.92 * v
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            };
            (s * 255.0).round() as u8
        })
        .collect()
}

/// Writes radiance as an sRGB PNG, or linear float RGB for `.exr`.
pub fn save_radiance(path: &Path, rgb: &[[f32; 3]], w: u32, h: u32) -> Result<()> {
    let exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr {
        let bytes: Vec<u8> = rgb.iter().flatten().flat_map(|v| v.to_ne_bytes()).collect();
        return crate::output::save_image(
            path,
            &bytes,
            w,
            h,
            image::ExtendedColorType::Rgb32F,
            image::ImageFormat::OpenExr,
        );
    }
    save_png(path, &srgb8(rgb), w, h, image::ExtendedColorType::Rgb8)
}

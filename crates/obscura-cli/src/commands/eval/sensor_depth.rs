//! `eval --sensor`: sensor-like linear depth made from a view's clean G-buffer depth
//! (`obscura_eval::sensor`), with the sensor's own noise model and encoding step.

use anyhow::{bail, Result};
use obscura::GpuContext;
use obscura_eval::sensor;

/// A G-buffer's depth as linear view depth (0 for the sky).
pub(super) fn linear_depth(
    ctx: &GpuContext,
    g: &obscura_scene::GBuffer,
    input: &obscura::AoInput<'_>,
) -> Result<Vec<f32>> {
    let lin = input.projection.linearize(input.convention)?;
    Ok(ctx
        .read_f32(&g.depth)?
        .into_iter()
        .map(|z| lin.apply(z).unwrap_or(0.0))
        .collect())
}

/// Sensor-like linear depth made from a G-buffer's depth ([`sensor_depth`]).
pub(super) struct SensorDepth {
    pub(super) depth: Vec<f32>,
    /// Keeps `view`'s texture alive.
    _texture: wgpu::Texture,
    pub(super) view: wgpu::TextureView,
    /// The sensor's σ(z) in view units.
    pub(super) known: obscura::DepthNoise,
    /// The step of its integer encoding in view units, if it has one.
    pub(super) quantum: Option<f32>,
}

/// Sensor-like linear depth from a G-buffer's depth (obscura_eval::sensor).
pub(super) fn sensor_depth(
    ctx: &GpuContext,
    g: &obscura_scene::GBuffer,
    input: &obscura::AoInput<'_>,
    s: sensor::Sensor,
    noise_scale: f32,
) -> Result<SensorDepth> {
    let clean = linear_depth(ctx, g, input)?;
    let focal_px = match input.projection {
        obscura::Projection::Perspective { fov_y, .. } => {
            0.5 * g.height as f32 / (0.5 * fov_y).tan()
        }
        _ => bail!("--sensor needs a perspective view"),
    };
    let (noisy, map) = sensor::simulate(&clean, focal_px, s, noise_scale, 0x5eed);
    eprintln!(
        "  {} depth: the view's depth range mapped onto {}..{} m",
        s.name(),
        sensor::NEAR_M,
        sensor::FAR_M
    );
    let texture = ctx.upload_r32("sensor depth", &noisy, g.width, g.height);
    let view = texture.create_view(&Default::default());
    let (constant, linear, quadratic) = map.sigma_in_depth(s.sigma_m(focal_px));
    let noise = obscura::DepthNoise {
        constant,
        linear,
        quadratic,
        // The sensor's noise dithers its millimetre terraces away beyond 0.58 m (σ of
        // half a step): no terraces to model.
        ..obscura::DepthNoise::NONE
    };
    // Kinect-like depth is stored as integer millimetres: its unit in view units.
    let quantum = match s {
        sensor::Sensor::Kinect => Some(0.001 / map.scale),
        sensor::Sensor::Stereo => None,
    };
    Ok(SensorDepth {
        depth: noisy,
        _texture: texture,
        view,
        known: noise,
        quantum,
    })
}

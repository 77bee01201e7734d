//! GPU textures read back to the CPU in the shapes the commands use: RGBA texels, and the
//! AO's bent normals.

use anyhow::{Context, Result};
use obscura::{Ao, GpuContext};

/// The texels of an `Rgba32Float` texture.
pub(crate) fn read_rgb(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<[f32; 4]>> {
    Ok(ctx
        .read_f32(texture)?
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect())
}

/// The last frame's bent normals and their size (full, or the AO's working resolution after
/// the box or tent filter).
pub(crate) fn read_bent_normals(ctx: &GpuContext, ao: &Ao) -> Result<(Vec<[f32; 3]>, u32, u32)> {
    let t = ao
        .bent_normals()
        .context("bent normals missing after a run")?;
    let v = ctx.read_f32(t)?;
    let bent = v.chunks_exact(4).map(|c| [c[0], c[1], c[2]]).collect();
    Ok((bent, t.width(), t.height()))
}

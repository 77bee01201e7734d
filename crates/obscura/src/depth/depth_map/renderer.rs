//! [`Renderer`]: AO of depth maps on one device, the loop a batch tool runs.

use super::{invalid, Framed};
use crate::{Error, Result};

/// AO of depth maps on one device: the passes compiled once and the input textures kept
/// across maps of the same size, the loop a batch tool or the Python package runs. Native
/// only (it blocks on the GPU; on the web, record an [`crate::Ao`] yourself).
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug)]
pub struct Renderer {
    ao: crate::Ao,
    /// The depth and normal textures of the last size, with their views.
    depth: Option<(wgpu::Texture, wgpu::TextureView)>,
    normals: Option<(wgpu::Texture, wgpu::TextureView)>,
}

/// `slot`'s texture refilled with `bytes`, or a new one where the size or format differs.
#[cfg(not(target_arch = "wasm32"))]
fn refill<'a>(
    slot: &'a mut Option<(wgpu::Texture, wgpu::TextureView)>,
    ctx: &crate::GpuContext,
    label: &str,
    bytes: &[u8],
    [width, height]: [u32; 2],
    format: wgpu::TextureFormat,
) -> &'a wgpu::TextureView {
    let fits =
        |t: &wgpu::Texture| t.width() == width && t.height() == height && t.format() == format;
    match slot {
        Some((tex, _)) if fits(tex) => ctx.write(tex, bytes),
        _ => {
            let tex = ctx.upload(label, bytes, width, height, format);
            let view = tex.create_view(&Default::default());
            *slot = Some((tex, view));
        }
    }
    &slot.as_ref().expect("filled above").1
}

#[cfg(not(target_arch = "wasm32"))]
impl Renderer {
    /// Compiles the passes for `options` on `ctx`'s device.
    pub fn new(ctx: &crate::GpuContext, options: crate::AoOptions) -> Result<Self> {
        Ok(Renderer {
            ao: crate::Ao::new(&ctx.device, options)?,
            depth: None,
            normals: None,
        })
    }

    /// The options the passes were compiled for.
    pub fn options(&self) -> &crate::AoOptions {
        self.ao.options()
    }

    /// The AO of `framed` at its own size (row-major, 1 = unoccluded). `normals`: view-space
    /// normals in obscura's frame (x right, y up, z towards the camera), padded like the
    /// depth ([`Framed::pad`]), or `None` to reconstruct them from depth. `frames` > 1
    /// accumulates a still camera (with [`crate::AoOptions::history`] > 0); each call
    /// starts the history and the frame sequence anew ([`crate::Ao::restart`]), so the same
    /// map gives the same AO.
    pub fn render(
        &mut self,
        ctx: &crate::GpuContext,
        framed: &Framed,
        normals: Option<&[[f32; 4]]>,
        params: &crate::AoParams,
        frames: u32,
    ) -> Result<Vec<f32>> {
        let size = framed.padded_size;
        let depth = refill(
            &mut self.depth,
            ctx,
            "depth map",
            bytemuck::cast_slice(&framed.depth),
            size,
            wgpu::TextureFormat::R32Float,
        );
        let normals = match normals {
            Some(n) => {
                if n.len() != framed.depth.len() {
                    return Err(invalid(format!(
                        "{} normals given for a {}x{} padded depth map",
                        n.len(),
                        size[0],
                        size[1]
                    )));
                }
                Some(refill(
                    &mut self.normals,
                    ctx,
                    "normal map",
                    bytemuck::cast_slice(n),
                    size,
                    wgpu::TextureFormat::Rgba32Float,
                ))
            }
            None => None,
        };
        let input = crate::AoInput {
            depth,
            convention: crate::DepthConvention::LinearView,
            projection: framed.projection,
            normals: normals.map(|v| (v, crate::NormalEncoding::ViewSigned)),
            viewport: None,
            guard_band: 0,
            second_layer: None,
            output: None,
        };
        self.ao.restart();
        for _ in 0..frames.max(1) {
            ctx.run(|enc| self.ao.record(&ctx.device, &ctx.queue, enc, &input, params))?;
        }
        let out = self
            .ao
            .output()
            .ok_or_else(|| Error::Gpu("no AO output after a frame".into()))?;
        framed.crop(&ctx.read_f32(out)?)
    }
}

//! The prepared `vec4(linear depth, view normal)` buffer as the shading passes read it
//! ([`crate::Lights`], [`crate::Ssdo`]): an AO's ([`crate::Ao::prepared_source`]) or any
//! texture in that format, whole or as the N×N deinterleaved layers.

use crate::passes::constants::PREPARED_FORMAT;
use crate::{Error, Result};

/// Where [`crate::Lights`] reads linear depth and view normals (`vec4(d, n)`, [`PREPARED_FORMAT`],
/// `TEXTURE_BINDING` usage): an AO's [`crate::Ao::prepared_source`], or a texture of the
/// caller's.
#[derive(Clone, Copy, Debug)]
pub enum Prepared<'a> {
    /// One texture at the frame's size.
    Full(&'a wgpu::Texture),
    /// `split` × `split` layers of a `texture_2d_array` (the AO's fused deinterleaved
    /// modes): pixel (x, y) at texel (x / split, y / split) of layer
    /// `x mod split + split · (y mod split)` (src/layout.rs).
    Layers {
        texture: &'a wgpu::Texture,
        split: u32,
    },
}

impl<'a> From<&'a wgpu::Texture> for Prepared<'a> {
    fn from(t: &'a wgpu::Texture) -> Self {
        Prepared::Full(t)
    }
}

impl Prepared<'_> {
    pub(crate) fn texture(&self) -> &wgpu::Texture {
        match *self {
            Prepared::Full(t) | Prepared::Layers { texture: t, .. } => t,
        }
    }

    /// 0 for one texture, else the split.
    pub(crate) fn split(&self) -> u32 {
        match *self {
            Prepared::Full(_) => 0,
            Prepared::Layers { split, .. } => split,
        }
    }

    /// Checks format, usage and size against the frame's `size`.
    pub(crate) fn validate(&self, size: [u32; 2]) -> Result<()> {
        let t = self.texture();
        let (want, layers) = match *self {
            Prepared::Full(_) => (size, 1),
            Prepared::Layers { split, .. } => {
                if split != 2 && split != 4 {
                    return Err(Error::InvalidSetting {
                        field: "split",
                        value: split.to_string(),
                        expected: "2 or 4 (the AO's deinterleaved modes)",
                    });
                }
                (
                    [size[0].div_ceil(split), size[1].div_ceil(split)],
                    split * split,
                )
            }
        };
        let ok = t.format() == PREPARED_FORMAT
            && [t.width(), t.height()] == want
            && t.depth_or_array_layers() == layers
            && t.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING);
        if ok {
            return Ok(());
        }
        Err(Error::InvalidTexture {
            what: "prepared",
            reason: format!(
                "{:?} {}x{}x{} ({:?}); expected {PREPARED_FORMAT:?}, {}x{}x{layers} for a {}x{} frame, with TEXTURE_BINDING",
                t.format(),
                t.width(),
                t.height(),
                t.depth_or_array_layers(),
                t.usage(),
                want[0],
                want[1],
                size[0],
                size[1],
            ),
        })
    }
}

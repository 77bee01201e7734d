//! What an [`Ao`] exposes of its last frame besides the output: the intermediate textures
//! that other passes shade from ([`crate::Lights`], [`crate::Ssdo`]) and that the tests
//! compare with the CPU mirrors.

use super::ao::Ao;
use super::plan::Res;
use crate::passes::shader::Pass;
use crate::shading::prepared::Prepared;

impl Ao {
    /// The MSAA resolve's output (`R32Float`, the depth texture's size; raw depth at the
    /// viewport's texels), once a frame with a multisampled depth input was recorded.
    pub fn resolved_depth(&self) -> Option<&wgpu::Texture> {
        self.resolve.as_ref().map(|r| &r.texture)
    }

    /// The library's own AO texture (`R32Float`, viewport-sized, 1 = unoccluded), once a
    /// frame was recorded without a caller-provided [`crate::AoInput::output`].
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Output))
    }

    /// A view of [`Ao::output`].
    pub fn output_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.view(Res::Output))
    }

    /// The full-resolution prepared `vec4(linear depth, view normal)` texture
    /// (`Rgba32Float`) when the plan has one (not in fused deinterleaved modes, nor below
    /// full resolution unless unfused or upsampled bilaterally), for debugging/tests.
    pub fn prepared_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.view(Res::Prepared))
    }

    /// The texture behind [`Ao::prepared_view`] (`Rgba32Float`), for passes that shade
    /// from it ([`crate::Lights`]).
    pub fn prepared(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Prepared))
    }

    /// The full-resolution depth and normals of the last frame for passes that shade from
    /// them ([`crate::Lights`]): the prepared buffer, or in the fused deinterleaved modes
    /// its N×N layers. `None` below full resolution, where only the working grid's exist.
    pub fn prepared_source(&self) -> Option<Prepared<'_>> {
        if self.options.resolution != crate::Resolution::Full {
            return None;
        }
        let sized = self.sized.as_ref()?;
        if let Some(t) = sized.texture(Res::Prepared) {
            return Some(Prepared::Full(t));
        }
        sized
            .texture(Res::PreparedLayers)
            .map(|texture| Prepared::Layers {
                texture,
                split: self.options.mode.split(),
            })
    }

    /// Full-resolution linear view depth (`R32Float`, 0 = sky) when AO runs below full
    /// resolution with the fused prepare ([`crate::AoOptions::fused`]) and an upsampler that needs
    /// no normals (else the prepared buffer holds it), for debugging/tests.
    pub fn linear_depth(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .and_then(|s| s.texture(Res::LinearDepth))
    }

    /// The second depth layer's linear view depth (`R32Float`, 0 = none) over the
    /// processed rectangle, as the prepare pass wrote it ([`crate::AoOptions::second_layer`]),
    /// for debugging/tests.
    pub fn second_layer(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .and_then(|s| s.texture(Res::SecondLayer))
    }

    /// The depth pyramid (`Rgba32Float`, `vec4(select, min, max, 0)`, mip m = level m + 1)
    /// when the estimator or the upsampler uses one.
    pub fn pyramid(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Pyramid))
    }

    /// The depth moments pyramid (`Rgba32Float`, `vec4(valid fraction, mean, variance, 0)`
    /// of linear depth, mip m = level m + 1) when the estimator is VO's area integral.
    pub fn moments(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Moments))
    }

    /// The prepared buffer downsampled `k ≥ 1` times by the depth rule (below full
    /// resolution), `ceil(size / 2^k)`, `Rgba32Float`.
    pub fn prepared_level(&self, k: u32) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Level(k)))
    }

    /// The bent normals of the last frame ([`crate::AoOptions::bent_normals`]), after the temporal
    /// pass, the denoiser and the upsampler where they run: `Rgba32Float` at full
    /// resolution (at the working resolution after the box or tent filter), `vec4(n, 0)`
    /// with n the unit bent normal in view space (+z toward the camera, as the prepared
    /// normals), zero on sky.
    pub fn bent_normals(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Bent))
    }

    /// The temporal history written by the last frame (`Rgba32Float` at the working
    /// resolution; with [`crate::Resolution::Scaled`] a full-size texture whose top-left
    /// `ceil(full × scale)` texels hold it: `vec4(AO, frames accumulated (0 = sky), linear
    /// depth, packed normal)`
    /// (`reference::unpack_normal` decodes it)), when
    /// [`crate::AoOptions::history`] is on and a frame was recorded.
    pub fn history(&self) -> Option<&wgpu::Texture> {
        let parity = self.temporal.parity;
        self.sized
            .as_ref()
            .filter(|_| self.temporal.frame > 0)
            .and_then(|s| s.texture(Res::History(parity)))
    }

    /// The bent-normal history written by the last frame (as [`Ao::bent_normals`]), when
    /// bent normals and [`crate::AoOptions::history`] are on and a frame was recorded.
    pub fn bent_history(&self) -> Option<&wgpu::Texture> {
        let parity = self.temporal.parity;
        self.sized
            .as_ref()
            .filter(|_| self.temporal.frame > 0)
            .and_then(|s| s.texture(Res::BentHistory(parity)))
    }

    /// The AO pass's own bent normals, when a temporal pass or the denoiser follows it (for
    /// tests against the CPU mirror).
    pub fn bent_normals_raw(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::BentRaw))
    }

    /// The AO at working resolution: below full resolution what the upsampler reads
    /// (after temporal accumulation and denoising), else the AO pass's own output before
    /// them, when the plan keeps one (not where it is packed for the denoiser, as
    /// [`Self::raw_ao`] says).
    pub fn working_ao(&self) -> Option<&wgpu::Texture> {
        let upsampled = self.plan.steps.iter().find_map(|st| match st.pass {
            Pass::Upsample { .. } | Pass::UpsampleScaled => {
                st.views.iter().find(|v| v.0 == 2).map(|v| v.1)
            }
            _ => None,
        });
        let r = match upsampled {
            Some(r @ (Res::AoWork | Res::AoTmp)) => r,
            _ => Res::AoWork,
        };
        self.sized.as_ref().and_then(|s| s.texture(r))
    }

    /// The prepared buffer at the last frame's scale with [`crate::Resolution::Scaled`]
    /// (`Rgba32Float`, created at full size; the working grid is its top-left
    /// `ceil(full × scale)` texels).
    pub fn scaled_prepared(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Scaled))
    }

    /// The AO pass's own output at working resolution when it does not write the output
    /// directly (for tests against the CPU mirrors). Below full resolution with both the
    /// temporal pass and the denoiser, the denoiser writes over it. `None` where the
    /// spatial denoiser follows the AO pass directly: the AO pass then stores its AO packed
    /// beside the geometry (passes/estimators/ao_packed.wgsl).
    pub fn raw_ao(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::AoWork))
    }

    /// The deinterleaved prepared layers (`Rgba32Float` array, N² layers) in deinterleaved modes.
    pub fn prepared_layers_view(&self) -> Option<&wgpu::TextureView> {
        self.sized
            .as_ref()
            .and_then(|s| s.view(Res::PreparedLayers))
    }
}

//! The frame plan's data types ([`super::plan`] builds them): the textures the passes
//! bind, the steps that bind them, and each texture's spec and lifetime.

use crate::passes::shader::Pass;

/// A texture the passes read or write. Sizes: `full` = the viewport, `work` = the AO's
/// working resolution (`ceil(full / resolution factor)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Res {
    /// `prepared`: full size, PREPARED_FORMAT.
    Prepared,
    /// `linear depth`: full size, LINEAR_DEPTH_FORMAT (written by
    /// [`PrepareStore::Down`](crate::passes::shader::PrepareStore::Down)).
    LinearDepth,
    /// `second layer`: full size, LINEAR_DEPTH_FORMAT: the second depth layer's linear
    /// depth, written by the prepare pass ([`crate::AoOptions::second_layer`]).
    SecondLayer,
    /// `prepared_layers`: work layer size × N² layers, PREPARED_FORMAT (deinterleaved).
    PreparedLayers,
    /// `prepared` downsampled k ≥ 1 times by the depth rule: `ceil(full / 2^k)`.
    Level(u32),
    /// `prepared` at the frame's scale ([`crate::Resolution::Scaled`]): created at full
    /// size, the working grid `ceil(full × scale)` used.
    Scaled,
    /// `pyramid`: `max(1, full >> 1)` with every mip, PYRAMID_FORMAT; all mips.
    Pyramid,
    /// One mip of the pyramid.
    PyramidMip(u32),
    /// `moments`: the pyramid's size and mips, MOMENTS_FORMAT (VO's area integral).
    Moments,
    /// One mip of the moments pyramid.
    MomentsMip(u32),
    /// `ao_work`: work size, AO_FORMAT (when post-processing follows the AO pass).
    AoWork,
    /// `ao_packed`: work size, AO_PACKED_FORMAT: the AO beside its geometry, written by the
    /// pass before the spatial denoiser (the AO pass or the temporal pass) for it.
    AoPacked,
    /// `ao_tmp`: work size, AO_FORMAT (the working AO's second texture: what a pass after
    /// the AO pass writes when it reads [`Res::AoWork`]).
    AoTmp,
    /// `ao_layers`: work layer size × N², AO_FORMAT (unfused deinterleaved).
    AoLayers,
    /// `ao_half`: `ceil(work / 2)`, AO_FORMAT (box or tent denoise).
    AoHalf,
    /// `output`: full size, AO_FORMAT.
    Output,
    /// The temporal history read this frame (last frame's): work size, HISTORY_FORMAT;
    /// one of the two [`Res::History`] textures, alternating by frame.
    HistoryPrev,
    /// The temporal history written this frame: the other [`Res::History`] texture.
    HistoryNext,
    /// History texture 0 or 1 (what `HistoryPrev`/`HistoryNext` resolve to).
    History(u32),
    /// `bent normals`: work size, BENT_FORMAT (the result, [`crate::Ao::bent_normals`]).
    Bent,
    /// `bent normals raw`: work size, BENT_FORMAT (the AO pass's, when a temporal pass or
    /// the denoiser follows).
    BentRaw,
    /// `bent normals accumulated`: work size, BENT_FORMAT (between the temporal pass and
    /// the denoiser).
    BentTmp,
    /// The bent-normal history read this frame, as [`Res::HistoryPrev`].
    BentHistoryPrev,
    /// The bent-normal history written this frame, as [`Res::HistoryNext`].
    BentHistoryNext,
    /// Bent-normal history texture 0 or 1: work size, BENT_FORMAT.
    BentHistory(u32),
}

impl Res {
    /// The texture this resource is on frame parity `parity` (history alternates).
    pub fn at_parity(self, parity: u32) -> Res {
        match self {
            Res::HistoryPrev => Res::History(parity),
            Res::HistoryNext => Res::History(1 - parity),
            Res::BentHistoryPrev => Res::BentHistory(parity),
            Res::BentHistoryNext => Res::BentHistory(1 - parity),
            r => r,
        }
    }
}

/// Which uniform buffer a pass binds: the full-resolution frame or the working one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameAt {
    Full,
    Work,
}

/// The invocation grid of a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grid {
    /// One invocation per pixel of a prepared level (0 = full resolution).
    Level(u32),
    /// One invocation per pixel of this frame's working grid ([`crate::Resolution::Scaled`]).
    Work,
    /// Work layer texels × N² layers (of this frame's working grid).
    Layers,
    /// One dispatch per pyramid (or moments) mip after the first, or per four of them (each
    /// reads the mip above).
    PyramidMips,
    /// Pyramid mip 0.
    PyramidBase,
}

/// One pass of the plan: what it binds (binding → texture), with which frame, over which grid.
#[derive(Clone, Debug)]
pub struct Step {
    pub pass: Pass,
    pub views: Vec<(u32, Res)>,
    pub frame: FrameAt,
    pub grid: Grid,
}

/// How long a texture's contents live.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lifetime {
    /// Written and read within one frame.
    Frame,
    /// Carried from one frame to the next (the temporal histories).
    AcrossFrames,
    /// The caller's (the AO output, when [`crate::AoInput::output`] is given; else created
    /// on the first frame that asks for the library's own).
    Caller,
}

/// A texture of the plan: what [`super::resources`] creates for a frame size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureSpec {
    pub res: Res,
    pub label: &'static str,
    /// Width and height of mip 0.
    pub size: (u32, u32),
    pub layers: u32,
    pub mips: u32,
    pub format: wgpu::TextureFormat,
    pub lifetime: Lifetime,
}

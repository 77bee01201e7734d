//! What temporal accumulation carries from frame to frame besides its history textures
//! (which the plan lists, [`super::plan::Lifetime::AcrossFrames`]): the frame count that
//! rotates the sampling patterns, which history texture is current, and the previous
//! frame's projection and working grid for reprojection.

use crate::passes::uniforms::FrameUniforms;
use crate::{AoOptions, CameraMotion};

/// What temporal accumulation remembers between frames.
#[derive(Debug, Default)]
pub(crate) struct TemporalState {
    /// Frames recorded so far (the sampling patterns rotate with it).
    pub(crate) frame: u32,
    /// Whether the history texture holds the previous frame at this size.
    pub(crate) valid: bool,
    /// Which history texture this frame reads (0 or 1).
    pub(crate) parity: u32,
    /// The previous frame's projection scale and kind.
    pub(crate) previous: Option<([f32; 2], u32)>,
    /// The previous frame's working grid (`size`, `inv_size`), which the history holds.
    pub(crate) grid: Option<([u32; 2], [f32; 2])>,
}

impl TemporalState {
    /// Points this frame's working uniforms at the grid the history holds (the last frame's,
    /// which [`crate::Resolution::Scaled`] may have run at another scale) and remembers this one.
    pub(crate) fn set_grid(&mut self, work: &mut FrameUniforms) {
        if let (Some((size, inv_size)), true) = (self.grid, work.history != 0) {
            work.prev_size = size;
            work.prev_inv_size = inv_size;
        }
        self.grid = Some((work.size, work.inv_size));
    }
}

impl TemporalState {
    /// Fills this frame's temporal uniforms and rotated patterns, and advances to the next
    /// frame; returns the parity of this frame's bind groups. Without temporal
    /// accumulation nothing changes (parity 0, the patterns of frame 0).
    pub(crate) fn apply(
        &mut self,
        o: &AoOptions,
        motion: CameraMotion,
        f: &mut FrameUniforms,
    ) -> u32 {
        if o.history == 0 {
            return 0;
        }
        let parity = self.parity;
        let same_kind = self.previous.is_some_and(|p| p.1 == f.perspective);
        let valid = self.valid && same_kind && motion != CameraMotion::Cut;
        f.history = valid as u32;
        if let (Some((scale, _)), true) = (self.previous, valid) {
            f.prev_ndc_to_view = scale;
        }
        if let CameraMotion::Moved {
            previous_from_current,
        } = motion
        {
            f.prev_from_view = previous_from_current;
        }
        if o.jitter {
            f.patterns = crate::passes::jitter::pattern_table_frame(
                crate::passes::jitter::rotation_sector(o.estimator, o.directions),
                self.frame,
            );
        }
        self.frame = self.frame.wrapping_add(1);
        self.valid = true;
        self.parity = 1 - parity;
        self.previous = Some((f.ndc_to_view, f.perspective));
        parity
    }
}

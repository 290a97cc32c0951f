//! What the temporal anti-aliasing keeps from frame to frame: the jitter's place, the
//! camera the history was drawn from, which history is read, and when the history
//! holds nothing to blend.

use ash::vk;
use shared::plan::{FramePlan, FrameRequest};

/// What the temporal anti-aliasing keeps between frames: the jitter's place, the
/// camera the history was drawn from and which history is read.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Temporal {
    /// Frames drawn with it.
    pub(super) frame: u32,
    /// The last frame's unjittered view-projection; `None` while the history holds
    /// nothing to blend.
    pub(super) previous: Option<glam::Mat4>,
    /// The history the next frame reads (the other is written).
    pub(super) read: usize,
    /// What the history was drawn as: (size, look, view); another empties it.
    drawn_as: Option<(vk::Extent2D, shared::settings::Look, shared::settings::View)>,
}

impl Temporal {
    /// Before a frame of `plan` into a target of `extent`: the history goes where the
    /// frame is drawn otherwise than it was (a new size, look or view, or no TAA).
    pub(super) fn begin(&mut self, plan: &FramePlan, extent: vk::Extent2D) {
        let drawn_as = plan.taa.then_some((extent, plan.look, plan.view));
        if drawn_as != self.drawn_as || drawn_as.is_none() {
            self.previous = None;
        }
        self.drawn_as = drawn_as;
    }

    /// After a frame of `plan` seen as `request` asks was recorded: its camera is the
    /// next frame's previous one, and the history it wrote the next one's read.
    pub(super) fn end(&mut self, plan: &FramePlan, request: &FrameRequest) {
        if plan.taa {
            self.previous = Some(request.eye.view_proj);
            self.read = 1 - self.read;
            self.frame = self.frame.wrapping_add(1);
        }
    }
}

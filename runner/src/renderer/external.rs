//! A frame drawn into someone else's targets (the embedding API, `crate::embed`):
//! simulate, cull and compact as in [`Renderer::record`], then the grass (and the
//! ground, if asked) drawn over the colour and depth the caller already rendered,
//! loaded and stored in their layouts. The natural look draws linear radiance (its
//! clumps, colours, translucency, sun shadows and fog) for the caller's own exposure
//! and tone map: the renderer's HDR image, tone map and sky would draw over the
//! caller's picture. No occlusion pre-pass, compute rasterizer, MSAA or temporal
//! anti-aliasing (the caller's own resolves the frame): the caller's depth test
//! hides what its scene hides.

use super::{FrameQueries, Mark, Renderer};
use crate::passes::draw::LoadedImages;
use crate::vulkan::Recorder;
use anyhow::Result;
use ash::vk;
use shared::gpu::layout::SimulatePush;
use shared::plan::{FramePlan, FrameRequest};

/// Colour and depth images of a caller, in `COLOR_ATTACHMENT_OPTIMAL` and
/// `DEPTH_ATTACHMENT_OPTIMAL`, single-sampled.
#[derive(Copy, Clone, Debug)]
pub struct ExternalTargets {
    /// The colour view (of the format the renderer was made for).
    pub color: vk::ImageView,
    /// The depth view ([`crate::passes::DEPTH_FORMAT`]; 0 near and 1 far, or
    /// reversed, as [`ExternalFrame::reverse_z`] says).
    pub depth: vk::ImageView,
    /// Their size.
    pub extent: vk::Extent2D,
}

/// What one frame drawn into a caller's targets asks of the renderer.
pub struct ExternalFrame {
    /// Where it draws.
    pub targets: ExternalTargets,
    /// What the frame shows (drawn at one sample, without occlusion or far blades,
    /// whatever its settings ask).
    pub request: FrameRequest,
    /// The simulation steps to run.
    pub push: SimulatePush,
    /// Draw the ground the blades grow on (else only the blades).
    pub ground: bool,
    /// The caller's depth is reversed: 1 near, 0 far (the depth test keeps the
    /// greater).
    pub reverse_z: bool,
}

impl Renderer {
    /// Records `frame` into `rec`, outside any rendering scope; its counters and
    /// timestamps go to `queries`.
    pub fn record_external(
        &mut self,
        rec: &Recorder,
        queries: &FrameQueries,
        frame: &ExternalFrame,
    ) -> Result<()> {
        let extent = frame.targets.extent;
        // The renderer's own depth image stays the compute passes' bound (unread)
        // depth: the descriptor set must hold one.
        self.ensure_targets(super::targets::TargetSpec {
            extent,
            hdr: false,
            samples: 1,
            taa: false,
            deferred: false,
            reverse_z: frame.reverse_z,
            shown: false,
        })?;
        // The caller's own depth makes no pyramid here, and its targets take one
        // sample, no history and no far blades, drawn at their size.
        let plan = FramePlan {
            samples: 1,
            taa: false,
            scale: 1.0,
            ..frame.request.plan().within(false, false)
        };
        let uniforms = self.prepare(&frame.request, &plan, frame.push, extent)?;
        let stamp = super::stamper(rec, queries);
        stamp(Mark::Start);
        // Orders this frame after the caller's rendering into the targets too (a
        // global dependency on every stage a frame uses).
        let colliders = &frame.request.colliders()[..uniforms.forces.colliders as usize];
        let questions = frame.request.questions();
        self.begin_compute(rec, &uniforms, (colliders, questions));
        self.record_tiles(rec, (&uniforms, colliders), frame.push)?;
        stamp(Mark::Pyramid);
        // The caller draws its own colliders: none in the shadow map.
        let asked = (colliders, false, super::Asked::of(&frame.request));
        self.record_simulation(rec, &plan, frame.push, asked, &stamp)?;
        let images = LoadedImages {
            color: frame.targets.color,
            depth: frame.targets.depth,
            extent,
        };
        self.draw
            .record_over(rec, &self.field, &images, &plan, frame.ground, &stamp);
        // No compute rasterizer, resolve, tone map or overlay here.
        for mark in [Mark::Raster, Mark::Resolve, Mark::Shade, Mark::ToneMap] {
            stamp(mark);
        }
        self.copy_counters(rec, queries);
        stamp(Mark::Overlay);
        Ok(())
    }
}

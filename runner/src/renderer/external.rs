//! A frame drawn into someone else's targets (the embedding API, `crate::embed`):
//! simulate, cull and compact as in [`Renderer::record`], then the grass (and the
//! ground, if asked) drawn over the colour and depth the caller already rendered,
//! loaded and stored in their layouts. The paper look only: the natural look's HDR
//! image, tone map and sky would draw over the caller's picture. No occlusion
//! pre-pass, compute rasterizer, shadows or MSAA: the caller's depth test hides what
//! its scene hides.

use super::{FrameQueries, Renderer};
use crate::vulkan::{Attachments, Recorder};
use anyhow::{Result, bail};
use ash::vk;
use shared::cull::OCCLUSION;
use shared::layout::{FrameUniforms, SimulatePush};
use shared::look::LOOK_NATURAL;

/// Colour and depth images of a caller, in `COLOR_ATTACHMENT_OPTIMAL` and
/// `DEPTH_ATTACHMENT_OPTIMAL`, single-sampled.
#[derive(Copy, Clone, Debug)]
pub struct ExternalTargets {
    /// The colour view (of the format the renderer was made for).
    pub color: vk::ImageView,
    /// The depth view ([`crate::passes::DEPTH_FORMAT`]; 0 near, 1 far).
    pub depth: vk::ImageView,
    /// Their size.
    pub extent: vk::Extent2D,
}

/// What one frame drawn into a caller's targets asks of the renderer.
pub struct ExternalFrame {
    /// Where it draws.
    pub targets: ExternalTargets,
    /// The frame's uniform block (paper look).
    pub uniforms: FrameUniforms,
    /// The simulation steps to run.
    pub push: SimulatePush,
    /// Draw the ground the blades grow on (else only the blades).
    pub ground: bool,
}

impl Renderer {
    /// Records `frame` into `rec`, outside any rendering scope; its counters go to
    /// `queries`.
    pub fn record_external(
        &mut self,
        rec: &Recorder,
        queries: &FrameQueries,
        frame: &ExternalFrame,
    ) -> Result<()> {
        let mut uniforms = frame.uniforms;
        if uniforms.look.style == LOOK_NATURAL {
            bail!(
                "an embedded field draws the paper look (the natural look's tone map and \
                 sky would cover the caller's picture)"
            );
        }
        let extent = frame.targets.extent;
        // The renderer's own depth image stays the compute passes' bound (unread)
        // depth: the descriptor set must hold one.
        self.ensure_targets(extent, false, 1)?;
        uniforms.cull.enabled &= !OCCLUSION;
        uniforms.hiz = Default::default();
        uniforms.look.samples = 1;
        uniforms.look.shadows = 0;
        uniforms.raster.below = 0.0;
        uniforms.raster.width = extent.width;
        uniforms.raster.height = extent.height;
        self.tile_uniforms(&mut uniforms);
        uniforms.forces.time =
            shared::simulate::step_time(frame.push.first_step + frame.push.steps);
        self.ground.follow(uniforms.camera.position);
        // Orders this frame after the caller's rendering into the targets too (a
        // global dependency on every stage a frame uses).
        self.begin_compute(rec, &uniforms);
        if let Some(tiles) = self.tiles.as_mut() {
            let seconds = frame.push.steps as f32 * shared::simulate::STEP_SECONDS;
            tiles.record(rec, &self.field, &uniforms, seconds)?;
        }
        let mesh = uniforms.grass.pipeline == shared::layout::PIPELINE_MESH;
        self.record_compute(rec, self.simulate_push(frame.push), false, mesh);
        let loaded = Attachments {
            color: Some((frame.targets.color, None)),
            color_resolve: None,
            depth: Some((frame.targets.depth, false)),
        };
        rec.begin_rendering_with(&loaded, extent);
        let grass = &uniforms.grass;
        self.grass.record(
            rec,
            &self.field,
            grass.view,
            uniforms.look.style,
            grass.pipeline,
        );
        if frame.ground {
            self.ground.record(rec, &self.field, &[]);
        }
        rec.end_rendering();
        self.copy_counters(rec, queries);
        Ok(())
    }
}

//! The occluders of the occlusion test: the scene's surfaces drawn depth-only with
//! this frame's camera, copied into the pyramid buffer as level 0, then reduced level
//! by level to the farthest depth of each 2×2 block (`shared::hiz`).

use crate::field::{Field, PUSH_CONSTANTS};
use crate::passes::ground::GroundPass;
use crate::shaders;
use crate::vulkan::pipeline::{Pipeline, ShaderModules};
use crate::vulkan::{Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use shared::cull::hiz::{HiZLayout, level_size};
use shared::gpu::layout::{HIZ_WORKGROUP, HiZPush};
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The pyramid reduction and the pyramid's layout for the current target.
pub struct OcclusionPass {
    build: Pipeline,
    /// Layout of the pyramid in `Field::pyramid`.
    pub hiz: HiZLayout,
}

impl OcclusionPass {
    /// The reduction pipeline; the pyramid is sized by [`OcclusionPass::resize`].
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules, field: &Field) -> Result<Self> {
        Ok(Self {
            build: Pipeline::compute(ctx, &field.layout, module, shaders::BUILD_HIZ)?,
            hiz: HiZLayout::default(),
        })
    }

    /// Sizes the pyramid for a target of `extent`. No frame may be in flight.
    pub fn resize(
        &mut self,
        ctx: &Arc<Context>,
        field: &mut Field,
        extent: vk::Extent2D,
    ) -> Result<()> {
        self.hiz = HiZLayout::new(extent.width, extent.height);
        field.resize_pyramid(ctx, self.hiz.len)
    }

    /// Records the occluder depth into `depth` (left in TRANSFER_SRC_OPTIMAL) and the
    /// pyramid, which is then ready for the compute pass to read. The uniforms must
    /// hold this pass's layout.
    pub fn record(&self, rec: &Recorder, field: &Field, ground: &GroundPass, depth: &Image) {
        let aspect = vk::ImageAspectFlags::DEPTH;
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        rec.image_barrier(
            depth.image,
            aspect,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            (tests | S::COPY, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (tests, depth_rw),
        );
        rec.begin_rendering(None, Some(depth.view), depth.extent);
        ground.record_occluders(rec, field);
        rec.end_rendering();
        rec.image_barrier(
            depth.image,
            aspect,
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            ),
            (S::LATE_FRAGMENT_TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (S::COPY, A::TRANSFER_READ),
        );
        rec.copy_image_to_buffer(depth.image, aspect, depth.extent, field.pyramid.buffer);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let written = (
            S::COPY | S::COMPUTE_SHADER,
            A::TRANSFER_WRITE | A::SHADER_WRITE,
        );
        let read = (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE);
        rec.memory_barrier(written, read);
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        rec.bind_pipeline(compute, self.build.pipeline, layout, set);
        for level in 1..self.hiz.levels {
            let (w, h) = level_size(self.hiz.width, self.hiz.height, level);
            let push = HiZPush { level };
            rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
            rec.dispatch((w.div_ceil(HIZ_WORKGROUP), h.div_ceil(HIZ_WORKGROUP)));
            rec.memory_barrier(written, read);
        }
    }
}

//! The temporal resolve (`shared::draw::temporal`, Karis 2014): after the draw, a
//! compute pass blends each pixel of the HDR image into the history its motion finds
//! (clipped to its neighbourhood) and writes the next history, which the tone map
//! shows. Two histories take turns: one read, the other written.

use super::to_sampled;
use crate::field::Field;
use crate::shaders;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::sampler::Sampler;
use crate::vulkan::{Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use shared::gpu::layout::TEMPORAL_WORKGROUP;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The resolve's set (`compute::temporal::resolve_taa`): the HDR image, the motion
/// target, the depth, the history read, its sampler, the frame block and the history
/// written.
pub const BINDINGS: [BindingSpec; 7] = [
    compute(0, vk::DescriptorType::SAMPLED_IMAGE),
    compute(1, vk::DescriptorType::SAMPLED_IMAGE),
    compute(2, vk::DescriptorType::SAMPLED_IMAGE),
    compute(3, vk::DescriptorType::SAMPLED_IMAGE),
    compute(4, vk::DescriptorType::SAMPLER),
    compute(5, vk::DescriptorType::STORAGE_BUFFER),
    compute(6, vk::DescriptorType::STORAGE_IMAGE),
];

/// Binding `binding` of type `ty`, seen by the compute stage.
const fn compute(binding: u32, ty: vk::DescriptorType) -> BindingSpec {
    BindingSpec {
        binding,
        ty,
        stages: vk::ShaderStageFlags::COMPUTE,
    }
}

/// What the temporal resolve reads and writes.
#[derive(Copy, Clone)]
pub struct TemporalImages<'a> {
    /// The frame as drawn (HDR, one sample).
    pub hdr: &'a Image,
    /// Each pixel's motion (`passes::by_target::MOTION_FORMAT`).
    pub motion: &'a Image,
    /// The draw's depth.
    pub depth: &'a Image,
    /// The two histories: one read, the other written.
    pub history: &'a [Image; 2],
}

/// The resolve's pipeline and its two sets: set k reads history k and writes the
/// other.
pub struct TemporalPass {
    sets: [DescriptorSet; 2],
    layout: PipelineLayout,
    pipeline: Pipeline,
    sampler: Sampler,
}

impl TemporalPass {
    /// The pipeline; its sets name the images with [`Self::set_images`].
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules) -> Result<Self> {
        let sets = [
            DescriptorSet::new(ctx, &BINDINGS)?,
            DescriptorSet::new(ctx, &BINDINGS)?,
        ];
        let layout = PipelineLayout::new(ctx, sets[0].layout, (vk::ShaderStageFlags::COMPUTE, 0))?;
        let pipeline = Pipeline::compute(ctx, &layout, module, shaders::RESOLVE_TAA)?;
        Ok(Self {
            sets,
            layout,
            pipeline,
            sampler: Sampler::linear_clamped(ctx)?,
        })
    }

    /// Reads and writes `images` (and `field`'s frame block) from now on. No frame
    /// may be in flight.
    pub fn set_images(&self, images: TemporalImages, field: &Field) {
        for (k, set) in self.sets.iter().enumerate() {
            set.write_sampled_image(0, images.hdr.view);
            set.write_sampled_image(1, images.motion.view);
            set.write_sampled_image(2, images.depth.view);
            set.write_sampled_image(3, images.history[k].view);
            set.write_sampler(4, self.sampler.sampler);
            let storage = vk::DescriptorType::STORAGE_BUFFER;
            set.write_buffer(5, storage, field.uniforms.buffer);
            set.write_storage_image(6, images.history[1 - k].view);
        }
    }

    /// The resolve of `images` over `extent`: history `read` read (none on a
    /// `reset`), the other written and left sampled for the tone map and the next
    /// frame; the HDR image, the motion target and the depth from the draw to sampled.
    pub fn record(
        &self,
        rec: &Recorder,
        images: TemporalImages,
        extent: vk::Extent2D,
        (read, reset): (usize, bool),
    ) {
        let color = vk::ImageAspectFlags::COLOR;
        let compute = (S::COMPUTE_SHADER, A::SHADER_READ);
        to_sampled(rec, images.hdr.image, compute);
        to_sampled(rec, images.motion.image, compute);
        rec.image_barrier(
            images.depth.image,
            vk::ImageAspectFlags::DEPTH,
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            compute,
        );
        let history = images.history;
        if reset {
            // Nothing to read, but the set names it in the sampled layout.
            rec.image_barrier(
                history[read].image,
                color,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                ),
                (S::COMPUTE_SHADER, A::NONE),
                compute,
            );
        }
        let written = &history[1 - read];
        // After the last frame's tone map and resolve read it.
        rec.image_barrier(
            written.image,
            color,
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
            (S::FRAGMENT_SHADER | S::COMPUTE_SHADER, A::NONE),
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
        );
        rec.bind_pipeline(
            vk::PipelineBindPoint::COMPUTE,
            self.pipeline.pipeline,
            self.layout.layout,
            self.sets[read].set,
        );
        let groups = |n: u32| n.div_ceil(TEMPORAL_WORKGROUP);
        rec.dispatch((groups(extent.width), groups(extent.height)));
        rec.image_barrier(
            written.image,
            color,
            (
                vk::ImageLayout::GENERAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::FRAGMENT_SHADER | S::COMPUTE_SHADER, A::SHADER_READ),
        );
    }
}

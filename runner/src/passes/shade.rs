//! The natural look shaded after the draw, at one sample per pixel
//! (`shared::draw::look::visibility`; Burns and Hunt's visibility buffer): the grass
//! drew, for each pixel it covers, which blade and where on it, packed into the HDR
//! image; this compute pass (`compute::shade::shade_natural`) shades those pixels in
//! place from the dressed blades and, with temporal anti-aliasing, writes every
//! pixel's own motion. It reads the field's set (the frame block, the dressed
//! blades, their previous control points and the shadow map) and its own (the two
//! images).

use crate::field::Field;
use crate::shaders;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::{Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use shared::gpu::layout::TEMPORAL_WORKGROUP;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// The pass's own set (set 1 of `compute::shade::shade_natural`): the HDR image, read
/// and shaded in place, and the motion image written.
pub const BINDINGS: [BindingSpec; 2] = [
    BindingSpec {
        binding: 0,
        ty: vk::DescriptorType::STORAGE_IMAGE,
        stages: vk::ShaderStageFlags::COMPUTE,
    },
    BindingSpec {
        binding: 1,
        ty: vk::DescriptorType::STORAGE_IMAGE,
        stages: vk::ShaderStageFlags::COMPUTE,
    },
];

/// The shading's pipeline and its set.
pub struct ShadePass {
    set: DescriptorSet,
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl ShadePass {
    /// The pipeline, over `field`'s set and its own; the images come with
    /// [`Self::set_images`].
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules, field: &Field) -> Result<Self> {
        let set = DescriptorSet::new(ctx, &BINDINGS)?;
        let sets = [field.descriptors.layout, set.layout];
        let layout = PipelineLayout::of_sets(ctx, &sets, (vk::ShaderStageFlags::COMPUTE, 0))?;
        let pipeline = Pipeline::compute(ctx, &layout, module, shaders::SHADE_NATURAL)?;
        Ok(Self {
            set,
            layout,
            pipeline,
        })
    }

    /// Shades `hdr` and writes `motion` from now on. No frame may be in flight.
    pub fn set_images(&self, hdr: &Image, motion: &Image) {
        self.set.write_storage_image(0, hdr.view);
        self.set.write_storage_image(1, motion.view);
    }

    /// The shading of `hdr` over `extent`, after the draw: `hdr` from the draw's
    /// colour attachment to shaded, and `motion` written; both are left in the colour
    /// attachment layout, as the draw leaves its targets, for the passes after.
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        (hdr, motion): (&Image, &Image),
        extent: vk::Extent2D,
    ) {
        let color = vk::ImageAspectFlags::COLOR;
        let shader_rw = (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE);
        rec.image_barrier(
            hdr.image,
            color,
            (L::COLOR_ATTACHMENT_OPTIMAL, L::GENERAL),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            shader_rw,
        );
        // After the last frame's resolve read it.
        rec.image_barrier(
            motion.image,
            color,
            (L::UNDEFINED, L::GENERAL),
            (S::COMPUTE_SHADER, A::NONE),
            shader_rw,
        );
        rec.bind_pipeline_sets(
            vk::PipelineBindPoint::COMPUTE,
            self.pipeline.pipeline,
            self.layout.layout,
            &[field.descriptors.set, self.set.set],
        );
        let groups = |n: u32| n.div_ceil(TEMPORAL_WORKGROUP);
        rec.dispatch((groups(extent.width), groups(extent.height)));
        for image in [hdr.image, motion.image] {
            rec.image_barrier(
                image,
                color,
                (L::GENERAL, L::COLOR_ATTACHMENT_OPTIMAL),
                (S::COMPUTE_SHADER, A::SHADER_WRITE),
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            );
        }
    }
}

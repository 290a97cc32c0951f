//! The natural look's last pass: a grid of cells over the screen that puts the sky
//! (or the meadow beyond the field) behind the scene in the HDR image, where its alpha
//! leaves room, and tone-maps it into the sRGB target (`shared::draw::look::sky::tone_map`,
//! Narkowicz's ACES fit). The sky is evaluated at the grid's corners and
//! interpolated; the sun disc and the tone map run per pixel.

use crate::shaders;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::gpu::layout::{FrameUniforms, ToneMapPush};
use std::sync::Arc;

/// The tone map's own set: the HDR image.
pub const BINDINGS: [BindingSpec; 1] = [BindingSpec {
    binding: 0,
    ty: vk::DescriptorType::SAMPLED_IMAGE,
    stages: vk::ShaderStageFlags::FRAGMENT,
}];

/// Push-constant range of the tone map's layout.
pub const PUSH_CONSTANTS: (vk::ShaderStageFlags, u32) = (
    vk::ShaderStageFlags::from_raw(
        vk::ShaderStageFlags::VERTEX.as_raw() | vk::ShaderStageFlags::FRAGMENT.as_raw(),
    ),
    size_of::<ToneMapPush>() as u32,
);

/// The tone-map pipeline and the set naming its source.
pub struct ToneMapPass {
    set: DescriptorSet,
    layout: PipelineLayout,
    pipeline: Pipeline,
}

impl ToneMapPass {
    /// The pipeline for a target of `format`.
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules, format: vk::Format) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let set = DescriptorSet::new(ctx, &BINDINGS)?;
        let layout = PipelineLayout::new(ctx, set.layout, PUSH_CONSTANTS)?;
        let stages = [
            (St::VERTEX, shaders::TONEMAP_VS),
            (St::FRAGMENT, shaders::TONEMAP_FS),
        ];
        let mut desc =
            GraphicsDesc::patches(module, &stages, &layout, format, vk::Format::UNDEFINED);
        desc.patch_control_points = 0;
        let pipeline = Pipeline::graphics(ctx, &desc)?;
        Ok(Self {
            set,
            layout,
            pipeline,
        })
    }

    /// Reads `hdr` (SHADER_READ_ONLY_OPTIMAL, the target's size) from now on. No frame
    /// may be in flight.
    pub fn set_source(&self, hdr: vk::ImageView) {
        self.set.write_sampled_image(0, hdr);
    }

    /// Puts the sky behind the HDR image `hdr` and tone-maps it into `target` (image,
    /// view, extent), for the frame of `uniforms`: the HDR image from attachment to
    /// sampled, the target from undefined to attachment.
    pub fn record(
        &self,
        rec: &Recorder,
        hdr: vk::Image,
        target: (vk::Image, vk::ImageView, vk::Extent2D),
        uniforms: &FrameUniforms,
    ) {
        use vk::AccessFlags2 as A;
        use vk::PipelineStageFlags2 as S;
        let color = vk::ImageAspectFlags::COLOR;
        rec.image_barrier(
            hdr,
            color,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            (S::FRAGMENT_SHADER, A::SHADER_READ),
        );
        rec.image_barrier(
            target.0,
            color,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::NONE),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
        );
        let camera = &uniforms.camera;
        let push = ToneMapPush {
            clip_to_world: camera.view_proj.inverse(),
            camera: camera.position.extend(uniforms.look.exposure),
            sun: uniforms.light.direction.extend(0.0),
            ground: shared::draw::look::ground::horizon_ground(&uniforms.look),
        };
        rec.begin_rendering(Some((target.1, None)), None, target.2);
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        rec.bind_pipeline(
            graphics,
            self.pipeline.pipeline,
            self.layout.layout,
            self.set.set,
        );
        rec.push_constants(
            self.layout.layout,
            PUSH_CONSTANTS.0,
            bytemuck::bytes_of(&push),
        );
        rec.draw(0, shared::gpu::layout::TONEMAP_VERTICES);
        rec.end_rendering();
    }
}

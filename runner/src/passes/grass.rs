//! The grass draw: the visible blades as one-vertex patches, drawn with one
//! multi-draw-indirect call over the chunks the compute pass wrote.

use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModule, vec4_vertex_input};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::Blade;
use std::sync::Arc;

/// The tessellated grass pipeline.
pub struct GrassPass {
    pipeline: Pipeline,
}

impl GrassPass {
    /// The pipeline for a colour target of `color_format`.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModule,
        field: &Field,
        color_format: vk::Format,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        // v0, v1, v2, up: four vec4 at locations 0..4.
        let (bindings, attributes) = vec4_vertex_input::<Blade>();
        let pipeline = Pipeline::graphics(
            ctx,
            &GraphicsDesc {
                module,
                stages: &[
                    (St::VERTEX, shaders::GRASS_VS),
                    (St::TESSELLATION_CONTROL, shaders::GRASS_TCS),
                    (St::TESSELLATION_EVALUATION, shaders::GRASS_TES),
                    (St::FRAGMENT, shaders::GRASS_FS),
                ],
                layout: &field.layout,
                vertex_bindings: &bindings,
                vertex_attributes: &attributes,
                patch_control_points: 1,
                polygon_mode: vk::PolygonMode::FILL,
                color_format,
                depth_format: super::DEPTH_FORMAT,
            },
        )?;
        Ok(Self { pipeline })
    }

    /// Records the draw inside the frame's rendering scope.
    pub fn record(&self, rec: &Recorder, field: &Field) {
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        rec.bind_pipeline(
            graphics,
            self.pipeline.pipeline,
            field.layout.layout,
            field.descriptors.set,
        );
        rec.bind_vertex_buffer(field.visible.buffer);
        rec.draw_indirect(field.draws.buffer, field.chunk_count);
    }
}

//! The ground: two triangles from the vertex index, textured in the fragment stage.

use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModule};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use std::sync::Arc;

/// The ground pipeline.
pub struct GroundPass {
    pipeline: Pipeline,
}

impl GroundPass {
    /// The pipeline for a colour target of `color_format`.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModule,
        field: &Field,
        color_format: vk::Format,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let pipeline = Pipeline::graphics(
            ctx,
            &GraphicsDesc {
                module,
                stages: &[
                    (St::VERTEX, shaders::GROUND_VS),
                    (St::FRAGMENT, shaders::GROUND_FS),
                ],
                layout: &field.layout,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: 0,
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
        rec.draw(6);
    }
}

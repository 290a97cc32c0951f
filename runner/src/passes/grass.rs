//! The grass draw: the visible blades as one-vertex patches, drawn with one
//! multi-draw-indirect call over the chunks the compute pass wrote; filled, or as a
//! wireframe in the wireframe view. There is no vertex buffer: the shaders read each
//! blade through its index in the visible buffer.

use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::look::LOOK_NATURAL;
use shared::shade::VIEW_WIREFRAME;
use std::sync::Arc;

/// The tessellated grass pipelines, filled and wireframe, of each look.
pub struct GrassPass {
    filled: Pipeline,
    wireframe: Pipeline,
    natural: Pipeline,
    natural_wireframe: Pipeline,
}

impl GrassPass {
    /// The pipelines for colour targets of `color_format` with `samples` samples.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let stages = [
            (St::VERTEX, shaders::GRASS_VS),
            (St::TESSELLATION_CONTROL, shaders::GRASS_TCS),
            (St::TESSELLATION_EVALUATION, shaders::GRASS_TES),
            (St::FRAGMENT, shaders::GRASS_FS),
        ];
        let mut desc = GraphicsDesc::patches(
            module,
            &stages,
            &field.layout,
            color_format,
            super::DEPTH_FORMAT,
        );
        desc.samples = samples;
        let filled = Pipeline::graphics(ctx, &desc)?;
        desc.polygon_mode = vk::PolygonMode::LINE;
        let wireframe = Pipeline::graphics(ctx, &desc)?;
        let stages = [
            (St::VERTEX, shaders::NATURAL_VS),
            (St::TESSELLATION_CONTROL, shaders::NATURAL_TCS),
            (St::TESSELLATION_EVALUATION, shaders::NATURAL_TES),
            (St::FRAGMENT, shaders::NATURAL_FS),
        ];
        desc.stages = &stages;
        desc.polygon_mode = vk::PolygonMode::FILL;
        let natural = Pipeline::graphics(ctx, &desc)?;
        desc.polygon_mode = vk::PolygonMode::LINE;
        let natural_wireframe = Pipeline::graphics(ctx, &desc)?;
        Ok(Self {
            filled,
            wireframe,
            natural,
            natural_wireframe,
        })
    }

    /// Records the draw inside the frame's rendering scope, in `view`
    /// (`shade::VIEW_*`) and the look `style` (`look::LOOK_*`).
    pub fn record(&self, rec: &Recorder, field: &Field, view: u32, style: u32) {
        let pipeline = match (style == LOOK_NATURAL, view == VIEW_WIREFRAME) {
            (false, false) => &self.filled,
            (false, true) => &self.wireframe,
            (true, false) => &self.natural,
            (true, true) => &self.natural_wireframe,
        };
        self.record_with(pipeline, rec, field);
    }

    /// Records the visible blades' draw with `pipeline` (one drawing them as patches).
    pub fn record_with(&self, pipeline: &Pipeline, rec: &Recorder, field: &Field) {
        rec.bind_pipeline(
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.pipeline,
            field.layout.layout,
            field.descriptors.set,
        );
        rec.draw_indirect(field.draws.buffer, field.chunk_count);
    }
}

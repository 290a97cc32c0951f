//! The triangle-throughput reference: patches tessellated like blades at a fixed level,
//! on a grid of small screen cells, shaded with one colour and timed, so the grass
//! draw can be reported as a share of what this device tessellates at most.

use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::layout::ThroughputPush;
use std::sync::Arc;

/// The reference pipeline.
pub struct ThroughputPass {
    pipeline: Pipeline,
}

impl ThroughputPass {
    /// The pipeline for a colour target of `color_format`.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let stages = [
            (St::VERTEX, shaders::THROUGHPUT_VS),
            (St::TESSELLATION_CONTROL, shaders::THROUGHPUT_TCS),
            (St::TESSELLATION_EVALUATION, shaders::THROUGHPUT_TES),
            (St::FRAGMENT, shaders::THROUGHPUT_FS),
        ];
        let desc = GraphicsDesc::patches(
            module,
            &stages,
            &field.layout,
            color_format,
            super::DEPTH_FORMAT,
        );
        Ok(Self {
            pipeline: Pipeline::graphics(ctx, &desc)?,
        })
    }

    /// Records `patches` patches inside a rendering scope, in draws of at most
    /// `per_draw` (the grass draw's chunk size).
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        push: ThroughputPush,
        patches: u32,
        per_draw: u32,
    ) {
        let layout = field.layout.layout;
        rec.bind_pipeline(
            vk::PipelineBindPoint::GRAPHICS,
            self.pipeline.pipeline,
            layout,
            field.descriptors.set,
        );
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        for first in (0..patches).step_by(per_draw.max(1) as usize) {
            rec.draw(first, per_draw.min(patches - first));
        }
    }
}

//! The benchmark's references, no part of a frame: the copy shader moving every blade
//! (the device's bandwidth), and patches tessellated like blades at a fixed level, or
//! the mesh path's strips of that level, on a grid of small screen cells, shaded with
//! one colour (its triangle throughput), so the frame's passes can be reported as a
//! share of what this device does at most.

use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::draw::meshlet::{mesh_grid, strip_segments};
use shared::gpu::layout::{COPY_WORKGROUP, CopyPush, ThroughputPush};
use std::sync::Arc;

/// The reference pipelines: the copy, tessellated patches, and mesh strips where the
/// device has mesh stages.
pub struct ReferencePass {
    copy: Pipeline,
    ctx: Arc<Context>,
    pipeline: Pipeline,
    mesh: Option<(Pipeline, ash::ext::mesh_shader::Device)>,
}

impl ReferencePass {
    /// The pipelines, for a colour target of `color_format`.
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
        let mesh_stages = [
            (St::MESH_EXT, shaders::THROUGHPUT_MESH),
            (St::FRAGMENT, shaders::THROUGHPUT_FS),
        ];
        let mesh = match &ctx.mesh_shader {
            Ok(commands) => {
                let desc = GraphicsDesc {
                    stages: &mesh_stages,
                    patch_control_points: 0,
                    ..desc
                };
                Some((Pipeline::graphics(ctx, &desc)?, commands.clone()))
            }
            Err(_) => None,
        };
        Ok(Self {
            copy: Pipeline::compute(ctx, &field.layout, module, shaders::COPY_BLADES)?,
            ctx: ctx.clone(),
            pipeline: Pipeline::graphics(ctx, &desc)?,
            mesh,
        })
    }

    /// Records the bandwidth reference: every blade copied into the buffer at
    /// `layout::BINDING_SCRATCH`.
    pub fn record_copy(&self, rec: &Recorder, field: &Field) {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        rec.bind_pipeline(
            vk::PipelineBindPoint::COMPUTE,
            self.copy.pipeline,
            layout,
            set,
        );
        // Four vec4 per blade.
        let push = CopyPush {
            count: field.blade_count * 4,
        };
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        rec.dispatch(self.ctx.workgroups(push.count, COPY_WORKGROUP));
    }

    /// Whether the device draws the mesh path's reference.
    pub fn has_mesh(&self) -> bool {
        self.mesh.is_some()
    }

    /// Records at least `strips` strips of the push constant's level through the mesh
    /// reference (whole workgroups) inside a rendering scope; nothing without one.
    pub fn record_mesh(&self, rec: &Recorder, field: &Field, push: ThroughputPush, strips: u32) {
        let Some((pipeline, commands)) = &self.mesh else {
            return;
        };
        let layout = field.layout.layout;
        rec.bind_pipeline(
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.pipeline,
            layout,
            field.descriptors.set,
        );
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        let grid = mesh_grid(strips, strip_segments(push.level));
        rec.draw_mesh_tasks(commands, grid.to_array());
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

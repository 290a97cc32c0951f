//! The grass draw, through either pipeline (`--pipeline`):
//!
//! - tessellation: the visible blades as one-vertex patches, drawn with one
//!   multi-draw-indirect call over the chunks the compute pass wrote; there is no
//!   vertex buffer: the shaders read each blade through its index in the visible
//!   buffer;
//! - mesh: one indirect task launch over the visible blades (the grid the compute
//!   pass wrote), task stages packing them into meshlets of blade strips
//!   (`shaders-rs/src/mesh.rs`).
//!
//! Filled, or as a wireframe in the wireframe view; both pipelines share each look's
//! fragment stage.

use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::layout::PIPELINE_MESH;
use shared::look::LOOK_NATURAL;
use shared::shade::VIEW_WIREFRAME;
use std::sync::Arc;

/// One pipeline's grass: filled and wireframe, for each look.
struct Looks {
    filled: Pipeline,
    wireframe: Pipeline,
    natural: Pipeline,
    natural_wireframe: Pipeline,
}

impl Looks {
    /// The four pipelines of `paper` and `natural` (stages, in order).
    fn new<'a>(
        ctx: &Arc<Context>,
        desc: &mut GraphicsDesc<'a>,
        paper: &'a [(vk::ShaderStageFlags, &'a str)],
        natural: &'a [(vk::ShaderStageFlags, &'a str)],
    ) -> Result<Self> {
        let mut make = |stages, mode| {
            desc.stages = stages;
            desc.polygon_mode = mode;
            Pipeline::graphics(ctx, desc)
        };
        let (fill, line) = (vk::PolygonMode::FILL, vk::PolygonMode::LINE);
        Ok(Self {
            filled: make(paper, fill)?,
            wireframe: make(paper, line)?,
            natural: make(natural, fill)?,
            natural_wireframe: make(natural, line)?,
        })
    }

    fn pick(&self, view: u32, style: u32) -> &Pipeline {
        match (style == LOOK_NATURAL, view == VIEW_WIREFRAME) {
            (false, false) => &self.filled,
            (false, true) => &self.wireframe,
            (true, false) => &self.natural,
            (true, true) => &self.natural_wireframe,
        }
    }
}

/// The grass pipelines: tessellated, and with task and mesh stages where the device
/// has them.
pub struct GrassPass {
    tess: Looks,
    mesh: Option<(Looks, ash::ext::mesh_shader::Device)>,
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
        let paper = [
            (St::VERTEX, shaders::GRASS_VS),
            (St::TESSELLATION_CONTROL, shaders::GRASS_TCS),
            (St::TESSELLATION_EVALUATION, shaders::GRASS_TES),
            (St::FRAGMENT, shaders::GRASS_FS),
        ];
        let natural = [
            (St::VERTEX, shaders::NATURAL_VS),
            (St::TESSELLATION_CONTROL, shaders::NATURAL_TCS),
            (St::TESSELLATION_EVALUATION, shaders::NATURAL_TES),
            (St::FRAGMENT, shaders::NATURAL_FS),
        ];
        let desc = |stages| {
            let mut desc = GraphicsDesc::patches(
                module,
                stages,
                &field.layout,
                color_format,
                super::DEPTH_FORMAT,
            );
            desc.samples = samples;
            desc
        };
        let tess = Looks::new(ctx, &mut desc(&paper), &paper, &natural)?;
        let mesh = match &ctx.mesh_shader {
            Ok(commands) => {
                let paper = [
                    (St::TASK_EXT, shaders::PAPER_TASK),
                    (St::MESH_EXT, shaders::PAPER_MESH),
                    (St::FRAGMENT, shaders::GRASS_FS),
                ];
                let natural = [
                    (St::TASK_EXT, shaders::NATURAL_TASK),
                    (St::MESH_EXT, shaders::NATURAL_MESH),
                    (St::FRAGMENT, shaders::NATURAL_FS),
                ];
                let mut desc = desc(&paper);
                desc.patch_control_points = 0;
                let looks = Looks::new(ctx, &mut desc, &paper, &natural)?;
                Some((looks, commands.clone()))
            }
            Err(_) => None,
        };
        Ok(Self { tess, mesh })
    }

    /// Records the draw inside the frame's rendering scope, in `view`
    /// (`shade::VIEW_*`), the look `style` (`look::LOOK_*`) and through `pipeline`
    /// (`layout::PIPELINE_*`; tessellation where the device has no mesh stages).
    pub fn record(&self, rec: &Recorder, field: &Field, view: u32, style: u32, pipeline: u32) {
        match &self.mesh {
            Some((looks, commands)) if pipeline == PIPELINE_MESH => {
                bind(rec, looks.pick(view, style), field);
                rec.draw_mesh_tasks_indirect(commands, field.mesh_draw.buffer);
            }
            _ => self.record_with(self.tess.pick(view, style), rec, field),
        }
    }

    /// Records the visible blades' draw with `pipeline` (one drawing them as patches).
    pub fn record_with(&self, pipeline: &Pipeline, rec: &Recorder, field: &Field) {
        bind(rec, pipeline, field);
        rec.draw_indirect(field.draws.buffer, field.chunk_count);
    }
}

fn bind(rec: &Recorder, pipeline: &Pipeline, field: &Field) {
    rec.bind_pipeline(
        vk::PipelineBindPoint::GRAPHICS,
        pipeline.pipeline,
        field.layout.layout,
        field.descriptors.set,
    );
}

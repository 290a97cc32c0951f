//! The grass draw, through either pipeline (`--pipeline`):
//!
//! - tessellation: the visible blades as one-vertex patches, drawn with one
//!   multi-draw-indirect call over the chunks the compute pass wrote; there is no
//!   vertex buffer: the shaders read each blade through its index in the visible
//!   buffer;
//! - mesh: one multi-draw-indirect mesh launch, one draw per strip length over the
//!   blades the compute pass binned by length (`shaders-rs/src/mesh.rs`).
//!
//! Filled, or as a wireframe in the wireframe view; both pipelines share each look's
//! fragment stage.

use super::by_target::DrawTarget;
use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::Result;
use ash::vk;
use shared::draw::meshlet::MESH_DRAWS;
use shared::settings::{GrassPipeline, Look, View};
use std::sync::Arc;

/// One pipeline's grass in each look and view: each view has its own fragment stage
/// (a branch on the view in the fragment stage cost the NVIDIA H100 dearly,
/// `shaders-rs/src/grass.rs`).
struct Looks {
    filled: Pipeline,
    wireframe: Pipeline,
    lod: Pipeline,
    natural: Pipeline,
    natural_wireframe: Pipeline,
    natural_lod: Pipeline,
}

impl Looks {
    /// The pipelines of each look for `target`, their geometry stages in `paper` and
    /// `natural` (in order, the fragment stage left out); with a motion target the
    /// paper look's shaded view writes it (through its geometry stages in
    /// `paper_motion`), the LOD and wireframe views keep it; on a `deferred` target
    /// the natural look's shaded view packs its visibility (`natural_vis`).
    fn new(
        ctx: &Arc<Context>,
        desc: &GraphicsDesc,
        target: DrawTarget,
        stages: &LookStages,
    ) -> Result<Self> {
        let make = |geometry: &[(vk::ShaderStageFlags, &str)], fragment, mode, written| {
            let mut stages = geometry.to_vec();
            stages.push((vk::ShaderStageFlags::FRAGMENT, fragment));
            let desc = GraphicsDesc {
                stages: &stages,
                polygon_mode: mode,
                second_color: target.second_color(written),
                ..*desc
            };
            Pipeline::graphics(ctx, &desc)
        };
        let (fill, line) = (vk::PolygonMode::FILL, vk::PolygonMode::LINE);
        let (paper, natural) = (stages.paper, stages.natural);
        let filled = if target.motion {
            make(stages.paper_motion, shaders::GRASS_TAA_FS, fill, true)?
        } else {
            make(paper, shaders::GRASS_FS, fill, false)?
        };
        let natural_filled = if target.deferred {
            make(stages.natural_vis, shaders::NATURAL_VIS_FS, fill, false)?
        } else {
            make(natural, shaders::NATURAL_FS, fill, false)?
        };
        Ok(Self {
            filled,
            wireframe: make(paper, shaders::GRASS_FS, line, false)?,
            lod: make(paper, shaders::GRASS_LOD_FS, fill, false)?,
            natural: natural_filled,
            natural_wireframe: make(natural, shaders::NATURAL_VIEW_FS, line, false)?,
            natural_lod: make(natural, shaders::NATURAL_VIEW_FS, fill, false)?,
        })
    }

    fn pick(&self, view: View, look: Look) -> &Pipeline {
        match (look, view) {
            (Look::Paper, View::Wireframe) => &self.wireframe,
            (Look::Paper, View::Lod) => &self.lod,
            (Look::Paper, View::Shaded) => &self.filled,
            (Look::Natural, View::Wireframe) => &self.natural_wireframe,
            (Look::Natural, View::Lod) => &self.natural_lod,
            (Look::Natural, View::Shaded) => &self.natural,
        }
    }
}

/// One path's geometry stages (the fragment stage left out).
struct LookStages<'a> {
    paper: &'a [(vk::ShaderStageFlags, &'a str)],
    /// The paper look's, giving each vertex its motion (temporal anti-aliasing).
    paper_motion: &'a [(vk::ShaderStageFlags, &'a str)],
    natural: &'a [(vk::ShaderStageFlags, &'a str)],
    /// The natural look's, for shading after the draw (`passes::shade`).
    natural_vis: &'a [(vk::ShaderStageFlags, &'a str)],
}

/// The grass pipelines: tessellated, and with mesh stages where the device has them.
pub struct GrassPass {
    tess: Looks,
    mesh: Option<(Looks, ash::ext::mesh_shader::Device)>,
    /// The paper look's mesh path capturing its vertices (`paper_mesh_capture`), for
    /// the test against the host's vertices; used instead of the mesh path while set.
    capture: Option<Pipeline>,
    /// Draw the mesh path through `capture`.
    pub capturing: bool,
}

impl GrassPass {
    /// The pipelines for `target`.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let paper = [
            (St::VERTEX, shaders::GRASS_VS),
            (St::TESSELLATION_CONTROL, shaders::GRASS_TCS),
            (St::TESSELLATION_EVALUATION, shaders::GRASS_TES),
        ];
        let paper_motion = [
            (St::VERTEX, shaders::GRASS_VS),
            (St::TESSELLATION_CONTROL, shaders::GRASS_TCS),
            (St::TESSELLATION_EVALUATION, shaders::GRASS_TAA_TES),
        ];
        let natural = [
            (St::VERTEX, shaders::NATURAL_VS),
            (St::TESSELLATION_CONTROL, shaders::NATURAL_TCS),
            (St::TESSELLATION_EVALUATION, shaders::NATURAL_TES),
        ];
        let natural_vis = [
            (St::VERTEX, shaders::NATURAL_VS),
            (St::TESSELLATION_CONTROL, shaders::NATURAL_TCS),
            (St::TESSELLATION_EVALUATION, shaders::NATURAL_VIS_TES),
        ];
        let mut desc = GraphicsDesc::patches(
            module,
            &[],
            &field.layout,
            target.format,
            super::DEPTH_FORMAT,
        );
        desc.samples = target.samples;
        desc.depth_compare = target.depth_compare();
        let stages = LookStages {
            paper: &paper,
            paper_motion: &paper_motion,
            natural: &natural,
            natural_vis: &natural_vis,
        };
        let tess = Looks::new(ctx, &desc, target, &stages)?;
        let mesh = match &ctx.mesh_shader {
            Ok(commands) => {
                desc.patch_control_points = 0;
                let stages = LookStages {
                    paper: &[(St::MESH_EXT, shaders::PAPER_MESH)],
                    paper_motion: &[(St::MESH_EXT, shaders::PAPER_TAA_MESH)],
                    natural: &[(St::MESH_EXT, shaders::NATURAL_MESH)],
                    natural_vis: &[(St::MESH_EXT, shaders::NATURAL_VIS_MESH)],
                };
                let looks = Looks::new(ctx, &desc, target, &stages)?;
                Some((looks, commands.clone()))
            }
            Err(_) => None,
        };
        let capture = match &mesh {
            Some(_) => {
                let stages = [
                    (St::MESH_EXT, shaders::PAPER_MESH_CAPTURE),
                    (St::FRAGMENT, shaders::GRASS_FS),
                ];
                let desc = GraphicsDesc {
                    stages: &stages,
                    second_color: target.second_color(false),
                    ..desc
                };
                Some(Pipeline::graphics(ctx, &desc)?)
            }
            None => None,
        };
        Ok(Self {
            tess,
            mesh,
            capture,
            capturing: false,
        })
    }

    /// Records the draw inside the frame's rendering scope, in `view`
    /// (`shade::VIEW_*`), the look `style` (`look::LOOK_*`) and through `pipeline`
    /// (`layout::PIPELINE_*`; tessellation where the device has no mesh stages).
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        view: View,
        look: Look,
        pipeline: GrassPipeline,
    ) {
        match &self.mesh {
            Some((looks, commands)) if pipeline == GrassPipeline::Mesh => {
                let picked = match &self.capture {
                    Some(capture) if self.capturing => capture,
                    _ => looks.pick(view, look),
                };
                bind(rec, picked, field);
                rec.draw_mesh_tasks_indirect(commands, field.mesh_draw.buffer, MESH_DRAWS);
            }
            _ => self.record_with(self.tess.pick(view, look), rec, field),
        }
    }

    /// Records the visible blades' draw with `pipeline` (one drawing them as patches).
    fn record_with(&self, pipeline: &Pipeline, rec: &Recorder, field: &Field) {
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

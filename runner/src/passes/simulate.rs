//! The compute pass: simulate and cull every blade (appending survivors through the
//! visible counter), then write one indirect draw command per chunk.

use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::pipeline::{Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use shared::gpu::layout::{
    CHUNK_WORKGROUP, CULL_WORKGROUP, ChunkPush, SIMULATE_WORKGROUP, SPEC_IMPULSES, SPEC_MESH_PATH,
    SPEC_WIND_FIELD, SimulatePush,
};
use shared::settings::WindField;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The compute pipelines of the pass: simulate and cull (with the mesh path's
/// binning), the draw commands, the clumps.
pub struct SimulatePass {
    ctx: Arc<Context>,
    /// The simulate-and-cull entry points' modules, for the pipelines made on first use.
    modules: ShaderModules,
    /// The simulate-and-cull pipelines by look (paper, natural), path (tessellation,
    /// mesh: `layout::SPEC_MESH_PATH`), wind field (`layout::SPEC_WIND_FIELD`) and
    /// wind impulses or none (`layout::SPEC_IMPULSES`), each made when a frame first
    /// needs it.
    simulate: [[[[Option<Pipeline>; 2]; WindField::ALL.len()]; 2]; 2],
    write_draws: Pipeline,
    clumps: Pipeline,
}

impl SimulatePass {
    /// The draw commands' and clumps' pipelines, and the simulate-and-cull
    /// modules whose pipelines are made when a frame first needs them.
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules, field: &Field) -> Result<Self> {
        let entries = [shaders::SIMULATE_CULL, shaders::SIMULATE_CULL_NATURAL];
        let spirv: Vec<(&'static str, &'static [u8])> = entries
            .iter()
            .map(|&entry| {
                shaders::module(entry)
                    .map(|bytes| (entry, bytes))
                    .with_context(|| format!("no SPIR-V for {entry}"))
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            ctx: ctx.clone(),
            modules: ShaderModules::new(ctx, &spirv)?,
            simulate: Default::default(),
            write_draws: Pipeline::compute(ctx, &field.layout, module, shaders::WRITE_DRAWS)?,
            clumps: Pipeline::compute(ctx, &field.layout, module, shaders::CLUMP_BLADES)?,
        })
    }

    /// Workgroups for `items` threads of `size` (`Context::workgroups`).
    fn workgroups(&self, items: u32, size: u32) -> (u32, u32) {
        self.ctx.workgroups(items, size)
    }

    /// Records the clump pass: every blade's clump from the frame block's seed and
    /// clump size, ready for the compute pass. The uniform update must come before.
    pub fn record_clumps(&self, rec: &Recorder, field: &Field) {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        rec.bind_pipeline(compute, self.clumps.pipeline, layout, set);
        rec.dispatch(self.workgroups(field.blade_count, SIMULATE_WORKGROUP));
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ),
        );
    }

    /// The simulate-and-cull pipeline of the `natural` or paper look, binning for the
    /// `mesh` path or not, stepping with the wind field `wind` (`sim::wind::WIND_*`)
    /// and wind impulses or not, made now if no frame needed it before.
    fn simulate(
        &mut self,
        field: &Field,
        (natural, mesh): (bool, bool),
        (wind, impulses): (u32, bool),
    ) -> Result<vk::Pipeline> {
        let kind = WindField::ALL
            .iter()
            .position(|&w| w as u32 == wind)
            .with_context(|| format!("no wind field {wind}"))?;
        let slot = &mut self.simulate[usize::from(natural)][usize::from(mesh)][kind]
            [usize::from(impulses)];
        if slot.is_none() {
            let entry = if natural {
                shaders::SIMULATE_CULL_NATURAL
            } else {
                shaders::SIMULATE_CULL
            };
            let constants = [
                (SPEC_WIND_FIELD, wind),
                (SPEC_MESH_PATH, u32::from(mesh)),
                (SPEC_IMPULSES, u32::from(impulses)),
            ];
            let pipeline = Pipeline::compute_specialised(
                &self.ctx,
                &field.layout,
                &self.modules,
                entry,
                &constants,
            )?;
            *slot = Some(pipeline);
        }
        Ok(slot.as_ref().context("the simulate pipeline")?.pipeline)
    }

    /// Records the pass. The counter reset and the uniform update must come before,
    /// with their barrier; this leaves the draw commands and the visible buffer ready
    /// for the indirect draw, and the counters for a transfer read.
    /// `natural` also dresses the visible blades for the natural look's draw; `mesh`
    /// bins them by strip length for the mesh path (`shared::meshlet`; the frame
    /// block's `grass.pipeline`); the blades step in the wind field `wind` (the frame
    /// block's `forces.wind_kind`), with its impulses where `wind.1`.
    pub fn record(
        &mut self,
        rec: &Recorder,
        field: &Field,
        push: SimulatePush,
        look_and_path: (bool, bool),
        wind: (u32, bool),
    ) -> Result<()> {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let simulate = self.simulate(field, look_and_path, wind)?;
        rec.bind_pipeline(compute, simulate, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        rec.dispatch(self.workgroups(field.blade_count, CULL_WORKGROUP));
        // The visible count is complete before the chunk pass reads it.
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ),
        );
        let chunks = ChunkPush {
            chunk_size: field.chunk_size,
            chunk_count: field.chunk_count,
        };
        rec.bind_pipeline(compute, self.write_draws.pipeline, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&chunks));
        rec.dispatch(self.workgroups(field.chunk_count, CHUNK_WORKGROUP));
        // For the draws, a capture's copy, and the compute passes after the draw (the
        // rasterizer and the natural look's shading read the far count's arguments).
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (
                S::DRAW_INDIRECT
                    | S::VERTEX_SHADER
                    | S::PRE_RASTERIZATION_SHADERS
                    | S::COPY
                    | S::COMPUTE_SHADER,
                A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ | A::TRANSFER_READ,
            ),
        );
        Ok(())
    }
}

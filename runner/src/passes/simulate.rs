//! The compute pass: simulate and cull every blade (appending survivors through the
//! visible counter), then write one indirect draw command per chunk; and the query
//! pass, the frame's questions answered over the simulated blades.

use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::pipeline::{Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use shared::gpu::layout::{
    CHUNK_WORKGROUP, COLLIDERS_HAND_OVER, COLLIDERS_HAND_OVER_ROOTS, COLLIDERS_NEAR,
    COLLIDERS_NONE, CULL_WORKGROUP, ChunkPush, FrameUniforms, NEAR_DISPATCH, PIPELINE_MESH,
    SIMULATE_WORKGROUP, SPEC_COLLIDERS, SPEC_GRAVITY_CENTRE, SPEC_IMPULSES, SPEC_MESH_PATH,
    SPEC_TILED, SPEC_WIND_FIELD, SPEC_WORKGROUP_TALLY, SimulatePush, WIND_FROM_FRAME, hands_over,
};
use shared::settings::WindField;
use shared::sim::cut::{COMMIT_WORKGROUP, CUT_SLOTS};
use shared::sim::grid::{GRID_CORNERS, GRID_WORKGROUP};
use shared::sim::simulate::watches;
use std::collections::HashMap;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// What a simulate-and-cull pipeline is made for: its entry point and its
/// specialisation constants, each leaving out the code a frame does not need (a branch
/// never taken still costs the pass its registers).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct SimulateVariant {
    /// The natural look's entry point, which also dresses the visible blades (else
    /// the paper look's).
    pub natural: bool,
    /// The mesh path's binning (`layout::SPEC_MESH_PATH`).
    pub mesh: bool,
    /// The wind field (`layout::SPEC_WIND_FIELD`, one of `sim::wind::WIND_*`).
    pub wind: u32,
    /// Wind impulses blow (`layout::SPEC_IMPULSES`).
    pub impulses: bool,
    /// What it does with the colliders (`layout::SPEC_COLLIDERS`: none, hand the
    /// blades near them over, or the collision pass).
    pub colliders: u32,
    /// Gravity pulls towards a centre (`layout::SPEC_GRAVITY_CENTRE`).
    pub centre: bool,
    /// The field is tiled (`layout::SPEC_TILED`).
    pub tiled: bool,
}

impl SimulateVariant {
    /// The variant a frame of `block` and `steps` steps needs, in the `natural` look or
    /// the paper look.
    pub fn of(block: &FrameUniforms, steps: u32, natural: bool) -> Self {
        let forces = &block.forces;
        Self {
            natural,
            mesh: block.grass.pipeline == PIPELINE_MESH,
            wind: forces.wind_kind,
            impulses: forces.impulses > 0,
            colliders: if forces.colliders == 0 {
                COLLIDERS_NONE
            } else if forces.cutting != 0 || !watches(steps) {
                COLLIDERS_HAND_OVER_ROOTS
            } else {
                COLLIDERS_HAND_OVER
            },
            centre: forces.centre_blend != 0.0,
            tiled: block.grass.tiled != 0,
        }
    }
}

/// The compute pipelines of the pass: simulate and cull (with the mesh path's
/// binning), the draw commands, the clumps.
pub struct SimulatePass {
    ctx: Arc<Context>,
    /// The simulate-and-cull entry points' modules, for the pipelines made on first use.
    modules: ShaderModules,
    /// The simulate-and-cull pipelines by what each is made for, each made when a
    /// frame first needs it.
    simulate: HashMap<SimulateVariant, Pipeline>,
    write_draws: Pipeline,
    clumps: Pipeline,
    grid: Pipeline,
    commit_cuts: Pipeline,
    answer: Pipeline,
    contacts: Pipeline,
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
            grid: Pipeline::compute(ctx, &field.layout, module, shaders::BUILD_COLLIDER_GRID)?,
            commit_cuts: Pipeline::compute(ctx, &field.layout, module, shaders::COMMIT_CUTS)?,
            answer: Pipeline::compute(ctx, &field.layout, module, shaders::ANSWER_QUESTIONS)?,
            contacts: Pipeline::compute(ctx, &field.layout, module, shaders::MARK_CONTACTS)?,
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

    /// The simulate-and-cull pipeline `variant` is made for, made now if no frame
    /// needed it before.
    fn simulate(&mut self, field: &Field, variant: SimulateVariant) -> Result<vk::Pipeline> {
        if !WindField::ALL.iter().any(|&w| w as u32 == variant.wind) {
            anyhow::bail!("no wind field {}", variant.wind);
        }
        // A software device compiles one pipeline for every field (`WIND_FROM_FRAME`).
        let variant = if self.ctx.is_software() {
            SimulateVariant {
                wind: WIND_FROM_FRAME,
                ..variant
            }
        } else {
            variant
        };
        if let Some(made) = self.simulate.get(&variant) {
            return Ok(made.pipeline);
        }
        let entry = if variant.natural {
            shaders::SIMULATE_CULL_NATURAL
        } else {
            shaders::SIMULATE_CULL
        };
        let constants = [
            (SPEC_WIND_FIELD, variant.wind),
            (SPEC_MESH_PATH, u32::from(variant.mesh)),
            (SPEC_IMPULSES, u32::from(variant.impulses)),
            (SPEC_COLLIDERS, variant.colliders),
            (SPEC_GRAVITY_CENTRE, u32::from(variant.centre)),
            (SPEC_TILED, u32::from(variant.tiled)),
            (SPEC_WORKGROUP_TALLY, u32::from(!self.ctx.is_software())),
        ];
        let pipeline = Pipeline::compute_specialised(
            &self.ctx,
            &field.layout,
            &self.modules,
            entry,
            &constants,
        )?;
        Ok(self.simulate.entry(variant).or_insert(pipeline).pipeline)
    }

    /// Records the query pass (`compute::query`): the frame's questions answered
    /// over every simulated blade, after the pass ([`SimulatePass::record`]) has left
    /// them simulated; its answers are then ready for a transfer read.
    pub fn record_questions(&self, rec: &Recorder, field: &Field) {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        rec.bind_pipeline(compute, self.answer.pipeline, layout, set);
        rec.dispatch(self.workgroups(field.simulated, SIMULATE_WORKGROUP));
    }

    /// Records the colliders' grid's build from `colliders` colliders:
    /// `GRID_CORNERS` threads each (`compute::grid`). Their update and the grid's clearing must come before,
    /// with their barrier.
    pub fn record_grid(&self, rec: &Recorder, field: &Field, colliders: u32) {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        rec.bind_pipeline(compute, self.grid.pipeline, layout, set);
        rec.dispatch(self.workgroups(colliders * GRID_CORNERS, GRID_WORKGROUP));
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ),
        );
    }

    /// Records the collision pass after the pass over every blade, dispatched as that
    /// pass left its dispatch: the blades near colliders simulated and tested
    /// with them (`layout::COLLIDERS_NEAR`), then the colliders they touch marked where
    /// the frame asks for `contacts`.
    fn record_near(
        &mut self,
        rec: &Recorder,
        field: &Field,
        push: SimulatePush,
        (variant, contacts): (SimulateVariant, bool),
    ) -> Result<()> {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let written = (S::COMPUTE_SHADER, A::SHADER_WRITE);
        // The pass over every blade grew the dispatch (`layout::near_groups`).
        rec.memory_barrier(
            written,
            (
                S::DRAW_INDIRECT | S::COMPUTE_SHADER,
                A::INDIRECT_COMMAND_READ | A::SHADER_READ | A::SHADER_WRITE,
            ),
        );
        let near = SimulateVariant {
            colliders: COLLIDERS_NEAR,
            ..variant
        };
        let pipeline = self.simulate(field, near)?;
        rec.bind_pipeline(compute, pipeline, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        let args = (NEAR_DISPATCH * 4) as u64;
        rec.dispatch_indirect(field.near.buffer, args);
        if contacts {
            // The colliders its blades touch, for a game's footsteps (`compute::query`).
            rec.memory_barrier(written, (S::COMPUTE_SHADER, A::SHADER_READ));
            rec.bind_pipeline(compute, self.contacts.pipeline, layout, set);
            rec.dispatch_indirect(field.near.buffer, args);
        }
        Ok(())
    }

    /// Records the pass. The counter reset and the uniform update must come before,
    /// with their barrier; this leaves the draw commands and the visible buffer ready
    /// for the indirect draw, and the counters for a transfer read.
    /// The pipeline is `variant`'s, which must agree with the frame block
    /// ([`SimulateVariant::of`]); with colliders, the `contacts` are marked after the
    /// collision pass where asked, and where the frame has a cutter (`cuts`) its cuts
    /// are committed after it (`compute::cut::commit_cuts`).
    pub fn record(
        &mut self,
        rec: &Recorder,
        field: &Field,
        push: SimulatePush,
        (variant, contacts, cuts): (SimulateVariant, bool, bool),
    ) -> Result<()> {
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let simulate = self.simulate(field, variant)?;
        rec.bind_pipeline(compute, simulate, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        rec.dispatch(self.workgroups(field.blade_count, CULL_WORKGROUP));
        if hands_over(variant.colliders) {
            self.record_near(rec, field, push, (variant, contacts))?;
        }
        // The visible count is complete before the chunk pass reads it, and the
        // frame's cuts pending before their commit.
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
        );
        if cuts {
            rec.bind_pipeline(compute, self.commit_cuts.pipeline, layout, set);
            rec.dispatch(self.workgroups(CUT_SLOTS, COMMIT_WORKGROUP));
        }
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

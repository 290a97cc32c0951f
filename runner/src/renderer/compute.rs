//! The compute part of a frame: the frame block, the colliders and the counters
//! uploaded and reset, the colliders' grid and the simulate-and-cull pass (with its
//! collision pass), the questions answered, the counters and answers copied for the
//! read-back.

use super::{FRAME_STAGES, FrameQueries, Renderer, SHADER_STAGES};
use crate::passes::simulate::SimulateVariant;
use crate::vulkan::Recorder;
use anyhow::Result;
use ash::vk;
use shared::gpu::counters;
use shared::gpu::layout::{FrameUniforms, SimulatePush};
use shared::plan::FrameRequest;
use shared::query::{QUERY_WORDS, Question};
use shared::sim::collide::Collider;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// What a frame asks of the grass besides its picture: its questions answered
/// (`shared::query`), the colliders touching blades marked, its cuts recorded.
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct Asked {
    /// It has questions.
    pub questions: bool,
    /// It marks the contacts.
    pub contacts: bool,
    /// It has a cutter (`Collider::cuts`): its cuts wait in the cut table until the
    /// commit after the collision pass (`compute::cut::commit_cuts`).
    pub cuts: bool,
}

impl Asked {
    /// What `request` asks.
    pub(super) fn of(request: &FrameRequest) -> Self {
        Self {
            questions: !request.questions().is_empty(),
            contacts: request.contacts(),
            cuts: request.colliders().iter().any(Collider::cuts),
        }
    }
}

impl Renderer {
    /// Orders the frame after the previous one, then updates the uniforms, the
    /// `colliders` (clearing their grid) and the `questions` (clearing their answers
    /// and the contacts) and clears the counters.
    pub(super) fn begin_compute(
        &self,
        rec: &Recorder,
        uniforms: &FrameUniforms,
        (colliders, questions): (&[Collider], &[Question]),
    ) {
        let field = &self.field;
        // Everything the previous frame read or wrote is done before this one
        // overwrites the uniforms, the counters, the pyramid and the blades.
        rec.memory_barrier(
            (FRAME_STAGES, A::MEMORY_WRITE),
            (FRAME_STAGES, A::MEMORY_READ | A::MEMORY_WRITE),
        );
        rec.update_buffer(field.uniforms.buffer, bytemuck::bytes_of(uniforms));
        if !colliders.is_empty() {
            rec.update_buffer(field.colliders.buffer, bytemuck::cast_slice(colliders));
            // The slots this frame's grid and watch use.
            let words = uniforms.collider_grid.words() as u64;
            rec.fill_buffer_start(field.collider_grid.buffer, words * 4, 0);
            // The collision pass's dispatch, grown by the pass over every blade.
            let none: [u32; 3] = [0, 0, 1];
            rec.update_buffer(field.near.buffer, bytemuck::cast_slice(&none));
        }
        let words = shared::query::query_words(questions);
        rec.update_buffer(field.queries.buffer, bytemuck::cast_slice(&words));
        // The counters, not the binned list's layout after them, which the frame
        // before left for this one.
        rec.fill_buffer_start(field.counters.buffer, counters::COUNTER_BYTES, 0);
        rec.memory_barrier(
            (S::CLEAR | S::COPY, A::TRANSFER_WRITE),
            (
                SHADER_STAGES,
                A::SHADER_READ | A::SHADER_WRITE | A::UNIFORM_READ,
            ),
        );
    }

    /// The colliders' grid where the frame has colliders, then simulate, cull and
    /// compact (and on the mesh path bin by strip length), with the pipeline made for
    /// the frame block's path, wind field, impulses and colliders (the contacts marked
    /// after the collision pass where the frame asks); then the frame's questions
    /// answered, where it asks any.
    pub(super) fn record_compute(
        &mut self,
        rec: &Recorder,
        push: SimulatePush,
        (natural, asks): (bool, Asked),
    ) -> Result<()> {
        let variant = SimulateVariant::of(&self.block, push.steps, natural);
        let colliders = self.block.forces.colliders;
        if colliders > 0 {
            self.simulate.record_grid(rec, &self.field, colliders);
        }
        self.simulate
            .record(rec, &self.field, push, (variant, asks.contacts, asks.cuts))?;
        if asks.questions {
            self.simulate.record_questions(rec, &self.field);
        }
        Ok(())
    }

    /// Copies the counters and the query buffer for the read-back, once the compute
    /// pass and the compute rasterizer have written them.
    pub(super) fn copy_counters(&self, rec: &Recorder, queries: &FrameQueries) {
        let field = &self.field;
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COPY, A::TRANSFER_READ),
        );
        // The counters, not the binned list's layout after them.
        rec.copy_buffer(
            field.counters.buffer,
            queries.counters.buffer,
            counters::COUNTER_BYTES,
        );
        let answers = (QUERY_WORDS * 4) as u64;
        rec.copy_buffer(field.queries.buffer, queries.answers.buffer, answers);
        rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
    }
}

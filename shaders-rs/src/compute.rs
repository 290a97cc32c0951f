//! The compute pass: simulate every blade, cull it, compact the survivors, then write
//! the indirect draw commands.

use shared::Blade;
use shared::cull::is_visible;
use shared::layout::{
    CHUNK_WORKGROUP, COUNTER_VISIBLE, ChunkPush, FrameUniforms, SIMULATE_WORKGROUP, SimulatePush,
    flat_index,
};
use shared::lod::chunk_range;
use shared::simulate::simulate;
use spirv_std::arch::atomic_i_increment;
use spirv_std::glam::UVec3;
use spirv_std::indirect_command::DrawIndirectCommand;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// One thread per blade: this frame's fixed steps of forces, collisions and validation
/// (the blade and its collision strength η are read and written back), then the
/// cull tests; a visible blade is appended to `visible` through the atomic counter.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn simulate_cull(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SimulatePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] strengths: &mut [f32],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    if index >= frame.blade_count() {
        return;
    }
    let i = index as usize;
    let (blade, strength) = simulate(
        (blades[i], strengths[i]),
        &frame.environment(),
        &frame.colliders,
        push.first_step,
        push.steps,
    );
    blades[i] = blade;
    strengths[i] = strength;
    if is_visible(
        &blade,
        index,
        frame.camera_pos(),
        frame.view_proj,
        &frame.cull_params(),
    ) {
        let slot = unsafe {
            atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                &mut counters[COUNTER_VISIBLE],
            )
        };
        visible[slot as usize] = blade;
    }
}

/// One thread per chunk: the draw command of its slice of the visible blades.
#[spirv(compute(threads(64)))]
pub fn write_draws(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &ChunkPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] draws: &mut [DrawIndirectCommand],
) {
    let chunk = flat_index(id, workgroups, CHUNK_WORKGROUP);
    if chunk >= push.chunk_count {
        return;
    }
    let (first, count) = chunk_range(counters[COUNTER_VISIBLE], chunk, push.chunk_size);
    draws[chunk as usize] = DrawIndirectCommand {
        vertex_count: count,
        instance_count: 1,
        first_vertex: first,
        first_instance: 0,
    };
}

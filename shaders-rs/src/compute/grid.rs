//! The colliders' spatial grid, built each frame that has colliders
//! (`shared::sim::grid`), and the indirect dispatch of the compute pass's collision
//! pass.

use shared::gpu::counters::COUNTER_NEAR;
use shared::gpu::layout::{CULL_WORKGROUP, FrameUniforms, NEAR_DISPATCH};
use shared::sim::collide::Collider;
use shared::sim::grid::{GRID_CORNERS, OCCUPANCY_WORDS};
use spirv_std::arch::atomic_or;
use spirv_std::glam::UVec3;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// One thread per collider and cube it may mark (`grid::GRID_CORNERS` each,
/// `grid::GRID_WORKGROUP` threads a workgroup): sets the collider's
/// bit, and its word's bit of occupancy, in the slot the cube hashes to
/// (`ColliderGrid::corner_cube`, `slot_base`), with atomic ors on the cleared grid.
#[spirv(compute(threads(64)))]
pub fn build_collider_grid(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 25)] colliders: &[Collider],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] grid: &mut [u32],
) {
    let i = id.x / GRID_CORNERS;
    if i < frame.forces.colliders {
        let g = &frame.collider_grid;
        let (marks, cube) = g.corner_cube(&colliders[i as usize], id.x % GRID_CORNERS);
        if marks {
            let base = g.slot_base(cube);
            let word = (i / 32) as usize;
            unsafe {
                atomic_or::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut grid[base + word / 32],
                    1 << (word % 32),
                );
                atomic_or::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut grid[base + OCCUPANCY_WORDS + word],
                    1 << (i % 32),
                );
            }
        }
    }
}

/// The collision pass's indirect dispatch (`layout::NEAR_DISPATCH`): a thread for
/// each blade the pass over every blade handed over (`counters::COUNTER_NEAR`), in
/// workgroups of `layout::CULL_WORKGROUP`, spilling into y past 65,535 of them as the
/// pass's own dispatch does (`layout::flat_index`).
#[spirv(compute(threads(1)))]
pub fn near_dispatch(
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 27)] near: &mut [u32],
) {
    let groups = counters[COUNTER_NEAR].div_ceil(CULL_WORKGROUP);
    let x = groups.min(MAX_GROUPS_X);
    near[NEAR_DISPATCH] = x;
    near[NEAR_DISPATCH + 1] = groups.div_ceil(MAX_GROUPS_X);
    near[NEAR_DISPATCH + 2] = 1;
}

/// Workgroups along x every Vulkan device can dispatch.
const MAX_GROUPS_X: u32 = 65535;

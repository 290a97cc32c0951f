//! The colliders' spatial grid, built each frame that has colliders
//! (`shared::sim::grid`).

use shared::gpu::layout::FrameUniforms;
use shared::sim::collide::Collider;
use shared::sim::grid::{GRID_CORNERS, mark_collider};
use shared::sim::watch::watch_collider;
use spirv_std::arch::{atomic_i_add, atomic_or};
use spirv_std::glam::UVec3;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// One thread per collider and cube it may mark (`grid::GRID_CORNERS` each,
/// `grid::GRID_WORKGROUP` threads a workgroup): sets the collider's
/// bit, and its word's bit of occupancy, in the slot the cube hashes to
/// (`ColliderGrid::corner_cube`, `slot_base`, `grid::mark_collider`), with atomic ors
/// on the cleared grid;
/// and, for a collider that pushes, counts it in the watch's slot of its
/// `corner`th watch cube (`ColliderGrid::watch_corner`, `watch_base`), writes its
/// capsule there where the count leaves room and sets the cube's mark
/// (`shared::sim::watch::watch_collider`).
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
        let collider = &colliders[i as usize];
        let or = |word: &mut u32, bits: u32| unsafe {
            atomic_or::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(word, bits);
        };
        let (watches, cube) = g.watch_corner(collider, id.x % GRID_CORNERS);
        if watches {
            let count = |n: &mut u32| unsafe {
                atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(n, 1)
            };
            watch_collider(grid, (g, cube), collider, count, or);
        }
        let (marks, cube) = g.corner_cube(collider, id.x % GRID_CORNERS);
        if marks {
            mark_collider(grid, g.slot_base(cube), i as usize, or);
        }
    }
}

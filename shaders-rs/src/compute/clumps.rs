//! Each blade's clump (natural look), when the field or the clumps' settings change.

use shared::Blade;
use shared::draw::look::clump::clump_at;
use shared::gpu::layout::{FrameUniforms, SIMULATE_WORKGROUP, flat_index};
use spirv_std::glam::{UVec3, Vec4};
use spirv_std::spirv;

/// One thread per blade: the clump of its root (`shared::draw::look::clump::clump_at`, 27 cells of
/// a Voronoi blend), run when the field, the seed or the clump size changes rather
/// than every frame.
#[spirv(compute(threads(64)))]
pub fn clump_blades(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &mut [Vec4],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    if index < frame.grass.blades {
        let look = &frame.look;
        let root = blades[index as usize].v0.truncate();
        clumps[index as usize] = clump_at(root, look.clump_size, look.seed).pack();
    }
}

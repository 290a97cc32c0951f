//! The benchmark's bandwidth reference: a plain copy of every blade.

use shared::gpu::layout::{COPY_WORKGROUP, CopyPush, flat_index};
use spirv_std::glam::{UVec3, Vec4};
use spirv_std::spirv;

/// The benchmark's bandwidth reference: the blade buffer copied into a scratch
/// buffer, one `vec4` (16 bytes) per thread, so neighbouring threads touch
/// neighbouring bytes; nothing else.
#[spirv(compute(threads(256)))]
pub fn copy_blades(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &CopyPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] scratch: &mut [Vec4],
) {
    let i = flat_index(id, workgroups, COPY_WORKGROUP);
    if i < push.count {
        scratch[i as usize] = blades[i as usize];
    }
}

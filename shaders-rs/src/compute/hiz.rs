//! The occluders' depth pyramid, one level a dispatch.

use shared::cull::hiz::{level_size, reduce};
use shared::gpu::layout::{FrameUniforms, HiZPush};
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// One thread per texel of pyramid level `push.level`: the farthest depth of the 2×2
/// texels below it.
#[spirv(compute(threads(8, 8)))]
pub fn build_hiz(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &HiZPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] pyramid: &mut [f32],
) {
    let hiz = &frame.hiz;
    let (w, h) = level_size(hiz.width, hiz.height, push.level);
    if id.x >= w || id.y >= h {
        return;
    }
    let value = reduce(pyramid, hiz, push.level, id.x, id.y);
    pyramid[(hiz.offset(push.level) + id.y * w + id.x) as usize] = value;
}

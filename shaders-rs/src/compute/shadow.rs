//! The grass's shadow casters drawn into the sun's shadow map by compute threads
//! (`shared::draw::look::shadow_raster`), one caster a thread, each texel an atomic
//! minimum of its depth word; `passes::shadow` copies the words into the map.

use crate::grass::caster;
use shared::Blade;
use shared::draw::look::shadow::CASTERS_PER_GROUP;
use shared::draw::look::shadow_raster::{caster_corners, raster_caster, texel_word};
use shared::draw::meshlet::group_index;
use shared::gpu::counters::{COUNTER_CASTERS, COUNTER_NEAR_CASTERS};
use shared::gpu::layout::FrameUniforms;
use spirv_std::arch::atomic_u_min;
use spirv_std::glam::{Mat4, UVec3, Vec4};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// Caster `k` of the list's `first` onwards, dressed (`grass::caster`), its one
/// segment's corners into cascade `cascade` of `view_proj`, drawn into `depth` (two
/// cascades' words a row).
#[allow(clippy::too_many_arguments)]
fn draw_caster(
    frame: &FrameUniforms,
    (blades, clumps, ids, casters): (&[Blade], &[Vec4], &[u32], &[u32]),
    (first, k): (u32, u32),
    (view_proj, cascade): (Mat4, u32),
    depth: &mut [u32],
) {
    let blade = caster(frame, blades, clumps, ids, casters[(first + k) as usize]);
    let at = (frame.look.shadow_size, cascade);
    let shape = (frame.grass.shape, frame.grass.tip_start);
    let corners = caster_corners(&blade, shape, view_proj, at);
    raster_caster(corners, at, &mut |x, y, d| unsafe {
        atomic_u_min::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut depth[texel_word(x, y, at.0)],
            d.to_bits(),
        );
    });
}

/// The far cascade: every caster, one a thread, workgroups of
/// `shadow::CASTERS_PER_GROUP` over the grid the compute pass wrote
/// (`shadow::caster_grid`).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(32)))]
pub fn raster_casters(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 13)] depth: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 23)] casters: &[u32],
) {
    let k = group_index(group, groups) * CASTERS_PER_GROUP + lane;
    if k < counters[COUNTER_CASTERS] {
        let source = (blades, clumps, ids, casters);
        let cascade = (frame.look.shadow_view_proj, 1);
        draw_caster(frame, source, (0, k), cascade, depth);
    }
}

/// [`raster_casters`] into the near cascade: its own casters, the list's second half.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(32)))]
pub fn raster_near_casters(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 13)] depth: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 23)] casters: &[u32],
) {
    let k = group_index(group, groups) * CASTERS_PER_GROUP + lane;
    if k < counters[COUNTER_NEAR_CASTERS] {
        let source = (blades, clumps, ids, casters);
        let cascade = (frame.look.near_view_proj, 0);
        draw_caster(frame, source, (frame.grass.blades, k), cascade, depth);
    }
}

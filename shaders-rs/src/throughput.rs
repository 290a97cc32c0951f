//! The triangle-throughput references: one-vertex patches tessellated like a blade,
//! or mesh workgroups of blade strips as the mesh path draws them, placed on a grid of
//! screen cells and shaded with one colour, so their draw time is what this device
//! needs to make and rasterise that many triangles through each pipeline.

use crate::mesh::strip_outputs;
use shared::cull::lod::tess_levels;
use shared::draw::meshlet::{group_index, strip_coord, strip_segments, strips_per_group};
use shared::draw::reference::{cell_point, patch_cell};
use shared::gpu::layout::ThroughputPush;
use spirv_std::glam::{UVec3, Vec3, Vec4};
use spirv_std::spirv;

/// The patch's screen cell and its level.
#[spirv(vertex)]
pub fn throughput_vs(
    #[spirv(vertex_index)] index: u32,
    #[spirv(push_constant)] push: &ThroughputPush,
    out_cell: &mut Vec4,
    out_level: &mut f32,
) {
    *out_cell = patch_cell(index, push);
    *out_level = push.level;
}

/// The fixed tessellation level of the push constants.
#[spirv(tessellation_control(output_vertices = 1))]
pub fn throughput_tcs(
    in_cell: [Vec4; 1],
    in_level: [f32; 1],
    out_cell: &mut [Vec4; 1],
    #[spirv(tess_level_outer)] outer: &mut [f32; 4],
    #[spirv(tess_level_inner)] inner: &mut [f32; 2],
) {
    out_cell[0] = in_cell[0];
    let (o, i) = tess_levels(in_level[0]);
    *outer = o;
    *inner = i;
}

/// The patch's cell, in clip space.
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn throughput_tes(
    #[spirv(tess_coord)] coord: Vec3,
    in_cell: [Vec4; 1],
    #[spirv(position)] out_position: &mut Vec4,
) {
    *out_position = cell_point(in_cell[0], coord.x, coord.y);
}

/// The mesh path's reference: each workgroup draws as many strips of the push
/// constant's level as the grass's mesh stage does (`meshlet::strips_per_group`),
/// strip i in cell i, with nothing else to compute.
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn throughput_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(push_constant)] push: &ThroughputPush,
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
) {
    let segments = strip_segments(push.level);
    let per = strips_per_group(segments);
    let (strip, k) = strip_outputs(lane, per, segments, indices);
    if strip < per {
        let cell = patch_cell(group_index(group, groups) * per + strip, push);
        let (u, v) = strip_coord(k, push.level);
        out_position[lane as usize] = cell_point(cell, u, v);
    }
}

/// One colour.
#[spirv(fragment)]
pub fn throughput_fs(out_color: &mut Vec4) {
    *out_color = Vec4::new(0.2, 0.5, 0.1, 1.0);
}

//! The triangle-throughput reference: one-vertex patches tessellated like a blade,
//! placed on a grid of screen cells and shaded with one colour, so their draw time is
//! what this device needs to tessellate and rasterise that many triangles.

use shared::layout::ThroughputPush;
use shared::lod::tess_levels;
use shared::reference::{cell_point, patch_cell};
use spirv_std::glam::{Vec3, Vec4};
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

/// One colour.
#[spirv(fragment)]
pub fn throughput_fs(out_color: &mut Vec4) {
    *out_color = Vec4::new(0.2, 0.5, 0.1, 1.0);
}

//! The mesh-shader grass pipelines (`--pipeline mesh`): no task stage; the compute
//! pass bins the visible blades by strip length (`shared::meshlet`) and writes one
//! indirect draw per bucket (and one for the blades that spilled out of theirs),
//! and each mesh workgroup of a draw of N segments builds
//! `meshlet::strips_per_group(N)` strips of N segments from `shared`'s Bezier and
//! shape functions: exactly 2N triangles each, with the varyings of the tessellation
//! path, so both paths share their fragment stages (`grass::grass_fs`,
//! `grass::natural_fs`).
//!
//! Output sizes are literals here (rust-gpu attributes take no constants): 32 vertices
//! and 30 triangles, `shared::draw::meshlet::MESHLET_VERTICES` and `MESHLET_TRIANGLES`; a
//! test reflects the modules to check that they agree.

use crate::grass::{natural_point, paper_vertex, point_motion};
use shared::Blade;
use shared::draw::look::clump::DressedBlade;
use shared::draw::meshlet::{
    MAX_STRIP_VERTICES, StripBlade, draw_segments, group_index, group_strips, strip_coord,
    strip_lane, strip_triangle, strip_triangles, strip_vertices, strips_per_group, top_segments,
};
use shared::draw::temporal::BladeMotion;
use shared::gpu::counters::draw_slice;
use shared::gpu::layout::FrameUniforms;
use spirv_std::arch::set_mesh_outputs_ext;
use spirv_std::glam::{UVec3, Vec3, Vec4};
use spirv_std::spirv;

/// Sets a mesh workgroup's outputs for `strips` strips of `segments` and writes their
/// triangles (one a lane); returns where invocation `lane`'s vertex lies: (strip,
/// vertex of the strip). The grass's mesh stages and the triangle reference's.
pub(crate) fn strip_outputs(
    lane: u32,
    strips: u32,
    segments: u32,
    indices: &mut [UVec3; 30],
) -> (u32, u32) {
    let (vertices, triangles) = (strip_vertices(segments), strip_triangles(segments));
    unsafe { set_mesh_outputs_ext(strips * vertices, strips * triangles) };
    if lane < strips * triangles {
        let strip = lane / triangles;
        indices[lane as usize] = strip_triangle(lane % triangles, strip * vertices);
    }
    strip_lane(lane, segments)
}

/// Sets the workgroup's outputs and writes its triangles, then gives this
/// invocation's vertex: (output index, the binned blade's slot, the binned blade,
/// (u, v, level)), if it has one. Draw `draw` holds its slice of the binned list
/// (`counters::draw_slice`: bucket `draw`'s strips, or the spilled ones), of
/// `meshlet::draw_segments` segments (`top` those of the longest bucket); workgroup
/// `group` of the launch `groups` takes the next [`strips_per_group`] of them.
#[allow(clippy::too_many_arguments)]
fn strip_vertex(
    draw: u32,
    top: u32,
    group: UVec3,
    groups: UVec3,
    lane: u32,
    counters: &[u32],
    binned: &[StripBlade],
    indices: &mut [UVec3; 30],
) -> Option<(usize, u32, StripBlade, Vec3)> {
    let segments = draw_segments(draw, top);
    let per = strips_per_group(segments);
    let first = group_index(group, groups) * per;
    let (base, count) = draw_slice(counters, draw);
    let strips = group_strips(count, first, per);
    let (strip, k) = strip_outputs(lane, strips, segments, indices);
    if strip >= strips {
        return None;
    }
    let at = base + first + strip;
    let blade = binned[at as usize];
    let (u, v) = strip_coord(k, blade.level);
    Some((lane as usize, at, blade, Vec3::new(u, v, blade.level)))
}

/// The paper look's mesh stage: strips of the stored blades, with the tessellation
/// evaluation stage's varyings (the normal with v, and the level).
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn paper_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(draw_index)] draw: u32,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &[StripBlade],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal_v: &mut [Vec4; 32],
    #[spirv(flat)] out_level: &mut [f32; 32],
) {
    let top = top_segments(frame.lod.most);
    let vertex = strip_vertex(draw, top, group, groups, lane, counters, binned, indices);
    if let Some((k, _, strip, uvl)) = vertex {
        let (clip, normal_v, _, _) = paper_vertex(frame, &blades[strip.source as usize], uvl);
        out_position[k] = clip;
        out_normal_v[k] = normal_v;
        out_level[k] = uvl.z;
    }
}

/// [`paper_mesh`] with temporal anti-aliasing: also each vertex's motion, from the
/// blade's previous control points in the motion buffer (at its index), for
/// `grass::grass_taa_fs`.
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn paper_taa_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(draw_index)] draw: u32,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &[StripBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 24)] motion: &[BladeMotion],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal_v: &mut [Vec4; 32],
    #[spirv(flat)] out_level: &mut [f32; 32],
    out_motion: &mut [Vec4; 32],
) {
    let top = top_segments(frame.lod.most);
    let vertex = strip_vertex(draw, top, group, groups, lane, counters, binned, indices);
    if let Some((k, _, strip, uvl)) = vertex {
        let index = strip.source as usize;
        let blade = &blades[index];
        let (clip, normal_v, point, v) = paper_vertex(frame, blade, uvl);
        out_position[k] = clip;
        out_normal_v[k] = normal_v;
        out_level[k] = uvl.z;
        // A vec4 (zw unused): lavapipe's mesh stages crash on arrays of vec2 outputs.
        let moved = point_motion(frame, motion, index, point, v, blade);
        out_motion[k] = moved.extend(0.0).extend(0.0);
    }
}

/// [`paper_mesh`] that also writes each vertex's clip position to the capture buffer
/// (the bandwidth reference's scratch binding), at the binned slot's
/// `MAX_STRIP_VERTICES` entries: for the test comparing it with the host's vertices.
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn paper_mesh_capture(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(draw_index)] draw: u32,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] capture: &mut [Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &[StripBlade],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal_v: &mut [Vec4; 32],
    #[spirv(flat)] out_level: &mut [f32; 32],
) {
    let top = top_segments(frame.lod.most);
    let vertex = strip_vertex(draw, top, group, groups, lane, counters, binned, indices);
    if let Some((k, at, strip, uvl)) = vertex {
        let (clip, normal_v, _, _) = paper_vertex(frame, &blades[strip.source as usize], uvl);
        out_position[k] = clip;
        out_normal_v[k] = normal_v;
        out_level[k] = uvl.z;
        let (_, vertex) = strip_lane(lane, draw_segments(draw, top));
        capture[(at * MAX_STRIP_VERTICES + vertex) as usize] = clip;
    }
}

/// The natural look's mesh stage: strips of the dressed blades, with the natural
/// tessellation evaluation stage's varyings (tint and width direction the same at
/// every vertex of a blade, read flat). Drawn this way with multisampling; at one
/// sample the natural look is shaded after the draw ([`natural_vis_mesh`]).
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn natural_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(draw_index)] draw: u32,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &[StripBlade],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal: &mut [Vec3; 32],
    out_world: &mut [Vec3; 32],
    out_uv_level: &mut [Vec3; 32],
    #[spirv(flat)] out_tint: &mut [Vec4; 32],
    #[spirv(flat)] out_width_dir: &mut [Vec3; 32],
) {
    let top = top_segments(frame.lod.most);
    let vertex = strip_vertex(draw, top, group, groups, lane, counters, binned, indices);
    if let Some((k, _, strip, uvl)) = vertex {
        let drawn = &dressed[strip.source as usize];
        let (p, v) = natural_point(frame, drawn, uvl);
        out_position[k] = frame.camera.view_proj * p.position.extend(1.0);
        out_normal[k] = p.normal;
        out_world[k] = p.position;
        out_uv_level[k] = Vec3::new(uvl.x, v, uvl.z);
        out_tint[k] = drawn.tint;
        out_width_dir[k] = p.width_dir;
    }
}

/// The natural look's mesh stage for shading after the draw (one sample per pixel,
/// `grass::natural_vis_fs`): each vertex's surface coordinates and, flat, the
/// blade's slot.
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn natural_vis_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(draw_index)] draw: u32,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &[StripBlade],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_uv: &mut [Vec4; 32],
    #[spirv(flat)] out_slot: &mut [f32; 32],
) {
    let top = top_segments(frame.lod.most);
    let vertex = strip_vertex(draw, top, group, groups, lane, counters, binned, indices);
    if let Some((k, _, strip, uvl)) = vertex {
        let (p, v) = natural_point(frame, &dressed[strip.source as usize], uvl);
        out_position[k] = frame.camera.view_proj * p.position.extend(1.0);
        out_uv[k] = Vec4::new(uvl.x, v, 0.0, 0.0);
        out_slot[k] = strip.source as f32;
    }
}

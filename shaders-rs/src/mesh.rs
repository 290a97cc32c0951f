//! The mesh-shader grass pipelines (`--pipeline mesh`): task stages that take 32
//! visible blades each, set their level of detail, drop what the look leaves out and
//! pack the rest into meshlets (`shared::meshlet`); mesh stages that build each
//! blade's strip from `shared`'s Bezier and shape functions, exactly 2N triangles for
//! N segments, with the varyings of the tessellation path, so both paths share their
//! fragment stages (`grass::grass_fs`, `grass::natural_fs`).
//!
//! Output sizes are literals here (rust-gpu attributes take no constants): 32 vertices
//! and 30 triangles, `shared::meshlet::MESHLET_VERTICES` and `MESHLET_TRIANGLES`; a
//! test reflects the modules to check that they agree.

use crate::grass::level_of;
use shared::Blade;
use shared::layout::{COUNTER_VISIBLE, FrameUniforms};
use shared::look::{DressedBlade, unpack_coverage};
use shared::meshlet::{
    BladeGroup, MESH_THREADS, TASK_BLADES, meshlet_extent, strip_coord, strip_segments,
    strip_triangle, strip_triangles, strip_vertices, task_slot, vertex_base,
};
use shared::shape::surface_point;
use spirv_std::arch::{
    IndexUnchecked, emit_mesh_tasks_ext_payload, set_mesh_outputs_ext,
    workgroup_memory_barrier_with_group_sync,
};
use spirv_std::glam::{UVec3, Vec3, Vec4};
use spirv_std::spirv;

/// Records one blade of the group (0 segments drops it), packs the group once every
/// invocation has, and launches one mesh workgroup per meshlet.
/// No panic path may lead here (`shared::meshlet`): task stages index without bounds
/// checks.
fn launch(payload: &mut BladeGroup, lane: u32, slot: u32, level: f32, segments: u32) -> ! {
    payload.set(lane, slot, level, segments);
    workgroup_memory_barrier_with_group_sync();
    // One invocation packs for the workgroup; every one launches the same count.
    if lane == 0 {
        payload.pack(TASK_BLADES);
    }
    workgroup_memory_barrier_with_group_sync();
    let meshlets = payload.meshlets;
    unsafe { emit_mesh_tasks_ext_payload(meshlets, 1, 1, payload) }
}

/// The paper look's task stage: the stored blade's level of detail.
#[allow(clippy::too_many_arguments)]
#[spirv(task_ext(threads(32)))]
pub fn paper_task(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(task_payload_workgroup_ext)] payload: &mut BladeGroup,
) {
    let slot = task_slot(group, groups, lane);
    let (mut index, mut level, mut segments) = (0, 1.0, 0);
    // SAFETY: the counter is in the buffer, visible slots below it hold blade indices.
    unsafe {
        if slot < *counters.index_unchecked(COUNTER_VISIBLE) {
            index = *visible.index_unchecked(slot as usize);
            level = level_of(blades.index_unchecked(index as usize), frame);
            segments = strip_segments(level);
        }
    }
    launch(payload, lane, index, level, segments)
}

/// The natural look's task stage: the dressed blade's level of detail; a thin blade
/// its coverage leaves out (`shared::look::dress`) is dropped.
#[allow(clippy::too_many_arguments)]
#[spirv(task_ext(threads(32)))]
pub fn natural_task(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(num_workgroups)] groups: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(task_payload_workgroup_ext)] payload: &mut BladeGroup,
) {
    let slot = task_slot(group, groups, lane);
    let (mut level, mut segments) = (1.0, 0);
    // SAFETY: the counter is in the buffer, each visible slot has its dressed blade.
    unsafe {
        if slot < *counters.index_unchecked(COUNTER_VISIBLE) {
            let drawn = dressed.index_unchecked(slot as usize);
            level = level_of(&drawn.blade, frame);
            let (mask, _) = unpack_coverage(drawn.tint.w);
            if mask != 0 {
                segments = strip_segments(level);
            }
        }
    }
    launch(payload, lane, slot, level, segments)
}

/// Each blade of meshlet `group.x` takes an invocation, which marks its vertices in
/// `owners` (blade | row-and-side << 8) and writes its triangles; after the barrier
/// every invocation finds its vertices' blades in one read. Returns (vertices,
/// triangles), their counts already set.
fn mark_blades(
    payload: &BladeGroup,
    group: UVec3,
    lane: u32,
    owners: &mut [u32; 32],
    indices: &mut [UVec3; 30],
) -> u32 {
    let (first, end, vertices, triangles) = meshlet_extent(payload, group.x);
    unsafe { set_mesh_outputs_ext(vertices, triangles) };
    let b = first + lane;
    if b < end {
        let base = vertex_base(payload, first, b);
        let segments = payload.segments[b as usize];
        let mut k = 0;
        while k < strip_vertices(segments) {
            owners[(base + k) as usize] = b | (k << 8);
            k += 1;
        }
        // Each strip has 2 more vertices than triangles.
        let triangle_base = base - 2 * (b - first);
        let mut t = 0;
        while t < strip_triangles(segments) {
            indices[(triangle_base + t) as usize] = strip_triangle(t, base);
            t += 1;
        }
    }
    workgroup_memory_barrier_with_group_sync();
    vertices
}

/// Calls `vertex(k, blade's slot, (u, v, level))` for each vertex k of the marked
/// meshlet this invocation shades.
fn for_vertices(
    payload: &BladeGroup,
    owners: &[u32; 32],
    vertices: u32,
    lane: u32,
    mut vertex: impl FnMut(usize, usize, Vec3),
) {
    let mut i = lane;
    while i < vertices {
        let owner = owners[i as usize];
        let b = (owner & 0xff) as usize;
        let level = payload.levels[b];
        let (u, v) = strip_coord(owner >> 8, level);
        vertex(
            i as usize,
            payload.slots[b] as usize,
            Vec3::new(u, v, level),
        );
        i += MESH_THREADS;
    }
}

/// The paper look's mesh stage: each blade of the meshlet as a strip, with the
/// tessellation evaluation stage's varyings.
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn paper_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(task_payload_workgroup_ext)] payload: &BladeGroup,
    #[spirv(workgroup)] owners: &mut [u32; 32],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal: &mut [Vec3; 32],
    out_world: &mut [Vec3; 32],
    out_uv_level: &mut [Vec3; 32],
) {
    let vertices = mark_blades(payload, group, lane, owners, indices);
    let grass = &frame.grass;
    for_vertices(payload, owners, vertices, lane, |k, slot, uvl| {
        let p = surface_point(&blades[slot], uvl.x, uvl.y, grass.shape, grass.tip_start);
        out_position[k] = frame.camera.view_proj * p.position.extend(1.0);
        out_normal[k] = p.normal;
        out_world[k] = p.position;
        out_uv_level[k] = uvl;
    });
}

/// The natural look's mesh stage: each dressed blade of the meshlet as a strip, with
/// the natural tessellation evaluation stage's varyings (tint and width direction the
/// same at every vertex of a blade, read flat).
#[allow(clippy::too_many_arguments)]
#[spirv(mesh_ext(
    threads(32),
    output_vertices = 32,
    output_primitives_ext = 30,
    output_triangles_ext
))]
pub fn natural_mesh(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(local_invocation_index)] lane: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(task_payload_workgroup_ext)] payload: &BladeGroup,
    #[spirv(workgroup)] owners: &mut [u32; 32],
    #[spirv(primitive_triangle_indices_ext)] indices: &mut [UVec3; 30],
    #[spirv(position)] out_position: &mut [Vec4; 32],
    out_normal: &mut [Vec3; 32],
    out_world: &mut [Vec3; 32],
    out_uv_level: &mut [Vec3; 32],
    #[spirv(flat)] out_tint: &mut [Vec4; 32],
    #[spirv(flat)] out_width_dir: &mut [Vec3; 32],
) {
    let vertices = mark_blades(payload, group, lane, owners, indices);
    let grass = &frame.grass;
    for_vertices(payload, owners, vertices, lane, |k, slot, uvl| {
        let drawn = &dressed[slot];
        let p = surface_point(&drawn.blade, uvl.x, uvl.y, grass.shape, grass.tip_start);
        out_position[k] = frame.camera.view_proj * p.position.extend(1.0);
        out_normal[k] = p.normal;
        out_world[k] = p.position;
        out_uv_level[k] = uvl;
        out_tint[k] = drawn.tint;
        out_width_dir[k] = p.width_dir;
    });
}

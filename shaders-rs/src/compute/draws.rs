//! The indirect draws of every path.

use shared::cull::lod::chunk_range;
use shared::draw::look::shadow::caster_grid;
use shared::draw::meshlet::{MESH_DRAWS, draw_segments, mesh_grid, top_segments};
use shared::draw::raster::{RASTER_GRID_WIDTH, prepare_dispatch, raster_dispatch};
use shared::gpu::counters::{COUNTER_CASTERS, COUNTER_FAR, COUNTER_NEAR_CASTERS, COUNTER_VISIBLE};
use shared::gpu::counters::{draw_slice, lay_out_draws};
use shared::gpu::layout::{
    CHUNK_WORKGROUP, ChunkPush, FrameUniforms, PREPARE_WORKGROUP, RASTER_DISPATCH, RASTER_DRAW,
    RASTER_PREPARE, SIMULATE_WORKGROUP, flat_index,
};
use spirv_std::glam::UVec3;
use spirv_std::indirect_command::{DrawIndirectCommand, DrawMeshTasksIndirectCommandEXT};
use spirv_std::spirv;

/// One thread per chunk: the draw command of its slice of the visible blades; the
/// first also writes the shadow casters' dispatches (after the mesh draws), the mesh path's
/// draws (one grid per bucket of strips and the spill's, their slices of the binned
/// list, and the next frame's layout of it: `counters::lay_out_draws`), and the
/// compute rasterizer's preparation, dispatch and resolve.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn write_draws(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &ChunkPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] draws: &mut [DrawIndirectCommand],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 12)]
    mesh_draws: &mut [DrawMeshTasksIndirectCommandEXT],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 16)] raster_args: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
) {
    let chunk = flat_index(id, workgroups, CHUNK_WORKGROUP);
    if chunk >= push.chunk_count {
        return;
    }
    let visible = counters[COUNTER_VISIBLE];
    if chunk == 0 {
        // The shadow casters' dispatches (`compute::shadow`), a caster a thread: all,
        // then the near cascade's.
        let grass_draws = MESH_DRAWS as usize;
        mesh_draws[grass_draws] = caster_grid(counters[COUNTER_CASTERS]).into();
        mesh_draws[grass_draws + 1] = caster_grid(counters[COUNTER_NEAR_CASTERS]).into();
        // The rasterizer's dispatch and the resolve's three vertices, if there are far
        // blades.
        let far = counters[COUNTER_FAR];
        let (x, y) = raster_dispatch(far, SIMULATE_WORKGROUP, RASTER_GRID_WIDTH);
        raster_args[RASTER_DISPATCH] = x;
        raster_args[RASTER_DISPATCH + 1] = y;
        raster_args[RASTER_DISPATCH + 2] = 1;
        raster_args[RASTER_DRAW] = if far > 0 { 3 } else { 0 };
        raster_args[RASTER_DRAW + 1] = 1;
        raster_args[RASTER_DRAW + 2] = 0;
        raster_args[RASTER_DRAW + 3] = 0;
        let size = (frame.raster.width, frame.raster.height);
        let (x, y) = prepare_dispatch(far, size, PREPARE_WORKGROUP);
        raster_args[RASTER_PREPARE] = x;
        raster_args[RASTER_PREPARE + 1] = y;
        raster_args[RASTER_PREPARE + 2] = 1;
        lay_out_draws(counters, frame.grass.blades);
        let mut draw = 0;
        let top = top_segments(frame.lod.most);
        while draw < MESH_DRAWS {
            let (_, strips) = draw_slice(counters, draw);
            mesh_draws[draw as usize] = mesh_grid(strips, draw_segments(draw, top)).into();
            draw += 1;
        }
    }
    let (first, count) = chunk_range(visible, chunk, push.chunk_size);
    draws[chunk as usize] = DrawIndirectCommand {
        vertex_count: count,
        instance_count: 1,
        first_vertex: first,
        first_instance: 0,
    };
}

//! The indirect draws: the mesh path's binning of the visible blades by strip length,
//! and the draw commands of every path.

use shared::cull::lod::chunk_range;
use shared::draw::look::LOOK_NATURAL;
use shared::draw::look::shadow::caster_grid;
use shared::draw::meshlet::{
    BUCKETS, StripBlade, bucket_segments, mesh_grid, packed_bucket, top_segments, unpack_level,
};
use shared::draw::raster::{RASTER_GRID_WIDTH, prepare_dispatch, raster_dispatch};
use shared::gpu::counters::{COUNTER_CASTERS, COUNTER_FAR, COUNTER_NEAR_CASTERS, COUNTER_VISIBLE};
use shared::gpu::counters::{binned_counter, bucket_base, strip_counter};
use shared::gpu::layout::{
    CHUNK_WORKGROUP, CULL_WORKGROUP, ChunkPush, FrameUniforms, PREPARE_WORKGROUP, RASTER_DISPATCH,
    RASTER_DRAW, RASTER_PREPARE, SIMULATE_WORKGROUP, flat_index,
};
use spirv_std::arch::{atomic_i_add, atomic_i_increment, workgroup_memory_barrier_with_group_sync};
use spirv_std::glam::UVec3;
use spirv_std::indirect_command::{DrawIndirectCommand, DrawMeshTasksIndirectCommandEXT};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// The mesh path's binning, one thread per slot of the visible list: each drawn blade
/// goes to the list of its strip length (`shared::meshlet`: bucket N after the
/// shorter strips), with what the mesh stage reads it from and its level. As in
/// [`simulate_cull`], places are counted in workgroup memory and each workgroup takes
/// its slots of a bucket with one device atomic: a device atomic per blade on nine
/// counters cost 1 ms at 4 M blades on the NVIDIA H100.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(128)))]
pub fn bin_blades(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 13)] levels: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &mut [StripBlade],
    #[spirv(workgroup)] tally: &mut [u32; BUCKETS as usize],
) {
    let slot = flat_index(id, workgroups, CULL_WORKGROUP);
    // A workgroup past the end of the list has nothing to bin (the same for all its
    // threads, so none of them waits at a barrier for the others): one thread per
    // slot the list can have, of which most are past its end.
    if slot - local >= counters[COUNTER_VISIBLE] {
        return;
    }
    if local < BUCKETS {
        tally[local as usize] = 0;
    }
    workgroup_memory_barrier_with_group_sync();
    let mut bucket = BUCKETS;
    let mut level = 0.0;
    let mut place = 0;
    if slot < counters[COUNTER_VISIBLE] {
        let packed = levels[slot as usize];
        level = unpack_level(packed).0;
        if level > 0.0 {
            bucket = packed_bucket(packed, frame.lod.most);
            place = unsafe {
                atomic_i_increment::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                    &mut tally[bucket as usize],
                )
            };
        }
    }
    workgroup_memory_barrier_with_group_sync();
    // Thread k takes the workgroup's slots of bucket k and keeps their start.
    if local < BUCKETS {
        let count = tally[local as usize];
        if count > 0 {
            let first = unsafe {
                atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut counters[binned_counter(local)],
                    count,
                )
            };
            tally[local as usize] = bucket_base(counters, local) + first;
        }
    }
    workgroup_memory_barrier_with_group_sync();
    if bucket < BUCKETS {
        let source = if frame.look.style == LOOK_NATURAL {
            slot
        } else {
            visible[slot as usize]
        };
        let at = tally[bucket as usize] + place;
        binned[at as usize] = StripBlade { source, level };
    }
}

/// One thread per chunk: the draw command of its slice of the visible blades; the
/// first also writes the shadow casters' draws (after the chunks'), the mesh path's
/// draws, one grid per strip length, and the compute rasterizer's preparation,
/// dispatch and resolve.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn write_draws(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &ChunkPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
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
        draws[push.chunk_count as usize] = DrawIndirectCommand {
            vertex_count: counters[COUNTER_CASTERS],
            instance_count: 1,
            first_vertex: 0,
            first_instance: 0,
        };
        // The near cascade's casters, in the list's second half.
        draws[push.chunk_count as usize + 1] = DrawIndirectCommand {
            vertex_count: counters[COUNTER_NEAR_CASTERS],
            instance_count: 1,
            first_vertex: frame.grass.blades,
            first_instance: 0,
        };
        // The same casters through the mesh path, a triangle a lane.
        let buckets = BUCKETS as usize;
        mesh_draws[buckets] = caster_grid(counters[COUNTER_CASTERS]).into();
        mesh_draws[buckets + 1] = caster_grid(counters[COUNTER_NEAR_CASTERS]).into();
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
        let mut draw = 0;
        let top = top_segments(frame.lod.most);
        while draw < BUCKETS {
            let n = bucket_segments(draw, top);
            mesh_draws[draw as usize] = mesh_grid(counters[strip_counter(draw)], n).into();
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

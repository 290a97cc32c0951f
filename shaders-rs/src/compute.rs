//! The compute passes: reduce the occluders' depth into a pyramid, then simulate every
//! blade, cull it, count each test's removals and compact the survivors, then write
//! the indirect draw commands.

use crate::{DepthImage, DepthImageMs};
use shared::Blade;
use shared::cull::{KEPT, cull_outcome};
use shared::hiz::{level_size, reduce};
use shared::layout::{
    CHUNK_WORKGROUP, COPY_WORKGROUP, COUNTER_COUNT, COUNTER_EXAMINED, COUNTER_FAR,
    COUNTER_RASTER_COVERED, COUNTER_RASTER_WRITTEN, COUNTER_VISIBLE, ChunkPush, CopyPush,
    FrameUniforms, HiZPush, PIPELINE_MESH, PREPARE_WORKGROUP, PreparePush, RASTER_DISPATCH,
    RASTER_DRAW, RASTER_PREPARE, SIMULATE_WORKGROUP, SimulatePush, far_slot, flat_index,
};
use shared::layout::{
    COUNTER_TILE_BLADES, COUNTER_TILES, COUNTER_TILES_HIDDEN, COUNTER_TILES_SHORT, EMPTY_SLOT,
    GENERATE_WORKGROUP, IDS_WORDS, POOL_WORDS, SelectPush, TILE_WORDS, TILES_DISPATCH, TILES_LIST,
    TILES_POOL, TilePush,
};
use shared::lod::{blade_level, chunk_range};
use shared::look::{Clump, DressedBlade, LOOK_NATURAL, clump_at, dress, unpack_coverage};
use shared::meshlet::{
    BUCKETS, StripBlade, binned_counter, bucket_base, bucket_segments, mesh_grid, packed_bucket,
    strip_counter, top_segments, unpack_level, visible_level,
};
use shared::raster::{
    Coverage, EMPTY, RASTER_GRID_WIDTH, in_front, is_far, packed_depth, pixel_index,
    prepare_dispatch, raster_blade, raster_dispatch,
};
use shared::simulate::simulate;
use shared::tiles::{
    TileParams, blade_id, drawn_width, fade_to_far, far_blade, far_count, kept, pack_map_point,
    tile_blade, tile_box, tile_in_view, tile_occluded, unpack_map_point,
};
use spirv_std::arch::{
    atomic_i_add, atomic_i_increment, atomic_load, atomic_u_max, atomic_u_min,
    workgroup_memory_barrier_with_group_sync,
};
use spirv_std::glam::{IVec2, UVec2, UVec3, Vec2, Vec3, Vec4};
use spirv_std::image::ImageWithMethods;
use spirv_std::image::sample_with::sample_index;
use spirv_std::indirect_command::{DrawIndirectCommand, DrawMeshTasksIndirectCommandEXT};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// The per-blade buffers the simulate-and-cull pass reads and writes.
pub struct BladeBuffers<'a> {
    blades: &'a mut [Blade],
    visible: &'a mut [u32],
    counters: &'a mut [u32],
    strengths: &'a mut [f32],
    pyramid: &'a [f32],
    levels: &'a mut [f32],
    ids: &'a [u32],
    tiles: &'a [u32],
    paint: &'a [u32],
}

/// One thread per blade: this frame's fixed steps of forces, collisions and validation
/// (the blade and its collision strength η are read and written back), then the cull
/// tests. Outcomes are tallied in workgroup memory, so each workgroup adds to each
/// device counter once; a visible blade's index (4 bytes, not its 64) lands at the
/// workgroup's base (one device atomic) plus its place within the workgroup. On the
/// mesh path each visible blade's level of detail goes to the same slot of the
/// levels buffer and is counted by strip length, for [`bin_blades`]. The paper look's
/// entry point: nothing of the natural look is compiled in.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn simulate_cull(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SimulatePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] strengths: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] pyramid: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 13)] levels: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; COUNTER_COUNT],
) {
    let buffers = BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        levels,
        ids,
        tiles,
        paint,
    };
    let mesh = frame.grass.pipeline == PIPELINE_MESH;
    let prepare = |_: u32, _: u32, kept: &Blade, _: &[u32], _: Vec2| {
        ((), if mesh { blade_level(kept, frame) } else { 0.0 })
    };
    simulate_and_cull(
        id,
        local,
        workgroups,
        frame,
        push,
        buffers,
        tally,
        prepare,
        |_, _| {},
    );
}

/// [`simulate_cull`] for the natural look: each visible blade as drawn
/// (`shared::look::dress`, from its clump) also goes to its slot of the dressed buffer;
/// its level of detail on the mesh path is the dressed blade's, 0 for a thin blade its
/// coverage leaves out.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn simulate_cull_natural(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SimulatePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] strengths: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] pyramid: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &mut [DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 13)] levels: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; COUNTER_COUNT],
) {
    let buffers = BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        levels,
        ids,
        tiles,
        paint,
    };
    let camera = frame.camera.position;
    let half = push.tiles.half_extent;
    let prepare = |index: u32, id: u32, kept: &Blade, paint: &[u32], at: Vec2| {
        let clump = Clump::unpack(clumps[index as usize]);
        let (blade, tint) = dress(kept, &clump, id, camera, &frame.cull, &frame.look);
        // The painted colour map (white where there is none).
        let colour = shared::paint::sample(paint, shared::paint::COLOUR, at, half);
        let tint = Vec4::new(
            tint.x * colour.x,
            tint.y * colour.y,
            tint.z * colour.z,
            tint.w,
        );
        let (mask, _) = unpack_coverage(tint.w);
        let mesh = frame.grass.pipeline == PIPELINE_MESH;
        let level = if mesh && mask != 0 {
            blade_level(&blade, frame)
        } else {
            0.0
        };
        (DressedBlade { blade, tint }, level)
    };
    let store = |slot: usize, drawn: DressedBlade| dressed[slot] = drawn;
    simulate_and_cull(
        id, local, workgroups, frame, push, buffers, tally, prepare, store,
    );
}

/// The body of both simulate-and-cull entry points: `prepare(index, id, blade, maps)` runs
/// for each visible blade and gives what `store(slot, ..)` writes once its slot of the
/// visible list is known, and its level of detail on the mesh path (0: not drawn).
/// In a tiled field (`GrassParams::tiled`) only the pool's blades are simulated, the
/// far tiles' blades count as far as this frame generated them, an empty blade
/// (width 0: a free slot, a blade its rank left) is skipped, and a blade's name is
/// its id (`tiles::blade_id`) rather than its index.
#[allow(clippy::too_many_arguments)]
fn simulate_and_cull<T: Copy + Default>(
    id: UVec3,
    local: u32,
    workgroups: UVec3,
    frame: &FrameUniforms,
    push: &SimulatePush,
    buffers: BladeBuffers,
    tally: &mut [u32; COUNTER_COUNT],
    mut prepare: impl FnMut(u32, u32, &Blade, &[u32], Vec2) -> (T, f32),
    mut store: impl FnMut(usize, T),
) {
    let BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        levels,
        ids,
        tiles,
        paint,
    } = buffers;
    if local < COUNTER_COUNT as u32 {
        tally[local as usize] = 0;
    }
    workgroup_memory_barrier_with_group_sync();

    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let grass = &frame.grass;
    let tiled = grass.tiled != 0;
    let simulated = index < grass.simulated;
    let mut in_field = index < grass.blades
        && (simulated || (tiled && index - grass.simulated < counters[COUNTER_TILE_BLADES]));
    let mesh = grass.pipeline == PIPELINE_MESH;
    let mut outcome = KEPT;
    let mut far = false;
    let mut place = 0;
    let mut prepared = T::default();
    let mut level = 0.0;
    let mut name = index;
    // Where it reads the painted maps (a tiled field's: `tiles::pack_map_point`; a
    // stored one's: its root over the map square).
    let mut map_at = Vec2::ZERO;
    // A pool blade's width as its distance thins it, like a far one's: a blade its
    // rank has left is still simulated (its trail decays as if seen) but not drawn.
    let mut pool_width = 0.0;
    // A tile nobody needs goes back to its far pose (`tiles::fade_to_far`).
    let mut fade = 0.0;
    let mut rest_tile = IVec2::ZERO;
    if in_field && tiled {
        let i = index as usize;
        name = ids[IDS_WORDS * i];
        map_at = unpack_map_point(ids[IDS_WORDS * i + 1], &push.tiles);
        if simulated {
            let params = &push.tiles;
            let per_tile = params.per_side * params.per_side;
            let slot = TILES_POOL + POOL_WORDS * (index / per_tile) as usize;
            let tile = IVec2::new(tiles[slot] as i32, tiles[slot + 1] as i32);
            let blade = &blades[i];
            let root = blade.root();
            let k = index % per_tile;
            // A blade of a held tile that grows there (its width at the root).
            in_field = tile.x != EMPTY_SLOT
                && blade.height() > 0.0
                && drawn_width(tile, k, root, root, params, paint) > 0.0;
            if in_field {
                pool_width = drawn_width(tile, k, root, frame.camera.position, params, paint);
                fade = f32::from_bits(tiles[slot + 2]);
                rest_tile = tile;
            }
        } else {
            in_field = kept(&blades[i]);
        }
    } else if in_field {
        // A stored blade reads the maps at its root, over the map square.
        map_at = shared::tiles::map_point(blades[index as usize].root(), &push.tiles);
    }
    let mut drawn = in_field;
    let mut blade = Blade::default();
    if in_field {
        let i = index as usize;
        blade = blades[i];
        if tiled && simulated {
            blade = blade.with_width(pool_width);
            drawn = pool_width > 0.0;
        }
        if simulated {
            let strength;
            (blade, strength) = simulate(
                (blade, strengths[i]),
                &frame.forces,
                &frame.colliders,
                push.first_step,
                push.steps,
            );
            if fade > 0.0 {
                let k = index % (push.tiles.per_side * push.tiles.per_side);
                let params = &push.tiles;
                let far = far_blade(rest_tile, k, blade.root(), params, paint, &frame.forces);
                blade = fade_to_far(&blade, &far, fade);
            }
            blades[i] = blade;
            strengths[i] = strength;
        }
    }
    if drawn {
        outcome = cull_outcome(
            &blade,
            name,
            frame.camera.position,
            frame.camera.view_proj,
            &frame.cull,
            pyramid,
            &frame.hiz,
        );
        // A visible blade short on screen goes to the compute rasterizer's list.
        let camera = &frame.camera;
        far =
            outcome == KEPT && is_far(&blade, camera.position, camera.focal_pixels, &frame.raster);
        let counter = if far { COUNTER_FAR } else { outcome as usize };
        place = unsafe {
            atomic_i_increment::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[counter],
            )
        };
        unsafe {
            atomic_i_increment::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[COUNTER_EXAMINED],
            );
        }
        if outcome == KEPT {
            (prepared, level) = prepare(index, name, &blade, paint, map_at);
            if mesh && !far && level > 0.0 {
                // Its bucket: its strip length, and near the camera its band, from
                // the level as the binning pass reads it back.
                level = visible_level(level, &blade, frame.camera.position);
                let bucket = packed_bucket(level, frame.lod.most);
                unsafe {
                    atomic_i_increment::<
                        u32,
                        { Scope::Workgroup as u32 },
                        { Semantics::NONE.bits() },
                    >(&mut tally[strip_counter(bucket)]);
                }
            }
        }
    }
    workgroup_memory_barrier_with_group_sync();

    // Thread k adds tally k to the device counter k; the visible and far ones keep
    // the base of the workgroup's slots in the tally for the others.
    if local < COUNTER_COUNT as u32 {
        let k = local as usize;
        let count = tally[k];
        if count > 0 {
            let base = unsafe {
                atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut counters[k],
                    count,
                )
            };
            if k == COUNTER_VISIBLE || k == COUNTER_FAR {
                tally[k] = base;
            }
        }
    }
    workgroup_memory_barrier_with_group_sync();

    if drawn && outcome == KEPT {
        let slot = if far {
            far_slot(tally[COUNTER_FAR] + place, frame.grass.blades)
        } else {
            tally[COUNTER_VISIBLE] + place
        } as usize;
        visible[slot] = index;
        store(slot, prepared);
        if mesh && !far {
            levels[slot] = level;
        }
    }
}

/// The mesh path's binning, one thread per slot of the visible list: each drawn blade
/// goes to the list of its strip length (`shared::meshlet`: bucket N after the
/// shorter strips), with what the mesh stage reads it from and its level. As in
/// [`simulate_cull`], places are counted in workgroup memory and each workgroup takes
/// its slots of a bucket with one device atomic: a device atomic per blade on nine
/// counters cost 1 ms at 4 M blades on the NVIDIA H100.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
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
    if local < BUCKETS {
        tally[local as usize] = 0;
    }
    workgroup_memory_barrier_with_group_sync();
    let slot = flat_index(id, workgroups, SIMULATE_WORKGROUP);
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

/// The compute rasterizer (`shared::raster`), paper look: one thread per far blade,
/// its line or, where it is wide, its surface (`raster_blade`), into the visibility
/// buffer ([`RasterTarget::plot`]).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn raster_far(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; 2],
) {
    let k = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let mut target = RasterTarget {
        frame,
        visibility,
        hardware,
    };
    let mut pixels = (0, 0);
    if k < counters[COUNTER_FAR] {
        let index = visible[far_slot(k, frame.grass.blades) as usize];
        let blade = &blades[index as usize];
        let camera = &frame.camera;
        let shape = (frame.grass.shape, frame.grass.tip_start);
        let name = blade_name(index, frame, ids);
        let coverage = Coverage::of(blade, name, shape, camera.position, camera.focal_pixels);
        pixels = target.draw(blade, k, &coverage);
    }
    count_pixels(local, pixels, counters, tally);
}

/// [`raster_far`] for the natural look: the dressed blade, drawn if its coverage keeps
/// it (`shared::look::dress`).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn raster_far_natural(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; 2],
) {
    let k = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let mut target = RasterTarget {
        frame,
        visibility,
        hardware,
    };
    let mut pixels = (0, 0);
    if k < counters[COUNTER_FAR] {
        let slot = far_slot(k, frame.grass.blades);
        let drawn = &dressed[slot as usize];
        let (mask, _) = unpack_coverage(drawn.tint.w);
        if mask != 0 {
            let (camera, shape) = (&frame.camera, (frame.grass.shape, frame.grass.tip_start));
            let focal = camera.focal_pixels;
            // The coverage hash of the blade's own name, as in the paper look: its
            // slot changes from frame to frame with the compaction's order.
            let name = blade_name(visible[slot as usize], frame, ids);
            let coverage = Coverage::of(&drawn.blade, name, shape, camera.position, focal);
            pixels = target.draw(&drawn.blade, k, &coverage);
        }
    }
    count_pixels(local, pixels, counters, tally);
}

/// Blade `index`'s name for the per-blade hashes: its index in a stored field, its
/// id (`tiles::blade_id`) in a tiled one.
fn blade_name(index: u32, frame: &FrameUniforms, ids: &[u32]) -> u32 {
    if frame.grass.tiled != 0 {
        ids[IDS_WORDS * index as usize]
    } else {
        index
    }
}

/// What the rasterizer draws into: the frame, the visibility buffer and the
/// hardware's depth.
struct RasterTarget<'a> {
    frame: &'a FrameUniforms,
    visibility: &'a mut [u64],
    hardware: &'a [f32],
}

impl RasterTarget<'_> {
    /// Far blade `k` into the visibility buffer (`raster_blade`). Returns (pixels
    /// covered, pixels written).
    fn draw(&mut self, blade: &Blade, k: u32, coverage: &Coverage) -> (u32, u32) {
        let (view_proj, params) = (self.frame.camera.view_proj, self.frame.raster);
        let mut written = 0;
        let covered = raster_blade(blade, k, coverage, view_proj, &params, |x, y, packed| {
            if self.plot(x, y, packed) {
                written += 1;
            }
        });
        (covered, written)
    }

    /// A far blade's sample into the visibility buffer, nearest first by atomic
    /// minimum: only where it is in front of the hardware's depth and of the value the
    /// pixel holds (`shared::raster::in_front`), so a hidden pixel costs a load
    /// instead of an atomic. Returns whether it took the atomic.
    fn plot(&mut self, x: u32, y: u32, packed: u64) -> bool {
        let i = pixel_index(x, y, self.frame.raster.width);
        let held = unsafe {
            atomic_load::<u64, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                &self.visibility[i],
            )
        };
        let front = in_front(packed_depth(packed), self.hardware[i]) && packed < held;
        if front {
            unsafe {
                atomic_u_min::<u64, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut self.visibility[i],
                    packed,
                );
            }
        }
        front
    }
}

/// The compute rasterizer's preparation, one thread per pixel (an indirect dispatch,
/// none without far blades): the visibility buffer's pixel cleared, and the
/// hardware's depth copied from the depth target into the rasterizer's buffer
/// (`shared::layout::BINDING_DEPTH_IMAGE`).
#[spirv(compute(threads(8, 8)))]
pub fn raster_prepare(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &mut [f32],
    #[spirv(descriptor_set = 0, binding = 18)] depth: &DepthImage,
) {
    let params = &frame.raster;
    if id.x < params.width && id.y < params.height {
        let i = pixel_index(id.x, id.y, params.width);
        let texel: Vec4 = depth.fetch(UVec2::new(id.x, id.y));
        visibility[i] = EMPTY;
        hardware[i] = texel.x;
    }
}

/// [`raster_prepare`] under MSAA: the farthest of the pixel's samples of the
/// multisampled depth target (`shared::layout::BINDING_DEPTH_IMAGE_MS`), so a far
/// blade is hidden early only where every sample hides it.
#[spirv(compute(threads(8, 8)))]
pub fn raster_prepare_ms(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(push_constant)] push: &PreparePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &mut [f32],
    #[spirv(descriptor_set = 0, binding = 19)] depth: &DepthImageMs,
) {
    let params = &frame.raster;
    if id.x < params.width && id.y < params.height {
        let i = pixel_index(id.x, id.y, params.width);
        let mut farthest = 0.0f32;
        let mut s = 0;
        while s < push.samples {
            let texel: Vec4 = depth.fetch_with(UVec2::new(id.x, id.y), sample_index(s));
            farthest = farthest.max(texel.x);
            s += 1;
        }
        visibility[i] = EMPTY;
        hardware[i] = farthest;
    }
}

/// Adds this thread's (covered, written) pixels to the rasterizer's counters: summed
/// in workgroup memory, then one device atomic per workgroup and counter.
fn count_pixels(
    local: u32,
    (covered, written): (u32, u32),
    counters: &mut [u32],
    tally: &mut [u32; 2],
) {
    if local < 2 {
        tally[local as usize] = 0;
    }
    workgroup_memory_barrier_with_group_sync();
    if covered > 0 {
        unsafe {
            atomic_i_add::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[0],
                covered,
            );
        }
    }
    if written > 0 {
        unsafe {
            atomic_i_add::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[1],
                written,
            );
        }
    }
    workgroup_memory_barrier_with_group_sync();
    if local < 2 {
        let n = tally[local as usize];
        if n > 0 {
            let counter = if local == 0 {
                COUNTER_RASTER_COVERED
            } else {
                COUNTER_RASTER_WRITTEN
            };
            unsafe {
                atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut counters[counter],
                    n,
                );
            }
        }
    }
}

/// One thread per blade of one tile (`shared::tiles`): blade `i` of the
/// pushed tile as the camera sees it, into slot `i` of the scratch binding (width 0
/// where its rank has left it). The GPU side of the tiled field's generation, checked
/// against the host's.
#[spirv(compute(threads(64)))]
pub fn generate_tile(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &TilePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] out: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let params = &push.params;
    if index < params.per_side * params.per_side {
        let camera = push.camera.truncate();
        out[index as usize] = tile_blade(push.tile, index, camera, params, paint);
    }
}

/// One thread per blade of a tile entering the tiled field's pool: blade
/// `i` of the pushed tile (every one kept: the pool's tiles are near, and a trampled
/// one keeps its blades as the camera leaves) into field slot `push.slot.x + i` in
/// the far tiles' pose (`tiles::far_blade`: it starts as it was drawn), with its id, no collision strength, and its clump in the natural look.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn generate_pool_tile(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &TilePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] strengths: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &mut [Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let params = &push.params;
    if index < params.per_side * params.per_side {
        let slot = (push.slot.x + index) as usize;
        let camera = push.camera.truncate();
        let tile = push.tile;
        write_tile_blade(
            slot, tile, index, camera, frame, params, paint, blades, ids, clumps,
        );
        strengths[slot] = 0.0;
    }
}

/// Writes blade `k` of `tile`, seen from `camera`, into `slot`: the blade in its far
/// pose ([`far_blade`]), its name and map point, and in the natural look its clump.
#[allow(clippy::too_many_arguments)]
fn write_tile_blade(
    slot: usize,
    tile: IVec2,
    k: u32,
    camera: Vec3,
    frame: &FrameUniforms,
    params: &TileParams,
    paint: &[u32],
    blades: &mut [Blade],
    ids: &mut [u32],
    clumps: &mut [Vec4],
) {
    let blade = far_blade(tile, k, camera, params, paint, &frame.forces);
    blades[slot] = blade;
    ids[IDS_WORDS * slot] = blade_id(tile, k);
    ids[IDS_WORDS * slot + 1] = pack_map_point(tile, k, &blade, params, paint);
    let look = &frame.look;
    if look.style == LOOK_NATURAL {
        clumps[slot] = clump_at(blade.v0.truncate(), look.clump_size, look.seed).pack();
    }
}

/// One thread per candidate tile of a square around the camera, in a tiled frame:
/// a tile in view ([`tile_in_view`]) that no pool slot holds (the pool's
/// table at `layout::TILES_POOL`) takes room for its first [`far_count`] blades in the
/// field's far part (one device atomic on `COUNTER_TILE_BLADES`; a tile the room runs
/// out in keeps what is left, its first, most spread blades, and is counted short),
/// and goes to the list at `layout::TILES_LIST`, whose length becomes the far
/// generation's indirect dispatch.
#[spirv(compute(threads(64)))]
#[allow(clippy::too_many_arguments)]
pub fn select_far_tiles(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SelectPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] pyramid: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    if index >= push.count.x * push.count.y {
        return;
    }
    let tile = push.first + UVec2::new(index % push.count.x, index / push.count.x).as_ivec2();
    let camera = push.camera.truncate();
    let (view_proj, params) = (push.view_proj, &push.params);
    let span = tile_box(tile, params, (push.ground.x, push.ground.y), paint);
    if !tile_in_view(tile, view_proj, camera, params, span, push.camera.w) {
        return;
    }
    // The occlusion test at tile level (the pyramid is empty when it is off).
    if tile_occluded(tile, params, span, view_proj, pyramid, &frame.hiz) {
        unsafe {
            atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                &mut counters[COUNTER_TILES_HIDDEN],
            );
        }
        return;
    }
    let mut slot = 0;
    while slot < push.far.x {
        let at = TILES_POOL + POOL_WORDS * slot as usize;
        if tiles[at] as i32 == tile.x && tiles[at + 1] as i32 == tile.y {
            return;
        }
        slot += 1;
    }
    let wanted = far_count(tile, camera, &push.params, span, paint);
    let first = unsafe {
        atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut counters[COUNTER_TILE_BLADES],
            wanted,
        )
    };
    let room = push.far.y;
    let count = if first >= room {
        0
    } else {
        wanted.min(room - first)
    };
    if count < wanted {
        unsafe {
            atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                &mut counters[COUNTER_TILES_SHORT],
            );
        }
    }
    let at = unsafe {
        atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut counters[COUNTER_TILES],
        )
    };
    let entry = TILES_LIST + TILE_WORDS * at as usize;
    tiles[entry] = tile.x as u32;
    tiles[entry + 1] = tile.y as u32;
    tiles[entry + 2] = push.far.z + first;
    tiles[entry + 3] = count;
    unsafe {
        atomic_u_max::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut tiles[TILES_DISPATCH],
            at + 1,
        );
    }
}

/// One workgroup per far tile in the list [`select_far_tiles`] made (an indirect
/// dispatch): its threads generate the tile's first blades as the camera sees them
/// (`tiles::tile_blade`: thinned and widened with distance) into the field's slots the
/// selection gave it, with their ids and, in the natural look, their clumps. Not
/// simulated: in the pose the frame's gravity and wind settle them into
/// (`tiles::far_blade`).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn generate_far(
    #[spirv(workgroup_id)] group: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SelectPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &mut [Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 11)] clumps: &mut [Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
) {
    let entry = TILES_LIST + TILE_WORDS * group.x as usize;
    let tile = IVec2::new(tiles[entry] as i32, tiles[entry + 1] as i32);
    let (first, count) = (tiles[entry + 2], tiles[entry + 3]);
    let camera = push.camera.truncate();
    let mut k = local;
    while k < count {
        let slot = (first + k) as usize;
        let params = &push.params;
        write_tile_blade(
            slot, tile, k, camera, frame, params, paint, blades, ids, clumps,
        );
        k += GENERATE_WORKGROUP;
    }
}

/// One thread per candidate tile of a square around the camera (`shared::tiles`):
/// the tiles [`tile_in_view`] keeps, appended to the scratch binding after
/// their count (word 0), two words each (x, z). The GPU side of the tiled field's
/// selection, checked against the host's.
#[spirv(compute(threads(64)))]
pub fn select_tiles(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(push_constant)] push: &SelectPush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] out: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    if index < push.count.x * push.count.y {
        let tile = push.first + UVec2::new(index % push.count.x, index / push.count.x).as_ivec2();
        let camera = push.camera.truncate();
        let span = tile_box(tile, &push.params, (push.ground.x, push.ground.y), paint);
        if tile_in_view(
            tile,
            push.view_proj,
            camera,
            &push.params,
            span,
            push.camera.w,
        ) {
            let at = unsafe {
                atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut out[0],
                )
            };
            out[1 + 2 * at as usize] = tile.x as u32;
            out[2 + 2 * at as usize] = tile.y as u32;
        }
    }
}

/// One thread per blade: the clump of its root (`shared::look::clump_at`, 27 cells of
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

/// One thread per chunk: the draw command of its slice of the visible blades; the
/// first also writes the mesh path's draws, one grid per strip length, and the compute
/// rasterizer's preparation, dispatch and resolve.
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

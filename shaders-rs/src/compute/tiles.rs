//! The tiled world on the GPU: tiles in view selected, their blades generated for the
//! pool and for the far field.

use shared::Blade;
use shared::cull::tile::{tile_box, tile_in_view, tile_occluded};
use shared::draw::look::LOOK_NATURAL;
use shared::draw::look::clump::clump_at;
use shared::gpu::counters::{
    COUNTER_TILE_BLADES, COUNTER_TILES, COUNTER_TILES_HIDDEN, COUNTER_TILES_SHORT,
};
use shared::gpu::layout::{FrameUniforms, SIMULATE_WORKGROUP, flat_index};
use shared::gpu::layout::{
    GENERATE_WORKGROUP, IDS_WORDS, POOL_WORDS, SelectPush, TILE_WORDS, TILES_DISPATCH, TILES_LIST,
    TILES_POOL, TilePush,
};
use shared::sim::simulate::{Environment, ForcesHeld};
use shared::world::tiles::{
    TileParams, blade_id, far_blade, far_count, pack_map_point, tile_blade,
};
use spirv_std::arch::{atomic_i_add, atomic_i_increment, atomic_u_max};
use spirv_std::glam::{IVec2, UVec2, UVec3, Vec3, Vec4};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

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
    #[spirv(spec_constant(id = 2, default = 0))] impulses: u32,
) {
    let index = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let params = &push.params;
    if index < params.per_side * params.per_side {
        let slot = (push.slot.x + index) as usize;
        let camera = push.camera.truncate();
        let tile = push.tile;
        let forces = blowing(frame, impulses);
        write_tile_blade(
            slot, tile, index, camera, frame, &forces, params, paint, blades, ids, clumps,
        );
        strengths[slot] = 0.0;
    }
}

/// The frame's forces with its wind impulses only where the pipeline was made for them
/// (`layout::SPEC_IMPULSES`, as the simulate-and-cull pass's), without its colliders
/// (the far pose feels none).
fn blowing(frame: &FrameUniforms, impulses: u32) -> Environment {
    let held = ForcesHeld {
        impulses: impulses != 0,
        colliders: false,
        centre: true,
    };
    frame.forces.specialised(frame.forces.wind_kind, held)
}

/// Writes blade `k` of `tile`, seen from `camera`, into `slot`: the blade in its far
/// pose under `forces` ([`far_blade`]), its name and map point, and in the natural
/// look its clump.
#[allow(clippy::too_many_arguments)]
fn write_tile_blade(
    slot: usize,
    tile: IVec2,
    k: u32,
    camera: Vec3,
    frame: &FrameUniforms,
    forces: &Environment,
    params: &TileParams,
    paint: &[u32],
    blades: &mut [Blade],
    ids: &mut [u32],
    clumps: &mut [Vec4],
) {
    let blade = far_blade(tile, k, camera, params, paint, forces, &frame.impulses);
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
#[spirv(compute(threads(256)))]
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
    #[spirv(storage_buffer, descriptor_set = 0, binding = 28)] cuts: &[u32],
    #[spirv(spec_constant(id = 2, default = 0))] impulses: u32,
) {
    let forces = blowing(frame, impulses);
    let entry = TILES_LIST + TILE_WORDS * group.x as usize;
    let tile = IVec2::new(tiles[entry] as i32, tiles[entry + 1] as i32);
    let (first, count) = (tiles[entry + 2], tiles[entry + 3]);
    let camera = push.camera.truncate();
    let mut k = local;
    while k < count {
        let slot = (first + k) as usize;
        let params = &push.params;
        write_tile_blade(
            slot, tile, k, camera, frame, &forces, params, paint, blades, ids, clumps,
        );
        // As the cuts leave it (`shared::sim::cut`), as the pool's blades are.
        blades[slot] = super::cut::cut_now(&blades[slot], frame, cuts);
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

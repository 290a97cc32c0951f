//! One thread per blade: this frame's simulation steps, the four culling tests and the
//! compaction of the survivors into the visible list.

use super::cut::{cut_blade, cut_now};
use super::tally::Tally;
use shared::Blade;
use shared::cull::blade::{KEPT, cull_outcome_as_drawn};
use shared::cull::lod::blade_level;
use shared::draw::look::clump::{Clump, DressedBlade, caster_blade, dress};
use shared::draw::look::coverage::unpack_coverage;
use shared::draw::look::shadow::{casts_shadow, in_shadow_map};
use shared::draw::meshlet::{BUCKETS, BinPlaces, StripBlade, visible_bucket};
use shared::draw::raster::is_far;
use shared::draw::temporal::BladeMotion;
use shared::gpu::counters::{
    COUNTER_CASTERS, COUNTER_COUNT, COUNTER_FAR, COUNTER_NEAR, COUNTER_NEAR_CASTERS,
    COUNTER_TILE_BLADES, COUNTER_VISIBLE, far_slot, strip_counter,
};
use shared::gpu::layout::{
    COLLIDERS_HAND_OVER_ROOTS, COLLIDERS_NEAR, IDS_WORDS, NEAR_DISPATCH, NEAR_LIST,
    WIND_FROM_FRAME, hands_over, near_groups,
};
use shared::gpu::layout::{CULL_WORKGROUP, FrameUniforms, SimulatePush, flat_index};
use shared::sim::collide::Collider;
use shared::sim::grid::{Nearby, REACH_MARGIN};
use shared::sim::simulate::{ForcesHeld, simulate, simulate_watched, watches};
use shared::world::pool::pool_blade;
use shared::world::tiles::{fade_to_far, far_blade, kept, unpack_map_point};
use spirv_std::arch::atomic_u_max;
use spirv_std::glam::{IVec2, UVec3, UVec4, Vec2, Vec4, Vec4Swizzles};
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// The per-blade buffers the simulate-and-cull pass reads and writes.
pub struct BladeBuffers<'a> {
    blades: &'a mut [Blade],
    visible: &'a mut [u32],
    counters: &'a mut [u32],
    strengths: &'a mut [f32],
    pyramid: &'a [f32],
    binned: &'a mut [StripBlade],
    ids: &'a [u32],
    tiles: &'a [u32],
    paint: &'a [u32],
    casters: &'a mut [u32],
    motion: &'a mut [BladeMotion],
    colliders: &'a [Collider],
    grid: &'a [u32],
    /// The grid's buffer again (the same binding), four words at a time: `Nearby::shapes`.
    shapes: &'a [UVec4],
    near: &'a mut [u32],
    cuts: &'a mut [u32],
}

/// One thread per blade: this frame's fixed steps of forces, collisions and validation
/// (the blade and its collision strength η are read and written back), then the cull
/// tests. Outcomes are tallied in workgroup memory, so each workgroup adds to each
/// device counter once; a visible blade's index (4 bytes, not its 64) lands at the
/// workgroup's base (one device atomic) plus its place within the workgroup (or each
/// blade takes its place from the device counter, where `workgroup_tally` is 0:
/// `layout::SPEC_WORKGROUP_TALLY`, [`Tally`]). On the
/// mesh path each visible blade is binned by strip length the same way, into its
/// bucket's part of the binned list as the frame before laid it out
/// (`shared::draw::meshlet::BinLayout`), or past it into the spill half. The paper look's
/// entry point: nothing of the natural look is compiled in, nor any wind field but
/// `wind_field`, a specialisation constant (`layout::SPEC_WIND_FIELD`), the wind
/// impulses only where `impulses` (`layout::SPEC_IMPULSES`), the collisions only where
/// `colliders` (`layout::SPEC_COLLIDERS`), and the mesh path's binning only where
/// `mesh_path` (`layout::SPEC_MESH_PATH`).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(128)))]
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
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &mut [StripBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 23)] casters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 24)] motion: &mut [BladeMotion],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 25)] collider_list: &[Collider],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] grid: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] shapes: &[UVec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 27)] near: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 28)] cuts: &mut [u32],
    #[spirv(workgroup)] tally: &mut [u32; COUNTER_COUNT],
    #[spirv(workgroup)] places: &mut [BinPlaces; BUCKETS as usize],
    #[spirv(spec_constant(id = 0, default = 1))] wind_field: u32,
    #[spirv(spec_constant(id = 1, default = 0))] mesh_path: u32,
    #[spirv(spec_constant(id = 2, default = 0))] impulses: u32,
    #[spirv(spec_constant(id = 3, default = 0))] colliders: u32,
    #[spirv(spec_constant(id = 4, default = 0))] centre: u32,
    #[spirv(spec_constant(id = 5, default = 0))] tiled: u32,
    #[spirv(spec_constant(id = 6, default = 1))] workgroup_tally: u32,
) {
    let buffers = BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        binned,
        ids,
        tiles,
        paint,
        casters,
        motion,
        colliders: collider_list,
        grid,
        shapes,
        near,
        cuts,
    };
    let mesh = mesh_path != 0;
    let prepare = |_: u32, _: u32, kept: &Blade, before: BladeMotion, _: &[u32], _: Vec2| {
        let level = if mesh {
            blade_level(kept, &frame.lod, &frame.camera, frame.grass.shape)
        } else {
            0.0
        };
        ((), before, level)
    };
    // The paper look's geometry stages read a blade by its index: so does its motion.
    simulate_and_cull(
        id,
        local,
        workgroups,
        frame,
        push,
        buffers,
        Tally {
            grouped: workgroup_tally != 0,
            counts: tally,
            places,
        },
        prepare,
        |_, _| {},
        |_| (false, false),
        |_, _, blade: &Blade| *blade,
        true,
        (wind_field, mesh_path),
        [impulses, colliders, centre, tiled],
    );
}

/// [`simulate_cull`] for the natural look: each visible blade as drawn
/// (`shared::draw::look::clump::dress`, from its clump) also goes to its slot of the dressed buffer;
/// its level of detail on the mesh path is the dressed blade's, 0 for a thin blade its
/// coverage leaves out.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(128)))]
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
    #[spirv(storage_buffer, descriptor_set = 0, binding = 14)] binned: &mut [StripBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 20)] tiles: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 22)] paint: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 23)] casters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 24)] motion: &mut [BladeMotion],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 25)] collider_list: &[Collider],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] grid: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 26)] shapes: &[UVec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 27)] near: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 28)] cuts: &mut [u32],
    #[spirv(workgroup)] tally: &mut [u32; COUNTER_COUNT],
    #[spirv(workgroup)] places: &mut [BinPlaces; BUCKETS as usize],
    #[spirv(spec_constant(id = 0, default = 1))] wind_field: u32,
    #[spirv(spec_constant(id = 1, default = 0))] mesh_path: u32,
    #[spirv(spec_constant(id = 2, default = 0))] impulses: u32,
    #[spirv(spec_constant(id = 3, default = 0))] colliders: u32,
    #[spirv(spec_constant(id = 4, default = 0))] centre: u32,
    #[spirv(spec_constant(id = 5, default = 0))] tiled: u32,
    #[spirv(spec_constant(id = 6, default = 1))] workgroup_tally: u32,
) {
    let buffers = BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        binned,
        ids,
        tiles,
        paint,
        casters,
        motion,
        colliders: collider_list,
        grid,
        shapes,
        near,
        cuts,
    };
    let camera = frame.camera.position;
    let half = push.tiles.half_extent;
    let prepare =
        |index: u32, id: u32, kept: &Blade, before: BladeMotion, paint: &[u32], at: Vec2| {
            let clump = Clump::unpack(clumps[index as usize]);
            let (blade, tint) = dress(kept, &clump, id, camera, &frame.cull, &frame.look);
            // The previous frame's control points as drawn: the dress's lean and height
            // do not depend on its width (the fades), so the caster's dress gives them.
            let moved = if frame.temporal.on != 0 {
                let before = kept.with_curve(before.guide.xyz(), before.tip.xyz());
                BladeMotion::of(&caster_blade(&before, &clump, id, frame.look.seed))
            } else {
                BladeMotion::default()
            };
            // The painted colour map (white where there is none).
            let colour =
                shared::world::paint::sample(paint, shared::world::paint::COLOUR, at, half);
            let tint = Vec4::new(
                tint.x * colour.x,
                tint.y * colour.y,
                tint.z * colour.z,
                tint.w,
            );
            let (mask, _) = unpack_coverage(tint.w);
            let level = if mesh_path != 0 && mask != 0 {
                blade_level(&blade, &frame.lod, &frame.camera, frame.grass.shape)
            } else {
                0.0
            };
            (DressedBlade { blade, tint }, moved, level)
        };
    let store = |slot: usize, drawn: DressedBlade| dressed[slot] = drawn;
    let look = &frame.look;
    let casts = |blade: &Blade| {
        let far = look.shadows != 0
            && casts_shadow(look.shadow_view_proj, blade, camera, look.caster_distance);
        (far, far && in_shadow_map(look.near_view_proj, blade))
    };
    // The tests see the blade as drawn: leaned and grown by its clump, whose tip can
    // reach into the view (or out from behind a surface) where the stored blade's
    // does not.
    let tested = |index: u32, id: u32, blade: &Blade| {
        let clump = Clump::unpack(clumps[index as usize]);
        caster_blade(blade, &clump, id, frame.look.seed)
    };
    simulate_and_cull(
        id,
        local,
        workgroups,
        frame,
        push,
        buffers,
        Tally {
            grouped: workgroup_tally != 0,
            counts: tally,
            places,
        },
        prepare,
        store,
        casts,
        tested,
        false,
        (wind_field, mesh_path),
        [impulses, colliders, centre, tiled],
    );
}

/// The body of both simulate-and-cull entry points: `prepare(index, id, blade, before,
/// maps)` runs for each visible blade (`before`: its control points before this
/// frame's steps; a value, not a reference: rust-gpu read a second `&Blade` argument
/// of the closure as NaN)
/// and gives what `store(slot, ..)` writes once its slot of the visible list is
/// known, the blade's control points as drawn the frame before (written to the motion
/// buffer while temporal anti-aliasing is on) and its level of detail on the mesh path
/// (0: not drawn). Where `by_index` (the paper look) the motion goes to the blade's
/// index and a strip names the blade by its index, else both by its visible slot.
/// Every blade in the field that `casts` says casts a shadow, whatever the camera's
/// tests decide, goes to the shadow casters' list, and to the near cascade's where
/// it says so too. The culling tests take the blade as `tested(index, id, blade)`
/// gives it: as the look draws it.
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
    mut tally: Tally,
    mut prepare: impl FnMut(u32, u32, &Blade, BladeMotion, &[u32], Vec2) -> (T, BladeMotion, f32),
    mut store: impl FnMut(usize, T),
    casts: impl Fn(&Blade) -> (bool, bool),
    tested: impl Fn(u32, u32, &Blade) -> Blade,
    by_index: bool,
    (wind_field, mesh_path): (u32, u32),
    [impulses, colliders, centre, tiled_field]: [u32; 4],
) {
    let BladeBuffers {
        blades,
        visible,
        counters,
        strengths,
        pyramid,
        binned,
        ids,
        tiles,
        paint,
        casters,
        motion,
        colliders: collider_list,
        grid,
        shapes,
        near,
        cuts,
    } = buffers;
    tally.clear(local);

    // What this pipeline does with the colliders (`layout::SPEC_COLLIDERS`): the
    // collision pass takes the blade its thread stands for from the handed list.
    let (hand_over, near_pass) = (hands_over(colliders), colliders == COLLIDERS_NEAR);
    let mut index = flat_index(id, workgroups, CULL_WORKGROUP);
    if near_pass {
        index = if index < counters[COUNTER_NEAR] {
            near[NEAR_LIST + index as usize]
        } else {
            u32::MAX
        };
    }
    // The wind field this pipeline was made for (`layout::SPEC_WIND_FIELD`), and the
    // impulses and colliders only where it was made for them (`layout::SPEC_IMPULSES`,
    // `SPEC_COLLIDERS`: the collision pass's alone).
    let held = ForcesHeld {
        impulses: impulses != 0,
        colliders: near_pass,
        centre: centre != 0,
    };
    let kind = if wind_field == WIND_FROM_FRAME {
        frame.forces.wind_kind
    } else {
        wind_field
    };
    let forces = frame.forces.specialised(kind, held);
    let nearby = Nearby {
        colliders: collider_list,
        words: grid,
        shapes,
        grid: frame.collider_grid,
    };
    let grass = &frame.grass;
    // A stored field's pipeline holds none of the tiled field's code
    // (`layout::SPEC_TILED`).
    let tiled = tiled_field != 0 && grass.tiled != 0;
    let simulated = index < grass.simulated;
    let mut in_field = index < grass.blades
        && (simulated || (tiled && index - grass.simulated < counters[COUNTER_TILE_BLADES]));
    // The path this pipeline was made for (`layout::SPEC_MESH_PATH`).
    let mesh = mesh_path != 0;
    let mut outcome = KEPT;
    let mut far = false;
    let mut place = 0;
    let (mut caster, mut near_caster) = (false, false);
    let (mut caster_place, mut near_caster_place) = (0, 0);
    let mut prepared = T::default();
    let mut moved = BladeMotion::default();
    let mut level = 0.0;
    // The mesh path's bucket (`BUCKETS`: not binned) and place among the
    // workgroup's blades of that bucket.
    let (mut bucket, mut strip_place) = (BUCKETS, 0);
    let mut name = index;
    // A pool blade's width as its distance thins it, like a far one's
    // (`world::pool::pool_blade`).
    let mut pool_width = 0.0;
    // A tile nobody needs goes back to its far pose (`tiles::fade_to_far`).
    let mut fade = 0.0;
    let mut rest_tile = IVec2::ZERO;
    if in_field && tiled {
        let i = index as usize;
        name = ids[IDS_WORDS * i];
        if simulated {
            let camera = frame.camera.position;
            let pool = pool_blade(index, &blades[i], tiles, &push.tiles, paint, camera);
            in_field = pool.grows;
            if in_field {
                pool_width = pool.width;
                fade = pool.fade;
                rest_tile = pool.tile;
            }
        } else {
            in_field = kept(&blades[i]);
        }
    }
    // A simulated blade is stepped without the colliders; one a collider may have
    // held at a step (asked after the steps, of the points where they left it and
    // their travel, in the watch's slot: `Nearby::may_have_touched`) goes to the
    // collision pass, which simulates and tests it instead, and so does, before its
    // steps, one a cutter reaches, and in a frame of more steps than the watch is for
    // (`simulate::watches`) one any collider reaches, the rest not watched. Only the
    // pipeline made for those frames looks up the grid's slot of the root.
    let mut handed = false;
    let looks_up = colliders == COLLIDERS_HAND_OVER_ROOTS;
    let wide = looks_up && !watches(push.steps);
    if looks_up && (frame.forces.cutting != 0 || wide) && in_field && simulated {
        let b = &blades[index as usize];
        let count = frame.forces.colliders;
        let slot = nearby.around(b.root(), b.height(), count);
        let (found, cutter) = nearby.reaches(b.root(), b.height() * REACH_MARGIN, &slot, count);
        handed = cutter || (wide && found);
        in_field = !handed;
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
            blade = cut_blade(blade, frame, nearby, near_pass, cuts, counters);
            let held = strengths[i];
            // Where nothing pushes, η changes only where it decays from above zero
            // (`collide::update_strength`, `Environment::strength_decay`): a flag held
            // through the steps instead of η.
            let lingering = held > 0.0;
            let strength;
            if hand_over && !wide {
                ((blade, strength), handed) = simulate_watched(
                    (blade, held),
                    &forces,
                    nearby,
                    &frame.impulses,
                    push.first_step,
                    push.steps,
                );
            } else {
                (blade, strength) = simulate(
                    (blade, held),
                    &forces,
                    nearby,
                    &frame.impulses,
                    push.first_step,
                    push.steps,
                );
            }
            // Its orientation and width, which no step reads, taken again rather than
            // held through the steps beside the travel (a cut leaves both).
            if hand_over {
                blade.v0.w = blades[i].v0.w;
                blade.v2.w = if tiled { pool_width } else { blades[i].v2.w };
            }
            if handed {
                in_field = false;
                drawn = false;
            }
            if fade > 0.0 && !handed {
                let k = index % (push.tiles.per_side * push.tiles.per_side);
                let params = &push.tiles;
                let far = far_blade(
                    rest_tile,
                    k,
                    blade.root(),
                    params,
                    paint,
                    &forces,
                    &frame.impulses,
                );
                blade = fade_to_far(&blade, &cut_now(&far, frame, cuts), fade);
            }
            // Unchanged (no collider near, none lingering): nothing to write back.
            let changed = if near_pass {
                strength != held
            } else {
                lingering
            };
            if changed && !handed {
                strengths[i] = strength;
            }
        }
    }
    if drawn {
        (caster, near_caster) = casts(&blade);
    }
    if caster {
        caster_place = tally.claim(counters, COUNTER_CASTERS);
    }
    if near_caster {
        near_caster_place = tally.claim(counters, COUNTER_NEAR_CASTERS);
    }
    if drawn {
        outcome = cull_outcome_as_drawn(
            &blade,
            |b: &Blade| tested(index, name, b),
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
        place = tally.claim(counters, counter);
        if outcome == KEPT {
            // Its control points before this frame's steps, read again rather than
            // held in registers through the steps and the tests.
            let before = BladeMotion::of(&blades[index as usize]);
            // Where it reads the painted maps (a tiled field's: `tiles::pack_map_point`;
            // a stored one's: its root over the map square), found here rather than held
            // through the steps.
            let map_at = if tiled {
                unpack_map_point(ids[IDS_WORDS * index as usize + 1], &push.tiles)
            } else {
                shared::world::tiles::map_point(blade.root(), &push.tiles)
            };
            (prepared, moved, level) = prepare(index, name, &blade, before, paint, map_at);
            if mesh && !far && level > 0.0 {
                // Its bucket: its strip length, and near the camera its band.
                let camera = frame.camera.position;
                bucket = visible_bucket(level, &blade, camera, frame.lod.most);
                strip_place = tally.claim(counters, strip_counter(bucket));
            }
        }
    } else if handed {
        // A handed blade is not drawn: its place is among the collision pass's.
        place = tally.claim(counters, COUNTER_NEAR);
    }
    // Only the curve moved: one 32-byte sector written back (`Blade`), after the
    // visible blade's old curve was read again above.
    if in_field && simulated {
        let i = index as usize;
        // Its own height stays in the buffer, whatever a cut leaves of it: read
        // again rather than held through the steps.
        let own_height = blades[i].v1.w;
        blades[i].v1 = blade.guide().extend(own_height);
        blades[i].v2 = blade.v2;
    }
    tally.settle(local, counters, mesh, grass.blades);

    if drawn && outcome == KEPT {
        let slot = if far {
            far_slot(tally.slot(COUNTER_FAR, place), frame.grass.blades)
        } else {
            tally.slot(COUNTER_VISIBLE, place)
        } as usize;
        visible[slot] = index;
        store(slot, prepared);
        if frame.temporal.on != 0 {
            motion[if by_index { index as usize } else { slot }] = moved;
        }
        if bucket < BUCKETS {
            let at = tally.strip_slot(counters, bucket, strip_place, grass.blades);
            let source = if by_index { index } else { slot as u32 };
            binned[at as usize] = StripBlade { source, level };
        }
    }
    if caster {
        casters[tally.slot(COUNTER_CASTERS, caster_place) as usize] = index;
    }
    if near_caster {
        casters[(grass.blades + tally.slot(COUNTER_NEAR_CASTERS, near_caster_place)) as usize] =
            index;
    }
    if handed {
        let place = tally.slot(COUNTER_NEAR, place);
        near[NEAR_LIST + place as usize] = index;
        // The first blade of a workgroup of the collision pass grows its dispatch.
        if place.is_multiple_of(CULL_WORKGROUP) {
            let (x, y) = near_groups(place);
            unsafe {
                atomic_u_max::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut near[NEAR_DISPATCH],
                    x,
                );
                atomic_u_max::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut near[NEAR_DISPATCH + 1],
                    y,
                );
            }
        }
    }
}

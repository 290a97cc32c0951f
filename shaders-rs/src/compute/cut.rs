//! The GPU side of cutting (`shared::sim::cut`): a simulated blade as the cut table
//! leaves it, cut again in the collision pass by the cutters near it, the cut's slot
//! claimed with a compare-and-swap and its stub left pending with an atomic maximum;
//! then the frame's cuts committed.

use shared::Blade;
use shared::gpu::counters::{COUNTER_CUTS, COUNTER_CUTS_DROPPED};
use shared::gpu::layout::{FrameUniforms, flat_index};
use shared::sim::cut::{
    COMMIT_WORKGROUP, CUT_SLOTS, CUT_WORDS, PENDING_WORD, as_cut, cell_key, commit, cut_near,
    cut_to, pending, place,
};
use shared::sim::grid::Nearby;
use spirv_std::arch::{atomic_compare_exchange, atomic_i_increment, atomic_u_max};
use spirv_std::glam::UVec3;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// `blade` as the cut table leaves it at the frame's time (`shared::sim::cut::as_cut`)
/// while the frame reads it (`Environment::cutting`); else itself.
pub fn cut_now(blade: &Blade, frame: &FrameUniforms, cuts: &[u32]) -> Blade {
    if frame.forces.cutting != 0 {
        as_cut(blade, cuts, frame.forces.time, frame.forces.regrow)
    } else {
        *blade
    }
}

/// A simulated blade as the cut table leaves it at the frame's time ([`cut_now`]);
/// in the collision pass (`near_pass`), cut again by the
/// cutters near it (`cut_near`), the cut recorded in its cell's slot (claimed by a
/// compare-and-swap: `cut::place`), its stub pending there (`cut::pending`) until
/// the frame's commit ([`commit_cuts`]), and counted (`COUNTER_CUTS`, or
/// `COUNTER_CUTS_DROPPED` where the table had no room).
pub fn cut_blade(
    blade: Blade,
    frame: &FrameUniforms,
    nearby: Nearby,
    near_pass: bool,
    cuts: &mut [u32],
    counters: &mut [u32],
) -> Blade {
    let (now, regrow) = (frame.forces.time, frame.forces.regrow);
    let mut blade = cut_now(&blade, frame, cuts);
    if near_pass && frame.forces.cutting != 0 {
        let stub = cut_near(&blade, &nearby, frame.forces.colliders);
        if stub < blade.height() {
            let key = cell_key(blade.root());
            let claimed = place(cuts, key, now, regrow, |words, at, held| {
                let seen = unsafe {
                    atomic_compare_exchange::<
                        u32,
                        { Scope::Device as u32 },
                        { Semantics::NONE.bits() },
                        { Semantics::NONE.bits() },
                    >(&mut words[at], key, held)
                };
                seen == held || seen == key
            });
            let counter = match claimed {
                Some(slot) => {
                    // Pending until the frame's commit (`commit_cuts`): the lowest stub.
                    let at = slot as usize * CUT_WORDS + PENDING_WORD;
                    unsafe {
                        atomic_u_max::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                            &mut cuts[at],
                            pending(stub),
                        );
                    }
                    COUNTER_CUTS
                }
                None => COUNTER_CUTS_DROPPED,
            };
            unsafe {
                atomic_i_increment::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut counters[counter],
                );
            }
            blade = cut_to(&blade, stub);
        }
    }
    blade
}

/// One thread per slot of the cut table, after the collision pass of a frame that
/// cuts: the slot's pending cut committed at the frame's time (`cut::commit`), so the
/// next frame reads it.
#[spirv(compute(threads(64)))]
pub fn commit_cuts(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 28)] cuts: &mut [u32],
) {
    let slot = flat_index(id, workgroups, COMMIT_WORKGROUP);
    if slot < CUT_SLOTS {
        commit(cuts, slot, frame.forces.time);
    }
}

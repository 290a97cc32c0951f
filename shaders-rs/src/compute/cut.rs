//! The GPU side of cutting (`shared::sim::cut`): a simulated blade as the cut table
//! leaves it, cut again in the collision pass by the cutters near it, the cut
//! recorded with a compare-and-swap.

use shared::Blade;
use shared::gpu::counters::{COUNTER_CUTS, COUNTER_CUTS_DROPPED};
use shared::gpu::layout::FrameUniforms;
use shared::sim::cut::{CUT_WORDS, as_cut, cell_key, cut_near, cut_to, place};
use shared::sim::grid::Nearby;
use spirv_std::arch::{atomic_compare_exchange, atomic_i_increment};
use spirv_std::memory::{Scope, Semantics};

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
/// compare-and-swap: `cut::place`) and counted (`COUNTER_CUTS`, or
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
                    let at = slot as usize * CUT_WORDS;
                    cuts[at + 1] = now.to_bits();
                    cuts[at + 2] = stub.to_bits();
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

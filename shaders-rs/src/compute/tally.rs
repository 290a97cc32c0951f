//! How the simulate-and-cull pass's blades take their places in the device's lists:
//! tallied in workgroup memory (one device atomic a counter a workgroup, three
//! workgroup barriers), or one device atomic a blade and no barrier
//! (`layout::SPEC_WORKGROUP_TALLY`).

use shared::draw::meshlet::{BUCKETS, BinPlaces};
use shared::gpu::counters::{
    COUNTER_CASTERS, COUNTER_COUNT, COUNTER_FAR, COUNTER_NEAR, COUNTER_NEAR_CASTERS,
    COUNTER_SPILLED, COUNTER_STRIPS, COUNTER_VISIBLE, bin_part,
};
use spirv_std::arch::{atomic_i_add, atomic_i_increment, workgroup_memory_barrier_with_group_sync};
use spirv_std::memory::{Scope, Semantics};

/// A workgroup's tally of the places its blades take, or none.
pub struct Tally<'a> {
    /// Tallied in workgroup memory (else each blade adds to the device counter).
    pub grouped: bool,
    /// Per counter: the workgroup's blades, then the base of their places.
    pub counts: &'a mut [u32; COUNTER_COUNT],
    /// Per bucket of the mesh path: where the workgroup's blades of it go.
    pub places: &'a mut [BinPlaces; BUCKETS as usize],
}

/// Adds `count` to device counter `k`: its value before.
fn add(counters: &mut [u32], k: usize, count: u32) -> u32 {
    unsafe {
        atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
            &mut counters[k],
            count,
        )
    }
}

impl Tally<'_> {
    /// Thread `local` clears its counter of the tally; all wait for the clearing.
    pub fn clear(&mut self, local: u32) {
        if self.grouped {
            if local < COUNTER_COUNT as u32 {
                self.counts[local as usize] = 0;
            }
            workgroup_memory_barrier_with_group_sync();
        }
    }

    /// One place of counter `k`: among the workgroup's (its base comes from
    /// [`Tally::settle`]), or in the device's list.
    pub fn claim(&mut self, counters: &mut [u32], k: usize) -> u32 {
        if self.grouped {
            unsafe {
                atomic_i_increment::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                    &mut self.counts[k],
                )
            }
        } else {
            add(counters, k, 1)
        }
    }

    /// Once every blade has claimed its places: thread k adds tally k to the device
    /// counter k. The visible, far, casters' and near lists keep the base of the
    /// workgroup's slots in the tally, the buckets their places in `places`: those
    /// their part of the binned list (`bin_part`, laid out by the frame before) has
    /// room for, the rest in the spill half after the list's `blades` slots.
    pub fn settle(&mut self, local: u32, counters: &mut [u32], mesh: bool, blades: u32) {
        if !self.grouped {
            return;
        }
        workgroup_memory_barrier_with_group_sync();
        if local < COUNTER_COUNT as u32 {
            let k = local as usize;
            let count = self.counts[k];
            if count > 0 {
                // A bucket's part of the binned list, read before the atomic, so that
                // the two wait together.
                let strips = mesh && (COUNTER_STRIPS..COUNTER_SPILLED).contains(&k);
                let b = if strips {
                    (k - COUNTER_STRIPS) as u32
                } else {
                    0
                };
                let (mut start, mut room) = (0, 0);
                if strips {
                    (start, room) = bin_part(counters, b, blades);
                }
                let base = add(counters, k, count);
                if k == COUNTER_VISIBLE
                    || k == COUNTER_FAR
                    || k == COUNTER_CASTERS
                    || k == COUNTER_NEAR_CASTERS
                    || k == COUNTER_NEAR
                {
                    self.counts[k] = base;
                } else if strips {
                    let fit = BinPlaces::fitting(count, base, room);
                    let spilled = if count > fit {
                        add(counters, COUNTER_SPILLED, count - fit)
                    } else {
                        0
                    };
                    self.places[b as usize] = BinPlaces::new(fit, (start, base), (blades, spilled));
                }
            }
        }
        workgroup_memory_barrier_with_group_sync();
    }

    /// The slot in counter `k`'s list of the place claimed as `place`.
    pub fn slot(&self, k: usize, place: u32) -> u32 {
        if self.grouped {
            self.counts[k] + place
        } else {
            place
        }
    }

    /// The slot in the binned list of the blade that claimed `place` in `bucket`: in
    /// the bucket's part where it has room, else in the spill half after the list's
    /// `blades` slots.
    pub fn strip_slot(&self, counters: &mut [u32], bucket: u32, place: u32, blades: u32) -> u32 {
        if self.grouped {
            return self.places[bucket as usize].slot(place);
        }
        let (start, room) = bin_part(counters, bucket, blades);
        let fit = BinPlaces::fitting(1, place, room);
        let spilled = if fit == 0 {
            add(counters, COUNTER_SPILLED, 1)
        } else {
            0
        };
        BinPlaces::new(fit, (start, place), (blades, spilled)).slot(0)
    }
}

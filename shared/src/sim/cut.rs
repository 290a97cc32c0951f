//! Cut and regrow. A collider marked as a cutter ([`Collider::cutting`]) cuts every
//! blade whose curve it holds: the blade keeps a stub up to the cutter's lowest point
//! and grows back to its own height over the frame block's regrowth time
//! ([`regrown`]), linearly, as Ghost of Yōtei's cut buffer lets grass grow back.
//!
//! Cuts are kept by place, not by blade: the ground is cut into square cells of
//! [`CUT_CELL`] units, and a cut cell holds its slot of a table of [`CUT_SLOTS`]
//! slots ([`CUT_WORDS`] words each: the cell's key, the time of the cut, the stub's
//! height, and the frame's pending cut), found by hashing the cell and probing up to
//! [`CUT_PROBES`] slots (open addressing). A frame's cuts wait in their slots'
//! pending words, the lowest stub kept, until the frame commits them ([`commit`]),
//! so every blade of the frame reads the table as the frame found it, whatever the
//! order the GPU runs them in. Every blade rooted in a cut cell reads the same cut, so a cut survives
//! a tiled world's pool turning over and reaches the far blades generated each frame;
//! the table is the same 4 MiB for any field, and a slot whose cell has grown back is
//! free again. A cut that finds its probes full of cells still growing back is
//! dropped (counted on the GPU: `counters::COUNTER_CUTS_DROPPED`).

use crate::Blade;
use crate::noise::hash_u32;
use crate::sim::collide::Collider;
use crate::sim::grid::{Nearby, each_marked};
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Side of a cut cell, world units.
pub const CUT_CELL: f32 = 0.25;
/// Slots of the cut table (a power of two): 262,144 cells, 16,384 square units.
pub const CUT_SLOTS: u32 = 1 << 18;
/// Words of a slot: the cell's key ([`NO_CELL`] where none), the time of its cut and
/// its stub's height (`f32` bits; a stub of 0 where the cell was never cut), and the
/// frame's pending cut ([`PENDING_WORD`]).
pub const CUT_WORDS: usize = 4;
/// Threads of a workgroup of the commit of a frame's cuts (`compute::cut`), a thread a
/// slot.
pub const COMMIT_WORKGROUP: u32 = 64;
/// The word of a slot that holds the lowest stub this frame's cuts leave its cell,
/// as [`pending`] writes it (0: none), until the frame commits it ([`commit`]).
pub const PENDING_WORD: usize = 3;
/// Slots a cell's key is looked for in, from its hashed slot on.
pub const CUT_PROBES: u32 = 8;
/// The key of a slot no cell has held.
pub const NO_CELL: u32 = 0;
/// The shortest stub a cut leaves (world units): a cutter touching the ground still
/// leaves the blade's root.
pub const MIN_STUB: f32 = 0.02;
/// Points of a blade's curve a cutter is tested at (v = 1/n to 1).
pub const CUT_POINTS: u32 = 8;

/// The height a blade of `height` stands at `since` seconds after a cut left a stub of
/// `stub`, growing back over `regrow` seconds: h(t) = s + (h − s)·min(t/T, 1), with the
/// stub no taller than the blade.
pub fn regrown(height: f32, stub: f32, since: f32, regrow: f32) -> f32 {
    let stub = stub.min(height);
    if regrow <= 0.0 || since >= regrow {
        return height;
    }
    stub + (height - stub) * (since / regrow).max(0.0)
}

/// The key of the cell holding `p` (its x and z cell coordinates, 15 bits each, and
/// a set top bit, so no key is [`NO_CELL`]); the cells repeat every 8,192 units.
pub fn cell_key(p: Vec3) -> u32 {
    let x = (p.x / CUT_CELL).floor() as i32 as u32 & 0x7fff;
    let z = (p.z / CUT_CELL).floor() as i32 as u32 & 0x7fff;
    0x8000_0000 | (x << 15) | z
}

/// The slot a cell's key is looked for first.
pub fn home_slot(key: u32) -> u32 {
    hash_u32(key) & (CUT_SLOTS - 1)
}

/// The `probe`th slot of `key` (open addressing, one slot on each time).
pub fn probe_slot(key: u32, probe: u32) -> u32 {
    (home_slot(key) + probe) & (CUT_SLOTS - 1)
}

/// A cell's cut: when it was made (simulated seconds) and the stub it left.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Cut {
    /// Simulated time of the cut, seconds.
    pub time: f32,
    /// The stub's height, world units.
    pub stub: f32,
}

impl Cut {
    /// Whether every blade of the cell has grown back at `now` (its slot is free).
    pub fn grown(&self, now: f32, regrow: f32) -> bool {
        now - self.time >= regrow
    }
}

/// The cut of the cell keyed `key` in table `words` ([`CUT_WORDS`] a slot), if any:
/// its slots probed until its key or a slot no cell has held.
pub fn find(words: &[u32], key: u32) -> Option<Cut> {
    slot_of(words, key).map(|slot| {
        let at = slot as usize * CUT_WORDS;
        Cut {
            time: f32::from_bits(words[at + 1]),
            stub: f32::from_bits(words[at + 2]),
        }
    })
}

/// The slot holding the cell keyed `key` in table `words`, along its probes up to the
/// first no cell has held.
fn slot_of(words: &[u32], key: u32) -> Option<u32> {
    let mut probe = 0;
    while probe < CUT_PROBES {
        let slot = probe_slot(key, probe);
        let held = words[slot as usize * CUT_WORDS];
        if held == key {
            return Some(slot);
        }
        if held == NO_CELL {
            return None;
        }
        probe += 1;
    }
    None
}

/// `blade` at height `height` (no taller than its own): its curve scaled towards its
/// root, so the simulation's length validation keeps it there.
pub fn cut_to(blade: &Blade, height: f32) -> Blade {
    let (root, h) = (blade.root(), blade.height());
    if height >= h || h <= 0.0 {
        return *blade;
    }
    let k = height / h;
    let mut cut = blade.with_curve(
        root + (blade.guide() - root) * k,
        root + (blade.tip() - root) * k,
    );
    cut.v1.w = height;
    cut
}

/// `blade` as the cuts of table `words` leave it at `now` with regrowth over `regrow`
/// seconds ([`regrown`] for its cell's cut, itself where its cell has none). A slot
/// this frame claimed for a cell never cut before holds a stub of 0 until the frame
/// commits its cut, and reads as no cut.
pub fn as_cut(blade: &Blade, words: &[u32], now: f32, regrow: f32) -> Blade {
    match find(words, cell_key(blade.root())) {
        Some(cut) if cut.time < now && cut.stub > 0.0 => cut_to(
            blade,
            regrown(blade.height(), cut.stub, now - cut.time, regrow),
        ),
        _ => *blade,
    }
}

/// The stub cutter `cutter` leaves of `blade`: the height above the root of the
/// cutter's lowest point (at least [`MIN_STUB`]), where the stub is shorter than the
/// blade and the cutter holds a point of its curve: one of [`CUT_POINTS`] points
/// along it, or the point just above that height (a quarter of the cutter's height
/// up), so a cutter thinner than the points' spacing (a mower's blade) still cuts.
#[allow(clippy::manual_range_contains)]
pub fn stub_left(blade: &Blade, cutter: &Collider) -> Option<f32> {
    let (v0, v1, v2) = (blade.root(), blade.guide(), blade.tip());
    let (lo, hi) = cutter.bounds();
    let stub = (lo.y - v0.y).max(MIN_STUB);
    if stub >= blade.height() {
        return None;
    }
    let holds = |t: f32| {
        let p = v0 * ((1.0 - t) * (1.0 - t)) + v1 * (2.0 * t * (1.0 - t)) + v2 * (t * t);
        cutter.may_hold(p) && cutter.penetration(p) != Vec3::ZERO
    };
    // Where the curve's height along up, h(t) = 2t(1 − t)·a + t²·b, first reaches
    // the level: q·t² + 2a·t − level = 0 with q = b − 2a.
    let up = blade.up_dir();
    let (a, b) = (up.dot(v1 - v0), up.dot(v2 - v0));
    let level = stub + 0.25 * (hi.y - lo.y);
    let q = b - 2.0 * a;
    let crossing = if q.abs() < 1e-6 {
        if a > 0.0 { level / (2.0 * a) } else { -1.0 }
    } else {
        let disc = 4.0 * a * a + 4.0 * q * level;
        if disc < 0.0 {
            -1.0
        } else {
            let root = disc.sqrt();
            let (t0, t1) = ((-2.0 * a - root) / (2.0 * q), (-2.0 * a + root) / (2.0 * q));
            let (first, second) = (t0.min(t1), t0.max(t1));
            if first >= 0.0 { first } else { second }
        }
    };
    // Compared by hand: `RangeInclusive::contains` makes rust-gpu load through a
    // pointer that is not logical (spirv-val rejects it).
    let mut found = crossing >= 0.0 && crossing <= 1.0 && holds(crossing);
    let mut i = 1;
    while i <= CUT_POINTS && !found {
        found = holds(i as f32 / CUT_POINTS as f32);
        i += 1;
    }
    if found { Some(stub) } else { None }
}

/// The stub the cutters near `blade` leave of it (the lowest [`stub_left`] of the
/// cutters in its slot of the colliders' grid, of the first `count` colliders); its own
/// height where none cuts it.
pub fn cut_near(blade: &Blade, near: &Nearby, count: u32) -> f32 {
    let slot = near.around(blade.root(), blade.height(), count);
    let mut stub = blade.height();
    each_marked(near.words, &slot, count, |i| {
        let c = &near.colliders[i as usize];
        if c.cuts()
            && let Some(s) = stub_left(blade, c)
        {
            stub = stub.min(s);
        }
        true
    });
    stub
}

/// The slot a cut of the cell keyed `key` takes at `now` (regrowth over `regrow`
/// seconds) in table `words`: its own wherever along its probes, else the first of
/// them that no cell holds or whose cell has grown back, which `claim(words, at, held)` must take from `held`
/// (its key word at `at`; a compare-and-swap on the GPU; true where the slot then
/// holds `key`). `None` where every probe holds another cell still growing back: the
/// cut is dropped.
pub fn place(
    words: &mut [u32],
    key: u32,
    now: f32,
    regrow: f32,
    mut claim: impl FnMut(&mut [u32], usize, u32) -> bool,
) -> Option<u32> {
    // The cell's own slot first, wherever along its probes it lies: a slot freed
    // before it must not take a second one, which blades would find first.
    if let Some(slot) = slot_of(words, key) {
        return Some(slot);
    }
    let mut probe = 0;
    while probe < CUT_PROBES {
        let slot = probe_slot(key, probe);
        let at = slot as usize * CUT_WORDS;
        let held = words[at];
        let free = held == NO_CELL || now - f32::from_bits(words[at + 1]) >= regrow;
        if held == key || (free && claim(words, at, held)) {
            return Some(slot);
        }
        probe += 1;
    }
    None
}

/// A cut leaving `stub` as a slot's pending word holds it: the complement of its bits,
/// so that the greatest of them, which an atomic maximum keeps, is the lowest stub (a
/// positive `f32`'s bits order as the numbers do), and 0 is none.
pub fn pending(stub: f32) -> u32 {
    !stub.max(MIN_STUB).to_bits()
}

/// Commits slot `slot`'s pending cut at `now`, the frame's time: its time and stub
/// become the cut's and the pending word none. What the frame's last pass over the
/// table does, after every cut of the frame is pending.
pub fn commit(words: &mut [u32], slot: u32, now: f32) {
    let at = slot as usize * CUT_WORDS;
    let held = words[at + PENDING_WORD];
    if held != 0 {
        words[at + 1] = now.to_bits();
        words[at + 2] = !held;
        words[at + PENDING_WORD] = 0;
    }
}

/// The host's cut table: the same slots the GPU's cuts fill.
#[cfg(not(target_arch = "spirv"))]
#[derive(Clone, Debug, PartialEq)]
pub struct CutTable {
    /// [`CUT_SLOTS`] slots of [`CUT_WORDS`] words.
    pub words: Vec<u32>,
}

#[cfg(not(target_arch = "spirv"))]
impl Default for CutTable {
    fn default() -> Self {
        Self {
            words: vec![NO_CELL; CUT_SLOTS as usize * CUT_WORDS],
        }
    }
}

#[cfg(not(target_arch = "spirv"))]
impl CutTable {
    /// Records a cut of `key`'s cell leaving `stub` at `now`, pending until
    /// [`CutTable::commit`]; false where it was dropped.
    pub fn pend(&mut self, key: u32, stub: f32, now: f32, regrow: f32) -> bool {
        let claimed = place(&mut self.words, key, now, regrow, |words, at, _| {
            words[at] = key;
            true
        });
        if let Some(slot) = claimed {
            let at = slot as usize * CUT_WORDS + PENDING_WORD;
            self.words[at] = self.words[at].max(pending(stub));
        }
        claimed.is_some()
    }

    /// Commits every slot's pending cut at `now` ([`commit`]).
    pub fn commit(&mut self, now: f32) {
        for slot in 0..CUT_SLOTS {
            commit(&mut self.words, slot, now);
        }
    }

    /// A whole frame's one cut: [`CutTable::pend`], then [`CutTable::commit`].
    pub fn cut(&mut self, key: u32, stub: f32, now: f32, regrow: f32) -> bool {
        let kept = self.pend(key, stub, now, regrow);
        self.commit(now);
        kept
    }
}

#[cfg(test)]
mod tests;

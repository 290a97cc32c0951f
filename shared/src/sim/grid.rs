//! The colliders' spatial grid: a blade tests only the colliders near its root, not
//! every one. Space is cut into cubes of side [`ColliderGrid::cell`], hashed into
//! [`ColliderGrid::slots`] slots (Teschner et al., *Optimized Spatial Hashing for
//! Collision Detection of Deformable Objects*, VMV 2003). A slot holds one bit per
//! collider ([`GRID_WORDS`] words: [`OCCUPANCY_WORDS`] words with a bit for each
//! word of colliders that has one, then [`COLLIDER_WORDS`] words of collider bits),
//! set by every collider whose bounds, grown by the blades' reach, overlap a cube
//! hashed there. The cube is half as large as the largest grown bounds, so a collider
//! marks at most 3 x 3 x 3 cubes. A blade reads the one slot of the cube holding its
//! root and pushes out of the marked colliders in ascending order: the order in which
//! a test of every collider would meet them, so the grid changes which colliders are
//! looked at, never the result. A hash collision only adds colliders that do not
//! touch (their displacement is exactly zero). The one exception is a tip one
//! collider pushed farther from its root than the reach within a step: a collider
//! beyond the reach is not looked at for it until validation has brought it back.
//!
//! The pass over every blade asks the watch's slots, past the grid's, instead
//! ([`crate::sim::watch`]).

use crate::Blade;
use crate::sim::collide::{Collider, MAX_COLLIDERS, fixed_midpoint, tip_push};
use spirv_std::glam::{IVec3, UVec4, Vec3, Vec4Swizzles};

/// Words of one slot's collider bits: one bit per collider.
pub const COLLIDER_WORDS: usize = MAX_COLLIDERS / 32;
/// Words of one slot's occupancy: bit w of them set where collider word w has a bit
/// (two, held in [`Slot`] as two numbers: an array indexed in a loop went to the
/// NVIDIA H100's local memory).
pub const OCCUPANCY_WORDS: usize = COLLIDER_WORDS / 32;
/// Words of one slot: the occupancy words, then the collider words.
pub const GRID_WORDS: usize = OCCUPANCY_WORDS + COLLIDER_WORDS;

const _: () = assert!(OCCUPANCY_WORDS == 2, "Slot holds two occupancy words");

/// Most slots of the renderer's grid (a power of two): 17 MB. A frame uses as many
/// as [`fitted`](crate::sim::colliders::fitted) gives for its colliders, and clears those.
pub const GRID_SLOTS: u32 = 65536;

/// Cubes a collider marks at most, and threads of the grid's build per collider.
pub const GRID_CORNERS: u32 = 27;

/// The grid's reach over the field's tallest blade: a blade's tip and midpoint stay
/// within its height of its root once validated (paper section 5.2), but within a
/// step the forces move the tip before validation brings it back (by the step's
/// push, a hundredth of the height in a strong wind), and the length validation
/// keeps is within a few percent of the height. Every unit of reach grows the blades
/// each collider hands to the collision pass by the square.
pub const REACH_MARGIN: f32 = 1.1;

/// How near a collider's surface a blade's tip or midpoint touches it
/// ([`Nearby::first_touching`]), world units: a tenth of the narrowest blade's height.
pub const TOUCH_MARGIN: f32 = 0.1;

/// [`Nearby::first_touching`]: no collider touches.
pub const NONE_TOUCHING: u32 = u32::MAX;

/// Threads of a workgroup of the grid's build: one per collider and cube it may mark.
pub const GRID_WORKGROUP: u32 = 64;

/// The grid of one frame, in the frame block (`FrameUniforms::collider_grid`).
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ColliderGrid {
    /// Side of a cube, world units: at least the largest collider's grown bounds.
    pub cell: f32,
    /// How far from its root a blade reaches: the field's tallest blade times
    /// [`REACH_MARGIN`]. A blade taller than this tests every collider.
    pub reach: f32,
    /// Slots (a power of two; 1: every collider in one slot, the test of them all).
    pub slots: u32,
    /// The lowest height (y) of a blade's root in the field: a collider marks no
    /// cube wholly below it ([`Self::over_roots`]).
    pub low: f32,
    /// The highest height of a blade's root: no cube wholly above it is marked.
    pub high: f32,
    /// Side of a cube of the watch's slots, world units: at least half the largest
    /// collider's bounds grown by [`WATCH_ALLOWANCE`](crate::sim::watch::WATCH_ALLOWANCE) (as many slots as the grid's).
    pub watch_cell: f32,
    /// Padding to 32 bytes.
    pub pad: [u32; 2],
}

impl Default for ColliderGrid {
    /// One slot: every collider is looked at.
    fn default() -> Self {
        Self {
            cell: 1.0,
            reach: 0.0,
            slots: 1,
            low: -ROOTS_ANYWHERE,
            high: ROOTS_ANYWHERE,
            watch_cell: 1.0,
            pad: [0; 2],
        }
    }
}

/// Sets collider `index`'s bit in the slot at word `base`, and its word's bit of the
/// slot's occupancy, through `or` (an atomic or on the GPU, `compute::grid`).
pub fn mark_collider(
    words: &mut [u32],
    base: usize,
    index: usize,
    mut or: impl FnMut(&mut u32, u32),
) {
    let w = index / 32;
    or(&mut words[base + w / 32], 1 << (w % 32));
    or(&mut words[base + OCCUPANCY_WORDS + w], 1 << (index % 32));
}

/// The roots' height range of a grid that knows none: every height.
pub const ROOTS_ANYWHERE: f32 = 1e30;

impl ColliderGrid {
    /// The cube holding `p`.
    pub fn cube(&self, p: Vec3) -> IVec3 {
        (p / self.cell).floor().as_ivec3()
    }

    /// The slot cube `c` hashes to: (x·73856093 ⊕ y·19349663 ⊕ z·83492791) mod slots
    /// (Teschner et al. 2003).
    pub fn slot_of(&self, c: IVec3) -> usize {
        (hash(c) & (self.slots - 1)) as usize
    }

    /// The first word of the slot cube `c` hashes to.
    pub fn slot_base(&self, c: IVec3) -> usize {
        self.slot_of(c) * GRID_WORDS
    }

    /// The cubes a collider marks: from the least to the greatest corner of its
    /// bounds grown by the reach, at most three along each axis, in height only
    /// those the roots' range meets (a blade looks its collider up at its root's
    /// cube; a collider whose grown bounds miss that range marks none).
    pub fn cubes_of(&self, collider: &Collider) -> (IVec3, IVec3) {
        let (lo, hi) = collider.bounds();
        let grow = Vec3::splat(self.reach);
        let (mut lo, mut hi) = (lo - grow, hi + grow);
        lo.y = lo.y.max(self.low);
        hi.y = hi.y.min(self.high);
        let (a, b) = (self.cube(lo), self.cube(hi));
        (a, b.min(a + IVec3::splat(2)))
    }

    /// This grid for a field whose roots lie between the heights `low` and `high`:
    /// a collider standing on a flat field marks one layer of cubes instead of
    /// three, so fewer slots are shared by cubes far apart.
    pub fn over_roots(self, (low, high): (f32, f32)) -> Self {
        Self { low, high, ..self }
    }

    /// The `corner`th (0..[`GRID_CORNERS`]) cube of those [`Self::cubes_of`] gives,
    /// and whether it is one of them.
    pub fn corner_cube(&self, collider: &Collider, corner: u32) -> (bool, IVec3) {
        let (lo, hi) = self.cubes_of(collider);
        let c = lo + corner_step(corner);
        (c.cmple(hi).all(), c)
    }
}

/// (x·73856093 ⊕ y·19349663 ⊕ z·83492791) (Teschner et al. 2003).
fn hash(c: IVec3) -> u32 {
    (c.x as u32).wrapping_mul(73_856_093)
        ^ (c.y as u32).wrapping_mul(19_349_663)
        ^ (c.z as u32).wrapping_mul(83_492_791)
}

/// The step from the least cube to the `corner`th of 3 x 3 x 3.
pub(crate) fn corner_step(corner: u32) -> IVec3 {
    IVec3::new(
        (corner % 3) as i32,
        ((corner / 3) % 3) as i32,
        (corner / 9) as i32,
    )
}

/// Where a blade finds its colliders, the same for each of its steps in a frame: the
/// first word of its slot, the slot's occupancy words (read once), and whether it
/// tests every collider instead.
#[derive(Copy, Clone, Debug, Default)]
pub struct Slot {
    /// The slot's first word.
    pub base: usize,
    /// Its occupancy words: bit w set where collider word w has a collider (with
    /// `every`, each word holding one of the colliders in use); words 0 to 31.
    pub low: u32,
    /// Words 32 to 63.
    pub high: u32,
    /// Every collider in use is tested, not the slot's.
    pub every: bool,
}

/// Pushes `blade` out of each collider marked in `slot` of `words`, in ascending
/// order (each sees the tip the one before left), of the first `count` of
/// `colliders`; with `slot.every`, out of each of them. Returns the blade with its new
/// tip and the total displacement.
pub fn collide_near(
    blade: &Blade,
    (colliders, words): (&[Collider], &[u32]),
    slot: &Slot,
    count: u32,
) -> (Blade, Vec3) {
    // Only the tip moves: the midpoint's other part is fixed.
    let fixed = fixed_midpoint(blade);
    let mut tip = blade.tip();
    let mut total = Vec3::ZERO;
    each_marked(words, slot, count, |i| {
        let c = &colliders[i as usize];
        // A cutter cuts (`sim::cut`) and does not push.
        if !c.cuts() {
            let d = tip_push(tip, fixed, c);
            tip += d;
            total += d;
        }
        true
    });
    (blade.with_curve(blade.guide(), tip), total)
}

/// Calls `visit(i)` for each collider `i` marked in `slot` of `words` (with
/// `slot.every`, each of the first `count`), in ascending order, until it returns
/// false: the walk over a slot's bits (the cuts' ([`crate::sim::cut::cut_near`]);
/// the collisions' ([`collide_near`]), the hand-over's and the contacts'). On the GPU,
/// `visit` does no device atomic: NVIDIA's compiler crashes on one there
/// (`docs/architecture.md`, "Five workarounds worth knowing").
pub fn each_marked(words: &[u32], slot: &Slot, count: u32, mut visit: impl FnMut(u32) -> bool) {
    let used = (count as usize).min(MAX_COLLIDERS) as u32;
    let mut going = true;
    let mut o = 0;
    while o < OCCUPANCY_WORDS as u32 && going {
        let mut occupied = if o == 0 { slot.low } else { slot.high };
        while occupied != 0 && going {
            let w = 32 * o + occupied.trailing_zeros();
            occupied &= occupied - 1;
            let mut bits = if slot.every {
                low_bits(used - 32 * w)
            } else {
                words[slot.base + OCCUPANCY_WORDS + w as usize]
            };
            while bits != 0 && going {
                let i = 32 * w + bits.trailing_zeros();
                bits &= bits - 1;
                going = visit(i);
            }
        }
        o += 1;
    }
}

/// `a − b`, or 0 where `b` is the greater (rust-gpu has no `saturating_sub`).
#[allow(clippy::implicit_saturating_sub)]
fn after(a: u32, b: u32) -> u32 {
    if a > b { a - b } else { 0 }
}

/// The lowest `n` bits set (all 32 from 32 on).
fn low_bits(n: u32) -> u32 {
    if n >= 32 { u32::MAX } else { (1u32 << n) - 1 }
}

/// A frame's colliders with the grid that finds them: what a blade's steps collide
/// with (the GPU's buffers, or the host's [`ColliderSet`](crate::sim::colliders::ColliderSet)).
#[derive(Copy, Clone)]
pub struct Nearby<'a> {
    /// The colliders.
    pub colliders: &'a [Collider],
    /// The grid's slots, [`GRID_WORDS`] words each.
    pub words: &'a [u32],
    /// The same words four at a time, how the watch reads its slots (a capsule in two).
    pub shapes: &'a [UVec4],
    /// The grid.
    pub grid: ColliderGrid,
}

impl Nearby<'_> {
    /// Whether a blade rooted at `root` that reaches `reach` from it (its height times
    /// [`REACH_MARGIN`]) may touch a collider of `slot` (of the first `count`), and
    /// whether one of those cuts: with `slot.every`, always (and whether any of them
    /// cuts); else whether the root is nearer than `reach` to a marked collider's
    /// surface ([`Collider::gap`], after its bounding sphere). A blade for which the
    /// first is false is pushed and cut by none of them, whatever the order: its tip
    /// and midpoint stay within `reach` of its root. What the compute pass's pass over
    /// every blade asks, in a frame with a cutter, before watching a blade's steps, or
    /// handing it to its collision pass straight away where a cutter reaches it.
    pub fn reaches(&self, root: Vec3, reach: f32, slot: &Slot, count: u32) -> (bool, bool) {
        let (mut found, mut cutter) = (false, false);
        each_marked(self.words, slot, count, |i| {
            let c = &self.colliders[i as usize];
            let within = c.bound.w + reach;
            let near = slot.every
                || ((root - c.bound.xyz()).length_squared() < within * within
                    && c.gap(root) < reach);
            found = found || near;
            cutter = near && c.cuts();
            !cutter
        });
        (found, cutter)
    }

    /// The first collider of `slot` (of the first `count`) that pushes and that `tip`
    /// or `mid` touches: within [`TOUCH_MARGIN`] of its surface ([`Collider::gap`]; a
    /// push leaves a point on the surface); [`NONE_TOUCHING`] where none does. What
    /// the collision pass's blades mark in the query buffer's contacts
    /// (`query::CONTACTS`), for a game's footsteps: a collider in the grass touches
    /// many blades, and one of them that touches no collider before it marks it.
    pub fn first_touching(&self, (tip, mid): (Vec3, Vec3), slot: &Slot, count: u32) -> u32 {
        let mut found = NONE_TOUCHING;
        each_marked(self.words, slot, count, |i| {
            let c = &self.colliders[i as usize];
            if !c.cuts() && c.gap(tip).min(c.gap(mid)) < TOUCH_MARGIN {
                found = i;
            }
            found == NONE_TOUCHING
        });
        found
    }

    /// Where the blade rooted at `root` of `height` finds the first `count`
    /// colliders: its cube's slot, or every one where the grid has a single slot or
    /// the blade is taller than its reach.
    pub fn around(&self, root: Vec3, height: f32, count: u32) -> Slot {
        let every = self.grid.slots <= 1 || height > self.grid.reach;
        if every {
            // Every word holding one of the first `count`.
            let full = count.min(MAX_COLLIDERS as u32).div_ceil(32);
            Slot {
                base: 0,
                low: low_bits(full),
                high: low_bits(after(full, 32)),
                every,
            }
        } else {
            let base = self.grid.slot_base(self.grid.cube(root));
            Slot {
                base,
                low: self.words[base],
                high: self.words[base + 1],
                every,
            }
        }
    }
}

/// No colliders.
pub const NOTHING_NEAR: Nearby<'static> = Nearby {
    colliders: &[],
    words: &[],
    shapes: &[],
    grid: ColliderGrid {
        cell: 1.0,
        reach: 0.0,
        slots: 1,
        low: -ROOTS_ANYWHERE,
        high: ROOTS_ANYWHERE,
        watch_cell: 1.0,
        pad: [0; 2],
    },
};

#[cfg(test)]
pub(crate) mod tests;

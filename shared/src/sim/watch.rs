//! The watch: what the pass over every blade, which steps a blade without the
//! colliders and hands one they may have touched to the collision pass, asks after
//! the steps ([`Nearby::may_have_touched`]). Space is cut into cubes of side
//! [`ColliderGrid::watch_cell`] that hold the point halfway between a blade's tip
//! and midpoint; each cube has a slot, past the grid's, with the capsules
//! ([`Collider::watched`]) of the first [`WATCH_SHAPES`] pushing colliders whose
//! bounds, grown by [`WATCH_ALLOWANCE`], overlap a cube there, and the count of all
//! of them, and a bit of the watch's marks, past the slots, set where any does. A
//! blade reads the bit, and only where it is set the slot: no bits to walk, no
//! collider to fetch. The cubes are small: they hold tips, not roots, so they need
//! not grow by a blade's reach.
//!
//! Slots and marks are laid out as a grid that wraps around (4 layers of W x W
//! columns, x fastest: [`wrapped`]) rather than hashed: a warp's blades stand in
//! neighbouring cubes, whose marks share a word that stays in the cache, and ground
//! narrower than the period (W is 128 cubes for 65,536 slots and 512 for their
//! marks: 256 and 1,024 units with walkers' cubes of 2) has no two cubes in one
//! place. Where two share a slot, it holds both cubes' colliders: more to test,
//! never one missed; a mark shared only sends a blade to the slot.

use super::grid::{ColliderGrid, GRID_WORDS, Nearby, corner_step};
use crate::Blade;
use crate::sim::collide::{Collider, within_capsule};
use spirv_std::glam::{IVec3, UVec4, Vec2, Vec3, Vec4, Vec4Swizzles};

/// What [`Nearby::may_have_touched`] adds to a travel (and the watch's cubes to
/// their allowance), world units: a thousand times the rounding of a distance at a
/// thousand units from the origin, so that no rounding of the travel or the
/// distances lets a point the forces moved into a collider go unseen.
pub const WATCH_MARGIN: f32 = 1e-3;

/// Pushing colliders whose capsules a slot of the watch holds: where more mark it,
/// its blades go to the collision pass.
pub const WATCH_SHAPES: u32 = 4;

/// Words of a capsule in a watch slot: its segment's first end and radius, its
/// second end, and one more (in the slot's first capsule, [`COUNT_WORD`]).
pub const SHAPE_WORDS: usize = 8;

/// Words of one slot of the watch.
pub const WATCH_WORDS: usize = WATCH_SHAPES as usize * SHAPE_WORDS;

/// The word of a watch slot that counts the pushing colliders marking it.
pub const COUNT_WORD: usize = 7;

/// Bits of the watch's marks for each of its slots: 128 KB for 65,536 slots.
pub const MARK_BITS: u32 = 16;

/// How far from the point halfway between a blade's tip and midpoint the points the
/// frame's steps moved them to may lie for the watch's slot to know every collider
/// that may have held one ([`Nearby::may_have_touched`]), world units: half the
/// distance from a tall blade's tip to its midpoint bent in a breeze (up to 0.9, 2.5
/// units tall, 0.3 standing) and a frame's travel. A blade beyond it goes to the
/// collision pass.
pub const WATCH_ALLOWANCE: f32 = 1.1;

impl ColliderGrid {
    /// The watch's cube holding `p`.
    pub fn watch_cube(&self, p: Vec3) -> IVec3 {
        (p / self.watch_cell).floor().as_ivec3()
    }

    /// The first word of the watch's slots: after the grid's, at a multiple of four
    /// words, so that a slot's capsules are read 16 bytes a load ([`Nearby::shapes`]).
    pub fn watch_start(&self) -> usize {
        (self.slots as usize * GRID_WORDS).next_multiple_of(4)
    }

    /// The first word of the watch's slot of cube `c` of the watch's cubes
    /// ([`wrapped`] to as many slots as the grid's).
    pub fn watch_base(&self, c: IVec3) -> usize {
        self.watch_start() + wrapped(c, self.slots) as usize * WATCH_WORDS
    }

    /// The first word of the watch's marks, after its slots.
    pub fn marks_start(&self) -> usize {
        self.watch_start() + self.slots as usize * WATCH_WORDS
    }

    /// Bits of the watch's marks: [`MARK_BITS`] a slot, at least four words.
    pub fn mark_bits(&self) -> u32 {
        (self.slots * MARK_BITS).max(128)
    }

    /// Words of the grid's slots and the watch's slots and marks: the grid's buffer.
    pub fn words(&self) -> usize {
        self.marks_start() + (self.mark_bits() / 32) as usize
    }

    /// The word of the watch's marks that holds cube `c`'s bit ([`wrapped`]), and
    /// the bit.
    pub fn watch_mark(&self, c: IVec3) -> (usize, u32) {
        let at = wrapped(c, self.mark_bits());
        (self.marks_start() + (at / 32) as usize, 1 << (at % 32))
    }

    /// The `corner`th (0..[`super::grid::GRID_CORNERS`]) of the watch's cubes a pushing
    /// `collider` marks, and whether it is one: from the least to the greatest
    /// corner of its bounds grown by [`WATCH_ALLOWANCE`] and [`WATCH_MARGIN`], at
    /// most three along each axis.
    pub fn watch_corner(&self, collider: &Collider, corner: u32) -> (bool, IVec3) {
        let (lo, hi) = collider.bounds();
        let grow = Vec3::splat(WATCH_ALLOWANCE + WATCH_MARGIN);
        let (a, b) = (self.watch_cube(lo - grow), self.watch_cube(hi + grow));
        let c = a + corner_step(corner);
        (
            !collider.cuts() && c.cmple(b.min(a + IVec3::splat(2))).all(),
            c,
        )
    }
}

/// Cube `c`'s place in a grid of `n` places (a power of two) that wraps around: four
/// layers in height of W x W columns, x fastest (W along x twice that along z where
/// the power is odd); 0 where `n` is less than 4.
pub fn wrapped(c: IVec3, n: u32) -> u32 {
    if n < 4 {
        return 0;
    }
    let across = (n / 4).trailing_zeros();
    let (x_bits, z_bits) = (across.div_ceil(2), across / 2);
    ((c.y as u32) & 3) << across
        | ((c.z as u32) & ((1 << z_bits) - 1)) << x_bits
        | ((c.x as u32) & ((1 << x_bits) - 1))
}

impl Nearby<'_> {
    /// Whether a pushing collider may have held a point that travelled to `blade`'s
    /// tip or midpoint along a path no longer than `travel` (x: the tip's, y: the
    /// midpoint's; `simulate::simulate_travelled`): the points may lie farther than
    /// [`WATCH_ALLOWANCE`] from the point halfway between them, or that point's cube
    /// is marked and its slot holds more than it has room for or a capsule nearer
    /// than the travel and [`WATCH_MARGIN`] to one of them ([`within_capsule`]; the
    /// distance to a surface changes no faster than the point moves). What the pass
    /// over every blade asks after its steps.
    pub fn may_have_touched(&self, blade: &Blade, travel: Vec2) -> bool {
        let (tip, mid) = (blade.tip(), blade.midpoint());
        let halfway = 0.5 * (tip + mid);
        let cube = self.grid.watch_cube(halfway);
        let (word, bit) = self.grid.watch_mark(cube);
        let mut found = 0.5 * tip.distance(mid) + travel.max_element() >= WATCH_ALLOWANCE;
        if !found && self.words[word] & bit != 0 {
            // The slot's first capsule and its count (the first capsule's last word)
            // in two loads, the rest as the count asks.
            let base = self.grid.watch_base(cube) / 4;
            let (a, b) = (self.shapes[base], self.shapes[base + 1]);
            let count = b.w;
            found = count > WATCH_SHAPES;
            let mut shape = (as_floats(a), as_floats(b).xyz());
            let mut k = 0;
            while k < count && !found {
                if k > 0 {
                    shape = watched_at(self.shapes, base + k as usize * SHAPE_WORDS / 4);
                }
                found = within_capsule(shape, tip, travel.x + WATCH_MARGIN)
                    || within_capsule(shape, mid, travel.y + WATCH_MARGIN);
                k += 1;
            }
        }
        found
    }
}

/// Four words as the floats whose bits they are.
fn as_floats(w: UVec4) -> Vec4 {
    Vec4::new(
        f32::from_bits(w.x),
        f32::from_bits(w.y),
        f32::from_bits(w.z),
        f32::from_bits(w.w),
    )
}

/// The capsule ([`Collider::watched`]) a watch slot holds at word `4 · at` (`at` in
/// [`Nearby::shapes`]).
fn watched_at(shapes: &[UVec4], at: usize) -> (Vec4, Vec3) {
    (as_floats(shapes[at]), as_floats(shapes[at + 1]).xyz())
}

/// Watches pushing `collider` in cube `cube` of the watch's cubes: counts it in the
/// cube's slot through `count` (which adds one to the slot's count word and gives
/// the count before it: an atomic add on the GPU, `compute::grid`), writes its
/// capsule there where the slot has room for it, and sets the cube's mark through
/// `mark` (an atomic or on the GPU).
pub fn watch_collider(
    words: &mut [u32],
    (grid, cube): (&ColliderGrid, IVec3),
    collider: &Collider,
    count: impl FnOnce(&mut u32) -> u32,
    mark: impl FnOnce(&mut u32, u32),
) {
    let base = grid.watch_base(cube);
    let n = count(&mut words[base + COUNT_WORD]);
    if n < WATCH_SHAPES {
        store_watched(words, base + n as usize * SHAPE_WORDS, collider);
    }
    let (word, bit) = grid.watch_mark(cube);
    mark(&mut words[word], bit);
}

/// Writes `collider`'s capsule ([`Collider::watched`]) into a watch slot at word
/// `at`, its last word left (a slot's count in its first capsule).
fn store_watched(words: &mut [u32], at: usize, collider: &Collider) {
    let (a, b) = collider.watched();
    words[at] = a.x.to_bits();
    words[at + 1] = a.y.to_bits();
    words[at + 2] = a.z.to_bits();
    words[at + 3] = a.w.to_bits();
    words[at + 4] = b.x.to_bits();
    words[at + 5] = b.y.to_bits();
    words[at + 6] = b.z.to_bits();
}

/// The `corner`th of the watch's cubes `collider` marks, watched on the host
/// ([`watch_collider`] as the GPU's build does it).
#[cfg(not(target_arch = "spirv"))]
pub fn watch_on_host(words: &mut [u32], grid: &ColliderGrid, collider: &Collider, corner: u32) {
    let (watches, cube) = grid.watch_corner(collider, corner);
    if watches {
        let count = |n: &mut u32| {
            *n += 1;
            *n - 1
        };
        watch_collider(words, (grid, cube), collider, count, |w, bit| *w |= bit);
    }
}

#[cfg(test)]
mod tests;

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

use crate::Blade;
use crate::sim::collide::{Collider, MAX_COLLIDERS, fixed_midpoint, tip_push};
use spirv_std::glam::{IVec3, Vec3, Vec4Swizzles};

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
/// as [`fitted`] gives for its colliders, and clears those.
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
    /// Padding to 16 bytes.
    pub pad: u32,
}

impl Default for ColliderGrid {
    /// One slot: every collider is looked at.
    fn default() -> Self {
        Self {
            cell: 1.0,
            reach: 0.0,
            slots: 1,
            pad: 0,
        }
    }
}

impl ColliderGrid {
    /// The cube holding `p`.
    pub fn cube(&self, p: Vec3) -> IVec3 {
        (p / self.cell).floor().as_ivec3()
    }

    /// The first word of the slot cube `c` hashes to: (x·73856093 ⊕ y·19349663 ⊕
    /// z·83492791) mod slots (Teschner et al. 2003).
    pub fn slot_base(&self, c: IVec3) -> usize {
        let h = (c.x as u32).wrapping_mul(73_856_093)
            ^ (c.y as u32).wrapping_mul(19_349_663)
            ^ (c.z as u32).wrapping_mul(83_492_791);
        (h & (self.slots - 1)) as usize * GRID_WORDS
    }

    /// The cubes a collider marks: from the least to the greatest corner of its
    /// bounds grown by the reach, at most three along each axis.
    pub fn cubes_of(&self, collider: &Collider) -> (IVec3, IVec3) {
        let (lo, hi) = collider.bounds();
        let grow = Vec3::splat(self.reach);
        let (a, b) = (self.cube(lo - grow), self.cube(hi + grow));
        (a, b.min(a + IVec3::splat(2)))
    }

    /// The `corner`th (0..[`GRID_CORNERS`]) cube of those [`Self::cubes_of`] gives,
    /// and whether it is one of them.
    pub fn corner_cube(&self, collider: &Collider, corner: u32) -> (bool, IVec3) {
        let (lo, hi) = self.cubes_of(collider);
        let step = IVec3::new(
            (corner % 3) as i32,
            ((corner / 3) % 3) as i32,
            (corner / 9) as i32,
        );
        let c = lo + step;
        (c.cmple(hi).all(), c)
    }
}

/// The grid a frame's colliders need: cubes half as large as the largest collider's
/// bounds grown by `reach` on every side, and 32 slots a collider (about three for
/// each cube it marks), a power of two from 64 to `most`.
#[cfg(not(target_arch = "spirv"))]
pub fn fitted(colliders: &[Collider], reach: f32, most: u32) -> ColliderGrid {
    let largest = colliders
        .iter()
        .map(|c| {
            let (lo, hi) = c.bounds();
            (hi - lo).max_element()
        })
        .fold(0.0f32, f32::max);
    let wanted = (colliders.len() as u32)
        .saturating_mul(32)
        .next_power_of_two();
    ColliderGrid {
        // A little over, so a collider exactly two cubes wide marks three at most.
        cell: (0.5 * (largest + 2.0 * reach) * 1.001).max(0.01),
        reach,
        slots: wanted.max(64).min(most.max(1)),
        pad: 0,
    }
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
    let used = (count as usize).min(MAX_COLLIDERS) as u32;
    let mut o = 0;
    while o < OCCUPANCY_WORDS as u32 {
        let mut occupied = if o == 0 { slot.low } else { slot.high };
        while occupied != 0 {
            let w = 32 * o + occupied.trailing_zeros();
            occupied &= occupied - 1;
            let mut bits = if slot.every {
                low_bits(used - 32 * w)
            } else {
                words[slot.base + OCCUPANCY_WORDS + w as usize]
            };
            while bits != 0 {
                let i = 32 * w + bits.trailing_zeros();
                bits &= bits - 1;
                let c = &colliders[i as usize];
                // A cutter cuts (`sim::cut`) and does not push.
                if !c.cuts() {
                    let d = tip_push(tip, fixed, c);
                    tip += d;
                    total += d;
                }
            }
        }
        o += 1;
    }
    (blade.with_curve(blade.guide(), tip), total)
}

/// Calls `visit(i)` for each collider `i` marked in `slot` of `words` (with
/// `slot.every`, each of the first `count`), in ascending order, until it returns
/// false: the walk over a slot's bits (the cuts' ([`crate::sim::cut::cut_near`]);
/// the collisions and the hand-over write it out).
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
/// with (the GPU's buffers, or the host's [`ColliderSet`]).
#[derive(Copy, Clone)]
pub struct Nearby<'a> {
    /// The colliders.
    pub colliders: &'a [Collider],
    /// The grid's slots, [`GRID_WORDS`] words each.
    pub words: &'a [u32],
    /// The grid.
    pub grid: ColliderGrid,
}

impl Nearby<'_> {
    /// Whether a blade rooted at `root` that reaches `reach` from it (its height times
    /// [`REACH_MARGIN`]) may touch a collider of `slot` (of the first `count`): with
    /// `slot.every`, always; else whether the root is nearer than `reach` to a
    /// marked collider's surface ([`Collider::gap`], after its bounding sphere). A
    /// blade for which it is false is pushed and cut by none of them, whatever the
    /// order: its tip and midpoint stay within `reach` of its root. What the compute
    /// pass's pass over every blade asks before handing a blade to its collision pass.
    pub fn reaches(&self, root: Vec3, reach: f32, slot: &Slot, count: u32) -> bool {
        if slot.every {
            return count > 0;
        }
        let mut found = false;
        let mut o = 0;
        while o < OCCUPANCY_WORDS as u32 && !found {
            let mut occupied = if o == 0 { slot.low } else { slot.high };
            while occupied != 0 && !found {
                let w = 32 * o + occupied.trailing_zeros();
                occupied &= occupied - 1;
                let mut bits = self.words[slot.base + OCCUPANCY_WORDS + w as usize];
                while bits != 0 && !found {
                    let i = 32 * w + bits.trailing_zeros();
                    bits &= bits - 1;
                    let c = &self.colliders[i as usize];
                    let within = c.bound.w + reach;
                    found = (root - c.bound.xyz()).length_squared() < within * within
                        && c.gap(root) < reach;
                }
            }
            o += 1;
        }
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
    grid: ColliderGrid {
        cell: 1.0,
        reach: 0.0,
        slots: 1,
        pad: 0,
    },
};

/// Sets collider `index`'s bit in the slot at `base` (the host's build; the GPU's
/// sets the same bits with atomic ors).
#[cfg(not(target_arch = "spirv"))]
pub fn mark(words: &mut [u32], base: usize, index: usize) {
    let w = index / 32;
    words[base + w / 32] |= 1 << (w % 32);
    words[base + OCCUPANCY_WORDS + w] |= 1 << (index % 32);
}

/// Colliders and their grid built on the host: the same slots the GPU builds.
#[cfg(not(target_arch = "spirv"))]
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColliderSet {
    /// The colliders.
    pub colliders: Vec<Collider>,
    /// The grid.
    pub grid: ColliderGrid,
    /// Its slots.
    pub words: Vec<u32>,
}

#[cfg(not(target_arch = "spirv"))]
impl ColliderSet {
    /// `colliders` (the first [`MAX_COLLIDERS`]) in `grid`.
    pub fn new(colliders: &[Collider], grid: ColliderGrid) -> Self {
        let colliders = colliders[..colliders.len().min(MAX_COLLIDERS)].to_vec();
        let mut words = vec![0; grid.slots.max(1) as usize * GRID_WORDS];
        for (i, c) in colliders.iter().enumerate() {
            for corner in 0..GRID_CORNERS {
                let (marks, cube) = grid.corner_cube(c, corner);
                if marks {
                    mark(&mut words, grid.slot_base(cube), i);
                }
            }
        }
        Self {
            colliders,
            grid,
            words,
        }
    }

    /// Every collider tested by every blade (one slot).
    pub fn every(colliders: &[Collider]) -> Self {
        Self::new(colliders, ColliderGrid::default())
    }

    /// Spheres (centre xyz, radius w), every one tested.
    pub fn spheres(spheres: &[spirv_std::glam::Vec4]) -> Self {
        let colliders: Vec<Collider> = spheres.iter().map(|s| Collider::from_sphere(*s)).collect();
        Self::every(&colliders)
    }

    /// What the blades' steps read.
    pub fn nearby(&self) -> Nearby<'_> {
        Nearby {
            colliders: &self.colliders,
            words: &self.words,
            grid: self.grid,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::collide::{COLLIDER_BOX, COLLIDER_CAPSULE};
    use spirv_std::glam::Quat;

    /// A small deterministic generator (a 32-bit xorshift).
    struct Rng(u32);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            self.0 as f32 / u32::MAX as f32
        }
    }

    /// A crowd of capsules, spheres and boxes over a square of `side` units.
    fn crowd(n: usize, side: f32) -> Vec<Collider> {
        let mut rng = Rng(7);
        (0..n)
            .map(|i| {
                let x = (rng.next() - 0.5) * side;
                let at = Vec3::new(x, 0.0, (rng.next() - 0.5) * side);
                match i % 3 {
                    0 => Collider::capsule(at + Vec3::Y * 0.3, at + Vec3::Y * 1.5, 0.3),
                    1 => Collider::sphere(at + Vec3::Y * 0.5, 0.2 + rng.next()),
                    _ => Collider::cuboid(
                        at + Vec3::Y * 0.5,
                        Vec3::new(0.8, 0.5, 1.6),
                        Quat::from_rotation_y(rng.next() * 6.0),
                        0.1,
                    ),
                }
            })
            .collect()
    }

    #[test]
    fn a_collider_marks_every_cube_a_blade_it_can_touch_stands_in() {
        let colliders = crowd(300, 60.0);
        assert!(colliders.iter().any(|c| c.kind == COLLIDER_BOX));
        assert!(colliders.iter().any(|c| c.kind == COLLIDER_CAPSULE));
        let set = ColliderSet::new(&colliders, fitted(&colliders, 2.5, 1024));
        let g = set.grid;
        for (i, c) in colliders.iter().enumerate() {
            let (lo, hi) = c.bounds();
            // Roots on a lattice over the grown bounds all find it in their slot.
            for x in 0..6 {
                for z in 0..6 {
                    for y in 0..4 {
                        let t = Vec3::new(x as f32, y as f32, z as f32) / Vec3::new(5.0, 3.0, 5.0);
                        let root = (lo - g.reach) + (hi - lo + 2.0 * g.reach) * t;
                        let base = g.slot_base(g.cube(root));
                        let w = i / 32;
                        assert!(set.words[base + OCCUPANCY_WORDS + w] & (1 << (i % 32)) != 0);
                        assert!(set.words[base + w / 32] & (1 << (w % 32)) != 0);
                    }
                }
            }
        }
    }

    /// The grid against every collider tested: the same pushes, bit for bit, for
    /// every blade of a field under a crowd of 1,024, dense (one collider to 3.5
    /// square units) and sparse (one to 120, where most blades are left out of the
    /// collision pass). Measured: 49.5 colliders looked at per blade in the dense
    /// crowd (cubes four times larger: 194, and this failed); none of its blades
    /// left out, 0.71 of the sparse crowd's (every blade handed over: 0, and this
    /// failed; `Nearby::reaches` without the reach failed the pushes' check).
    #[test]
    fn the_grid_pushes_every_blade_as_testing_every_collider_does() {
        let (dense, dense_left) = grid_against_every(60.0);
        assert!(dense < 60.0, "{dense} colliders looked at per blade");
        let (_, sparse_left) = grid_against_every(350.0);
        eprintln!("LEFT {dense_left} {sparse_left}");
        assert!(dense_left < 0.1, "{dense_left}");
        assert!(sparse_left > 0.5, "{sparse_left} of the blades left out");
    }

    /// Blades under a crowd of 1,024 over a square of `side`: their pushes through
    /// the grid and through every collider, which must be the same bit for bit; the
    /// colliders looked at per blade, and the share of the blades
    /// [`Nearby::reaches`] leaves out of the collision pass.
    fn grid_against_every(side: f32) -> (f32, f32) {
        let colliders = crowd(1024, side);
        let reach = crate::blade::HEIGHT.1;
        let grid = ColliderSet::new(&colliders, fitted(&colliders, reach, 4096));
        let every = ColliderSet::every(&colliders);
        let blades = crate::world::generate::square_field(8192, side / 2.0, 5);
        let mut touched = 0;
        let mut looked = 0usize;
        let mut left = 0;
        for b in &blades {
            // Leaned, so tips and midpoints reach out of the roots' cubes; the tip
            // stays within the blade's height of its root, as validation keeps it.
            let lean = (b.tip() + Vec3::new(1.0, -0.4, 0.6) - b.root()).normalize();
            let b = b.with_curve(b.guide(), b.root() + lean * b.height());
            let near = grid.nearby();
            let count = colliders.len() as u32;
            let slot = near.around(b.root(), b.height(), count);
            assert!(!slot.every);
            let by_grid = collide_near(&b, (near.colliders, near.words), &slot, count);
            let e = every.nearby();
            let all = e.around(b.root(), b.height(), count);
            assert!(all.every);
            let by_all = collide_near(&b, (e.colliders, e.words), &all, count);
            assert_eq!(by_grid, by_all);
            // A blade the collision pass would not be handed is pushed by none.
            if !near.reaches(b.root(), b.height() * REACH_MARGIN, &slot, count) {
                assert_eq!(by_all.1, Vec3::ZERO);
                left += 1;
            }
            touched += usize::from(by_all.1 != Vec3::ZERO);
            looked += (OCCUPANCY_WORDS..GRID_WORDS)
                .map(|w| near.words[slot.base + w].count_ones() as usize)
                .sum::<usize>();
        }
        // Enough blades touched that the order of the pushes is tested; the grid
        // looks at a twentieth of the dense crowd (it marks 49.5 a slot).
        assert!(touched > 50, "{touched} blades touched");
        let n = blades.len() as f32;
        (looked as f32 / n, left as f32 / n)
    }

    /// A collider past the first 1,024 (the second occupancy word) is found by the
    /// grid and by the test of every one alike.
    #[test]
    fn the_last_of_a_full_buffer_is_found() {
        let mut colliders: Vec<_> = (0..MAX_COLLIDERS)
            .map(|i| Collider::sphere(Vec3::new(100.0 + i as f32, 0.0, 0.0), 0.3))
            .collect();
        colliders[MAX_COLLIDERS - 1] = Collider::sphere(Vec3::new(0.1, 2.0, 0.0), 0.3);
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0);
        for count in [MAX_COLLIDERS, MAX_COLLIDERS - 1] {
            let used = &colliders[..count];
            for set in [
                ColliderSet::new(used, fitted(used, 2.5, 64)),
                ColliderSet::every(used),
            ] {
                let n = set.nearby();
                let slot = n.around(b.root(), b.height(), count as u32);
                let found = (n.colliders, n.words);
                let (_, pushed) = collide_near(&b, found, &slot, count as u32);
                let expected = if count == MAX_COLLIDERS { -0.2 } else { 0.0 };
                assert!(
                    (pushed - Vec3::new(expected, 0.0, 0.0)).length() < 1e-5,
                    "{pushed}"
                );
            }
        }
    }

    #[test]
    fn every_collider_tested_when_the_count_is_not_a_whole_word() {
        // The first 32 far away, the next five on the tip.
        let spheres: Vec<_> = (0..37)
            .map(|i| {
                let x = if i < 32 {
                    100.0
                } else {
                    (i - 32) as f32 * 0.01
                };
                Collider::sphere(Vec3::new(x, 2.0, 0.0), 0.3)
            })
            .collect();
        let set = ColliderSet::every(&spheres);
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0);
        let n = set.nearby();
        // 37 colliders: the 33rd to 37th of the second word are pushed out of too.
        let pushed = |count| {
            let slot = n.around(b.root(), b.height(), count);
            collide_near(&b, (n.colliders, n.words), &slot, count).1
        };
        assert_eq!(pushed(32), Vec3::ZERO);
        assert!(pushed(37).length() > 0.1, "{}", pushed(37));
        assert_eq!(pushed(0), Vec3::ZERO);
    }
}

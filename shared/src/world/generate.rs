//! Blade generation on a square ground, reproducible from a seed (host only).

use crate::Blade;
use spirv_std::glam::Vec3;

/// The ranges heights, widths and stiffnesses are drawn in (course defaults), shared
/// with the tiles' generation on the GPU.
pub use crate::blade::{HEIGHT, STIFFNESS, WIDTH};
/// Blades per square unit of the course scene (2^13 blades on 15 × 15).
pub const DENSITY: f32 = 8192.0 / 225.0;

/// SplitMix64: a tiny generator whose sequence never changes with a dependency's
/// version, so a seed names the same field forever.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let unit = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * unit
    }
}

/// Side of the square ground that holds `count` blades at the course density.
pub fn side_for(count: u32) -> f32 {
    (count as f32 / DENSITY).sqrt().max(2.0)
}

/// `count` blades at rest on the square of side `side` centred on the origin in the
/// XZ plane (up = +Y), with random orientation, height, width and stiffness.
pub fn square_field(count: u32, side: f32, seed: u64) -> Vec<Blade> {
    let mut rng = SplitMix64::new(seed);
    let half = 0.5 * side;
    (0..count)
        .map(|_| {
            let root = Vec3::new(rng.range(-half, half), 0.0, rng.range(-half, half));
            let orientation = rng.range(0.0, core::f32::consts::TAU);
            let height = rng.range(HEIGHT.0, HEIGHT.1);
            let width = rng.range(WIDTH.0, WIDTH.1);
            let stiffness = rng.range(STIFFNESS.0, STIFFNESS.1);
            Blade::at_rest(root, Vec3::Y, orientation, height, width, stiffness)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_field_and_ranges_hold() {
        let a = square_field(500, 10.0, 7);
        assert_eq!(a, square_field(500, 10.0, 7));
        assert_ne!(a, square_field(500, 10.0, 8));
        for b in &a {
            assert!(b.root().x.abs() <= 5.0 && b.root().z.abs() <= 5.0 && b.root().y == 0.0);
            assert!((HEIGHT.0..HEIGHT.1).contains(&b.height()));
            assert!((WIDTH.0..WIDTH.1).contains(&b.width()));
            assert!((STIFFNESS.0..STIFFNESS.1).contains(&b.stiffness()));
        }
    }
}

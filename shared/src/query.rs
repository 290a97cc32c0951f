//! Questions a game asks of the grass: how tall, dense and bent it is around a point,
//! and how much of a ray through it the blades hide (concealment, for stealth).
//!
//! Each blade's part in an answer is a function of the blade alone
//! ([`point_part`], [`ray_part`]) in fixed-point units ([`HEIGHT_UNITS`],
//! [`BEND_UNITS`], [`COVER_UNITS`]), so a sum over any set of blades, on the host or
//! by atomic adds on the GPU, is the same whole numbers in any order; [`Tally`]
//! holds the sums and turns them into an answer.

use crate::Blade;
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Fixed-point units of a height (world units) in a [`Tally`]: 1/256.
pub const HEIGHT_UNITS: f32 = 256.0;
/// Fixed-point units of a bend (0 standing to 1 flat) in a [`Tally`]: 1/1024.
pub const BEND_UNITS: f32 = 1024.0;
/// Fixed-point units of a blade's cover of a ray in a [`Tally`]: 1/4096.
pub const COVER_UNITS: f32 = 4096.0;

/// The grass around a point: the blades rooted within `radius` of `centre`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Around {
    /// The point asked about (on or near the ground).
    pub centre: Vec3,
    /// How far from it a blade's root counts, world units.
    pub radius: f32,
}

/// A ray through the grass, from an eye to a target: what the blades near it hide.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Sight {
    /// The eye.
    pub from: Vec3,
    /// The target.
    pub to: Vec3,
    /// The ray's radius: a blade crossing within it covers its share of the ray's
    /// width (its own width over twice the radius).
    pub radius: f32,
}

/// The sums of the blades' parts in one answer, in whole fixed-point units.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Blades counted.
    pub blades: u32,
    /// Their standing heights, in 1/[`HEIGHT_UNITS`].
    pub height: u32,
    /// Their bends, in 1/[`BEND_UNITS`].
    pub bend: u32,
    /// Their cover of a ray, in 1/[`COVER_UNITS`].
    pub cover: u32,
}

/// A blade's standing height: its tip's height over its root along its up
/// direction, never below 0.
pub fn standing_height(blade: &Blade) -> f32 {
    blade.up_dir().dot(blade.tip() - blade.root()).max(0.0)
}

/// A blade's bend: 0 standing straight, 1 flat on the ground (1 − standing height
/// over its height).
pub fn bend(blade: &Blade) -> f32 {
    (1.0 - standing_height(blade) / blade.height().max(1e-6)).clamp(0.0, 1.0)
}

/// `blade`'s part in the answer about `around`: counted, with its standing height and
/// its bend, where its root is within the radius; else nothing.
pub fn point_part(blade: &Blade, around: &Around) -> Tally {
    let within = (blade.root() - around.centre).length_squared() <= around.radius * around.radius;
    if !within || blade.width() <= 0.0 {
        return Tally::default();
    }
    Tally {
        blades: 1,
        height: fixed(standing_height(blade), HEIGHT_UNITS),
        bend: fixed(bend(blade), BEND_UNITS),
        cover: 0,
    }
}

/// `blade`'s part in what `sight` sees: where the point of the ray nearest the
/// blade's root is within the ray's radius of the blade's axis (measured across its
/// up direction) and between its root and its standing height, the blade covers its
/// width over the ray's width (2·radius), up to all of it; else nothing.
pub fn ray_part(blade: &Blade, sight: &Sight) -> Tally {
    let (root, up) = (blade.root(), blade.up_dir());
    let along = sight.to - sight.from;
    let t = ((root - sight.from).dot(along) / along.length_squared().max(1e-12)).clamp(0.0, 1.0);
    let p = sight.from + along * t;
    let rise = up.dot(p - root);
    let across = (p - root) - up * rise;
    let crosses = across.length_squared() <= sight.radius * sight.radius
        && rise >= 0.0
        && rise <= standing_height(blade);
    if !crosses || blade.width() <= 0.0 {
        return Tally::default();
    }
    let share = (blade.width() / (2.0 * sight.radius.max(1e-6))).min(1.0);
    Tally {
        blades: 1,
        cover: fixed(share, COVER_UNITS),
        ..Tally::default()
    }
}

/// `value` in whole units of 1/`units`, rounded to the nearest.
fn fixed(value: f32, units: f32) -> u32 {
    (value * units + 0.5) as u32
}

impl core::ops::Add for Tally {
    type Output = Tally;

    /// The sum of two tallies.
    fn add(self, other: Tally) -> Tally {
        Tally {
            blades: self.blades + other.blades,
            height: self.height + other.height,
            bend: self.bend + other.bend,
            cover: self.cover + other.cover,
        }
    }
}

impl Tally {
    /// Blades per square unit within `radius` (the blades over the disc's area).
    pub fn density(&self, radius: f32) -> f32 {
        self.blades as f32 / (core::f32::consts::PI * radius * radius).max(1e-12)
    }

    /// The mean standing height of the blades counted (0 where none).
    pub fn mean_height(&self) -> f32 {
        self.height as f32 / HEIGHT_UNITS / self.blades.max(1) as f32
    }

    /// The mean bend of the blades counted (0 where none).
    pub fn mean_bend(&self) -> f32 {
        self.bend as f32 / BEND_UNITS / self.blades.max(1) as f32
    }

    /// How much of the ray the blades hide, 0 to 1: 1 − exp(−Σ cover), the
    /// Beer–Lambert transmittance of blades that each block their share of the ray's
    /// width, placed at random along it.
    pub fn concealment(&self) -> f32 {
        1.0 - (-(self.cover as f32 / COVER_UNITS)).exp()
    }
}

/// The answer about `around` over `blades` (the host's, from the same parts the GPU
/// adds).
#[cfg(not(target_arch = "spirv"))]
pub fn tally_around(blades: &[Blade], around: &Around) -> Tally {
    blades
        .iter()
        .fold(Tally::default(), |t, b| t + point_part(b, around))
}

/// What `sight` sees over `blades` (the host's, from the same parts the GPU adds).
#[cfg(not(target_arch = "spirv"))]
pub fn tally_sight(blades: &[Blade], sight: &Sight) -> Tally {
    blades
        .iter()
        .fold(Tally::default(), |t, b| t + ray_part(b, sight))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A blade standing at (x, 0, z), `height` tall, 0.1 wide.
    fn standing(x: f32, z: f32, height: f32) -> Blade {
        Blade::at_rest(Vec3::new(x, 0.0, z), Vec3::Y, 0.0, height, 0.1, 5.0)
    }

    #[test]
    fn around_a_point_the_count_height_and_bend_are_the_blades() {
        // A lattice of blades 0.5 apart, 2 tall: a radius of 1.01 holds the 13 of
        // the lattice points within 1 of the centre (1 + 4 + 4 + 4).
        let blades: Vec<Blade> = (-4..=4)
            .flat_map(|i| (-4..=4).map(move |j| standing(0.5 * i as f32, 0.5 * j as f32, 2.0)))
            .collect();
        let around = Around {
            centre: Vec3::ZERO,
            radius: 1.01,
        };
        let t = tally_around(&blades, &around);
        assert_eq!(t.blades, 13);
        assert!((t.mean_height() - 2.0).abs() < 1e-3, "{}", t.mean_height());
        assert!(t.mean_bend() < 1e-3);
        assert!((t.density(1.01) - 13.0 / (core::f32::consts::PI * 1.0201)).abs() < 1e-4);
        // One blade laid over to a quarter of its height: bend 0.75.
        let b = standing(0.0, 0.0, 2.0);
        let flat = b.with_curve(Vec3::new(0.5, 0.5, 0.0), Vec3::new(1.9, 0.5, 0.0));
        let p = point_part(&flat, &around);
        assert_eq!(p.height, 128);
        assert_eq!(p.bend, 768);
        // Nothing around a point away from the lattice.
        let far = Around {
            centre: Vec3::new(10.0, 0.0, 0.0),
            radius: 1.0,
        };
        assert_eq!(tally_around(&blades, &far), Tally::default());
    }

    #[test]
    fn a_ray_through_a_row_of_blades_is_hidden_by_their_widths() {
        // Ten blades 2 tall in a row across the ray's path at x = 3, 0.05 apart;
        // the ray runs along x at height 1 with radius 0.25: each blade covers
        // 0.1 / 0.5 = 0.2 of its width, so Σ = 2 and the ray is 1 − e⁻² hidden.
        let row: Vec<Blade> = (0..10)
            .map(|i| standing(3.0, -0.225 + 0.05 * i as f32, 2.0))
            .collect();
        let sight = Sight {
            from: Vec3::new(0.0, 1.0, 0.0),
            to: Vec3::new(6.0, 1.0, 0.0),
            radius: 0.25,
        };
        let t = tally_sight(&row, &sight);
        assert_eq!((t.blades, t.cover), (10, 10 * 819));
        let expected = 1.0 - (-2.0f32).exp();
        assert!(
            (t.concealment() - expected).abs() < 1e-3,
            "{}",
            t.concealment()
        );
        // Over the blades' tops, or stopping short of them: nothing hidden.
        let over = Sight {
            from: Vec3::new(0.0, 2.5, 0.0),
            to: Vec3::new(6.0, 2.5, 0.0),
            ..sight
        };
        assert_eq!(tally_sight(&row, &over).concealment(), 0.0);
        let short = Sight {
            to: Vec3::new(2.0, 1.0, 0.0),
            ..sight
        };
        assert_eq!(tally_sight(&row, &short).blades, 0);
        // Bent down to half their height, they no longer reach a ray at 1.2.
        let bent: Vec<Blade> = row
            .iter()
            .map(|b| {
                b.with_curve(
                    b.root() + Vec3::new(0.5, 0.5, 0.0),
                    b.root() + Vec3::new(1.7, 1.0, 0.0),
                )
            })
            .collect();
        let higher = Sight {
            from: Vec3::new(0.0, 1.2, 0.0),
            to: Vec3::new(6.0, 1.2, 0.0),
            ..sight
        };
        assert_eq!(tally_sight(&row, &higher).blades, 10);
        assert_eq!(tally_sight(&bent, &higher).blades, 0);
    }

    #[test]
    fn the_sums_are_the_same_in_any_order() {
        let blades = crate::world::generate::square_field(2000, 8.0, 4);
        let around = Around {
            centre: Vec3::new(0.5, 0.0, -0.3),
            radius: 2.0,
        };
        let forward = tally_around(&blades, &around);
        let mut reversed = blades.clone();
        reversed.reverse();
        assert_eq!(forward, tally_around(&reversed, &around));
        assert!(forward.blades > 300, "{forward:?}");
    }
}

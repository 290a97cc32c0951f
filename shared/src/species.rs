//! Species: what grows in a field besides the paper's one grass. A species changes a
//! blade's height, stiffness, outline and colour; the simulation, the culling, the
//! levels of detail, the compute rasterizer and the shadows see it through those, so
//! each species is the same blade model with other numbers (the Bezier curve and its
//! forces, paper sections 3 to 5), and its outline is a shape function τ(u, v) of the
//! paper's section 6.2 (`draw::shape`).
//!
//! | species | height | stiffness | outline | colour |
//! |---|---|---|---|---|
//! | [`GRASS`] | 1 | 1 | the field's shape | the grass palette |
//! | [`DANDELION`] | 1 | 1 | the paper's fifth shape, 3 widths | the grass palette |
//! | [`FLOWER`] | 1.2 | 1.5 | a stem, a head 3 widths across | stem green, head [`FLOWER_HEAD`] |
//! | [`SEED_GRASS`] | 1.5 | 0.75 | a stalk, a spindle of seeds 0.8 widths across | stalk green, head [`SEED_HEAD`] |
//!
//! A blade's species is carried in its orientation θ: species `k` adds `k` times
//! [`TURNS`] (whole turns, so the angle's sine and cosine, all the rest of the model
//! sees, stay the same; the blade has no other word to spare). Fields get species
//! from a type map (`world::paint::TYPE`) or by weights ([`Mix`]).

use crate::Blade;
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// The paper's grass, drawn in the field's shape.
pub const GRASS: u32 = 0;
/// A dandelion leaf (the paper's fifth shape).
pub const DANDELION: u32 = 1;
/// A flower: a thin stem with a coloured head.
pub const FLOWER: u32 = 2;
/// A tall seed grass: a stalk with a spindle-shaped seed head.
pub const SEED_GRASS: u32 = 3;
/// Species there are.
pub const COUNT: u32 = 4;

/// The angle that marks one step of species: two whole turns.
pub const TURNS: f32 = 2.0 * core::f32::consts::TAU;

/// The species of `blade` from its orientation ([`TURNS`] per species; an angle
/// below zero or beyond the last reads as the nearest species).
pub fn of(blade: &Blade) -> u32 {
    of_orientation(blade.orientation())
}

/// The species an orientation θ marks ([`of`]).
pub fn of_orientation(orientation: f32) -> u32 {
    // Grass, the common case, with one comparison (every vertex of every blade asks).
    if orientation < TURNS {
        return GRASS;
    }
    // Clamped before the cast: a negative float to an unsigned integer is undefined
    // on the GPU. A product, not a quotient: a division is a dozen instructions there.
    (orientation * (1.0 / TURNS))
        .floor()
        .clamp(0.0, (COUNT - 1) as f32) as u32
}

/// Orientation θ (0 to 2π) marked as species `species`.
pub fn mark(orientation: f32, species: u32) -> f32 {
    orientation + species as f32 * TURNS
}

/// Factor on a blade's height.
pub fn height_factor(species: u32) -> f32 {
    if species == FLOWER {
        1.2
    } else if species == SEED_GRASS {
        1.5
    } else {
        1.0
    }
}

/// The tallest [`height_factor`] of all species.
pub const TALLEST: f32 = 1.5;

/// Factor on a blade's stiffness: a flower's stem stands stiffer than a blade of grass,
/// a tall seed grass bends more easily.
pub fn stiffness_factor(species: u32) -> f32 {
    if species == FLOWER {
        1.5
    } else if species == SEED_GRASS {
        0.75
    } else {
        1.0
    }
}

/// A blade grown as `species`: the same blade with the species' mark on its
/// orientation and its height and stiffness times the species' factors. A blade
/// marked already keeps its own species.
pub fn grown_as(blade: &Blade, species: u32) -> Blade {
    if of(blade) != GRASS || species == GRASS {
        return *blade;
    }
    Blade::at_rest(
        blade.root(),
        blade.up_dir(),
        mark(blade.orientation(), species),
        blade.height() * height_factor(species),
        blade.width(),
        blade.stiffness() * stiffness_factor(species),
    )
}

/// Where a flower's head starts along its blade (v).
pub const FLOWER_HEAD_FROM: f32 = 0.75;
/// Where a seed grass's head starts along its blade (v).
pub const SEED_HEAD_FROM: f32 = 0.5;

/// The share of a flower's strip (of its rows, [`row_v`]) that lies in its head: 5
/// of its 9 segments.
pub const FLOWER_HEAD_ROWS: f32 = 5.0 / 9.0;

/// Where along the blade (v) the row at `t` of a strip or a tessellated patch (0 at
/// the root, 1 at the tip; rows evenly spaced in `t`) lies for `species`. A flower's
/// rows crowd into its head ([`FLOWER_HEAD_ROWS`] of them past
/// [`FLOWER_HEAD_FROM`]), so its round outline is drawn with six rows rather than
/// three; the thin stem below takes the rest. Piecewise linear, so the strip still
/// morphs continuously across its levels; any other species' rows lie at `t`.
pub fn row_v(species: u32, t: f32) -> f32 {
    if species != FLOWER {
        t
    } else if t < 1.0 - FLOWER_HEAD_ROWS {
        t * (FLOWER_HEAD_FROM / (1.0 - FLOWER_HEAD_ROWS))
    } else {
        FLOWER_HEAD_FROM
            + (t - (1.0 - FLOWER_HEAD_ROWS)) * ((1.0 - FLOWER_HEAD_FROM) / FLOWER_HEAD_ROWS)
    }
}

/// Where the head of `species` starts along the blade (v); past the tip for a species
/// with none.
pub fn head_from(species: u32) -> f32 {
    if species == FLOWER {
        FLOWER_HEAD_FROM
    } else if species == SEED_GRASS {
        SEED_HEAD_FROM
    } else {
        2.0
    }
}

/// A flower head's colour (linear albedo): a buttercup yellow.
pub const FLOWER_HEAD: Vec3 = Vec3::new(0.75, 0.45, 0.02);
/// A seed head's colour (linear albedo): ripening seeds, a dull straw.
pub const SEED_HEAD: Vec3 = Vec3::new(0.20, 0.16, 0.07);

/// The albedo at height `v` of a blade of `species` whose own colour there is
/// `blade` (the look's gradient or palette): its head's colour past [`head_from`],
/// scaled by `value` (the blade's brightness against its look's mean, so heads vary
/// as the blades do).
pub fn albedo(species: u32, blade: Vec3, v: f32, value: f32) -> Vec3 {
    if v < head_from(species) {
        blade
    } else if species == FLOWER {
        FLOWER_HEAD * value
    } else {
        SEED_HEAD * value
    }
}

/// A height v along a blade of `species` as one varying: v + 4·species. A triangle's
/// vertices share their blade's species, so the interpolated varying is the
/// interpolated v plus the same offset; [`untag_v`] reads both back, also from a
/// sample a little outside the triangle.
pub fn tag_v(v: f32, species: u32) -> f32 {
    v + 4.0 * species as f32
}

/// The (v, species) of [`tag_v`].
pub fn untag_v(tagged: f32) -> (f32, u32) {
    let species = ((tagged - 0.5) * 0.25)
        .round()
        .clamp(0.0, (COUNT - 1) as f32);
    (tagged - 4.0 * species, species as u32)
}

/// How a field mixes its species where no type map picks one: a weight 0 to 255 per
/// species in one word (species `k` in byte `k`), the GPU's form of the setting.
/// All zero is all grass.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Mix {
    /// Weight of species `k` in byte `k`.
    pub weights: u32,
}

impl Mix {
    /// Grass only.
    pub const GRASS: Mix = Mix { weights: 0 };

    /// The mix of weights (grass, dandelion, flower, seed grass), each 0 to 255;
    /// grass alone, at any weight, is the one grass-only mix ([`Mix::GRASS`]).
    pub fn new(weights: [u8; COUNT as usize]) -> Self {
        if weights[1] == 0 && weights[2] == 0 && weights[3] == 0 {
            return Self::GRASS;
        }
        Self {
            weights: u32::from_le_bytes(weights),
        }
    }

    /// Weight of `species`, 0 to 255.
    pub fn weight(&self, species: u32) -> u32 {
        (self.weights >> (8 * species)) & 0xff
    }

    /// The species a blade whose uniform draw is `unit` (0..1) grows as: each with the
    /// share its weight has of the sum; grass where every weight is zero.
    pub fn pick(&self, unit: f32) -> u32 {
        let total = self.weight(0) + self.weight(1) + self.weight(2) + self.weight(3);
        if total == 0 {
            return GRASS;
        }
        let mut at = unit * total as f32;
        let mut species = 0;
        while species < COUNT - 1 {
            let w = self.weight(species) as f32;
            if at < w {
                return species;
            }
            at -= w;
            species += 1;
        }
        COUNT - 1
    }

    /// The tallest height factor of the species this mix grows.
    pub fn tallest(&self) -> f32 {
        let mut tallest: f32 = 1.0;
        let mut species = 0;
        while species < COUNT {
            if self.weight(species) > 0 {
                tallest = tallest.max(height_factor(species));
            }
            species += 1;
        }
        tallest
    }
}

/// The species' names on the command line and in settings files, by species.
pub const NAMES: [&str; COUNT as usize] = ["grass", "dandelion", "flower", "seed-grass"];

#[cfg(not(target_arch = "spirv"))]
impl core::str::FromStr for Mix {
    type Err = String;

    /// Weights by name, "grass=6,flower=1,seed-grass=1" ([`NAMES`], each 0 to 255,
    /// each at most once, one above 0).
    fn from_str(s: &str) -> Result<Self, String> {
        let mut weights = [0u8; COUNT as usize];
        let mut named = [false; COUNT as usize];
        for part in s.split(',') {
            let (name, weight) = part.split_once('=').ok_or_else(|| {
                format!("{part:?} is not name=weight (names: {})", NAMES.join(", "))
            })?;
            let k = NAMES
                .iter()
                .position(|n| *n == name.trim())
                .ok_or_else(|| format!("{name:?} is not a species ({})", NAMES.join(", ")))?;
            if named[k] {
                return Err(format!("{name:?} is named twice"));
            }
            named[k] = true;
            weights[k] = weight
                .trim()
                .parse()
                .map_err(|_| format!("{weight:?} is not a weight from 0 to 255"))?;
        }
        if weights.iter().all(|&w| w == 0) {
            return Err(format!("{s:?} gives every species a weight of 0"));
        }
        Ok(Mix::new(weights))
    }
}

#[cfg(not(target_arch = "spirv"))]
impl core::fmt::Display for Mix {
    /// The weights above 0 by name, as [`Mix::from_str`](core::str::FromStr) reads
    /// them; "grass=1" for grass only.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.weights == 0 {
            return write!(f, "grass=1");
        }
        let parts: Vec<String> = (0..COUNT)
            .filter(|&k| self.weight(k) > 0)
            .map(|k| format!("{}={}", NAMES[k as usize], self.weight(k)))
            .collect();
        write!(f, "{}", parts.join(","))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mark_carries_the_species_and_leaves_the_angle() {
        let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 1.0, 2.0, 0.1, 10.0);
        for species in 0..COUNT {
            let grown = grown_as(&blade, species);
            assert_eq!(of(&grown), species);
            assert!((grown.width_dir() - blade.width_dir()).length() < 1e-5);
            assert_eq!(grown.height(), 2.0 * height_factor(species));
            assert_eq!(grown.stiffness(), 10.0 * stiffness_factor(species));
            // Grown again, a species other than grass stays what it became.
            if species != GRASS {
                assert_eq!(grown_as(&grown, FLOWER), grown);
            }
        }
        assert_eq!(of_orientation(-1.0), GRASS);
        assert_eq!(of_orientation(100.0), SEED_GRASS);
        assert_eq!(of_orientation(core::f32::consts::TAU - 1e-4), GRASS);
        let tallest = (0..COUNT).map(height_factor).fold(0.0, f32::max);
        assert_eq!(TALLEST, tallest);
    }

    #[test]
    fn a_tagged_v_reads_back_also_a_little_outside() {
        for species in 0..COUNT {
            for v in [-0.2f32, 0.0, 0.3, 1.0, 1.2] {
                let (back, s) = untag_v(tag_v(v, species));
                assert_eq!(s, species);
                assert!((back - v).abs() < 1e-5, "{v} {back}");
            }
        }
    }

    #[test]
    fn a_mix_grows_each_species_by_its_share() {
        let mix = Mix::new([100, 0, 60, 40]);
        let n = 10_000;
        let mut counts = [0u32; COUNT as usize];
        for i in 0..n {
            counts[mix.pick((i as f32 + 0.5) / n as f32) as usize] += 1;
        }
        assert_eq!(counts, [5000, 0, 3000, 2000]);
        assert_eq!(Mix::GRASS.pick(0.7), GRASS);
        assert_eq!(Mix::new([0, 0, 0, 1]).pick(0.0), SEED_GRASS);
        assert_eq!(Mix::GRASS.tallest(), 1.0);
        assert_eq!(mix.tallest(), 1.5);
        assert_eq!(Mix::new([1, 0, 1, 0]).tallest(), 1.2);
    }

    #[test]
    fn a_mix_reads_back_what_it_writes_and_refuses_the_rest() {
        let mix: Mix = "grass=6, flower=1,seed-grass=2".parse().unwrap();
        assert_eq!(mix, Mix::new([6, 0, 1, 2]));
        assert_eq!(mix.to_string().parse::<Mix>().unwrap(), mix);
        assert_eq!(
            Mix::GRASS.to_string().parse::<Mix>().unwrap().pick(0.9),
            GRASS
        );
        for bad in [
            "grass",
            "grass=256",
            "moss=1",
            "grass=0",
            "grass=1,grass=2",
            "",
            "nan",
        ] {
            assert!(bad.parse::<Mix>().is_err(), "{bad}");
        }
    }

    #[test]
    fn heads_take_their_colour_past_their_start() {
        let green = Vec3::new(0.1, 0.3, 0.05);
        assert_eq!(albedo(GRASS, green, 1.0, 1.0), green);
        assert_eq!(albedo(FLOWER, green, 0.7, 1.0), green);
        assert_eq!(albedo(FLOWER, green, 0.9, 1.0), FLOWER_HEAD);
        assert_eq!(albedo(SEED_GRASS, green, 0.6, 0.5), SEED_HEAD * 0.5);
    }

    /// A flower's rows: from the root to the tip, rising, continuous where the stem
    /// meets the head, and five of nine segments in the head; any other species' rows
    /// where they were.
    #[test]
    fn a_flowers_rows_crowd_into_its_head() {
        for species in [GRASS, DANDELION, SEED_GRASS] {
            assert_eq!(row_v(species, 0.3), 0.3);
        }
        assert_eq!(row_v(FLOWER, 0.0), 0.0);
        assert!((row_v(FLOWER, 1.0) - 1.0).abs() < 1e-6);
        let knee = 1.0 - FLOWER_HEAD_ROWS;
        assert!((row_v(FLOWER, knee - 1e-6) - row_v(FLOWER, knee)).abs() < 1e-4);
        assert!((row_v(FLOWER, knee) - FLOWER_HEAD_FROM).abs() < 1e-6);
        let rows: Vec<f32> = (0..=9).map(|k| row_v(FLOWER, k as f32 / 9.0)).collect();
        assert!(rows.windows(2).all(|w| w[1] > w[0]), "{rows:?}");
        let head = rows
            .iter()
            .filter(|&&v| v > FLOWER_HEAD_FROM + 1e-6)
            .count();
        assert_eq!(head, 5, "{rows:?}");
    }
}

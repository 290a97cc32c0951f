//! Questions a game asks of the grass: how tall, dense and bent it is around a point,
//! and how much of a ray through it the blades hide (concealment, for stealth).
//!
//! Each blade's part in an answer is a function of the blade alone
//! ([`point_part`], [`ray_part`]) in fixed-point units ([`HEIGHT_UNITS`],
//! [`BEND_UNITS`], [`COVER_UNITS`]), so a sum over any set of blades, on the host or
//! by atomic adds on the GPU, is the same whole numbers in any order; [`Tally`]
//! holds the sums and turns them into an answer.
//!
//! On the GPU a frame asks up to [`MAX_QUESTIONS`] [`Question`]s through the query
//! buffer (`gpu::layout::BINDING_QUERIES`, laid out by [`ASKED`], [`CONTACTS`],
//! [`ANSWERS`] and [`QUESTIONS`]); after the collision pass, each collider touching
//! one of its blades (`sim::grid::Nearby::first_touching`) is marked there too, which the
//! host turns into events as a collider enters or leaves the grass.

use crate::Blade;
use crate::sim::collide::MAX_COLLIDERS;
use spirv_std::glam::{Vec3, Vec4, Vec4Swizzles};
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

/// Most questions one frame answers on the GPU.
pub const MAX_QUESTIONS: usize = 16;
/// [`Question`] kind: the grass [`Around`] a point.
pub const ASK_AROUND: u32 = 0;
/// [`Question`] kind: what the blades hide of a [`Sight`].
pub const ASK_SIGHT: u32 = 1;

/// One question as the query buffer holds it: an [`Around`] (centre `a.xyz`, radius
/// `a.w`) or a [`Sight`] (from `a.xyz`, radius `a.w`, to `b.xyz`), its kind in
/// `b.w` ([`ASK_AROUND`], [`ASK_SIGHT`]).
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Question {
    /// The centre or the eye, and the radius.
    pub a: Vec4,
    /// The target (a sight's), and the kind.
    pub b: Vec4,
}

impl Question {
    /// The question about the grass around a point.
    pub fn around(around: Around) -> Self {
        Self {
            a: around.centre.extend(around.radius),
            b: Vec4::new(0.0, 0.0, 0.0, ASK_AROUND as f32),
        }
    }

    /// The question about what the blades hide of a sight.
    pub fn sight(sight: Sight) -> Self {
        Self {
            a: sight.from.extend(sight.radius),
            b: sight.to.extend(ASK_SIGHT as f32),
        }
    }

    /// Whether it asks about a sight (else about a point).
    pub fn is_sight(&self) -> bool {
        self.b.w == ASK_SIGHT as f32
    }

    /// `blade`'s part in its answer ([`point_part`] or [`ray_part`]).
    pub fn part(&self, blade: &Blade) -> Tally {
        if self.is_sight() {
            let sight = Sight {
                from: self.a.xyz(),
                to: self.b.xyz(),
                radius: self.a.w,
            };
            ray_part(blade, &sight)
        } else {
            let around = Around {
                centre: self.a.xyz(),
                radius: self.a.w,
            };
            point_part(blade, &around)
        }
    }

    /// Question `q` of the query buffer's `words`.
    pub fn read(words: &[u32], q: usize) -> Self {
        let at = QUESTIONS + QUESTION_WORDS * q;
        let f = |k: usize| f32::from_bits(words[at + k]);
        Self {
            a: Vec4::new(f(0), f(1), f(2), f(3)),
            b: Vec4::new(f(4), f(5), f(6), f(7)),
        }
    }

    /// The answer over `blades` (the host's, from the same parts the GPU adds).
    #[cfg(not(target_arch = "spirv"))]
    pub fn tally(&self, blades: &[Blade]) -> Tally {
        blades
            .iter()
            .fold(Tally::default(), |t, b| t + self.part(b))
    }
}

/// Words of a [`Question`] in the query buffer.
pub const QUESTION_WORDS: usize = 8;
/// Words of a [`Tally`] in the query buffer.
pub const TALLY_WORDS: usize = 4;
/// Query buffer word: how many of its questions the frame asks (at most
/// [`MAX_QUESTIONS`]).
pub const ASKED: usize = 0;
/// First query buffer word of the colliders touching blades this frame, one bit a
/// collider (bit `i % 32` of word `CONTACTS + i / 32`), set by the collision pass.
pub const CONTACTS: usize = 4;
/// Words of the contact bits.
pub const CONTACT_WORDS: usize = MAX_COLLIDERS / 32;
/// First query buffer word of the answers, a [`Tally`] a question (blades, height,
/// bend, cover), added to by the query pass.
pub const ANSWERS: usize = CONTACTS + CONTACT_WORDS;
/// First query buffer word of the questions, [`QUESTION_WORDS`] each.
pub const QUESTIONS: usize = ANSWERS + TALLY_WORDS * MAX_QUESTIONS;
/// Words of the query buffer: what the host uploads at a frame's start (the asked
/// count and the questions, the contacts and the answers cleared) and reads back.
pub const QUERY_WORDS: usize = QUESTIONS + QUESTION_WORDS * MAX_QUESTIONS;

/// The query buffer a frame starts with: `questions` (at most [`MAX_QUESTIONS`]
/// taken), no contacts and empty answers.
#[cfg(not(target_arch = "spirv"))]
pub fn query_words(questions: &[Question]) -> Vec<u32> {
    let asked = questions.len().min(MAX_QUESTIONS);
    let mut words = vec![0; QUERY_WORDS];
    words[ASKED] = asked as u32;
    let bytes: &[u32] = bytemuck::cast_slice(&questions[..asked]);
    words[QUESTIONS..QUESTIONS + bytes.len()].copy_from_slice(bytes);
    words
}

/// The query buffer's first word of question `q`'s answer (a [`Tally`]'s four words:
/// blades, height, bend, cover).
pub fn answer_at(q: usize) -> usize {
    ANSWERS + TALLY_WORDS * q
}

/// Where collider `i`'s contact bit is: (query buffer word, bit mask).
pub fn contact_bit(i: u32) -> (usize, u32) {
    (CONTACTS + (i / 32) as usize, 1 << (i % 32))
}

impl Tally {
    /// Calls `add(word, value)` for each of its sums with the query buffer word it
    /// goes to, as question `q`'s answer ([`Tally::read`]'s order).
    pub fn add_to(&self, q: usize, mut add: impl FnMut(usize, u32)) {
        let at = answer_at(q);
        add(at, self.blades);
        add(at + 1, self.height);
        add(at + 2, self.bend);
        add(at + 3, self.cover);
    }

    /// The answer to question `q` in the query buffer's `words`.
    pub fn read(words: &[u32], q: usize) -> Self {
        let at = answer_at(q);
        Self {
            blades: words[at],
            height: words[at + 1],
            bend: words[at + 2],
            cover: words[at + 3],
        }
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
    fn questions_go_through_the_query_buffer_unchanged() {
        let around = Around {
            centre: Vec3::new(1.0, 0.5, -2.0),
            radius: 1.5,
        };
        let sight = Sight {
            from: Vec3::new(0.0, 1.0, 0.0),
            to: Vec3::new(6.0, 1.0, 0.0),
            radius: 0.25,
        };
        let asked = [Question::around(around), Question::sight(sight)];
        let words = query_words(&asked);
        assert_eq!(words[ASKED], 2);
        assert_eq!(Question::read(&words, 0), asked[0]);
        assert_eq!(Question::read(&words, 1), asked[1]);
        assert!(!asked[0].is_sight() && asked[1].is_sight());
        assert_eq!(Tally::read(&words, 1), Tally::default());
        let mut answered = words.clone();
        let t = Tally {
            blades: 3,
            height: 700,
            bend: 90,
            cover: 5,
        };
        t.add_to(1, |at, v| answered[at] += v);
        assert_eq!(Tally::read(&answered, 1), t);
        assert_eq!(Tally::read(&answered, 0), Tally::default());
        // The kinds answer as the host's tallies do.
        let blades = crate::world::generate::square_field(500, 4.0, 9);
        assert_eq!(asked[0].tally(&blades), tally_around(&blades, &around));
        assert_eq!(asked[1].tally(&blades), tally_sight(&blades, &sight));
        // More than the buffer holds: the first MAX_QUESTIONS asked.
        let many = vec![asked[0]; MAX_QUESTIONS + 3];
        assert_eq!(query_words(&many)[ASKED], MAX_QUESTIONS as u32);
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

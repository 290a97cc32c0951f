//! The blade surface of the tessellation evaluation stage (paper section 6.2): the
//! Bezier curve by De Casteljau, widened along t1 and cut by a shape function.

use crate::Blade;
use crate::species;
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// τ = u: a rectangle, full width to the tip.
pub const SHAPE_QUAD: u32 = 0;
/// τ = u + ½v − uv: a triangle closing at the tip.
pub const SHAPE_TRIANGLE: u32 = 1;
/// τ = u − uv²: a rounded, quadratic outline.
pub const SHAPE_QUADRATIC: u32 = 2;
/// τ = ½ + (u − ½)(1 − max(v − k, 0)/(1 − k)): full width up to k, then a triangle.
pub const SHAPE_TRIANGLE_TIP: u32 = 3;
/// τ = ½ + (u − ½)·(1 − v)·(0.25 + 0.75·(1 − fract(3v))): the paper's fifth shape, a
/// dandelion leaf narrowing to the tip with three lobes whose teeth point back to the
/// root. PAPER.md gives no formula for it; this one is ours (see [`shape_tau`]).
pub const SHAPE_DANDELION: u32 = 4;

/// A flower ([`species::FLOWER`]): a stem an eighth of the outline's width, and past
/// [`species::FLOWER_HEAD_FROM`] a head, the full width at its middle and closed at
/// the tip: τ = ½ + (u − ½)·max(stem, 1 − ((v − c)/r)²) with c and r the head's
/// middle and half its length along v.
pub const SHAPE_FLOWER: u32 = 5;
/// A seed grass ([`species::SEED_GRASS`]): a stalk a third of the outline's width,
/// and past [`species::SEED_HEAD_FROM`] a spindle of seeds, τ = ½ + (u − ½)·max(stalk,
/// 4t(1 − t)) with t running 0 to 1 over the head.
pub const SHAPE_SEED_HEAD: u32 = 6;

/// The middle of a flower's head along its blade (c of [`SHAPE_FLOWER`]).
const FLOWER_HEAD_MIDDLE: f32 = 0.5 * (1.0 + species::FLOWER_HEAD_FROM);
/// One over half the head's length (1/r of [`SHAPE_FLOWER`]).
const FLOWER_HEAD_PER_HALF: f32 = 2.0 / (1.0 - species::FLOWER_HEAD_FROM);
/// One over a seed head's length along its blade.
const SEED_HEAD_PER_LENGTH: f32 = 1.0 / (1.0 - species::SEED_HEAD_FROM);

/// The shape blade `blade` is drawn with when the field's is `shape`: grass is drawn in
/// the field's shape, every other species in its own ([`species::of`]).
pub fn blade_shape(blade: &Blade, shape: u32) -> u32 {
    species_shape(species::of(blade), shape)
}

/// The shape of `species` in a field whose shape is `shape`.
pub fn species_shape(species: u32, shape: u32) -> u32 {
    if species == species::GRASS {
        shape
    } else if species == species::DANDELION {
        SHAPE_DANDELION
    } else if species == species::FLOWER {
        SHAPE_FLOWER
    } else if species == species::SEED_GRASS {
        SHAPE_SEED_HEAD
    } else {
        shape
    }
}

/// Width of a flower's stem, a share of its outline's.
pub const FLOWER_STEM: f32 = 0.12;
/// Width of a seed grass's stalk, a share of its outline's.
pub const SEED_STALK: f32 = 0.35;

/// Lobes of the dandelion leaf.
pub const DANDELION_LOBES: f32 = 3.0;

/// How many times its blade's width a leaf of `shape` spans at its widest: a dandelion
/// leaf is far broader than a blade of grass (3 times), a flower's head 3 times, a seed
/// head 0.8 times, every other shape 1.
pub fn shape_width(shape: u32) -> f32 {
    // The field's shapes, the common case, with one comparison.
    if shape < SHAPE_DANDELION {
        1.0
    } else if shape == SHAPE_DANDELION || shape == SHAPE_FLOWER {
        3.0
    } else if shape == SHAPE_SEED_HEAD {
        0.8
    } else {
        1.0
    }
}

/// The shape function τ(u, v) for `shape` (one of the `SHAPE_*` constants);
/// `tip_start` is k of the triangle-tip shape.
pub fn shape_tau(shape: u32, u: f32, v: f32, tip_start: f32) -> f32 {
    if shape == SHAPE_TRIANGLE {
        u + 0.5 * v - u * v
    } else if shape == SHAPE_QUADRATIC {
        u - u * v * v
    } else if shape == SHAPE_TRIANGLE_TIP {
        let k = tip_start.min(0.999);
        0.5 + (u - 0.5) * (1.0 - (v - k).max(0.0) / (1.0 - k))
    } else if shape == SHAPE_DANDELION {
        // Each lobe is widest at its lower end and narrows upwards, so its tooth
        // points back towards the root (a runcinate leaf).
        let lobe = v * DANDELION_LOBES;
        let tooth = 1.0 - (lobe - lobe.floor());
        0.5 + (u - 0.5) * (1.0 - v) * (0.25 + 0.75 * tooth)
    } else if shape == SHAPE_FLOWER {
        // Products and sums only: a geometry stage may run every branch of this
        // function for every vertex, and a square root or a sine there costs every
        // blade, grass too.
        let d = (v - FLOWER_HEAD_MIDDLE) * FLOWER_HEAD_PER_HALF;
        let head = (1.0 - d * d).max(0.0);
        // The stem runs up to the head's middle; above it the head closes to the tip.
        let stem = if d < 0.0 { FLOWER_STEM } else { 0.0 };
        0.5 + (u - 0.5) * head.max(stem)
    } else if shape == SHAPE_SEED_HEAD {
        let t = ((v - species::SEED_HEAD_FROM) * SEED_HEAD_PER_LENGTH).max(0.0);
        let seeds = (4.0 * t * (1.0 - t)).max(0.0);
        let stalk = if t < 0.5 { SEED_STALK } else { 0.0 };
        0.5 + (u - 0.5) * seeds.max(stalk)
    } else {
        u
    }
}

/// A point of the blade surface: position and unit normal.
#[derive(Copy, Clone, Debug)]
pub struct SurfacePoint {
    /// World position.
    pub position: Vec3,
    /// Unit normal n = normalize(t0 × t1) (one of the two faces).
    pub normal: Vec3,
    /// The width direction t1.
    pub width_dir: Vec3,
}

/// The blade surface at (u across the width, v along the height), both in 0..1:
/// a = v0 + v(v1 − v0), b = v1 + v(v2 − v1), c = a + v(b − a); c0, c1 = c ∓ ½w·t1;
/// p = (1 − τ)·c0 + τ·c1; tangent t0 = normalize(b − a). `shape` is the field's; a
/// blade of another species is drawn in its own ([`blade_shape`]).
pub fn surface_point(blade: &Blade, u: f32, v: f32, shape: u32, tip_start: f32) -> SurfacePoint {
    shaped_point(blade, u, v, blade_shape(blade, shape), tip_start)
}

/// [`surface_point`] in the shape `shape`, whatever the blade's species.
pub fn shaped_point(blade: &Blade, u: f32, v: f32, shape: u32, tip_start: f32) -> SurfacePoint {
    let (v0, v1, v2) = (blade.root(), blade.guide(), blade.tip());
    let a = v0 + v * (v1 - v0);
    let b = v1 + v * (v2 - v1);
    let c = a + v * (b - a);
    let t1 = blade.width_dir();
    let half = 0.5 * shape_width(shape) * blade.width() * t1;
    let tau = shape_tau(shape, u, v, tip_start);
    let position = (1.0 - tau) * (c - half) + tau * (c + half);
    // An upright blade has v1 = v2, so b − a vanishes at the tip: fall back to up.
    let along = b - a;
    let t0 = if along.length_squared() > 1e-12 {
        along.normalize()
    } else {
        blade.up_dir()
    };
    SurfacePoint {
        position,
        normal: t0.cross(t1).normalize_or_zero(),
        width_dir: t1,
    }
}

/// The vertex of a strip or a tessellated patch at (u, `t`) on a blade of `species`
/// in a field that is `mixed` (`GrassParams::mixed`): its row's v along the blade
/// (`species::row_v`: a flower's rows crowd into its head), the surface point there
/// in its species' shape, and its species. In a field of grass alone every blade is
/// drawn in the field's `shape` at v = `t` as grass, whatever `species` says: the
/// shape then stays the same for every vertex of the draw, which the NVIDIA H200's
/// paper look draws 3 to 4 % faster than a shape chosen per blade (`docs/species.md`;
/// the natural look's stages, measured no faster so, place their rows with
/// `species::row_v` and [`surface_point`] in every field).
pub fn row_point(
    blade: &Blade,
    (species, mixed): (u32, bool),
    (u, t): (f32, f32),
    shape: u32,
    tip_start: f32,
) -> (SurfacePoint, f32, u32) {
    if mixed {
        let v = species::row_v(species, t);
        let shape = species_shape(species, shape);
        (shaped_point(blade, u, v, shape, tip_start), v, species)
    } else {
        (
            shaped_point(blade, u, t, shape, tip_start),
            t,
            species::GRASS,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tau_at_the_domain_corners() {
        // (u, v) = (0,0), (1,0), (0,1), (1,1) for each shape.
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
        let expect = [
            (SHAPE_QUAD, [0.0, 1.0, 0.0, 1.0]),
            (SHAPE_TRIANGLE, [0.0, 1.0, 0.5, 0.5]),
            (SHAPE_QUADRATIC, [0.0, 1.0, 0.0, 0.0]),
            (SHAPE_TRIANGLE_TIP, [0.0, 1.0, 0.5, 0.5]),
        ];
        for (shape, taus) in expect {
            for ((u, v), tau) in corners.iter().zip(taus) {
                let got = shape_tau(shape, *u, *v, 0.5);
                assert!(
                    (got - tau).abs() < 1e-6,
                    "shape {shape} at ({u},{v}): {got}"
                );
            }
        }
        // The dandelion: full width at the root, closed at the tip, and narrower just
        // below a lobe's upper end than just above it (the teeth point back).
        assert_eq!(shape_tau(SHAPE_DANDELION, 1.0, 0.0, 0.5), 1.0);
        assert!((shape_tau(SHAPE_DANDELION, 1.0, 1.0, 0.5) - 0.5).abs() < 1e-6);
        let below = shape_tau(SHAPE_DANDELION, 1.0, 1.0 / 3.0 - 0.01, 0.5);
        let above = shape_tau(SHAPE_DANDELION, 1.0, 1.0 / 3.0 + 0.01, 0.5);
        assert!(above - below > 0.15, "{below} {above}");
        // Triangle-tip keeps the full width below k.
        assert_eq!(shape_tau(SHAPE_TRIANGLE_TIP, 1.0, 0.4, 0.5), 1.0);
    }

    #[test]
    fn the_dandelion_is_broad_and_finely_cut() {
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.2, 10.0);
        let leaf = surface_point(&b, 1.0, 0.0, SHAPE_DANDELION, 0.5).position;
        let blade = surface_point(&b, 1.0, 0.0, SHAPE_QUAD, 0.5).position;
        assert!((leaf.x - 3.0 * blade.x).abs() < 1e-6);
    }

    /// A flower: a stem 0.12 of its head, the head its full 3 widths at its middle
    /// and closed at the tip; a seed grass: a stalk 0.35 of its head's width, the
    /// head 0.8 widths at its middle. Each drawn so for its species' mark whatever the
    /// field's shape.
    #[test]
    fn flowers_and_seed_heads_have_their_outlines() {
        let half_width = |species: u32, v: f32| {
            let b = Blade::at_rest(
                Vec3::ZERO,
                Vec3::Y,
                species::mark(0.0, species),
                2.0,
                0.1,
                10.0,
            );
            surface_point(&b, 1.0, v, SHAPE_QUAD, 0.5).position.x
        };
        let middle = species::FLOWER_HEAD_FROM + 0.5 * (1.0 - species::FLOWER_HEAD_FROM);
        assert!((half_width(species::FLOWER, middle) - 0.15).abs() < 1e-5);
        assert!((half_width(species::FLOWER, 0.3) - 0.018).abs() < 1e-5);
        assert!(half_width(species::FLOWER, 1.0).abs() < 1e-5);
        let middle = species::SEED_HEAD_FROM + 0.5 * (1.0 - species::SEED_HEAD_FROM);
        assert!((half_width(species::SEED_GRASS, middle) - 0.04).abs() < 1e-5);
        assert!((half_width(species::SEED_GRASS, 0.3) - 0.35 * 0.04).abs() < 1e-5);
        assert!(half_width(species::SEED_GRASS, 1.0).abs() < 1e-5);
        assert!((half_width(species::GRASS, 0.3) - 0.05).abs() < 1e-5);
    }

    #[test]
    fn surface_of_an_upright_quad_blade() {
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.2, 10.0);
        let p = surface_point(&b, 0.0, 0.0, SHAPE_QUAD, 0.5);
        assert!((p.position - Vec3::new(-0.1, 0.0, 0.0)).length() < 1e-6);
        let p = surface_point(&b, 1.0, 1.0, SHAPE_QUAD, 0.5);
        assert!((p.position - Vec3::new(0.1, 2.0, 0.0)).length() < 1e-6);
        // Normal = t0 × t1 = Y × X = −Z, also at the tip where b − a vanishes.
        assert!((p.normal - -Vec3::Z).length() < 1e-6);
        let mid = surface_point(&b, 0.5, 0.5, SHAPE_TRIANGLE, 0.5);
        // τ = ½ puts it on the curve, which at v = ½ is ¼v0 + ¾v1 here (v1 = v2).
        assert!((mid.position - Vec3::new(0.0, 1.5, 0.0)).length() < 1e-6);
    }
}

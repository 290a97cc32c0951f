//! The blade surface of the tessellation evaluation stage (paper section 6.2): the
//! Bezier curve by De Casteljau, widened along t1 and cut by a shape function.

use crate::Blade;
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

/// The shape blade `blade` is drawn with when the field's is `shape`: a blade a type
/// map made a dandelion ([`DANDELION_TURNS`]) is one whatever the field's shape.
pub fn blade_shape(blade: &Blade, shape: u32) -> u32 {
    if blade.orientation() >= DANDELION_TURNS {
        SHAPE_DANDELION
    } else {
        shape
    }
}

/// A blade's orientation at or beyond this (two whole turns) marks it a dandelion: the
/// angle's sine and cosine are the same, so nothing else sees the mark (a painted type
/// map's dandelions, `paint::TYPE`; the blade has no other word to spare).
pub const DANDELION_TURNS: f32 = 2.0 * core::f32::consts::TAU;

/// Lobes of the dandelion leaf.
pub const DANDELION_LOBES: f32 = 3.0;

/// How many times its blade's width a leaf of `shape` spans: a dandelion leaf is far
/// broader than a blade of grass (3 times), every other shape 1.
pub fn shape_width(shape: u32) -> f32 {
    if shape == SHAPE_DANDELION { 3.0 } else { 1.0 }
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
/// dandelion of a type map is drawn as one ([`blade_shape`]).
pub fn surface_point(blade: &Blade, u: f32, v: f32, shape: u32, tip_start: f32) -> SurfacePoint {
    let shape = blade_shape(blade, shape);
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

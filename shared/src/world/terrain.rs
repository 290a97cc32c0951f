//! The generated world: `valley`, a height field of 2 km × 2 km and more
//! (it repeats nowhere: sines of incommensurate wavelengths), with a winding bare path
//! along its floor, as pure functions of a ground point so the tiles' blades (GPU) and
//! the ground mesh (host) stand on the same surface.
//!
//! h(x, z) = Σ aᵢ · sin(kᵢ · (uᵢx + vᵢz) + φᵢ) − D · (1 − smoothstep(0, W, d)), with d
//! the distance across the path, whose centre line winds as x = A · sin(z / L). The
//! gradient is analytic (each sine differentiated, the carve through the smoothstep),
//! so normals need no finite differences.

use crate::noise::{hash_unit, smoothstep};
use spirv_std::glam::{IVec2, Vec2, Vec3};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// The hills: (amplitude in metres, wavelength in metres, direction (u, v), phase).
const HILLS: [(f32, f32, Vec2, f32); 5] = [
    (28.0, 1370.0, Vec2::new(0.8, 0.6), 0.4),
    (16.0, 610.0, Vec2::new(-0.28, 0.96), 1.3),
    (7.0, 233.0, Vec2::new(0.6, -0.8), 2.1),
    (3.0, 97.0, Vec2::new(-0.96, -0.28), 0.7),
    (1.0, 41.0, Vec2::new(0.28, 0.96), 2.9),
];
/// How far the path's centre line swings across the valley (m).
pub const PATH_SWING: f32 = 60.0;
/// Metres along z per radian of the path's swing.
pub const PATH_WAVELENGTH: f32 = 180.0;
/// Half-width of the path's carve (m): the ground dips over this distance from its
/// centre line.
pub const PATH_HALF_WIDTH: f32 = 6.0;
/// How deep the path is carved at its centre (m).
pub const PATH_DEPTH: f32 = 0.6;
/// Within this distance of the centre line the ground is bare (no blade grows).
pub const PATH_BARE: f32 = 2.5;

/// The path's centre line at `z`: its x, and dx/dz.
pub fn path_centre(z: f32) -> (f32, f32) {
    let t = z / PATH_WAVELENGTH;
    (PATH_SWING * t.sin(), PATH_SWING / PATH_WAVELENGTH * t.cos())
}

/// Signed distance across the path (m, along x), and its derivative in (x, z).
fn across_path(p: Vec2) -> (f32, Vec2) {
    let (x, slope) = path_centre(p.y);
    (p.x - x, Vec2::new(1.0, -slope))
}

/// Height of the valley at ground point `p` = (x, z), in metres: the hills less the
/// path's carve.
pub fn valley_height(p: Vec2) -> f32 {
    hills_height(p) - path_carve(p)
}

/// The hills alone: the sum of sines.
fn hills_height(p: Vec2) -> f32 {
    let mut h = 0.0;
    let mut i = 0;
    while i < HILLS.len() {
        let (a, wavelength, dir, phase) = HILLS[i];
        h += a * (core::f32::consts::TAU / wavelength * dir.dot(p) + phase).sin();
        i += 1;
    }
    h
}

/// How deep the path is carved at `p`: [`PATH_DEPTH`] on its centre line, nothing
/// from [`PATH_HALF_WIDTH`] off it.
fn path_carve(p: Vec2) -> f32 {
    let (d, _) = across_path(p);
    PATH_DEPTH * (1.0 - smoothstep(0.0, PATH_HALF_WIDTH, d.abs()))
}

/// Gradient (∂h/∂x, ∂h/∂z) of [`valley_height`], analytic.
pub fn valley_gradient(p: Vec2) -> Vec2 {
    let mut g = Vec2::ZERO;
    let mut i = 0;
    while i < HILLS.len() {
        let (a, wavelength, dir, phase) = HILLS[i];
        let k = core::f32::consts::TAU / wavelength;
        g += a * k * (k * dir.dot(p) + phase).cos() * dir;
        i += 1;
    }
    let (d, dd) = across_path(p);
    let t = d.abs() / PATH_HALF_WIDTH;
    if t < 1.0 {
        // d/dt of −D·(1 − smoothstep(t)) = D · 6t(1 − t); t = |d| / W.
        g += PATH_DEPTH * 6.0 * t * (1.0 - t) / PATH_HALF_WIDTH * d.signum() * dd;
    }
    g
}

/// The surface normal of the valley at `p`: normalize(−∂h/∂x, 1, −∂h/∂z).
pub fn valley_normal(p: Vec2) -> Vec3 {
    let g = valley_gradient(p);
    Vec3::new(-g.x, 1.0, -g.y).normalize()
}

/// The valley's ground as drawn: a grid around the camera (`scene`'s), its vertex
/// `u` cells from the centre along an axis at `spacing` · (e^(growth·|u|) − 1) /
/// growth, so cells are `spacing` wide at the camera and grow in proportion to the
/// distance (about the same size on screen near and far), and the vertex stage
/// places each on [`valley_height`] with [`valley_normal`]. A grid of a fixed number
/// of cells whatever the world's size: the ground's memory does not grow with it.
pub fn grid_offset(u: f32, growth: f32, spacing: f32) -> f32 {
    let far = spacing * ((growth * u.abs()).exp() - 1.0) / growth.max(1e-6);
    if u < 0.0 { -far } else { far }
}

/// The growth of [`grid_offset`] that puts vertex `half_cells` at `reach` (bisection;
/// `reach` beyond `spacing` · `half_cells`).
#[cfg(not(target_arch = "spirv"))]
pub fn grid_growth(half_cells: u32, spacing: f32, reach: f32) -> f32 {
    let (mut lo, mut hi) = (1e-6f32, 10.0f32);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if grid_offset(half_cells as f32, mid, spacing) < reach {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// At most this much height per unit of ground anywhere on the valley (the sum of
/// the hills' a·k and the path's steepest carve, 1.5 · D / W: 0.98): a tile's ground
/// lies within this times its half diagonal of its centre's height.
pub const VALLEY_MAX_SLOPE: f32 = 1.0;

/// Whether the ground at `p` is bare: on the path or under a rock, where no blade
/// grows.
pub fn bare(p: Vec2) -> bool {
    across_path(p).0.abs() < PATH_BARE || under_rock(p)
}

/// Rocks lie in a grid of cells this wide, at most one a cell.
pub const ROCK_CELL: f32 = 60.0;
/// The chance a cell holds a rock.
pub const ROCK_CHANCE: f32 = 0.12;
/// Rocks' radii (m) are drawn in this range.
pub const ROCK_RADIUS: (f32, f32) = (1.5, 4.0);

/// The rock of `cell` (x, z of its centre, its radius), if the cell has one: a
/// hash of the cell decides, the rock jittered within the cell's middle and never on
/// the path. Rocks are flattened half-buried spheres (the scene's bare mesh).
pub fn rock_in_cell(cell: IVec2) -> Option<Vec3> {
    let unit = |k: u32| {
        hash_unit(
            (cell.x as u32).wrapping_mul(0x2c1b_3c6d)
                ^ (cell.y as u32).wrapping_mul(0x297a_2d39)
                ^ k.wrapping_mul(0x9e37_79b9),
        )
    };
    if unit(0) >= ROCK_CHANCE {
        return None;
    }
    let at = (cell.as_vec2() + Vec2::new(0.2 + 0.6 * unit(1), 0.2 + 0.6 * unit(2))) * ROCK_CELL;
    let radius = ROCK_RADIUS.0 + (ROCK_RADIUS.1 - ROCK_RADIUS.0) * unit(3);
    if across_path(at).0.abs() < PATH_HALF_WIDTH + radius {
        return None;
    }
    Some(Vec3::new(at.x, at.y, radius))
}

/// Whether `p` lies under a rock (within 0.9 of its radius: the blades at its foot
/// lean against it).
pub fn under_rock(p: Vec2) -> bool {
    let cell = (p / ROCK_CELL).floor().as_ivec2();
    let mut under = false;
    let mut dz = -1;
    while dz <= 1 {
        let mut dx = -1;
        while dx <= 1 {
            if let Some(rock) = rock_in_cell(cell + IVec2::new(dx, dz)) {
                under |= (p - Vec2::new(rock.x, rock.y)).length() < 0.9 * rock.z;
            }
            dx += 1;
        }
        dz += 1;
    }
    under
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Planted faults: a chance of 0.3 gave 379 rocks and failed; `bare` without the
    /// rocks failed.
    #[test]
    fn rocks_lie_off_the_path_and_bare_the_ground_under_them() {
        let rocks: Vec<Vec3> = (-17..17)
            .flat_map(|z| (-17..17).map(move |x| IVec2::new(x, z)))
            .filter_map(rock_in_cell)
            .collect();
        // About ROCK_CHANCE of the 1,156 cells, less those the path crosses.
        assert!((60..160).contains(&rocks.len()), "{} rocks", rocks.len());
        for r in &rocks {
            let centre = Vec2::new(r.x, r.y);
            assert!(across_path(centre).0.abs() > PATH_HALF_WIDTH + r.z);
            assert!(bare(centre) && under_rock(centre + Vec2::new(0.8 * r.z, 0.0)));
            assert!(!under_rock(centre + Vec2::new(r.z, 0.0)));
        }
    }

    #[test]
    fn no_slope_is_steeper_than_the_bound() {
        let steepest = points()
            .map(|p| valley_gradient(p).length())
            .fold(0.0f32, f32::max);
        assert!(steepest < VALLEY_MAX_SLOPE, "{steepest}");
        assert!(steepest > 0.5, "{steepest}: the bound is loose");
    }

    #[test]
    fn the_ground_grid_grows_with_distance_and_reaches_the_asked_distance() {
        let (cells, spacing, reach) = (80, 0.5, 2900.0);
        let growth = grid_growth(cells, spacing, reach);
        assert!((grid_offset(cells as f32, growth, spacing) - reach).abs() < 0.01 * reach);
        assert!((grid_offset(1.0, growth, spacing) - spacing).abs() < 0.05 * spacing);
        assert_eq!(
            grid_offset(-3.0, growth, spacing),
            -grid_offset(3.0, growth, spacing)
        );
        // A cell's width over its distance stays about even (within a factor of two
        // from ten cells out).
        let ratio = |u: f32| {
            let width = grid_offset(u + 1.0, growth, spacing) - grid_offset(u, growth, spacing);
            width / grid_offset(u, growth, spacing)
        };
        let (near, far) = (ratio(10.0), ratio(cells as f32 - 1.0));
        assert!(near / far < 2.0 && near > far, "{near} {far}");
    }

    /// Points spread over 2 km × 2 km around the origin, and a few near the path.
    fn points() -> impl Iterator<Item = Vec2> {
        (0..4000).map(|i| {
            let a = crate::noise::hash_unit(i * 2) - 0.5;
            let b = crate::noise::hash_unit(i * 2 + 1) - 0.5;
            let p = Vec2::new(2000.0 * a, 2000.0 * b);
            if i % 4 == 0 {
                // Within the carve.
                Vec2::new(path_centre(p.y).0 + 12.0 * a, p.y)
            } else {
                p
            }
        })
    }

    #[test]
    fn the_gradient_is_the_heights_slope() {
        // Against central differences over 20 cm: within 1e-3 (slopes here are up to
        // about 0.5; f32 sines of arguments near 150 rad round the heights by about
        // 1e-5 m, 1e-4 of slope over 20 cm, and the carve's curvature leaves 5e-5).
        // Not across the carve's edge, where its curvature jumps and a difference
        // straddling it errs by 2.5e-3 over 20 cm, 5e-4 over 2 cm. Planted fault: the
        // carve's term left out of the gradient failed (0.15).
        let e = 0.1;
        let mut worst = 0.0f32;
        let edge = |p: Vec2| (across_path(p).0.abs() - PATH_HALF_WIDTH).abs() < 2.0 * e;
        for p in points().filter(|&p| !edge(p)) {
            let fd = Vec2::new(
                valley_height(p + Vec2::X * e) - valley_height(p - Vec2::X * e),
                valley_height(p + Vec2::Y * e) - valley_height(p - Vec2::Y * e),
            ) / (2.0 * e);
            worst = worst.max((fd - valley_gradient(p)).abs().max_element());
        }
        assert!(worst < 1e-3, "{worst}");
    }

    #[test]
    fn hills_and_a_path_along_the_floor() {
        let heights: Vec<f32> = points().map(valley_height).collect();
        let (lo, hi) = heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
        // Hills tens of metres high across the 2 km.
        assert!(hi - lo > 40.0 && hi - lo < 112.0, "{lo}..{hi}");
        // The path is carved below its banks and bare; its banks grow grass.
        for z in [-900.0, -300.0, 0.0, 450.0, 870.0] {
            let (x, _) = path_centre(z);
            let centre = Vec2::new(x, z);
            let bank = Vec2::new(x + 1.5 * PATH_HALF_WIDTH, z);
            assert!(bare(centre) && !bare(bank));
            // The carve: its full depth on the centre line, none on the bank.
            let dip = hills_height(centre) - valley_height(centre);
            assert!((dip - PATH_DEPTH).abs() < 1e-4, "dip {dip} at z = {z}");
            assert_eq!(valley_height(bank), hills_height(bank));
        }
        // Normals point up and are unit length.
        for p in points() {
            let n = valley_normal(p);
            assert!((n.length() - 1.0).abs() < 1e-5 && n.y > 0.8, "{n}");
        }
    }
}

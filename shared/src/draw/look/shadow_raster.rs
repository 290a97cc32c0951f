//! The grass's shadow casters drawn into the sun's shadow map by a compute pass, not
//! by the hardware rasterizer. Each caster's one segment (`shadow::CASTER_LEVEL`: its
//! four corners, two triangles) is drawn by one thread into its cascade's half of a
//! buffer of depth words, one word a texel: every texel whose centre a triangle covers
//! takes an atomic minimum of the triangle's depth there (a positive `f32`'s bits
//! order as the float does), as a depth test of LESS would keep it. The buffer is then
//! copied into the map's depth image and the surfaces are drawn over it by the
//! hardware, so the map holds what drawing both there held.
//!
//! Why: a caster seen from the sun is a long thin triangle pair, a few texels wide and
//! tens to hundreds long, and the hardware's rasterizer walks such a triangle tile by
//! tile for a few covered texels each. On the NVIDIA H100, whose few raster units are
//! shared by every graphics pass, the casters took about 1 ms of the natural look's
//! frame, rising with the map's side, not its area (docs/look.md). A compute thread
//! walks the caster row by row instead, one atomic per covered texel. Compute
//! rasterization after Nanite's (Karis et al., *Nanite: a deep dive*, SIGGRAPH 2021),
//! which draws small triangles the same way; the coverage rule is the hardware's:
//! a texel is drawn when its centre lies in the triangle.
//!
//! Every function here runs on the GPU and on the host.

use super::shadow::shadow_coord;
use crate::Blade;
use crate::draw::shape::surface_point;
use spirv_std::glam::{Mat4, Vec3};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// The depth word of an empty texel: the far plane, 1.0, as `f32` bits.
pub const EMPTY_DEPTH: u32 = 0x3f80_0000;

/// Where world point `p` falls in cascade `cascade` (0 near, 1 far) of a shadow map of
/// two cascades `side` texels a side laid side by side: x and y in texels over the
/// whole map (the cascade's half: the near one left), and the depth (0..1 inside the
/// map's depth range), by the cascade's `view_proj` (`shadow::shadow_coord`).
pub fn map_point(view_proj: Mat4, p: Vec3, side: u32, cascade: u32) -> Vec3 {
    let c = shadow_coord(view_proj, p);
    let side = side as f32;
    Vec3::new((c.x + cascade as f32) * side, c.y * side, c.z)
}

/// The four corners of a caster's one segment (`shadow::CASTER_LEVEL`) in map points
/// of cascade `cascade` ([`map_point`]): its dressed `blade`'s surface
/// (`shape::surface_point` in `shape`, `tip_start`) at (u, v) = (0, 0), (1, 0), (0, 1)
/// and (1, 1), the order [`raster_caster`] takes.
pub fn caster_corners(
    blade: &Blade,
    (shape, tip_start): (u32, f32),
    view_proj: Mat4,
    (side, cascade): (u32, u32),
) -> [Vec3; 4] {
    let corner = |u: f32, v: f32| {
        let p = surface_point(blade, u, v, shape, tip_start).position;
        map_point(view_proj, p, side, cascade)
    };
    [
        corner(0.0, 0.0),
        corner(1.0, 0.0),
        corner(0.0, 1.0),
        corner(1.0, 1.0),
    ]
}

/// The index of texel (`x`, `y`) among the depth words of a map of two cascades
/// `side` texels a side: rows of both cascades, `2 · side` words each.
pub fn texel_word(x: u32, y: u32, side: u32) -> usize {
    (y * 2 * side + x) as usize
}

/// The texels of cascade `cascade` of a map of `side` texels a side (columns
/// `cascade · side` up to `(cascade + 1) · side`, rows 0 up to `side`) whose centres
/// triangle (`a`, `b`, `c`) covers, its edges included, in map points ([`map_point`]):
/// `plot(x, y, depth)` for each, the depth on the triangle's plane there, kept only
/// from 0 to 1 (what the hardware's depth clipping keeps). A triangle of no area
/// covers nothing. Walked row by row: each row's span is where the row's centre line
/// crosses the triangle's edges. Returns the texels plotted.
// The depth is compared by hand, as in `raster::raster_wide`.
#[allow(clippy::manual_range_contains)]
pub fn raster_triangle(
    (a, b, c): (Vec3, Vec3, Vec3),
    (side, cascade): (u32, u32),
    plot: &mut impl FnMut(u32, u32, f32),
) -> u32 {
    let (ab, ac) = (b - a, c - a);
    let area = ab.x * ac.y - ac.x * ab.y;
    if area == 0.0 || area.is_nan() {
        return 0;
    }
    // The plane's depth: z = a.z + dz_dx (x − a.x) + dz_dy (y − a.y).
    let dz_dx = (ab.z * ac.y - ac.z * ab.y) / area;
    let dz_dy = (ac.z * ab.x - ab.z * ac.x) / area;
    let first_column = (cascade * side) as f32;
    let last_column = first_column + side as f32 - 1.0;
    let y_min = a.y.min(b.y).min(c.y);
    let y_max = a.y.max(b.y).max(c.y);
    let mut y = (y_min - 0.5).ceil().max(0.0);
    let y_end = (y_max - 0.5).floor().min(side as f32 - 1.0);
    let mut plotted = 0;
    while y <= y_end {
        let centre = y + 0.5;
        let (lo, hi) = row_span((a, b, c), centre);
        let mut x = (lo - 0.5).ceil().max(first_column);
        let x_end = (hi - 0.5).floor().min(last_column);
        while x <= x_end {
            let depth = a.z + dz_dx * (x + 0.5 - a.x) + dz_dy * (centre - a.y);
            if depth >= 0.0 && depth <= 1.0 {
                plot(x as u32, y as u32, depth);
                plotted += 1;
            }
            x += 1.0;
        }
        y += 1.0;
    }
    plotted
}

/// Where the line at height `y` crosses triangle (`a`, `b`, `c`): the least and the
/// greatest x of its crossings with the three edges (an edge along the line counts
/// with both ends); empty (least above greatest) where it misses.
fn row_span((a, b, c): (Vec3, Vec3, Vec3), y: f32) -> (f32, f32) {
    let mut lo = f32::INFINITY;
    let mut hi = f32::NEG_INFINITY;
    let mut cross = |p: Vec3, q: Vec3| {
        if y < p.y.min(q.y) || y > p.y.max(q.y) {
            return;
        }
        if p.y == q.y {
            lo = lo.min(p.x.min(q.x));
            hi = hi.max(p.x.max(q.x));
        } else {
            let x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    };
    cross(a, b);
    cross(b, c);
    cross(c, a);
    (lo, hi)
}

/// A caster's one segment from its four corners in map points (u, v) = (0, 0),
/// (1, 0), (0, 1), (1, 1): the two triangles the hardware drew of it, each by
/// [`raster_triangle`]. Returns the texels plotted (those on the shared edge twice).
pub fn raster_caster(
    corners: [Vec3; 4],
    at: (u32, u32),
    plot: &mut impl FnMut(u32, u32, f32),
) -> u32 {
    let [c00, c10, c01, c11] = corners;
    raster_triangle((c00, c10, c01), at, plot) + raster_triangle((c01, c10, c11), at, plot)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::generate::SplitMix64;

    /// Whether texel centre `p` lies in the triangle, either winding, edges included.
    fn inside((a, b, c): (Vec3, Vec3, Vec3), p: Vec3) -> bool {
        let edge = |s: Vec3, t: Vec3| (t.x - s.x) * (p.y - s.y) - (t.y - s.y) * (p.x - s.x);
        let (e0, e1, e2) = (edge(a, b), edge(b, c), edge(c, a));
        (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0)
    }

    /// The depth at `p` by barycentric weights.
    fn barycentric_depth((a, b, c): (Vec3, Vec3, Vec3), p: Vec3) -> f32 {
        let area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        let wb = ((p.x - a.x) * (c.y - a.y) - (c.x - a.x) * (p.y - a.y)) / area;
        let wc = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / area;
        a.z + wb * (b.z - a.z) + wc * (c.z - a.z)
    }

    /// The row walk plots exactly the texels a test of every centre of the map finds
    /// inside, with the barycentric depth, for random triangles of every shape
    /// (long and thin ones among them, and ones reaching out of the cascade).
    #[test]
    fn the_row_walk_covers_the_centres_inside() {
        let mut rng = SplitMix64::new(7);
        let side = 48;
        for case in 0..400 {
            let cascade = case % 2;
            let point = |rng: &mut SplitMix64| {
                let x = rng.range(-8.0, side as f32 + 8.0) + (cascade * side) as f32;
                Vec3::new(x, rng.range(-8.0, side as f32 + 8.0), rng.range(-0.2, 1.2))
            };
            let (a, mut b, mut c) = (point(&mut rng), point(&mut rng), point(&mut rng));
            if case % 3 == 0 {
                // Thin: two corners close together.
                b = a + (b - a) * 0.05;
            }
            if case % 5 == 0 {
                c = Vec3::new(a.x + rng.range(-1.5, 1.5), c.y, c.z);
            }
            let t = (a, b, c);
            let mut got = std::collections::BTreeMap::new();
            raster_triangle(t, (side, cascade), &mut |x, y, d| {
                assert!(got.insert((x, y), d).is_none(), "({x}, {y}) twice");
            });
            for y in 0..side {
                for x in cascade * side..(cascade + 1) * side {
                    let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
                    let depth = barycentric_depth(t, p);
                    let expected = inside(t, p) && (0.0..=1.0).contains(&depth);
                    // A centre within a hair of an edge or the depth range may go
                    // either way.
                    let near_edge = [(a, b), (b, c), (c, a)].iter().any(|&(s, e)| {
                        let d = e - s;
                        let cross = d.x * (p.y - s.y) - d.y * (p.x - s.x);
                        cross.abs() < 1e-3 * d.truncate().length().max(1.0)
                    });
                    let near_clip = depth.abs() < 1e-4 || (depth - 1.0).abs() < 1e-4;
                    match got.get(&(x, y)) {
                        Some(&d) => {
                            assert!(expected || near_edge || near_clip, "{t:?}: ({x}, {y})");
                            assert!((d - depth).abs() < 5e-5, "{t:?}: {d} against {depth}");
                        }
                        None => assert!(!expected || near_edge || near_clip, "{t:?}: ({x}, {y})"),
                    }
                }
            }
        }
    }

    /// Hand-worked: a right triangle with legs of 4 texels covers the 10 centres on or
    /// under its hypotenuse (4 + 3 + 2 + 1), with the depth rising along x; one of no
    /// area covers nothing; one in the near cascade draws nothing in the far one.
    #[test]
    fn a_hand_worked_triangle() {
        let t = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.4),
            Vec3::new(0.0, 4.0, 0.0),
        );
        let mut texels = vec![];
        let n = raster_triangle(t, (8, 0), &mut |x, y, d| texels.push((x, y, d)));
        assert_eq!(n, 10);
        for &(x, y, d) in &texels {
            assert!(x + y <= 3, "({x}, {y})");
            assert!((d - 0.1 * (x as f32 + 0.5)).abs() < 1e-6, "({x}, {y}): {d}");
        }
        assert!(texels.iter().any(|&(x, y, _)| (x, y) == (3, 0)));
        let flat = (t.0, t.1, Vec3::new(8.0, 0.0, 0.0));
        assert_eq!(raster_triangle(flat, (8, 0), &mut |_, _, _| panic!()), 0);
        assert_eq!(raster_triangle(t, (8, 1), &mut |_, _, _| panic!()), 0);
    }

    /// A caster's two triangles cover its quad: a 2 by 6 texel rectangle, 12 texels,
    /// the 6 on the shared diagonal's texels plotted once more at most.
    #[test]
    fn a_caster_covers_its_quad() {
        let corner = |x: f32, y: f32| Vec3::new(x, y, 0.5);
        let corners = [
            corner(10.0, 2.0),
            corner(12.0, 2.0),
            corner(10.0, 8.0),
            corner(12.0, 8.0),
        ];
        let mut texels = std::collections::BTreeSet::new();
        let n = raster_caster(corners, (16, 0), &mut |x, y, d| {
            assert_eq!(d, 0.5);
            texels.insert((x, y));
        });
        assert_eq!(texels.len(), 12);
        assert!((12..=18).contains(&n), "{n}");
        assert!(
            texels
                .iter()
                .all(|&(x, y)| (10..12).contains(&x) && (2..8).contains(&y))
        );
    }

    #[test]
    fn map_points_fall_in_their_cascade() {
        let view_proj = Mat4::IDENTITY;
        let p = map_point(view_proj, Vec3::new(0.0, 0.5, 0.25), 100, 1);
        assert_eq!(p, Vec3::new(150.0, 75.0, 0.25));
        let p = map_point(view_proj, Vec3::new(-1.0, -1.0, 0.0), 100, 0);
        assert_eq!(p, Vec3::new(0.0, 0.0, 0.0));
    }
}

//! The built-in surfaces: plane, hills, sphere, the walled field, and the valley.
//!
//! Each is a [`SurfaceMesh`] with unit vertex normals and triangles counter-clockwise
//! seen from the normal side, ready for [`shared::world::mesh::scatter`].

use glam::Vec3;
use shared::world::mesh::SurfaceMesh;
use std::collections::HashMap;
use std::f32::consts::TAU;

/// Most cells along a side of [`plane`] and [`hills`] (16.8 million vertices).
pub const MAX_CELLS: u32 = 4096;
/// Most subdivision levels of [`sphere`] (20·4⁸ ≈ 1.3 million triangles).
pub const MAX_SUBDIVISIONS: u32 = 8;

/// A flat square of side `side` centred on the origin in the XZ plane (y = 0, up +Y), as
/// a grid of `cells`×`cells` quads (`cells` clamped to 1..=[`MAX_CELLS`]).
pub fn plane(side: f32, cells: u32) -> SurfaceMesh {
    grid(side, cells, |_, _| 0.0, |_, _| Vec3::Y)
}

/// The plane waves summed by [`hills_height`]: amplitude (× side), direction (cycles
/// per side along x and z) and phase. The amplitudes add up to 0.08.
const HILLS: [(f32, f32, f32, f32); 4] = [
    (0.030, 1.0, 0.3, 0.4),
    (0.025, -0.4, 1.1, 1.3),
    (0.015, 1.7, 1.2, 2.1),
    (0.010, -2.3, 2.6, 0.7),
];

/// Height of the rolling hills at (x, z) on a ground of side `side`: a sum of four
/// sines, h = side · Σ aᵢ · sin(2π/side · (uᵢx + vᵢz) + φᵢ), at most 0.08·side high or
/// deep, with one or two hills across the square; the shape scales with `side`.
pub fn hills_height(x: f32, z: f32, side: f32) -> f32 {
    let k = TAU / side;
    side * HILLS
        .iter()
        .map(|&(a, u, v, phase)| a * (k * (u * x + v * z) + phase).sin())
        .sum::<f32>()
}

/// Gradient (∂h/∂x, ∂h/∂z) of [`hills_height`], by differentiating each sine.
fn hills_gradient(x: f32, z: f32, side: f32) -> (f32, f32) {
    let k = TAU / side;
    HILLS
        .iter()
        .fold((0.0, 0.0), |(dx, dz), &(a, u, v, phase)| {
            // side · a · k = 2π·a: the slope does not depend on the size.
            let c = side * a * k * (k * (u * x + v * z) + phase).cos();
            (dx + c * u, dz + c * v)
        })
}

/// Rolling hills: the height field [`hills_height`] over the square of side `side`
/// centred on the origin, as a grid of `cells`×`cells` quads (`cells` clamped to
/// 1..=[`MAX_CELLS`]), normals from the analytic gradient: normalize(−∂h/∂x, 1, −∂h/∂z).
pub fn hills(side: f32, cells: u32) -> SurfaceMesh {
    grid(
        side,
        cells,
        |x, z| hills_height(x, z, side),
        |x, z| {
            let (dx, dz) = hills_gradient(x, z, side);
            Vec3::new(-dx, 1.0, -dz).normalize()
        },
    )
}

/// The valley (`shared::terrain`): its height field over the square of
/// side `side` (metres) centred on the origin, as a grid of `cells`×`cells` quads
/// (`cells` clamped to 1..=[`MAX_CELLS`]), normals from the analytic gradient. The
/// ground the tiled field's blades will stand on (`shared::world::tiles::TERRAIN_VALLEY`);
/// not yet a scene.
pub fn valley(side: f32, cells: u32) -> SurfaceMesh {
    use glam::Vec2;
    use shared::world::terrain::{valley_height, valley_normal};
    grid(
        side,
        cells,
        |x, z| valley_height(Vec2::new(x, z)),
        |x, z| valley_normal(Vec2::new(x, z)),
    )
}

/// The valley's ground grid around the camera (`shared::world::terrain::grid_offset`):
/// `cells`×`cells` quads, `spacing` wide at the centre and growing with the distance
/// out to `reach` at the edge, flat at y = 0, its vertices placed on the valley by
/// the vertex stage around the camera (`layout::SurfacePush::terrain`).
pub fn ground_grid(cells: u32, spacing: f32, reach: f32) -> SurfaceMesh {
    use shared::world::terrain::{grid_growth, grid_offset};
    let cells = cells.clamp(2, MAX_CELLS) & !1;
    let half = cells / 2;
    let growth = grid_growth(half, spacing, reach);
    let coordinate = |i: u32| grid_offset(i as f32 - half as f32, growth, spacing);
    grid_over(cells, coordinate, |_, _| 0.0, |_, _| Vec3::Y)
}

/// The valley's rocks (`shared::world::terrain::rock_in_cell`) within the square of side
/// `side`: each a sphere of its radius flattened to 0.6 of it in height and sunk a
/// quarter of its radius into the ground, rough (its vertices pushed in and out by a
/// hash), one subdivision (80 triangles).
pub fn valley_rocks(side: f32) -> SurfaceMesh {
    use glam::{IVec2, Vec2};
    use shared::world::terrain::{ROCK_CELL, rock_in_cell, valley_height};
    let cells = (0.5 * side / ROCK_CELL).ceil() as i32;
    let mut rocks = SurfaceMesh::default();
    for z in -cells..cells {
        for x in -cells..cells {
            let Some(rock) = rock_in_cell(IVec2::new(x, z)) else {
                continue;
            };
            let at = Vec2::new(rock.x, rock.y);
            if at.abs().max_element() > 0.5 * side {
                continue;
            }
            let r = rock.z;
            let centre = Vec3::new(at.x, valley_height(at) - 0.25 * r, at.y);
            let mut mesh = sphere(Vec3::ZERO, 1.0, 1);
            for (i, (p, n)) in mesh.positions.iter_mut().zip(&mut mesh.normals).enumerate() {
                let rough = 0.85 + 0.3 * shared::noise::hash_unit(i as u32 ^ (x * 977 + z) as u32);
                let scale = Vec3::new(r, 0.6 * r, r) * rough;
                *p = centre + *p * scale;
                *n = (*n / scale).normalize();
            }
            rocks.append(&mesh);
        }
    }
    rocks
}

/// A height field `height(x, z)` with normals `normal(x, z)` over the square of side
/// `side` centred on the origin, `cells`×`cells` quads of two triangles each.
fn grid(
    side: f32,
    cells: u32,
    height: impl Fn(f32, f32) -> f32,
    normal: impl Fn(f32, f32) -> Vec3,
) -> SurfaceMesh {
    let cells = cells.clamp(1, MAX_CELLS);
    let coordinate = |i: u32| side * (i as f32 / cells as f32 - 0.5);
    grid_over(cells, coordinate, height, normal)
}

/// [`grid`] with vertex `i` along each axis at `coordinate(i)`.
fn grid_over(
    cells: u32,
    coordinate: impl Fn(u32) -> f32,
    height: impl Fn(f32, f32) -> f32,
    normal: impl Fn(f32, f32) -> Vec3,
) -> SurfaceMesh {
    let n = cells + 1;
    let mut mesh = SurfaceMesh::default();
    for j in 0..n {
        for i in 0..n {
            let (x, z) = (coordinate(i), coordinate(j));
            mesh.positions.push(Vec3::new(x, height(x, z), z));
            mesh.normals.push(normal(x, z));
        }
    }
    let index = |i: u32, j: u32| j * n + i;
    for j in 0..cells {
        for i in 0..cells {
            // Seen from +Y (x right, z down the screen) (x, z) → (x, z+1) → (x+1, z)
            // turns counter-clockwise.
            let (a, b) = (index(i, j), index(i, j + 1));
            let (c, d) = (index(i + 1, j), index(i + 1, j + 1));
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([c, b, d]);
        }
    }
    mesh
}

/// The stone blocks of [`walls`]: (min corner, max corner) as fractions of the side
/// (x, z) and of the wall height (y).
const WALLS: [([f32; 3], [f32; 3]); 4] = [
    ([-0.40, 0.0, -0.06], [0.05, 1.0, -0.02]),
    ([-0.05, 0.0, 0.16], [0.40, 0.8, 0.20]),
    ([-0.32, 0.0, 0.26], [-0.12, 1.4, 0.40]),
    ([0.18, 0.0, -0.36], [0.22, 0.9, -0.10]),
];

/// The occluder scene: a square field of side `side` (a grid of `cells`×`cells`)
/// with stone walls and a block standing on it, returned as (ground with holes where
/// a triangle lies wholly under a stone, the stones). Walls are a quarter of the side high (at least 2.5), so
/// from a low camera they hide much of the grass behind them.
pub fn walls(side: f32, cells: u32) -> (SurfaceMesh, SurfaceMesh) {
    let height = (0.25 * side).max(2.5);
    let boxes: Vec<(Vec3, Vec3)> = WALLS
        .iter()
        .map(|(lo, hi)| {
            let scale = |f: [f32; 3]| Vec3::new(f[0] * side, f[1] * height, f[2] * side);
            // Sunk a little into the ground so no seam shows.
            (scale(*lo) - Vec3::Y * 0.05, scale(*hi))
        })
        .collect();
    // Holes only where a triangle lies wholly under a stone: a triangle the stone's
    // edge crosses stays, its inner part hidden in the stone, so ground and stone meet
    // without a crack (cutting every triangle whose centroid was under a stone left
    // slivers of sky along the stones' feet).
    let mut ground = plane(side, cells);
    ground.triangles.retain(|tri| {
        !boxes.iter().any(|(lo, hi)| {
            tri.iter().all(|&i| {
                let p = ground.positions[i as usize];
                (lo.x..=hi.x).contains(&p.x) && (lo.z..=hi.z).contains(&p.z)
            })
        })
    });
    let mut stones = SurfaceMesh::default();
    for (lo, hi) in boxes {
        add_box(&mut stones, lo, hi);
    }
    (ground, stones)
}

/// Appends the six faces of the box [`lo`, `hi`], each with its own outward normal.
fn add_box(mesh: &mut SurfaceMesh, lo: Vec3, hi: Vec3) {
    let corner = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    // Each face: normal and two edge directions (u, v) with u × v = normal.
    let faces = [
        (
            Vec3::X,
            [
                (true, false, false),
                (true, true, false),
                (true, true, true),
                (true, false, true),
            ],
        ),
        (
            -Vec3::X,
            [
                (false, false, false),
                (false, false, true),
                (false, true, true),
                (false, true, false),
            ],
        ),
        (
            Vec3::Y,
            [
                (false, true, false),
                (false, true, true),
                (true, true, true),
                (true, true, false),
            ],
        ),
        (
            -Vec3::Y,
            [
                (false, false, false),
                (true, false, false),
                (true, false, true),
                (false, false, true),
            ],
        ),
        (
            Vec3::Z,
            [
                (false, false, true),
                (true, false, true),
                (true, true, true),
                (false, true, true),
            ],
        ),
        (
            -Vec3::Z,
            [
                (false, false, false),
                (false, true, false),
                (true, true, false),
                (true, false, false),
            ],
        ),
    ];
    for (normal, quad) in faces {
        let base = mesh.positions.len() as u32;
        for (x, y, z) in quad {
            mesh.positions.push(corner(x, y, z));
            mesh.normals.push(normal);
        }
        mesh.triangles.push([base, base + 1, base + 2]);
        mesh.triangles.push([base, base + 2, base + 3]);
    }
}

/// A sphere of `radius` (its absolute value) at `centre`: an icosahedron subdivided
/// `subdivisions` times (clamped to [`MAX_SUBDIVISIONS`]), vertices pushed out onto the
/// sphere, outward unit normals.
pub fn sphere(centre: Vec3, radius: f32, subdivisions: u32) -> SurfaceMesh {
    let (directions, triangles) = icosphere(subdivisions.min(MAX_SUBDIVISIONS));
    SurfaceMesh {
        positions: directions
            .iter()
            .map(|&d| centre + d * radius.abs())
            .collect(),
        normals: directions,
        triangles,
        uvs: Vec::new(),
    }
}

/// Unit vertices and counter-clockwise (seen from outside) triangles of an
/// icosahedron subdivided `levels` times: each triangle into four by its edge
/// midpoints, shared between neighbours so the sphere stays closed.
fn icosphere(levels: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5.0_f32.sqrt()) / 2.0;
    let mut vertices: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    // Whatever order the table above is in, face the triangles outwards: the midpoint
    // split below keeps the winding of its parent.
    for tri in &mut triangles {
        let [a, b, c] = tri.map(|v| vertices[v as usize]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            tri.swap(1, 2);
        }
    }
    for _ in 0..levels {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (vertices[a as usize] + vertices[b as usize]).normalize();
                vertices.push(m);
                (vertices.len() - 1) as u32
            })
        };
        triangles = triangles
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = midpoint(a, b, &mut vertices);
                let bc = midpoint(b, c, &mut vertices);
                let ca = midpoint(c, a, &mut vertices);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    (vertices, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// Unit normals, and every triangle counter-clockwise: its face normal on the side
    /// of its vertex normals.
    fn assert_well_formed(mesh: &SurfaceMesh) {
        assert_eq!(mesh.positions.len(), mesh.normals.len());
        for n in &mesh.normals {
            assert!((n.length() - 1.0).abs() < 1e-5, "|n| = {}", n.length());
        }
        for (i, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = mesh.triangle(i);
            let face = (b - a).cross(c - a);
            for v in tri {
                assert!(face.dot(mesh.normals[*v as usize]) > 0.0, "triangle {i}");
            }
        }
    }

    #[test]
    fn walls_stand_on_a_field_with_holes_under_them() {
        let (ground, stones) = walls(20.0, 40);
        assert_well_formed(&ground);
        assert_well_formed(&stones);
        // 4 boxes of 6 faces of 2 triangles.
        assert_eq!(stones.triangles.len(), 48);
        let (lo, hi) = stones.bounds().unwrap();
        assert!(lo.y < 0.0 && hi.y >= 5.0 * 1.4 - 1e-4, "{lo} {hi}");
        // Some ground is removed under the stones, most of it stays.
        let full = plane(20.0, 40).area();
        assert!(ground.area() < full && ground.area() > 0.8 * full);
    }

    #[test]
    fn plane_is_flat_square_of_side_squared_area() {
        let mesh = plane(7.0, 5);
        assert_eq!(mesh.positions.len(), 36);
        assert_eq!(mesh.triangles.len(), 50);
        assert!((mesh.area() - 49.0).abs() < 1e-3);
        assert_eq!(
            mesh.bounds(),
            Some((Vec3::new(-3.5, 0.0, -3.5), Vec3::new(3.5, 0.0, 3.5)))
        );
        assert_well_formed(&mesh);
        // Zero cells still make a square.
        assert_eq!(plane(2.0, 0).triangles.len(), 2);
    }

    #[test]
    fn sphere_area_is_close_to_four_pi_r_squared() {
        let centre = Vec3::new(1.0, -2.0, 3.0);
        let mesh = sphere(centre, 2.0, 3);
        assert_eq!(mesh.triangles.len(), 20 * 4usize.pow(3));
        // Euler: V − E + F = 2 with E = 3F/2, so the mesh is closed.
        assert_eq!(mesh.positions.len(), 2 + mesh.triangles.len() / 2);
        let exact = 4.0 * PI * 4.0;
        assert!(
            (mesh.area() / exact - 1.0).abs() < 0.02,
            "{} vs {exact}",
            mesh.area()
        );
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(((*p - centre).length() - 2.0).abs() < 1e-5);
            assert!((*p - centre).normalize().dot(*n) > 0.9999);
        }
        assert_well_formed(&mesh);
        assert_well_formed(&sphere(Vec3::ZERO, 1.0, 0));
    }

    #[test]
    fn the_valley_mesh_stands_on_its_height_field() {
        // 2 km in 512 cells (3.9 m): the faces follow the analytic normals within 18°
        // (measured: 13°, where the path's 12 m carve bends over three cells), and
        // every vertex lies on the height field. Planted fault: normals all up failed.
        let mesh = valley(2000.0, 512);
        assert_well_formed(&mesh);
        let mut worst = 1.0f32;
        for (i, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = mesh.triangle(i);
            let face = (b - a).cross(c - a).normalize();
            for v in tri {
                worst = worst.min(face.dot(mesh.normals[*v as usize]));
            }
        }
        assert!(worst > 0.95, "face·normal down to {worst}");
        for p in &mesh.positions {
            let h = shared::world::terrain::valley_height(glam::Vec2::new(p.x, p.z));
            assert_eq!(p.y, h);
        }
        let (lo, hi) = mesh.bounds().unwrap();
        assert!(hi.y - lo.y > 40.0, "hills: {lo} {hi}");
    }

    #[test]
    fn hills_normals_agree_with_faces_and_gradient() {
        let side = 24.0;
        let mesh = hills(side, 48);
        assert_well_formed(&mesh);
        for (i, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = mesh.triangle(i);
            let face = (b - a).cross(c - a).normalize();
            for v in tri {
                let dot = face.dot(mesh.normals[*v as usize]);
                assert!(dot > 0.9, "triangle {i}: face·normal = {dot}");
            }
        }
        let (lo, hi) = mesh.bounds().unwrap();
        assert!(lo.y >= -0.08 * side && hi.y <= 0.08 * side);
        assert!(hi.y - lo.y > 0.03 * side, "not much of a hill: {lo} {hi}");
        // The analytic gradient matches central differences.
        let e = 1e-2;
        for (x, z) in [(0.0, 0.0), (3.7, -8.1), (-11.0, 5.5)] {
            let (dx, dz) = hills_gradient(x, z, side);
            let fx = (hills_height(x + e, z, side) - hills_height(x - e, z, side)) / (2.0 * e);
            let fz = (hills_height(x, z + e, side) - hills_height(x, z - e, side)) / (2.0 * e);
            assert!((dx - fx).abs() < 1e-3 && (dz - fz).abs() < 1e-3);
        }
    }
}

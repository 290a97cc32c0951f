//! Unit tests of `surface`.

use super::*;
use crate::world::mesh::SurfaceMesh;
use crate::world::tiles::{TERRAIN_MESH, TileParams, kept, tile_blade, tile_count};
use spirv_std::glam::Vec2;

/// A grid of `n` × `n` quads over x in `x0`..`x1`, z in −2..2, at height `f`,
/// with normals from `f`'s slope.
fn sheet(n: u32, (x0, x1): (f32, f32), f: impl Fn(f32, f32) -> f32) -> SurfaceMesh {
    let mut mesh = SurfaceMesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let x = x0 + (x1 - x0) * i as f32 / n as f32;
            let z = -2.0 + 4.0 * j as f32 / n as f32;
            let e = 1e-3;
            let dx = (f(x + e, z) - f(x - e, z)) / (2.0 * e);
            let dz = (f(x, z + e) - f(x, z - e)) / (2.0 * e);
            mesh.positions.push(Vec3::new(x, f(x, z), z));
            mesh.normals.push(Vec3::new(-dx, 1.0, -dz).normalize());
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            // Counter-clockwise seen from above.
            mesh.triangles.push([v, v + n + 1, v + 1]);
            mesh.triangles.push([v + 1, v + n + 1, v + n + 2]);
        }
    }
    mesh
}

/// A flat half (x −3..1) and a half rising at 60° (x 1..5, twice the area over
/// the same ground), both 4 wide in z, of a few large triangles.
fn scene() -> SurfaceMesh {
    let mut mesh = sheet(2, (-3.0, 1.0), |_, _| 0.0);
    mesh.append(&sheet(2, (1.0, 5.0), |x, _| (x - 1.0) * 3f32.sqrt()));
    mesh
}

fn params(size: f32, per_side: u32) -> TileParams {
    TileParams {
        size,
        per_side,
        full_distance: 1e6,
        terrain: TERRAIN_MESH,
        half_extent: 8.0,
        ..TileParams::default()
    }
}

/// The world's set holding `mesh`'s table for `params`.
fn set_for(mesh: &SurfaceMesh, params: &TileParams) -> Vec<u32> {
    let room = params.per_side * params.per_side;
    let table = build(mesh, params.size, room);
    crate::world::paint::with_surface(Vec::new(), &table)
}

/// Every tile's pieces lie in its column and their areas add up to the mesh's:
/// the tiles share the surface out, nothing twice, nothing left. Tiles of 1.7
/// (not a divisor of anything in the scene), a wavy sheet stacked over the two
/// halves. Planted fault: pieces left unclipped (a triangle in every tile it
/// touches) failed (a corner outside its tile's column).
#[test]
fn the_tiles_share_the_surface_out_exactly() {
    let mut mesh = scene();
    mesh.append(&sheet(12, (-3.0, 3.0), |x, z| {
        9.0 + (2.0 * x).sin() * z.cos()
    }));
    let params = params(1.7, 32);
    let set = set_for(&mesh, &params);
    let mut total = 0.0f64;
    for tz in -3..3 {
        for tx in -4..4 {
            let t = IVec2::new(tx, tz);
            let part = tile(&set, t);
            let (lo, hi) = crate::world::tiles::tile_square(t, &params);
            let mut area = 0.0f32;
            for k in 0..part.pieces as usize {
                let p = part.first as usize + PIECE_WORDS * k;
                let corners = [0, 1, 2].map(|c| vec3_at(&set, p + 1 + 3 * c));
                for c in corners {
                    let inside = c.x >= lo.x - 1e-4 && c.x <= hi.x + 1e-4;
                    assert!(
                        inside && c.z >= lo.y - 1e-4 && c.z <= hi.y + 1e-4,
                        "{t}: {c}"
                    );
                    assert!(c.y >= part.ground.0 && c.y <= part.ground.1, "{t}: {c}");
                }
                area += crate::world::mesh::triangle_area(corners[0], corners[1], corners[2]);
                let running = f32::from_bits(set[p]);
                assert!(
                    (running - area).abs() <= 1e-4 * area.max(1.0),
                    "{running} {area}"
                );
            }
            assert!((area - part.area).abs() <= 1e-4 * area.max(1.0));
            total += f64::from(part.area);
        }
    }
    let whole = f64::from(mesh.area());
    assert!(
        (total - whole).abs() < 1e-4 * whole,
        "{total} against {whole}"
    );
    // Outside the table's tiles, and without a table: nothing.
    assert_eq!(tile(&set, IVec2::new(40, 0)).pieces, 0);
    assert_eq!(tile(&[], IVec2::ZERO), SurfaceTile::default());
}

/// Blades grow by area, not by ground: on the half rising at 60° (twice the
/// surface over the same ground) as many blades a square unit of surface as on
/// the flat half, within 4 % ([`SLOPE_ROOM`] leaves room for it), also in the
/// tile holding some of each; each blade's up is its half's normal. Strips 0.5
/// wide across the flat half (a tile border every 2.5) hold as many blades across
/// a border as inside a tile, within 5 % (about 660 a strip), and so do the first
/// eighth of each tile's blades (what a far tile keeps at √8 times the
/// keep-every-blade distance) within 15 % (about 82). Planted faults: roots spread
/// over the tile's square (`root_of`) instead of its area failed (the flat half
/// 1.25 times as dense as the sloped); pieces in mesh order rather than Morton
/// order failed the first eighth (a strip with 1.19 times the mean).
#[test]
fn blades_grow_by_area_on_every_slope_without_seams() {
    let mesh = scene();
    let params = params(2.5, 64);
    let set = set_for(&mesh, &params);
    let (mut flat, mut sloped) = (0u32, 0u32);
    let mut strips = vec![0u32; 8];
    let mut firsts = vec![0u32; 8];
    for tz in -1..1 {
        for tx in -2..2 {
            let t = IVec2::new(tx, tz);
            let count = tile_count(t, &params, &set);
            for k in 0..count {
                let b = tile_blade(t, k, Vec3::Y, &params, &set);
                assert!(kept(&b), "{t} {k}");
                if b.root().x < 1.0 {
                    flat += 1;
                    assert!((b.up_dir() - Vec3::Y).length() < 1e-4);
                    let s = ((b.root().x + 3.0) / 0.5) as usize;
                    strips[s] += 1;
                    if k < count / 8 {
                        firsts[s] += 1;
                    }
                } else {
                    sloped += 1;
                    let normal = Vec3::new(-3f32.sqrt(), 1.0, 0.0).normalize();
                    assert!((b.up_dir() - normal).length() < 1e-3, "{}", b.up_dir());
                }
            }
            // Past its count a tile's blades are empty.
            let past = tile_blade(t, tile_count(t, &params, &set), Vec3::Y, &params, &set);
            assert_eq!(past.height(), 0.0);
        }
    }
    // Flat: 4 x 4 units; sloped: 4 x 8 units of surface over 4 x 4 of ground.
    let (flat_density, sloped_density) = (flat as f32 / 16.0, sloped as f32 / 32.0);
    println!("{flat_density} a square unit flat, {sloped_density} sloped");
    println!("strips {strips:?}, first eighths {firsts:?}");
    assert!((sloped_density / flat_density - 1.0).abs() < 0.04);
    for (counts, within) in [(strips, 0.05), (firsts, 0.15)] {
        let mean = counts.iter().sum::<u32>() as f32 / counts.len() as f32;
        for (i, &c) in counts.iter().enumerate() {
            let off = (c as f32 - mean).abs() / mean;
            assert!(off < within, "strip {i}: {c} against {mean}");
        }
    }
}

/// A painted map lies over a mesh's texture coordinates where it has them: a
/// density map black on its left half (u < 0.5) over a square whose u runs
/// against x leaves the right half (x > 0) bare, and over the same square without
/// texture coordinates (the map over the world's square) the left half. Blades
/// counted per half at full density, off the map's blend between its halves.
/// Planted fault: the texture coordinates ignored (the map always over the
/// world's square) failed (0 left). A mesh put together from parts keeps its
/// texture coordinates only if every part has them.
#[test]
fn painted_maps_follow_the_texture_coordinates() {
    let mut mirrored = sheet(8, (-4.0, 4.0), |_, _| 0.0);
    mirrored.uvs = mirrored
        .positions
        .iter()
        .map(|p| Vec2::new(0.5 - p.x / 8.0, 0.5 + p.z / 8.0))
        .collect();
    let plain = sheet(8, (-4.0, 4.0), |_, _| 0.0);
    let left_black = crate::world::paint::grey(&[0, 0, 0, 0, 255, 255, 255, 255]);
    let maps = crate::world::paint::words(&[(crate::world::paint::DENSITY, 8, 1, &left_black)]);
    let params = TileParams {
        half_extent: 4.0,
        ..params(2.0, 32)
    };
    let halves = |mesh: &SurfaceMesh| {
        let room = params.per_side * params.per_side;
        let set = crate::world::paint::with_surface(maps.clone(), &build(mesh, params.size, room));
        assert_eq!(has_uvs(&set), mesh.has_uvs());
        let (mut left, mut right) = (0, 0);
        for tz in -2..2 {
            for tx in -2..2 {
                let t = IVec2::new(tx, tz);
                for k in 0..tile_count(t, &params, &set) {
                    let b = tile_blade(t, k, Vec3::Y, &params, &set);
                    // Off the map's blend between its halves (x within 0.5 of 0).
                    if kept(&b) && b.root().x < -0.5 {
                        left += 1;
                    } else if kept(&b) && b.root().x > 0.5 {
                        right += 1;
                    }
                }
            }
        }
        (left, right)
    };
    let (left, right) = halves(&mirrored);
    println!("texture coordinates: {left} left, {right} right");
    assert!(left > 1000 && right == 0, "{left} {right}");
    let (left, right) = halves(&plain);
    println!("world square: {left} left, {right} right");
    assert!(left == 0 && right > 1000, "{left} {right}");
    // Parts with and without texture coordinates.
    let mut both = mirrored.clone();
    both.append(&mirrored);
    assert!(both.has_uvs());
    both.append(&plain);
    assert!(!both.has_uvs() && both.uvs.is_empty());
}

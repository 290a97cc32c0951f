//! A loaded scene's surface cut into the tiled field's tiles: "tiles over
//! their triangles, by area". A tile's column (its square in x and z, at any height)
//! holds the pieces of the scene's triangles inside it, clipped to the square, so
//! the tiles share the surface's area out exactly: no blade grows twice, no seam is
//! left. A tile grows blades in proportion to its pieces' area, each blade on a
//! piece picked by area, so the density in blades per square unit is the same on
//! every slope (at most a tile's room: a column with more surface than its square,
//! a steep one or two surfaces stacked, grows its room's worth).
//!
//! The table travels as `u32` words in the world's set (`paint`, after the maps; its
//! header's [`paint::SURFACE`](crate::paint::SURFACE) gives where): [`HEADER_WORDS`]
//! words (the first tile's x and z, the tiles along x and z, and 1 where the mesh
//! has texture coordinates), then one record of [`RECORD_WORDS`] per tile, row by
//! row (the first piece, the pieces, the blades, the area, the lowest and highest
//! point), then the pieces, [`PIECE_WORDS`] each (the running area of the tile's
//! pieces at its end, its three corners, their unit normals and their texture
//! coordinates).

use spirv_std::glam::{IVec2, Vec2, Vec3};

/// Words before the tile records.
pub const HEADER_WORDS: usize = 5;
/// Words of a tile's record.
pub const RECORD_WORDS: usize = 6;
/// Words of a piece.
pub const PIECE_WORDS: usize = 25;

/// A tile's part of the surface.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct SurfaceTile {
    /// Where its first piece's words start in the set (in the table, from the
    /// table's start).
    pub first: u32,
    /// Its pieces.
    pub pieces: u32,
    /// The blades it grows.
    pub blades: u32,
    /// Its pieces' area.
    pub area: f32,
    /// Its lowest and highest point.
    pub ground: (f32, f32),
}

/// Where the surface table starts in `set` (0: none).
pub fn table(set: &[u32]) -> usize {
    if set.len() <= crate::paint::SURFACE {
        return 0;
    }
    set[crate::paint::SURFACE] as usize
}

/// Whether the surface in `set` has texture coordinates: the painted maps are then
/// read at a blade's, not over the world's square.
pub fn has_uvs(set: &[u32]) -> bool {
    let base = table(set);
    base != 0 && set[base + 4] != 0
}

/// `tile`'s part of the surface in `set`: no pieces outside the table's tiles or
/// without a table.
pub fn tile(set: &[u32], tile: IVec2) -> SurfaceTile {
    let base = table(set);
    if base == 0 {
        return SurfaceTile::default();
    }
    let at = tile - IVec2::new(set[base] as i32, set[base + 1] as i32);
    let (nx, nz) = (set[base + 2] as i32, set[base + 3] as i32);
    if at.x < 0 || at.y < 0 || at.x >= nx || at.y >= nz {
        return SurfaceTile::default();
    }
    let r = base + HEADER_WORDS + RECORD_WORDS * (at.y * nx + at.x) as usize;
    SurfaceTile {
        first: base as u32 + set[r],
        pieces: set[r + 1],
        blades: set[r + 2],
        area: f32::from_bits(set[r + 3]),
        ground: (f32::from_bits(set[r + 4]), f32::from_bits(set[r + 5])),
    }
}

fn vec2_at(set: &[u32], at: usize) -> Vec2 {
    Vec2::new(f32::from_bits(set[at]), f32::from_bits(set[at + 1]))
}

fn vec3_at(set: &[u32], at: usize) -> Vec3 {
    Vec3::new(
        f32::from_bits(set[at]),
        f32::from_bits(set[at + 1]),
        f32::from_bits(set[at + 2]),
    )
}

/// The point of `t` at `u` (0..1) of its area, taken piece by piece in order: the
/// piece whose running area first passes u·area (a binary search), and in it the
/// point at the share f of its own area that u has gone past its start
/// ([`in_triangle`]), so that nearby shares of u are nearby points and a stratified
/// u gives stratified points. Returns the position, the unit normal and the texture
/// coordinates interpolated there.
pub fn point(set: &[u32], t: &SurfaceTile, u: f32) -> Spot {
    let target = u * t.area;
    let (mut lo, mut hi) = (0u32, t.pieces.max(1) - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        let end = f32::from_bits(set[t.first as usize + PIECE_WORDS * mid as usize]);
        if end <= target {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    let p = t.first as usize + PIECE_WORDS * lo as usize;
    let end = f32::from_bits(set[p]);
    let start = if lo == 0 {
        0.0
    } else {
        f32::from_bits(set[p - PIECE_WORDS])
    };
    let f = ((target - start) / (end - start).max(1e-30)).clamp(0.0, 1.0);
    let w = in_triangle(f);
    let (c0, c1, c2) = (
        vec3_at(set, p + 1),
        vec3_at(set, p + 4),
        vec3_at(set, p + 7),
    );
    let (n0, n1, n2) = (
        vec3_at(set, p + 10),
        vec3_at(set, p + 13),
        vec3_at(set, p + 16),
    );
    let (t0, t1, t2) = (
        vec2_at(set, p + 19),
        vec2_at(set, p + 21),
        vec2_at(set, p + 23),
    );
    let position = c0 * w.x + c1 * w.y + c2 * w.z;
    let n = n0 * w.x + n1 * w.y + n2 * w.z;
    Spot {
        position,
        normal: n.normalize_or(Vec3::Y),
        uv: t0 * w.x + t1 * w.y + t2 * w.z,
    }
}

/// A point of the surface ([`point`]).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Spot {
    /// Its position.
    pub position: Vec3,
    /// The unit normal there.
    pub normal: Vec3,
    /// The texture coordinates there (zero on a mesh without them).
    pub uv: Vec2,
}

/// How much more surface than its square a tile has room for: a tile grows `room` /
/// SLOPE_ROOM blades over a flat square, so ground up to 60° steep (twice the area
/// over the same square) is as dense as flat; a steeper or stacked column fills its
/// room and is sparser.
pub const SLOPE_ROOM: f32 = 2.0;

/// Blades a square unit of surface grows on tiles of side `size` with room for
/// `room` blades ([`SLOPE_ROOM`]).
pub fn per_area(size: f32, room: u32) -> f32 {
    room as f32 / (SLOPE_ROOM * size * size)
}

/// The table of `mesh` cut into tiles of side `size` with room for `room` blades
/// each, each growing [`per_area`] blades a square unit of its pieces.
#[cfg(not(target_arch = "spirv"))]
pub fn build(mesh: &crate::mesh::SurfaceMesh, size: f32, room: u32) -> Vec<u32> {
    let per_area = per_area(size, room);
    let Some((lo, hi)) = mesh.bounds() else {
        return vec![0; HEADER_WORDS];
    };
    let first = (Vec2::new(lo.x, lo.z) / size).floor().as_ivec2();
    let last = (Vec2::new(hi.x, hi.z) / size).floor().as_ivec2();
    let (nx, nz) = (
        (last.x - first.x + 1) as usize,
        (last.y - first.y + 1) as usize,
    );
    // Each tile's pieces.
    let mut pieces: Vec<Vec<[Spot; 3]>> = vec![Vec::new(); nx * nz];
    for i in 0..mesh.triangles.len() {
        let Some(abc) = mesh.corners(i) else { continue };
        let weights = [Vec3::X, Vec3::Y, Vec3::Z];
        let corners: Vec<Spot> = (0..3)
            .map(|k| Spot {
                position: abc[k],
                normal: mesh.normal_at(i, abc, weights[k]),
                uv: mesh.uv_at(i, weights[k]),
            })
            .collect();
        let min = abc
            .iter()
            .fold(Vec2::splat(f32::MAX), |m, p| m.min(Vec2::new(p.x, p.z)));
        let max = abc
            .iter()
            .fold(Vec2::splat(f32::MIN), |m, p| m.max(Vec2::new(p.x, p.z)));
        if !(min.is_finite() && max.is_finite()) {
            continue;
        }
        let (t0, t1) = (
            (min / size).floor().as_ivec2(),
            (max / size).floor().as_ivec2(),
        );
        for tz in t0.y.max(first.y)..=t1.y.min(last.y) {
            for tx in t0.x.max(first.x)..=t1.x.min(last.x) {
                let square_lo = Vec2::new(tx as f32, tz as f32) * size;
                let polygon = clip_to_square(&corners, square_lo, square_lo + Vec2::splat(size));
                let cell = (tz - first.y) as usize * nx + (tx - first.x) as usize;
                for k in 1..polygon.len().saturating_sub(1) {
                    let piece = [polygon[0], polygon[k], polygon[k + 1]];
                    split(piece, size / SPLIT, &mut pieces[cell]);
                }
            }
        }
    }
    // Each tile's pieces in Morton order of their centres, so that a run of the area
    // is a compact patch and every prefix of the blades' strata is spread over it.
    for list in &mut pieces {
        let centre = |p: &[Spot; 3]| (p[0].position + p[1].position + p[2].position) / 3.0;
        let (lo, hi) = list.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
            (lo.min(centre(p)), hi.max(centre(p)))
        });
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        list.sort_by_cached_key(|p| {
            let c = (centre(p) - lo) / extent * 1023.0;
            morton3(c.x as u32, c.y as u32, c.z as u32)
        });
    }
    let uvs = u32::from(mesh.has_uvs());
    let mut words = vec![first.x as u32, first.y as u32, nx as u32, nz as u32, uvs];
    let records = words.len();
    words.resize(records + RECORD_WORDS * nx * nz, 0);
    for (cell, list) in pieces.iter().enumerate() {
        let start = words.len();
        let (mut area, mut low, mut high) = (0.0f64, f32::MAX, f32::MIN);
        for piece in list {
            let [a, b, c] = piece.map(|k| k.position);
            area += f64::from(crate::mesh::triangle_area(a, b, c));
            words.push((area as f32).to_bits());
            for v in piece
                .iter()
                .map(|k| k.position)
                .chain(piece.iter().map(|k| k.normal))
            {
                words.extend([v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]);
            }
            for k in piece {
                words.extend([k.uv.x.to_bits(), k.uv.y.to_bits()]);
                (low, high) = (low.min(k.position.y), high.max(k.position.y));
            }
        }
        let blades = ((area * f64::from(per_area)).round() as u32).min(room);
        let r = records + RECORD_WORDS * cell;
        let (low, high) = if list.is_empty() {
            (0.0, 0.0)
        } else {
            (low, high)
        };
        words[r..r + RECORD_WORDS].copy_from_slice(&[
            start as u32,
            list.len() as u32,
            blades,
            (area as f32).to_bits(),
            low.to_bits(),
            high.to_bits(),
        ]);
    }
    words
}

/// The barycentric weights of the point at share `f` (0..1) of a triangle's area:
/// f's base-4 digits pick, level by level, one of the four triangles the midpoints
/// cut a triangle into (the three corners' and the middle one), ten levels deep, and
/// the point is the last one's centre. Each quarter of f is a quarter of the area,
/// so the point is uniform by area, and a run of f is a compact patch (the
/// triangle's own stratification, after Basu and Owen's low-discrepancy triangle
/// sequences).
pub fn in_triangle(f: f32) -> Vec3 {
    let digits = (f * (1u32 << 20) as f32) as u32;
    let (mut a, mut b, mut c) = (Vec3::X, Vec3::Y, Vec3::Z);
    let mut level = 0;
    while level < 10 {
        let d = (digits >> (18 - 2 * level)) & 3;
        let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
        (a, b, c) = match d {
            0 => (a, ab, ca),
            1 => (ab, b, bc),
            2 => (ca, bc, c),
            _ => (bc, ca, ab),
        };
        level += 1;
    }
    (a + b + c) / 3.0
}

/// Pieces are split until no edge is longer than a tile's side over this, so that
/// even a mesh of a few large triangles spreads a tile's blades evenly.
pub const SPLIT: f32 = 8.0;

#[cfg(not(target_arch = "spirv"))]
impl Spot {
    /// The spot `t` of the way to `other` (a piece's corner as the table is built).
    fn lerp(self, other: Spot, t: f32) -> Spot {
        Spot {
            position: self.position.lerp(other.position, t),
            normal: self.normal.lerp(other.normal, t),
            uv: self.uv.lerp(other.uv, t),
        }
    }
}

/// `piece`, halved across its longest edge until no edge is longer than `longest`,
/// into `out` (pieces of no area left out).
#[cfg(not(target_arch = "spirv"))]
fn split(piece: [Spot; 3], longest: f32, out: &mut Vec<[Spot; 3]>) {
    let [a, b, c] = piece.map(|k| k.position);
    let area = crate::mesh::triangle_area(a, b, c);
    if area.is_nan() || area <= 0.0 {
        return;
    }
    let edges = [(a - b).length(), (b - c).length(), (c - a).length()];
    let (i, &length) = edges
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(y.1))
        .unwrap_or((0, &0.0));
    if length <= longest || out.len() > 1 << 20 {
        out.push(piece);
        return;
    }
    // Corners from the longest edge's start: (p, q) the edge, r the opposite.
    let [p, q, r] = [piece[i], piece[(i + 1) % 3], piece[(i + 2) % 3]];
    let m = p.lerp(q, 0.5);
    split([p, m, r], longest, out);
    split([m, q, r], longest, out);
}

/// The 30-bit Morton code of three 10-bit coordinates.
#[cfg(not(target_arch = "spirv"))]
fn morton3(x: u32, y: u32, z: u32) -> u32 {
    let spread = |v: u32| {
        let mut v = v.min(1023);
        v = (v | (v << 16)) & 0x0300_00ff;
        v = (v | (v << 8)) & 0x0300_f00f;
        v = (v | (v << 4)) & 0x030c_30c3;
        (v | (v << 2)) & 0x0924_9249
    };
    spread(x) | (spread(y) << 1) | (spread(z) << 2)
}

/// The part of the polygon `corners` inside the column over the square `lo`..`hi` in
/// x and z (Sutherland–Hodgman against its four sides), normals and texture
/// coordinates interpolated with the positions.
#[cfg(not(target_arch = "spirv"))]
fn clip_to_square(corners: &[Spot], lo: Vec2, hi: Vec2) -> Vec<Spot> {
    // Each side as (axis: 0 x, 2 z; bound; keep below the bound).
    let sides = [
        (0, lo.x, false),
        (0, hi.x, true),
        (2, lo.y, false),
        (2, hi.y, true),
    ];
    let mut polygon = corners.to_vec();
    for (axis, bound, below) in sides {
        let inside = |p: &Spot| {
            let d = p.position[axis] - bound;
            if below { d <= 0.0 } else { d >= 0.0 }
        };
        let mut out = Vec::with_capacity(polygon.len() + 1);
        for i in 0..polygon.len() {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            if inside(&a) {
                out.push(a);
            }
            if inside(&a) != inside(&b) {
                let t = (bound - a.position[axis]) / (b.position[axis] - a.position[axis]);
                out.push(a.lerp(b, t));
            }
        }
        polygon = out;
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::SurfaceMesh;
    use crate::tiles::{TERRAIN_MESH, TileParams, kept, tile_blade, tile_count};
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
        crate::paint::with_surface(Vec::new(), &table)
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
                let (lo, hi) = crate::tiles::tile_square(t, &params);
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
                    area += crate::mesh::triangle_area(corners[0], corners[1], corners[2]);
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
        let left_black = crate::paint::grey(&[0, 0, 0, 0, 255, 255, 255, 255]);
        let maps = crate::paint::words(&[(crate::paint::DENSITY, 8, 1, &left_black)]);
        let params = TileParams {
            half_extent: 4.0,
            ..params(2.0, 32)
        };
        let halves = |mesh: &SurfaceMesh| {
            let room = params.per_side * params.per_side;
            let set = crate::paint::with_surface(maps.clone(), &build(mesh, params.size, room));
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
}

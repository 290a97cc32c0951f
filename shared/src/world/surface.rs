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
//! header's [`paint::SURFACE`](crate::world::paint::SURFACE) gives where): [`HEADER_WORDS`]
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
    if set.len() <= crate::world::paint::SURFACE {
        return 0;
    }
    set[crate::world::paint::SURFACE] as usize
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
pub fn build(mesh: &crate::world::mesh::SurfaceMesh, size: f32, room: u32) -> Vec<u32> {
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
            area += f64::from(crate::world::mesh::triangle_area(a, b, c));
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
    let area = crate::world::mesh::triangle_area(a, b, c);
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
mod tests;

//! Triangle meshes the grass grows on: area-weighted scattering and surface queries (host only).
//!
//! The paper grows blades on arbitrary 3D surfaces (section 3): each blade keeps the
//! surface normal at its root as `up`. Roots are spread by area, so the density in
//! blades per square unit is the same on every triangle, small or large.

use crate::Blade;
use crate::world::generate::{HEIGHT, STIFFNESS, SplitMix64, WIDTH};
use spirv_std::glam::{Vec2, Vec3};

/// A triangle mesh the grass grows on: unit vertex normals, counter-clockwise triangles.
///
/// Every index in `triangles` is meant to be below `positions.len()`, with one normal
/// per position. The queries here skip triangles whose indices are out of range and
/// fall back to the face normal where a vertex normal is missing, so a malformed mesh
/// gives fewer blades, never a panic (except [`SurfaceMesh::triangle`], which indexes).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Vertex indices of each triangle, counter-clockwise seen from the normal side.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates, one per position, or none (empty): where painted maps are
    /// read on a mesh that has them (`surface`).
    pub uvs: Vec<Vec2>,
}

impl SurfaceMesh {
    /// The corners of triangle `i`.
    ///
    /// # Panics
    /// When `i` or one of its indices is out of range, like slice indexing.
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        self.triangles[i].map(|v| self.positions[v as usize])
    }

    /// The corners of triangle `i`, or `None` when it or one of its indices is out of range.
    pub(crate) fn corners(&self, i: usize) -> Option<[Vec3; 3]> {
        let [a, b, c] = *self.triangles.get(i)?;
        Some([
            *self.positions.get(a as usize)?,
            *self.positions.get(b as usize)?,
            *self.positions.get(c as usize)?,
        ])
    }

    /// Total area of the triangles.
    pub fn area(&self) -> f32 {
        (0..self.triangles.len())
            .map(|i| self.triangle_weight(i))
            .sum::<f64>() as f32
    }

    /// Area of triangle `i` as a scattering weight: zero when it is out of range or
    /// its area is not a finite positive number.
    fn triangle_weight(&self, i: usize) -> f64 {
        match self.corners(i) {
            Some([a, b, c]) => {
                let area = triangle_area(a, b, c);
                if area.is_finite() && area > 0.0 {
                    f64::from(area)
                } else {
                    0.0
                }
            }
            None => 0.0,
        }
    }

    /// The area-weighted mean of the triangles' upward facing (their unit normal's y):
    /// near 1 for a terrain, near 0 for a closed object (a torus, a planet).
    pub fn mean_upness(&self) -> f32 {
        let (mut up, mut area) = (0.0f64, 0.0f64);
        for i in 0..self.triangles.len() {
            if let Some([a, b, c]) = self.corners(i) {
                let n = (b - a).cross(c - a);
                let w = f64::from(n.length()) * 0.5;
                if w.is_finite() && w > 0.0 {
                    up += f64::from(n.normalize().y) * w;
                    area += w;
                }
            }
        }
        if area > 0.0 { (up / area) as f32 } else { 0.0 }
    }

    /// Smallest and largest corner of the box around the vertices; `None` when there
    /// are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// Appends the triangles of `other`, re-basing its indices past this mesh's vertices.
    ///
    /// Indices that would overflow `u32` saturate (and so stay out of range, skipped by
    /// the queries) rather than wrap onto unrelated vertices.
    /// Texture coordinates stay only while every part has them.
    pub fn append(&mut self, other: &SurfaceMesh) {
        let base = u32::try_from(self.positions.len()).unwrap_or(u32::MAX);
        if self.positions.is_empty() {
            self.uvs = other.uvs.clone();
        } else if self.has_uvs() && other.has_uvs() {
            self.uvs.extend_from_slice(&other.uvs);
        } else {
            self.uvs.clear();
        }
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| t.map(|v| v.saturating_add(base))),
        );
    }

    /// True when every vertex has texture coordinates.
    pub fn has_uvs(&self) -> bool {
        !self.positions.is_empty() && self.uvs.len() == self.positions.len()
    }

    /// The texture coordinates at barycentric `weights` of triangle `i`; zero
    /// without them.
    pub(crate) fn uv_at(&self, i: usize, weights: Vec3) -> Vec2 {
        let [a, b, c] = self.triangles[i];
        let uv = |v: u32| self.uvs.get(v as usize).copied().unwrap_or(Vec2::ZERO);
        uv(a) * weights.x + uv(b) * weights.y + uv(c) * weights.z
    }

    /// True when the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Unit face normal of the triangle (a, b, c): counter-clockwise corners see it
    /// pointing at them. `Vec3::Y` for a zero-area triangle.
    fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
        (b - a).cross(c - a).normalize_or(Vec3::Y)
    }

    /// The unit normal at barycentric `weights` of triangle `i` (corners `abc`): the
    /// interpolated vertex normals, or the face normal where they cancel or are missing.
    pub(crate) fn normal_at(&self, i: usize, abc: [Vec3; 3], weights: Vec3) -> Vec3 {
        let face = Self::face_normal(abc);
        let [ia, ib, ic] = self.triangles[i];
        let normal = |v: u32| self.normals.get(v as usize).copied();
        match (normal(ia), normal(ib), normal(ic)) {
            (Some(na), Some(nb), Some(nc)) => {
                let n = na * weights.x + nb * weights.y + nc * weights.z;
                // A sum this short means the vertex normals disagree too much to trust.
                if n.is_finite() && n.length_squared() > 1e-12 {
                    n.normalize()
                } else {
                    face
                }
            }
            _ => face,
        }
    }
}

/// Area of the triangle (a, b, c): half the length of (b − a) × (c − a).
pub fn triangle_area(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    0.5 * (b - a).cross(c - a).length()
}

/// A point on a surface and the unit normal there.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position on the surface.
    pub position: Vec3,
    /// Unit surface normal at `position`.
    pub normal: Vec3,
}

/// Offsets the seed of the blade attributes so they do not repeat the stream that placed
/// the roots (same seed, same roots in [`scatter_roots`] and [`scatter`]).
const ATTRIBUTE_STREAM: u64 = 0x5851_f42d_4c95_7f2d;

/// Root, up and triangle index of each scattered blade.
///
/// `count` roots are spread by area: each picks a triangle with probability
/// proportional to its area (a cumulative-area table and a binary search, so counts per
/// triangle are multinomial), then a uniform point in it with the square-root trick
/// `a·(1−√r1) + b·√r1·(1−r2) + c·√r1·r2`. Zero-area triangles get no blades. The
/// normal of each point is the interpolated vertex normal (unit; the face normal where
/// that interpolation is about zero). Same seed, same roots. Empty when the mesh has
/// no area.
pub fn scatter_roots(mesh: &SurfaceMesh, count: u32, seed: u64) -> Vec<(u32, SurfacePoint)> {
    // f64 sums keep the table exact enough for millions of triangles.
    let mut total = 0.0_f64;
    let mut last_positive = None;
    let cumulative: Vec<f64> = (0..mesh.triangles.len())
        .map(|i| {
            let weight = mesh.triangle_weight(i);
            if weight > 0.0 {
                last_positive = Some(i);
            }
            total += weight;
            total
        })
        .collect();
    let Some(last_positive) = last_positive else {
        return Vec::new();
    };

    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let pick = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * total;
            // The first triangle whose running total passes `pick`; a zero-area triangle
            // adds nothing to the total, so it is never the first to pass.
            let i = cumulative.partition_point(|&c| c <= pick);
            // `pick` rounds up to `total` once in a blue moon.
            let i = if i >= cumulative.len() {
                last_positive
            } else {
                i
            };
            let abc @ [a, b, c] = mesh.triangle(i);
            let s = rng.range(0.0, 1.0).sqrt();
            let r2 = rng.range(0.0, 1.0);
            let weights = Vec3::new(1.0 - s, s * (1.0 - r2), s * r2);
            let position = a * weights.x + b * weights.y + c * weights.z;
            let normal = mesh.normal_at(i, abc, weights);
            (i as u32, SurfacePoint { position, normal })
        })
        .collect()
}

/// Blades at rest on the mesh: roots from [`scatter_roots`], `up` the interpolated
/// vertex normal there, orientation, height, width and stiffness drawn like
/// [`crate::world::generate::square_field`] (same ranges). Same seed, same blades.
pub fn scatter(mesh: &SurfaceMesh, count: u32, seed: u64) -> Vec<Blade> {
    scatter_scaled(mesh, count, seed, 1.0)
}

/// [`scatter`] with blades `scale` times as tall and as wide, and `1/scale` times as
/// stiff, so they bend by the same share of their height under the same forces: the
/// recovery's displacement at equilibrium is force over stiffness (paper eq. 4).
/// Scale 1 is [`scatter`] exactly. The blades come in [`spatial_order`].
pub fn scatter_scaled(mesh: &SurfaceMesh, count: u32, seed: u64, scale: f32) -> Vec<Blade> {
    let mut rng = SplitMix64::new(seed ^ ATTRIBUTE_STREAM);
    let blades: Vec<Blade> = scatter_roots(mesh, count, seed)
        .into_iter()
        .map(|(_, root)| {
            let orientation = rng.range(0.0, core::f32::consts::TAU);
            let height = rng.range(HEIGHT.0, HEIGHT.1) * scale;
            let width = rng.range(WIDTH.0, WIDTH.1) * scale;
            let stiffness = rng.range(STIFFNESS.0, STIFFNESS.1) / scale;
            Blade::at_rest(
                root.position,
                root.normal,
                orientation,
                height,
                width,
                stiffness,
            )
        })
        .collect();
    spatial_order(blades)
}

/// `blades` ordered along the Z-order (Morton) curve of their roots over the roots'
/// bounding box, 21 bits an axis (Morton, *A computer oriented geodetic data base*,
/// IBM 1966); ties keep their order. Neighbours in the buffer then stand together,
/// so the 32 or 128 blades a GPU runs at once read the same slot of the colliders'
/// grid, the same clump cells and the same texels of the depth pyramid, and take the
/// same branches.
pub fn spatial_order(mut blades: Vec<Blade>) -> Vec<Blade> {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for b in &blades {
        lo = lo.min(b.root());
        hi = hi.max(b.root());
    }
    let scale = Vec3::splat(MORTON_CELLS) / (hi - lo).max(Vec3::splat(1e-6));
    blades.sort_by_cached_key(|b| {
        let q = ((b.root() - lo) * scale)
            .min(Vec3::splat(MORTON_CELLS))
            .as_uvec3();
        spread_bits(q.x) | spread_bits(q.y) << 1 | spread_bits(q.z) << 2
    });
    blades
}

/// The greatest cell index along an axis of [`spatial_order`]'s curve (21 bits).
const MORTON_CELLS: f32 = ((1 << 21) - 1) as f32;

/// The low 21 bits of `v` spread to every third bit of the result.
fn spread_bits(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

/// Blades for a density in blades per square unit (rounded), saturating at `u32::MAX`;
/// zero for a negative or non-finite density.
pub fn count_for_density(mesh: &SurfaceMesh, density: f32) -> u64 {
    let area: f64 = (0..mesh.triangles.len())
        .map(|i| mesh.triangle_weight(i))
        .sum();
    let count = (area * f64::from(density)).round();
    if count.is_nan() || count <= 0.0 {
        0
    } else {
        // `as` saturates, also for +inf.
        (count.min(f64::from(u32::MAX))) as u64
    }
}

/// Closest point to `p` on the triangle (a, b, c) and its barycentric weights
/// (Ericson, *Real-Time Collision Detection*, 5.1.5: find the Voronoi region of `p`).
fn closest_on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> (Vec3, Vec3) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Vec3::X);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Vec3::Y);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, Vec3::new(1.0 - v, v, 0.0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Vec3::Z);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, Vec3::new(1.0 - w, 0.0, w));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, Vec3::new(0.0, 1.0 - w, w));
    }
    let sum = va + vb + vc;
    if sum.is_nan() || sum <= 0.0 {
        // Only a (numerically) flat triangle gets here: it is its three edges.
        return [
            (a, b, Vec3::X, Vec3::Y),
            (b, c, Vec3::Y, Vec3::Z),
            (a, c, Vec3::X, Vec3::Z),
        ]
        .into_iter()
        .map(|(s, e, ws, we)| {
            let d = e - s;
            let t = if d.length_squared() > 0.0 {
                ((p - s).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (s + d * t, ws * (1.0 - t) + we * t)
        })
        .min_by(|x, y| p.distance_squared(x.0).total_cmp(&p.distance_squared(y.0)))
        .unwrap_or((a, Vec3::X));
    }
    let v = vb / sum;
    let w = vc / sum;
    (a + ab * v + ac * w, Vec3::new(1.0 - v - w, v, w))
}

/// The closest point of triangle `i` of `mesh` to `p`: its squared distance, the
/// point, its barycentric weights and the triangle's corners (`None` for a triangle
/// whose corners are missing, or so degenerate that the point is not finite).
pub(crate) fn closest_on_mesh_triangle(
    mesh: &SurfaceMesh,
    i: usize,
    p: Vec3,
) -> Option<(f32, Vec3, Vec3, [Vec3; 3])> {
    let abc = mesh.corners(i)?;
    let (q, weights) = closest_on_triangle(p, abc);
    let d = p.distance_squared(q);
    // A degenerate triangle can give no point at all: it is no candidate.
    d.is_finite().then_some((d, q, weights, abc))
}

/// Where the ray `origin + t·dir` meets triangle `i` of `mesh` (Möller–Trumbore, both
/// faces): t, the barycentric weights and the corners; `None` when it misses, runs
/// parallel to it, or meets it at t ≤ 0.
pub(crate) fn ray_mesh_triangle(
    mesh: &SurfaceMesh,
    i: usize,
    origin: Vec3,
    dir: Vec3,
) -> Option<(f32, Vec3, [Vec3; 3])> {
    let abc @ [a, b, c] = mesh.corners(i)?;
    let e1 = b - a;
    let e2 = c - a;
    let pvec = dir.cross(e2);
    let det = e1.dot(pvec);
    // |det| = |dir|·|e1 × e2|·cos(angle to the normal): relative, so the test does
    // not depend on the scale of the scene.
    let parallel = 1e-7 * dir.length() * e1.cross(e2).length();
    if !det.is_finite() || det.abs() <= parallel {
        return None;
    }
    let inv = 1.0 / det;
    let tvec = origin - a;
    let u = tvec.dot(pvec) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qvec = tvec.cross(e1);
    let v = dir.dot(qvec) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qvec) * inv;
    (t > 0.0).then_some((t, Vec3::new(1.0 - u - v, u, v), abc))
}

/// Closest point on the mesh to `p` (brute force over the triangles; [`bvh::MeshBvh`]
/// answers the same from a hierarchy), with the interpolated normal there; of equally
/// close triangles the first. `None` for a mesh without triangles.
pub fn closest_point(mesh: &SurfaceMesh, p: Vec3) -> Option<SurfacePoint> {
    let mut best: Option<(f32, usize, Vec3, Vec3, [Vec3; 3])> = None;
    for i in 0..mesh.triangles.len() {
        let Some((d, q, weights, abc)) = closest_on_mesh_triangle(mesh, i, p) else {
            continue;
        };
        if best.is_none_or(|(best_d, ..)| d < best_d) {
            best = Some((d, i, q, weights, abc));
        }
    }
    let (_, i, position, weights, abc) = best?;
    Some(SurfacePoint {
        position,
        normal: mesh.normal_at(i, abc, weights),
    })
}

/// First hit of the ray `origin + t·dir` (t > 0) with the mesh, with the interpolated
/// normal there (as stored, not turned towards the ray); of hits at the same t the
/// first triangle's. Both faces of a triangle are hit (Möller–Trumbore without
/// culling); rays parallel to a triangle miss it. Brute force; [`bvh::MeshBvh`] answers
/// the same from a hierarchy.
pub fn ray_hit(mesh: &SurfaceMesh, origin: Vec3, dir: Vec3) -> Option<SurfacePoint> {
    let mut best: Option<(f32, usize, Vec3, [Vec3; 3])> = None;
    for i in 0..mesh.triangles.len() {
        let Some((t, weights, abc)) = ray_mesh_triangle(mesh, i, origin, dir) else {
            continue;
        };
        if best.is_none_or(|(best_t, ..)| t < best_t) {
            best = Some((t, i, weights, abc));
        }
    }
    let (t, i, weights, abc) = best?;
    Some(SurfacePoint {
        position: origin + dir * t,
        normal: mesh.normal_at(i, abc, weights),
    })
}

pub mod bvh;

#[cfg(test)]
mod tests;

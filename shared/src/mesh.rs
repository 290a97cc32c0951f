//! Triangle meshes the grass grows on: area-weighted scattering and surface queries (host only).
//!
//! The paper grows blades on arbitrary 3D surfaces (section 3): each blade keeps the
//! surface normal at its root as `up`. Roots are spread by area, so the density in
//! blades per square unit is the same on every triangle, small or large.

use crate::Blade;
use crate::generate::{HEIGHT, STIFFNESS, SplitMix64, WIDTH};
use spirv_std::glam::Vec3;

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
    fn corners(&self, i: usize) -> Option<[Vec3; 3]> {
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
    pub fn append(&mut self, other: &SurfaceMesh) {
        let base = u32::try_from(self.positions.len()).unwrap_or(u32::MAX);
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| t.map(|v| v.saturating_add(base))),
        );
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
    fn normal_at(&self, i: usize, abc: [Vec3; 3], weights: Vec3) -> Vec3 {
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
/// [`crate::generate::square_field`] (same ranges). Same seed, same blades.
pub fn scatter(mesh: &SurfaceMesh, count: u32, seed: u64) -> Vec<Blade> {
    let mut rng = SplitMix64::new(seed ^ ATTRIBUTE_STREAM);
    scatter_roots(mesh, count, seed)
        .into_iter()
        .map(|(_, root)| {
            let orientation = rng.range(0.0, core::f32::consts::TAU);
            let height = rng.range(HEIGHT.0, HEIGHT.1);
            let width = rng.range(WIDTH.0, WIDTH.1);
            let stiffness = rng.range(STIFFNESS.0, STIFFNESS.1);
            Blade::at_rest(
                root.position,
                root.normal,
                orientation,
                height,
                width,
                stiffness,
            )
        })
        .collect()
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

/// Closest point on the mesh to `p` (brute force over the triangles), with the
/// interpolated normal there. `None` for a mesh without triangles.
pub fn closest_point(mesh: &SurfaceMesh, p: Vec3) -> Option<SurfacePoint> {
    let mut best: Option<(f32, usize, [Vec3; 3], Vec3, Vec3)> = None;
    for i in 0..mesh.triangles.len() {
        let Some(abc) = mesh.corners(i) else { continue };
        let (q, weights) = closest_on_triangle(p, abc);
        let d = p.distance_squared(q);
        if best.is_none_or(|(best_d, ..)| d < best_d) {
            best = Some((d, i, abc, q, weights));
        }
    }
    let (_, i, abc, position, weights) = best?;
    Some(SurfacePoint {
        position,
        normal: mesh.normal_at(i, abc, weights),
    })
}

/// First hit of the ray `origin + t·dir` (t > 0) with the mesh, with the interpolated
/// normal there (as stored, not turned towards the ray). Both faces of a triangle are
/// hit (Möller–Trumbore without culling); rays parallel to a triangle miss it.
pub fn ray_hit(mesh: &SurfaceMesh, origin: Vec3, dir: Vec3) -> Option<SurfacePoint> {
    let mut best: Option<(f32, usize, [Vec3; 3], Vec3)> = None;
    for i in 0..mesh.triangles.len() {
        let Some(abc @ [a, b, c]) = mesh.corners(i) else {
            continue;
        };
        let e1 = b - a;
        let e2 = c - a;
        let pvec = dir.cross(e2);
        let det = e1.dot(pvec);
        // |det| = |dir|·|e1 × e2|·cos(angle to the normal): relative, so the test does
        // not depend on the scale of the scene.
        let parallel = 1e-7 * dir.length() * e1.cross(e2).length();
        if !det.is_finite() || det.abs() <= parallel {
            continue;
        }
        let inv = 1.0 / det;
        let tvec = origin - a;
        let u = tvec.dot(pvec) * inv;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let qvec = tvec.cross(e1);
        let v = dir.dot(qvec) * inv;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let t = e2.dot(qvec) * inv;
        if t > 0.0 && best.is_none_or(|(best_t, ..)| t < best_t) {
            best = Some((t, i, abc, Vec3::new(1.0 - u - v, u, v)));
        }
    }
    let (t, i, abc, weights) = best?;
    Some(SurfacePoint {
        position: origin + dir * t,
        normal: mesh.normal_at(i, abc, weights),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh of separate triangles with face normals as vertex normals.
    fn soup(triangles: &[[Vec3; 3]]) -> SurfaceMesh {
        let mut mesh = SurfaceMesh::default();
        for (i, &abc) in triangles.iter().enumerate() {
            let n = SurfaceMesh::face_normal(abc);
            mesh.positions.extend(abc);
            mesh.normals.extend([n; 3]);
            let base = 3 * i as u32;
            mesh.triangles.push([base, base + 1, base + 2]);
        }
        mesh
    }

    /// Four right triangles of areas 1, 2, 3, 4, tilted differently, one upside down.
    fn four_triangles() -> SurfaceMesh {
        soup(&[
            [
                Vec3::ZERO,
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(2.0, 0.0, 0.0),
            ],
            [
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(5.0, 1.6, 1.2),
                Vec3::new(7.0, 0.0, 0.0),
            ],
            [
                Vec3::new(0.0, 3.0, 0.0),
                Vec3::new(3.0, 3.0, 0.0),
                Vec3::new(0.0, 3.0, 2.0),
            ],
            [
                Vec3::new(0.0, 0.0, 5.0),
                Vec3::new(0.0, 4.0, 5.0),
                Vec3::new(2.0, 0.0, 5.0),
            ],
        ])
    }

    /// Pearson's chi-square statistic of `observed` counts against `expected` ones.
    fn chi_square(observed: &[u32], expected: &[f64]) -> f64 {
        observed
            .iter()
            .zip(expected)
            .map(|(&o, &e)| (f64::from(o) - e).powi(2) / e)
            .sum()
    }

    /// Upper 0.1 % point of the chi-square distribution with 3 degrees of freedom: a
    /// correct sampler exceeds it with probability 0.001.
    const CHI_SQUARE_3DOF_P001: f64 = 16.27;

    /// Barycentric weights of `p` in the triangle (a, b, c) (in its plane).
    fn barycentric(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
        let (v0, v1, v2) = (b - a, c - a, p - a);
        let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
        let (d20, d21) = (v2.dot(v0), v2.dot(v1));
        let denom = d00 * d11 - d01 * d01;
        let v = (d11 * d20 - d01 * d21) / denom;
        let w = (d00 * d21 - d01 * d20) / denom;
        Vec3::new(1.0 - v - w, v, w)
    }

    #[test]
    fn area_bounds_append_and_empty() {
        let mesh = four_triangles();
        assert!((mesh.area() - 10.0).abs() < 1e-5);
        let (lo, hi) = mesh.bounds().unwrap();
        assert_eq!(lo, Vec3::ZERO);
        assert_eq!(hi, Vec3::new(7.0, 4.0, 5.0));
        assert_eq!(SurfaceMesh::default().bounds(), None);
        assert!(SurfaceMesh::default().is_empty());

        let mut twice = mesh.clone();
        twice.append(&mesh);
        assert_eq!(twice.triangles.len(), 8);
        assert_eq!(twice.triangles[4], [12, 13, 14]);
        assert_eq!(twice.triangle(7), mesh.triangle(3));
        assert!((twice.area() - 20.0).abs() < 1e-5);
    }

    #[test]
    fn counts_per_triangle_are_proportional_to_area() {
        let mesh = four_triangles();
        let n = 20_000;
        let mut observed = [0u32; 4];
        for (i, _) in scatter_roots(&mesh, n, 42) {
            observed[i as usize] += 1;
        }
        let expected: Vec<f64> = [1.0, 2.0, 3.0, 4.0]
            .iter()
            .map(|a| f64::from(n) * a / 10.0)
            .collect();
        // Counts per triangle are multinomial with p_i = area_i / total: Pearson's
        // statistic follows chi-square with 4 − 1 = 3 degrees of freedom.
        let x2 = chi_square(&observed, &expected);
        assert!(
            x2 < CHI_SQUARE_3DOF_P001,
            "chi-square {x2:.2} ≥ {CHI_SQUARE_3DOF_P001} (p < 0.001): counts {observed:?}, expected {expected:?}"
        );
    }

    #[test]
    fn zero_area_and_broken_triangles_get_no_blades() {
        let mut mesh = soup(&[
            [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            [Vec3::ZERO, Vec3::Z, Vec3::X],
            [Vec3::ONE, Vec3::ONE, Vec3::ONE],
        ]);
        mesh.triangles.push([0, 1, 99]);
        for (i, _) in scatter_roots(&mesh, 2000, 3) {
            assert_eq!(i, 1);
        }
        assert!(scatter(&SurfaceMesh::default(), 100, 1).is_empty());
        let flat = soup(&[[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]]);
        assert!(scatter(&flat, 100, 1).is_empty());
    }

    #[test]
    fn every_root_lies_on_its_triangle() {
        let mesh = four_triangles();
        for (i, root) in scatter_roots(&mesh, 5000, 9) {
            let abc = mesh.triangle(i as usize);
            let w = barycentric(root.position, abc);
            for x in w.to_array() {
                assert!((-1e-5..=1.0 + 1e-5).contains(&x), "weights {w} of {root:?}");
            }
            let n = SurfaceMesh::face_normal(abc);
            let off_plane = (root.position - abc[0]).dot(n).abs();
            assert!(off_plane < 1e-4, "{off_plane} off the plane of {i}");
        }
    }

    #[test]
    fn every_up_is_unit_and_on_the_side_of_the_vertex_normals() {
        // Vertex normals that differ per corner, all leaning to +Y, plus the tilted soup.
        let mut mesh = SurfaceMesh {
            positions: vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0), Vec3::X],
            normals: vec![
                Vec3::new(0.5, 1.0, 0.0).normalize(),
                Vec3::new(-0.3, 1.0, 0.4).normalize(),
                Vec3::new(0.0, 1.0, -0.8).normalize(),
            ],
            triangles: vec![[0, 1, 2]],
        };
        mesh.append(&four_triangles());
        let roots = scatter_roots(&mesh, 5000, 5);
        for ((i, root), blade) in roots.iter().zip(scatter(&mesh, 5000, 5)) {
            let up = blade.up_dir();
            assert!((up.length() - 1.0).abs() < 1e-5, "|up| = {}", up.length());
            assert_eq!(up, root.normal);
            assert_eq!(blade.root(), root.position);
            for v in mesh.triangles[*i as usize] {
                assert!(up.dot(mesh.normals[v as usize]) > 0.0);
            }
            assert!((HEIGHT.0..HEIGHT.1).contains(&blade.height()));
            assert!((WIDTH.0..WIDTH.1).contains(&blade.width()));
            assert!((STIFFNESS.0..STIFFNESS.1).contains(&blade.stiffness()));
        }
    }

    #[test]
    fn up_falls_back_to_the_face_normal_when_normals_cancel() {
        let mesh = SurfaceMesh {
            positions: vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0), Vec3::X],
            normals: vec![Vec3::ZERO; 3],
            triangles: vec![[0, 1, 2]],
        };
        for blade in scatter(&mesh, 100, 1) {
            assert_eq!(blade.up_dir(), Vec3::Y);
        }
    }

    #[test]
    fn same_seed_same_blades_different_seed_different() {
        let mesh = four_triangles();
        let a = scatter(&mesh, 1000, 7);
        assert_eq!(a.len(), 1000);
        assert_eq!(a, scatter(&mesh, 1000, 7));
        assert_ne!(a, scatter(&mesh, 1000, 8));
        assert_eq!(scatter_roots(&mesh, 1000, 7), scatter_roots(&mesh, 1000, 7));
    }

    #[test]
    fn roots_are_uniform_inside_a_triangle() {
        let abc = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-2.0, 1.0, 3.0),
            Vec3::new(4.0, 2.0, 1.0),
        ];
        let mesh = soup(&[abc]);
        let n = 20_000;
        // The midpoints cut the triangle into four of equal area: the corner triangle of
        // a holds the points with weight a ≥ ½, likewise b and c; the middle one the rest.
        let mut observed = [0u32; 4];
        for (_, root) in scatter_roots(&mesh, n, 11) {
            let w = barycentric(root.position, abc);
            let part = if w.x >= 0.5 {
                0
            } else if w.y >= 0.5 {
                1
            } else if w.z >= 0.5 {
                2
            } else {
                3
            };
            observed[part] += 1;
        }
        // The middle count is binomial(n, ¼): standard deviation √(¼·¾/n) ≈ 0.0031, so
        // 0.015 is about five of them (a false alarm about once in 1.7 million).
        let middle = f64::from(observed[3]) / f64::from(n);
        assert!((middle - 0.25).abs() < 0.015, "middle fraction {middle}");
        // And all four together, as in the per-triangle test (3 degrees of freedom).
        let x2 = chi_square(&observed, &[f64::from(n) / 4.0; 4]);
        assert!(
            x2 < CHI_SQUARE_3DOF_P001,
            "chi-square {x2:.2}: {observed:?}"
        );
    }

    #[test]
    fn density_rounds_and_saturates() {
        let mesh = four_triangles(); // area 10
        assert_eq!(count_for_density(&mesh, 2.5), 25);
        assert_eq!(count_for_density(&mesh, 0.26), 3);
        assert_eq!(count_for_density(&mesh, 1e30), u64::from(u32::MAX));
        assert_eq!(count_for_density(&mesh, f32::INFINITY), u64::from(u32::MAX));
        assert_eq!(count_for_density(&mesh, -1.0), 0);
        assert_eq!(count_for_density(&mesh, f32::NAN), 0);
        assert_eq!(count_for_density(&SurfaceMesh::default(), 10.0), 0);
    }

    /// The triangle (0,0,0), (0,0,2), (2,0,0) in y = 0, normal +Y.
    fn floor() -> SurfaceMesh {
        soup(&[[
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 0.0),
        ]])
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn closest_point_hand_worked() {
        let mesh = floor();
        // Straight above the inside: drop onto the plane.
        let q = closest_point(&mesh, Vec3::new(0.5, 3.0, 0.5)).unwrap();
        assert!(close(q.position, Vec3::new(0.5, 0.0, 0.5)));
        assert!(close(q.normal, Vec3::Y));
        // Beyond the hypotenuse x + z = 2: (2, 1, 2) drops to (2, 0, 2), outside, whose
        // nearest point on the edge from (0,0,2) to (2,0,0) is its midpoint (1, 0, 1).
        let q = closest_point(&mesh, Vec3::new(2.0, 1.0, 2.0)).unwrap();
        assert!(close(q.position, Vec3::new(1.0, 0.0, 1.0)), "{q:?}");
        // Beyond the edge on the x axis, below the plane.
        let q = closest_point(&mesh, Vec3::new(1.2, -1.0, -3.0)).unwrap();
        assert!(close(q.position, Vec3::new(1.2, 0.0, 0.0)), "{q:?}");
        // Beyond the corner (0,0,0).
        let q = closest_point(&mesh, Vec3::new(-1.0, 0.5, -2.0)).unwrap();
        assert!(close(q.position, Vec3::ZERO), "{q:?}");
        // Beyond the corner (2,0,0).
        let q = closest_point(&mesh, Vec3::new(5.0, 0.0, -0.5)).unwrap();
        assert!(close(q.position, Vec3::new(2.0, 0.0, 0.0)), "{q:?}");
        // Two triangles: the nearer one wins.
        let mut two = mesh.clone();
        two.append(&soup(&[[
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 2.0),
        ]]));
        let q = closest_point(&two, Vec3::new(0.5, 1.5, 0.5)).unwrap();
        assert!(close(q.position, Vec3::new(0.5, 2.0, 0.5)) && close(q.normal, -Vec3::Y));
        assert_eq!(closest_point(&SurfaceMesh::default(), Vec3::ZERO), None);
        // A flat triangle is its edges: no NaN.
        let flat = soup(&[[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]]);
        let q = closest_point(&flat, Vec3::new(1.5, 1.0, 0.0)).unwrap();
        assert!(close(q.position, Vec3::new(1.5, 0.0, 0.0)), "{q:?}");
    }

    #[test]
    fn ray_hit_hand_worked() {
        let mesh = floor();
        // Down onto the top face.
        let hit = ray_hit(&mesh, Vec3::new(0.5, 2.0, 0.25), -Vec3::Y).unwrap();
        assert!(close(hit.position, Vec3::new(0.5, 0.0, 0.25)));
        assert!(close(hit.normal, Vec3::Y));
        // Up onto the back face, slanted: from (0,−1,0) towards (1,0,0.5), t = 1.
        let hit = ray_hit(&mesh, Vec3::new(0.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.5)).unwrap();
        assert!(close(hit.position, Vec3::new(1.0, 0.0, 0.5)), "{hit:?}");
        // Misses: pointing away (t < 0), beyond the hypotenuse, parallel, zero direction.
        assert_eq!(ray_hit(&mesh, Vec3::new(0.5, 2.0, 0.5), Vec3::Y), None);
        assert_eq!(ray_hit(&mesh, Vec3::new(1.5, 2.0, 1.5), -Vec3::Y), None);
        assert_eq!(ray_hit(&mesh, Vec3::new(-1.0, 0.0, 0.5), Vec3::X), None);
        assert_eq!(ray_hit(&mesh, Vec3::new(0.5, 2.0, 0.5), Vec3::ZERO), None);
        // The first of two hits.
        let mut two = mesh.clone();
        two.append(&soup(&[[
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(2.0, 1.0, 0.0),
        ]]));
        let hit = ray_hit(&two, Vec3::new(0.5, 2.0, 0.5), -Vec3::Y).unwrap();
        assert!(close(hit.position, Vec3::new(0.5, 1.0, 0.5)));
        let hit = ray_hit(&two, Vec3::new(0.5, -2.0, 0.5), Vec3::Y).unwrap();
        assert!(close(hit.position, Vec3::new(0.5, 0.0, 0.5)));
    }
}

//! Unit tests of the mesh sampling, closest point and ray hit.

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
        uvs: Vec::new(),
    };
    mesh.append(&four_triangles());
    // The blades come in spatial order: each found by its root.
    let bits = |p: Vec3| p.to_array().map(f32::to_bits);
    let roots: std::collections::HashMap<_, _> = scatter_roots(&mesh, 5000, 5)
        .into_iter()
        .map(|(i, root)| (bits(root.position), (i, root)))
        .collect();
    for blade in scatter(&mesh, 5000, 5) {
        let (i, root) = &roots[&bits(blade.root())];
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
        uvs: Vec::new(),
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

mod hierarchy {
    use super::*;
    use crate::world::mesh::bvh::MeshBvh;
    use proptest::prelude::*;

    /// A grid of `n` × `n` quads over [0, n]² at y = 0, two triangles each, sharing
    /// vertices: many equally close triangles, rays landing on shared edges.
    fn grid(n: u32) -> SurfaceMesh {
        let mut mesh = SurfaceMesh::default();
        for z in 0..=n {
            for x in 0..=n {
                mesh.positions.push(Vec3::new(x as f32, 0.0, z as f32));
                // Normals that differ per vertex, so a wrong triangle shows.
                mesh.normals
                    .push(Vec3::new(0.1 * (x % 3) as f32, 1.0, 0.1 * (z % 2) as f32).normalize());
            }
        }
        let at = |x: u32, z: u32| z * (n + 1) + x;
        for z in 0..n {
            for x in 0..n {
                mesh.triangles.push([at(x, z), at(x, z + 1), at(x + 1, z)]);
                mesh.triangles
                    .push([at(x + 1, z), at(x, z + 1), at(x + 1, z + 1)]);
            }
        }
        mesh
    }

    fn point(extent: f32) -> impl Strategy<Value = Vec3> {
        (-extent..extent, -extent..extent, -extent..extent).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// Triangles anywhere in a small box, some of them slivers and some repeated.
    fn soup_mesh() -> impl Strategy<Value = SurfaceMesh> {
        prop::collection::vec((point(4.0), point(4.0), point(4.0), 0..4u8), 1..80).prop_map(
            |tris| {
                let corners: Vec<[Vec3; 3]> = tris
                    .iter()
                    .map(|&(a, b, c, kind)| match kind {
                        0 => [a, b, a + (b - a) * 0.5],
                        1 => [a, a, c],
                        _ => [a, b, c],
                    })
                    .chain(tris.iter().take(3).map(|&(a, b, c, _)| [a, b, c]))
                    .collect();
                soup(&corners)
            },
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

        /// The hierarchy gives exactly the exhaustive search's answers: the same
        /// closest point and normal, the same first hit.
        #[test]
        fn the_hierarchy_answers_as_the_exhaustive_search(
            mesh in soup_mesh(),
            queries in prop::collection::vec((point(6.0), point(1.0)), 1..16),
        ) {
            let bvh = MeshBvh::new(&mesh);
            for (p, dir) in queries {
                prop_assert_eq!(bvh.closest_point(&mesh, p), closest_point(&mesh, p));
                prop_assert_eq!(bvh.ray_hit(&mesh, p, dir), ray_hit(&mesh, p, dir));
            }
        }

        /// On a grid of shared vertices, where many triangles are equally close and
        /// dropped rays land on shared edges, the first triangle wins in both.
        #[test]
        fn ties_on_a_grid_go_to_the_first_triangle(
            n in 1u32..24,
            queries in prop::collection::vec((0u32..48, 0u32..48, -2.0f32..2.0), 1..24),
        ) {
            let mesh = grid(n);
            let bvh = MeshBvh::new(&mesh);
            for (x, z, y) in queries {
                // On vertices, edges and quad centres, above, on and below the grid.
                let p = Vec3::new(x as f32 * 0.5, y, z as f32 * 0.5);
                prop_assert_eq!(bvh.closest_point(&mesh, p), closest_point(&mesh, p));
                let above = p + Vec3::Y * 3.0;
                prop_assert_eq!(
                    bvh.ray_hit(&mesh, above, Vec3::NEG_Y),
                    ray_hit(&mesh, above, Vec3::NEG_Y)
                );
            }
        }
    }

    #[test]
    fn an_empty_mesh_has_no_answer() {
        let mesh = SurfaceMesh::default();
        let bvh = MeshBvh::new(&mesh);
        assert_eq!(bvh.closest_point(&mesh, Vec3::ZERO), None);
        assert_eq!(bvh.ray_hit(&mesh, Vec3::ZERO, Vec3::Y), None);
    }
}

#[test]
fn upness_tells_a_terrain_from_a_closed_object() {
    let flat = SurfaceMesh {
        positions: vec![Vec3::ZERO, Vec3::Z, Vec3::X],
        normals: vec![Vec3::Y; 3],
        triangles: vec![[0, 1, 2]],
        uvs: Vec::new(),
    };
    assert!((flat.mean_upness() - 1.0).abs() < 1e-6);
    // A closed box: every face has its opposite, the mean is zero.
    let mut closed = flat.clone();
    closed
        .positions
        .extend([Vec3::Y, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)]);
    closed.normals.extend([-Vec3::Y; 3]);
    closed.triangles.push([3, 4, 5]);
    assert!(closed.mean_upness().abs() < 1e-6);
    assert_eq!(SurfaceMesh::default().mean_upness(), 0.0);
}

#[test]
fn scaled_blades_are_the_same_blades_resized() {
    let mesh = SurfaceMesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::new(4.0, 0.0, 0.0),
        ],
        normals: vec![Vec3::Y; 3],
        triangles: vec![[0, 1, 2]],
        uvs: Vec::new(),
    };
    let one = scatter(&mesh, 50, 9);
    assert_eq!(scatter_scaled(&mesh, 50, 9, 1.0), one);
    let small = scatter_scaled(&mesh, 50, 9, 0.25);
    for (a, b) in one.iter().zip(&small) {
        assert_eq!(a.root(), b.root());
        assert_eq!(a.orientation(), b.orientation());
        assert!((b.height() - 0.25 * a.height()).abs() < 1e-6);
        assert!((b.width() - 0.25 * a.width()).abs() < 1e-6);
        // Four times as stiff: the same forces bend it by a quarter of the distance.
        assert!((b.stiffness() - 4.0 * a.stiffness()).abs() < 1e-4);
    }
}

#[test]
fn blades_come_in_z_order_and_a_workgroup_stands_together() {
    // Every third bit: 0b111 → 0b1001001; the top of 21 bits to bit 60.
    assert_eq!(spread_bits(0b111), 0b100_1001);
    assert_eq!(spread_bits(1 << 20), 1 << 60);
    // Four roots of a square in XZ, given out of order, come along the Z curve:
    // (0, 0), then x, then z, then both.
    let at = |x: f32, z: f32| Blade::at_rest(Vec3::new(x, 0.0, z), Vec3::Y, 0.0, 1.0, 0.1, 5.0);
    let given = vec![at(1.0, 1.0), at(0.0, 1.0), at(1.0, 0.0), at(0.0, 0.0)];
    let roots: Vec<Vec3> = spatial_order(given).iter().map(|b| b.root()).collect();
    let expected = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    assert_eq!(roots, expected.map(|(x, z)| Vec3::new(x, 0.0, z)));
    // A field of 16,384 blades on 64 x 64 units (4 a square unit): the same blades,
    // and each run of 128 (a workgroup of the compute pass) close together. Measured:
    // a run's bounding box 86.6 square units on average, 2.7 times the 32 its blades
    // cover (in generation order: 3,960, nearly the whole field).
    let mesh = soup(&[
        [
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 64.0),
            Vec3::new(64.0, 0.0, 0.0),
        ],
        [
            Vec3::new(64.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 64.0),
            Vec3::new(64.0, 0.0, 64.0),
        ],
    ]);
    let blades = scatter(&mesh, 16_384, 3);
    let mut shuffled: Vec<Blade> = scatter_roots(&mesh, 16_384, 3)
        .iter()
        .map(|(_, r)| Blade::at_rest(r.position, r.normal, 0.0, 1.0, 0.1, 5.0))
        .collect();
    let box_area = |run: &[Blade]| {
        let lo = run.iter().fold(Vec3::MAX, |a, b| a.min(b.root()));
        let hi = run.iter().fold(Vec3::MIN, |a, b| a.max(b.root()));
        (hi.x - lo.x) * (hi.z - lo.z)
    };
    let mean = |blades: &[Blade]| {
        let runs: Vec<f32> = blades.chunks(128).map(box_area).collect();
        runs.iter().sum::<f32>() / runs.len() as f32
    };
    let (ordered, unordered) = (mean(&blades), mean(&shuffled));
    assert!(ordered < 100.0, "{ordered} square units a run");
    assert!(
        unordered > 1000.0,
        "{unordered} square units a run unordered"
    );
    let key = |b: &Blade| (b.root().x.to_bits(), b.root().z.to_bits());
    shuffled = spatial_order(shuffled);
    let sorted_keys = |v: &[Blade]| {
        let mut k: Vec<_> = v.iter().map(key).collect();
        k.sort();
        k
    };
    assert_eq!(sorted_keys(&blades), sorted_keys(&shuffled));
}

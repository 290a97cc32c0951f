//! Host benchmarks of the shared math, per blade: what one compute-shader thread or
//! one tessellation-evaluation invocation runs. `cargo bench -p shared`.

use divan::{Bencher, black_box};
use shared::Blade;
use shared::cull::blade as cull;
use shared::cull::blade::{CullParams, cull_outcome};
use shared::cull::hiz;
use shared::cull::hiz::HiZLayout;
use shared::cull::lod::{focal_pixels, screen_level};
use shared::draw::shape::{SHAPE_QUADRATIC, surface_point};
use shared::glam::camera::rh;
use shared::glam::{Mat4, Vec3, Vec4};
use shared::sim::colliders::ColliderSet;
use shared::sim::impulse::NO_IMPULSES;
use shared::sim::simulate::{Environment, simulate};
use shared::world::generate::{side_for, square_field};
use shared::world::mesh::bvh::MeshBvh;
use shared::world::mesh::{SurfaceMesh, closest_point, ray_hit};

fn main() {
    divan::main();
}

const BLADES: u32 = 4096;

fn field() -> Vec<Blade> {
    square_field(BLADES, side_for(BLADES), 7)
}

fn camera() -> (Vec3, Mat4) {
    let eye = Vec3::new(0.0, 3.0, -25.0);
    let view = rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y);
    let proj = rh::proj::vulkan::perspective(50f32.to_radians(), 16.0 / 9.0, 0.1, 500.0);
    (eye, proj * view)
}

/// One frame (one fixed step) of forces, collisions and validation for every blade.
#[divan::bench(args = [0, 4])]
fn simulate_one_step(bencher: Bencher, balls: usize) {
    let blades = field();
    let env = Environment {
        colliders: balls as u32,
        ..Default::default()
    };
    let spheres: Vec<Vec4> = (0..balls)
        .map(|i| Vec4::new(i as f32 * 2.0 - 3.0, 0.5, 0.0, 1.0))
        .collect();
    let set = ColliderSet::spheres(&spheres);
    bencher
        .counter(divan::counter::ItemsCount::new(BLADES))
        .bench(|| {
            for b in &blades {
                black_box(simulate((*b, 0.0), &env, set.nearby(), &NO_IMPULSES, 0, 1));
            }
        });
}

/// The four cull tests in order, occlusion against a pyramid of a far wall.
#[divan::bench]
fn cull_every_blade(bencher: Bencher) {
    let blades = field();
    let (eye, view_proj) = camera();
    let (layout, pyramid): (HiZLayout, Vec<f32>) = hiz::build(&vec![0.999; 320 * 180], 320, 180);
    let params = CullParams {
        orientation_threshold: 0.9,
        frustum_tolerance: 0.5,
        max_distance: 60.0,
        buckets: 8,
        enabled: cull::ALL,
        edge_on_pixels: 2.0,
        focal_pixels: 1000.0,
        padding: [0; 2],
    };
    bencher
        .counter(divan::counter::ItemsCount::new(BLADES))
        .bench(|| {
            for (i, b) in blades.iter().enumerate() {
                black_box(cull_outcome(
                    b, i as u32, eye, view_proj, &params, &pyramid, &layout,
                ));
            }
        });
}

/// The evaluation stage's work for one blade at 7 segments: 16 surface points.
#[divan::bench]
fn shape_one_blade(bencher: Bencher) {
    let blade = field()[0];
    bencher.bench(|| {
        for row in 0..8 {
            for side in 0..2 {
                let (u, v) = (side as f32, row as f32 / 7.0);
                black_box(surface_point(black_box(&blade), u, v, SHAPE_QUADRATIC, 0.5));
            }
        }
    });
}

/// The control stage's level of detail.
#[divan::bench]
fn lod_level(bencher: Bencher) {
    let focal = focal_pixels(50f32.to_radians(), 1080.0);
    bencher.bench(|| {
        black_box(screen_level(
            black_box(1.8),
            black_box(37.0),
            focal,
            16.0,
            7.0,
            1.0,
        ))
    });
}

/// The host's depth-pyramid reduction of a 1920×1080 depth image.
#[divan::bench(sample_count = 20)]
fn hiz_build_1080p(bencher: Bencher) {
    let depth: Vec<f32> = (0..1920 * 1080).map(|i| (i % 977) as f32 / 977.0).collect();
    bencher.bench(|| black_box(hiz::build(&depth, 1920, 1080)));
}

/// Rolling ground of 1,448 × 1,448 quads: 4,193,408 triangles, the size at which issue
/// 15 measured the exhaustive ball placement at about 35 ms.
fn big_ground() -> &'static SurfaceMesh {
    static MESH: std::sync::OnceLock<SurfaceMesh> = std::sync::OnceLock::new();
    MESH.get_or_init(|| {
        let n = 1448u32;
        let mut mesh = SurfaceMesh::default();
        for z in 0..=n {
            for x in 0..=n {
                let (fx, fz) = (x as f32 * 0.1, z as f32 * 0.1);
                mesh.positions
                    .push(Vec3::new(fx, (fx * 0.3).sin() + (fz * 0.2).cos(), fz));
                mesh.normals.push(Vec3::Y);
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
    })
}

/// Where the k-th placement drops the ball: points spread over the ground.
fn placement(k: u32) -> Vec3 {
    let t = k as f32 * 2.399_963;
    Vec3::new(72.4 + 60.0 * t.cos(), 10.0, 72.4 + 60.0 * t.sin())
}

/// One placement of the ball through the hierarchy on 4 M triangles: a ray dropped
/// onto the ground, and the closest point (what sliding it asks).
#[divan::bench(sample_count = 50)]
fn ball_placement_4m_triangles_bvh(bencher: Bencher) {
    let mesh = big_ground();
    let bvh = MeshBvh::new(mesh);
    let mut k = 0;
    bencher.bench_local(|| {
        k += 1;
        let p = placement(k);
        black_box(bvh.ray_hit(mesh, p, Vec3::NEG_Y));
        black_box(bvh.closest_point(mesh, p - Vec3::Y * 9.0))
    });
}

/// The same placement by the exhaustive search over every triangle.
#[divan::bench(sample_count = 3, sample_size = 1)]
fn ball_placement_4m_triangles_exhaustive(bencher: Bencher) {
    let mesh = big_ground();
    let mut k = 0;
    bencher.bench_local(|| {
        k += 1;
        let p = placement(k);
        black_box(ray_hit(mesh, p, Vec3::NEG_Y));
        black_box(closest_point(mesh, p - Vec3::Y * 9.0))
    });
}

/// Building the hierarchy over 4 M triangles (once per scene, at start-up).
#[divan::bench(sample_count = 3, sample_size = 1)]
fn bvh_build_4m_triangles(bencher: Bencher) {
    let mesh = big_ground();
    bencher.bench(|| black_box(MeshBvh::new(mesh)));
}

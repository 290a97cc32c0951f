//! Host benchmarks of the shared math, per blade: what one compute-shader thread or
//! one tessellation-evaluation invocation runs. `cargo bench -p shared`.

use divan::{Bencher, black_box};
use shared::Blade;
use shared::collide::MAX_COLLIDERS;
use shared::cull::{self, CullParams, cull_outcome};
use shared::generate::{side_for, square_field};
use shared::glam::camera::rh;
use shared::glam::{Mat4, Vec3, Vec4};
use shared::hiz::{self, HiZLayout};
use shared::lod::{focal_pixels, screen_level};
use shared::shape::{SHAPE_QUADRATIC, surface_point};
use shared::simulate::{Environment, simulate};

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
    let mut spheres = [Vec4::ZERO; MAX_COLLIDERS];
    for (i, s) in spheres.iter_mut().take(balls).enumerate() {
        *s = Vec4::new(i as f32 * 2.0 - 3.0, 0.5, 0.0, 1.0);
    }
    bencher
        .counter(divan::counter::ItemsCount::new(BLADES))
        .bench(|| {
            for b in &blades {
                black_box(simulate((*b, 0.0), &env, &spheres, 0, 1));
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

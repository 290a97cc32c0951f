//! Blades from tiles (issue 19): the GPU's generation against the host's.

use runner::app::headless::FORMAT;
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use shared::glam::{IVec2, Vec3};
use shared::tiles::{TERRAIN_FLAT, TERRAIN_VALLEY, TileParams, TilePush, kept, tile_blade};

/// `compute::generate_tile` against the host running `shared::tiles::tile_blade` on
/// the same tile: the same blades kept (at most 0.2 % decided differently, where a
/// blade's rank lies within rounding of its density: the GPU's square root need not be
/// correctly rounded), and each kept blade's control points, width and stiffness
/// within 1e-5 (relative, of at least 1). Three tiles of the plane: one beside the
/// camera (every blade at its own width), one 40 units off (a fifth kept, widened),
/// one 120 units off (a few kept); and one of the valley across its bare path, the
/// camera some 20 metres above it. Measured on lavapipe: every blade decided alike,
/// equal to the bit on the plane and within 2.1e-7 on the valley (its sines); 2,304,
/// 490, 40 and 432 kept. Planted fault: the GPU generating blade i + 1 in slot i
/// failed (control points 6.1 apart).
#[test]
fn the_gpu_generates_the_hosts_blades() {
    tests::with_device("the_gpu_generates_the_hosts_blades", |ctx| {
        let scene = Scene::build(
            &SceneKind::Plane,
            None,
            BladeCount::Total(64),
            5,
            |_| Ok(()),
        )
        .unwrap();
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
        let camera = Vec3::new(4.0, 1.7, 4.0);
        for (terrain, tile, at_least, at_most) in [
            (TERRAIN_FLAT, IVec2::new(0, 0), 1.0, 1.0),
            (TERRAIN_FLAT, IVec2::new(4, 2), 0.1, 0.4),
            (TERRAIN_FLAT, IVec2::new(-15, 2), 0.0, 0.05),
            // Across the valley's path near the origin (its centre line at x = 0).
            (TERRAIN_VALLEY, IVec2::new(-1, 0), 0.1, 0.6),
        ] {
            let params = TileParams {
                terrain,
                ..TileParams::default()
            };
            let push = TilePush {
                params,
                tile,
                pad: Default::default(),
                camera: camera.extend(0.0),
            };
            let gpu = renderer.generate_tile(&push).unwrap();
            let count = (params.per_side * params.per_side) as usize;
            assert_eq!(gpu.len(), count);
            let (mut differ, mut both, mut largest) = (0, 0, 0.0f32);
            for (i, g) in gpu.iter().enumerate() {
                let h = tile_blade(tile, i as u32, camera, &params);
                if kept(g) != kept(&h) {
                    differ += 1;
                    continue;
                }
                if !kept(&h) {
                    continue;
                }
                both += 1;
                for (a, b) in [(g.v0, h.v0), (g.v1, h.v1), (g.v2, h.v2), (g.up, h.up)] {
                    let d = (a - b).abs() / b.abs().max(shared::glam::Vec4::ONE);
                    largest = largest.max(d.max_element());
                }
            }
            let share = both as f64 / count as f64;
            println!(
                "tile {tile}: {both} of {count} kept on both, {differ} decided differently, \
                 largest difference {largest:e}"
            );
            assert!(differ * 500 <= count, "{differ} blades decided differently");
            assert!(largest <= 1e-5, "{largest}");
            assert!(
                (at_least..=at_most).contains(&share),
                "{share} of the blades kept at tile {tile}"
            );
        }
    });
}

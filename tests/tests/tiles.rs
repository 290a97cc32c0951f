//! Blades from tiles: the GPU's generation against the host's.

use runner::app::headless::FORMAT;
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use shared::glam::{IVec2, Vec2, Vec3, Vec3Swizzles};
use shared::gpu::layout::TilePush;
use shared::sim::impulse::{IMPULSE_BLAST, IMPULSE_DOWNWASH, Impulse, Impulses, NO_IMPULSES};
use shared::world::tiles::{TERRAIN_FLAT, TERRAIN_VALLEY, TileParams, far_blade, kept, tile_blade};

/// A renderer to run the tile passes with (its own field is a few blades of the plane).
fn renderer(ctx: &std::sync::Arc<runner::vulkan::Context>) -> Renderer {
    let scene = Scene::build(
        &SceneKind::Plane,
        None,
        BladeCount::Total(64),
        5,
        |_| Ok(()),
    )
    .unwrap();
    Renderer::new(ctx, &scene.meshes(), FORMAT).unwrap()
}

/// `compute::generate_tile` against the host running `shared::world::tiles::tile_blade` on
/// the same tile: the same blades kept (at most 0.2 % decided differently, where a
/// blade's rank lies within rounding of its density: the GPU's square root need not be
/// correctly rounded), and each kept blade's control points, width and stiffness
/// within 1e-5 (relative, of at least 1). Three tiles of the plane: one beside the
/// camera (every blade at its own width), one 40 units off (a tenth kept, widened),
/// one 160 units off (a few kept); and one of the valley across its bare path, the
/// camera some 20 metres above it. Measured on lavapipe: every blade decided alike,
/// equal to the bit on the plane and within 1.2e-6 on the valley (its sines); 4,096,
/// 431, 42 and 791 kept. Planted fault: the GPU generating blade i + 1 in slot i
/// failed (control points 6.1 apart).
#[test]
fn the_gpu_generates_the_hosts_blades() {
    tests::with_device("the_gpu_generates_the_hosts_blades", |ctx| {
        let renderer = renderer(&ctx);
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
                slot: Default::default(),
                camera: camera.extend(0.0),
            };
            let gpu = renderer.generate_tile(&push).unwrap();
            let count = (params.per_side * params.per_side) as usize;
            assert_eq!(gpu.len(), count);
            let (mut differ, mut both, mut largest) = (0, 0, 0.0f32);
            for (i, g) in gpu.iter().enumerate() {
                let h = tile_blade(tile, i as u32, camera, &params, &[]);
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

/// `compute::select_tiles` against the host running `shared::cull::tile::tile_in_view` on
/// the same square of candidates (80 × 80 tiles of 32/3 units around the camera, reach
/// 300): the same tiles, but where a corner lies within rounding of a plane of the
/// view (at most 0.5 % of those selected; measured on lavapipe: none of the 678 and
/// 665 selected differ). Two cameras, looking a little down and a little up.
/// Planted fault: the GPU reaching half as far failed (856 tiles differ).
#[test]
fn the_gpu_selects_the_hosts_tiles() {
    use shared::cull::tile::tile_in_view;
    use shared::glam::camera::rh;
    use shared::glam::{UVec2, Vec4};
    use shared::gpu::layout::SelectPush;
    tests::with_device("the_gpu_selects_the_hosts_tiles", |ctx| {
        let renderer = renderer(&ctx);
        let params = TileParams::default();
        let eye = Vec3::new(3.0, 1.7, -2.0);
        for look in [Vec3::new(10.0, 1.0, -20.0), Vec3::new(-5.0, 6.0, -20.0)] {
            let view = rh::view::look_at_mat4(eye, look, Vec3::Y);
            let view_proj = rh::proj::vulkan::perspective(1.0, 16.0 / 9.0, 0.1, 2000.0) * view;
            let push = SelectPush {
                view_proj,
                camera: eye.extend(300.0),
                first: IVec2::new(-40, -40),
                count: UVec2::new(80, 80),
                ground: Vec4::new(0.0, 0.0, 0.0, 0.0),
                params,
                far: Default::default(),
            };
            let mut gpu = renderer.select_tiles(&push).unwrap();
            gpu.sort_by_key(|t| (t.x, t.y));
            let host: Vec<IVec2> = (-40..40)
                .flat_map(|x| (-40..40).map(move |z| IVec2::new(x, z)))
                .filter(|&t| {
                    let span = shared::cull::tile::tile_box(t, &params, (0.0, 0.0), &[]);
                    tile_in_view(t, view_proj, eye, &params, span, 300.0)
                })
                .collect();
            let differ = host.iter().filter(|t| !gpu.contains(t)).count()
                + gpu.iter().filter(|t| !host.contains(t)).count();
            println!(
                "looking at {look}: {} tiles on the GPU, {} on the host, {differ} differ",
                gpu.len(),
                host.len()
            );
            assert!(host.len() > 100, "{} tiles in view", host.len());
            assert!(differ * 200 <= host.len(), "{differ} tiles differ");
        }
    });
}

/// Two blades of the same height, within the GPU's float rounding (a product of three
/// factors, which the NVIDIA H100 fuses differently from the host: 1e-7 relative).
fn same_height(gpu: &shared::Blade, host: &shared::Blade) -> bool {
    (gpu.height() - host.height()).abs() <= 1e-6 * host.height()
}

/// A small tiled world on the plane: tiles of 4 units with 16² blades, every blade
/// kept to 6 units, a pool of `pool` tiles for those within 3 units, room for 32,768
/// far blades out to 40 units, the world `half` units each way.
fn small_world(pool: u32, half: f32) -> (Scene, runner::tiles::TiledSpec) {
    let mut scene = Scene::build(
        &SceneKind::Plane,
        None,
        BladeCount::Total(64),
        5,
        |_| Ok(()),
    )
    .unwrap();
    let spec = runner::tiles::TiledSpec {
        params: TileParams {
            size: 4.0,
            per_side: 16,
            seed: 3,
            full_distance: 6.0,
            terrain: TERRAIN_FLAT,
            half_extent: half,
            ..TileParams::default()
        },
        pool_tiles: pool,
        pool_radius: 3.0,
        far_blades: 1 << 15,
        reach: 40.0,
        ground: (0.0, 0.0),
        area: f64::from(2.0 * half).powi(2),
    };
    scene.make_tiled(spec);
    (scene, spec)
}

/// One frame of no time of `scene` seen by `camera` at `size`: its pixels, and the
/// driver (finished) whose renderer holds the frame's buffers.
fn still_frame(
    ctx: &std::sync::Arc<runner::vulkan::Context>,
    scene: &Scene,
    settings: &shared::settings::Settings,
    camera: &runner::camera::OrbitCamera,
    size: (u32, u32),
) -> (Vec<u8>, runner::app::driver::FrameDriver) {
    blown_frame(ctx, scene, settings, camera, size, &Impulses::default())
}

/// [`still_frame`] with the wind `impulses` blowing.
fn blown_frame(
    ctx: &std::sync::Arc<runner::vulkan::Context>,
    scene: &Scene,
    settings: &shared::settings::Settings,
    camera: &runner::camera::OrbitCamera,
    (width, height): (u32, u32),
    impulses: &Impulses,
) -> (Vec<u8>, runner::app::driver::FrameDriver) {
    let mut target = runner::app::headless::Offscreen::new(ctx, width, height).unwrap();
    let renderer = Renderer::new(ctx, &scene.meshes(), FORMAT).unwrap();
    let mut driver = runner::app::driver::FrameDriver::new(ctx, renderer).unwrap();
    let eye = camera.viewpoint(target.size());
    let request = settings.request(&eye, &[]).with_impulses(impulses);
    driver
        .run(&mut target, 0.0, |_| request.clone(), true)
        .unwrap();
    driver.finish().unwrap();
    (target.pixels().unwrap(), driver)
}

/// [`small_world`] 80 units wide with every blade kept at any distance and room for
/// them all, for the painted maps' tests.
fn open_world() -> (Scene, runner::tiles::TiledSpec) {
    let (mut scene, mut spec) = small_world(8, 40.0);
    spec.params.full_distance = 1e4;
    spec.far_blades = 1 << 17;
    spec.reach = 200.0;
    scene.make_tiled(spec);
    (scene, spec)
}

/// A camera `at` (x, z) on the plane, 2.9 units up, looking 10 units along −z.
fn camera_at(at: shared::glam::Vec2) -> runner::camera::OrbitCamera {
    let mut camera = runner::camera::OrbitCamera::framing(10.0);
    camera.target = Vec3::new(at.x, 0.5, at.y - 10.0);
    camera.yaw = 0.0;
    camera.pitch = 0.2;
    camera.distance = 12.0;
    camera
}

/// A whole tiled frame against the host: the far tiles the GPU listed are the tiles
/// in view (`tiles::tile_in_view`) the pool does not hold, each with its
/// `tiles::far_count` blades equal to the host's `far_blade` (the same kept, control
/// points within 1e-5) and their ids; the pool's tiles hold the host's blades, drawn
/// as wide as `tiles::drawn_width` says at their distance, and every far blade's map
/// point (`tiles::pack_map_point`) is the host's within a step. On the plane, on a
/// mesh's surface (the built-in hills, tiled over its triangles by
/// `shared::surface`) and on an OBJ square under a density map read at its texture
/// coordinates. Measured on lavapipe: the plane 76 far tiles (2,843 blades), the
/// hills 39 (1,368), the textured square 39 (1,319), none short of room, every blade
/// alike. On the NVIDIA H100 the same, except 22 far and 7 pool blades of the hills
/// rooted elsewhere in their piece (at most 4.8e-4 away: where the GPU's division
/// rounds the share of a piece's area differently, `surface::in_triangle` carries a
/// digit) and the textured square's points within 1.1e-4. Planted fault: the far generation packing blade k + 1's map point in slot k
/// failed (on the textured square). Planted
/// faults: the far generation writing blade k + 1 in slot k failed (540 blades
/// decided differently); the far generation growing the hills' tiles on flat ground
/// failed (480).
#[test]
fn a_tiled_frame_generates_the_hosts_blades() {
    tests::with_device("a_tiled_frame_generates_the_hosts_blades", |ctx| {
        let (scene, spec) = small_world(8, 1000.0);
        let calm = Impulses::default();
        tiled_frame_against_the_host(&ctx, &scene, &spec, Vec2::new(1.0, 2.0), &calm);
        let (scene, spec) = mesh_world();
        tiled_frame_against_the_host(&ctx, &scene, &spec, Vec2::new(-1.0, 4.0), &calm);
        let (scene, spec) = textured_world();
        tiled_frame_against_the_host(&ctx, &scene, &spec, Vec2::new(-1.0, 4.0), &calm);
    });
}

/// [`a_tiled_frame_generates_the_hosts_blades`] with a blast and a rotor's downwash
/// blowing over the far tiles: the GPU's far blades lean as the host's
/// (`tiles::far_blade` with the impulses), and the impulses move them.
#[test]
fn the_far_tiles_lean_in_the_wind_impulses() {
    tests::with_device("the_far_tiles_lean_in_the_wind_impulses", |ctx| {
        let (scene, spec) = small_world(8, 1000.0);
        let mut impulses = Impulses::default();
        let blast = Impulse::new(
            IMPULSE_BLAST,
            Vec3::new(-20.0, 0.0, -20.0),
            -0.1,
            60.0,
            80.0,
            10.0,
        );
        let rotor = Impulse::new(
            IMPULSE_DOWNWASH,
            Vec3::new(30.0, 0.0, -40.0),
            -1.0,
            40.0,
            60.0,
            10.0,
        );
        impulses.add(blast).unwrap();
        impulses.add(rotor).unwrap();
        tiled_frame_against_the_host(&ctx, &scene, &spec, Vec2::new(1.0, 2.0), &impulses);
    });
}

/// A 16-unit square read from an OBJ file whose texture coordinates run against x
/// (u = 0.5 − x/16), under a density map black on its left half: tiled over its
/// triangles, the map read at each blade's texture coordinates (the square's x > 0
/// bare). Tiles as [`mesh_world`]'s.
fn textured_world() -> (Scene, runner::tiles::TiledSpec) {
    let mut obj = String::new();
    let n = 8;
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (
                -8.0 + 16.0 * i as f32 / n as f32,
                -8.0 + 16.0 * j as f32 / n as f32,
            );
            // OBJ's v runs up the image: v = 1 − (z/16 + 0.5) puts the image's top at −z.
            obj += &format!("v {x} 0 {z}\nvt {} {}\n", 0.5 - x / 16.0, 0.5 - z / 16.0);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i + 1;
            let (a, b, c, d) = (v, v + 1, v + n + 1, v + n + 2);
            obj += &format!("f {a}/{a} {c}/{c} {b}/{b}\nf {b}/{b} {c}/{c} {d}/{d}\n");
        }
    }
    let path = std::env::temp_dir().join(format!("grass-textured-{}.obj", std::process::id()));
    std::fs::write(&path, obj).unwrap();
    let kind = SceneKind::File(path.clone());
    let file = kind.read().unwrap();
    let mut scene = Scene::build(&kind, file, BladeCount::Total(64), 5, |_| Ok(())).unwrap();
    let _ = std::fs::remove_file(&path);
    assert!(scene.surface.has_uvs());
    let left_black = shared::world::paint::grey(&[0, 0, 0, 0, 255, 255, 255, 255]);
    scene.paint =
        shared::world::paint::words(&[(shared::world::paint::DENSITY, 8, 1, &left_black)]);
    let (_, mut spec) = mesh_world();
    spec.ground = scene.ground_range();
    spec.area = f64::from(scene.surface.area());
    scene.make_tiled(spec);
    (scene, spec)
}

/// The built-in hills (16 units wide) tiled over their triangles: [`small_world`]'s
/// layout with tiles of 2 (room for 16² blades), every blade kept to 3 units, 4 pool
/// tiles for those within 1 unit.
fn mesh_world() -> (Scene, runner::tiles::TiledSpec) {
    let mut scene = Scene::build(
        &SceneKind::Hills,
        None,
        BladeCount::Total(64),
        5,
        |_| Ok(()),
    )
    .unwrap();
    let (_, mut spec) = small_world(4, 8.0);
    spec.params.size = 2.0;
    spec.params.full_distance = 3.0;
    spec.params.terrain = shared::world::tiles::TERRAIN_MESH;
    spec.pool_radius = 1.0;
    spec.ground = scene.ground_range();
    spec.area = f64::from(scene.surface.area());
    scene.make_tiled(spec);
    (scene, spec)
}

/// [`a_tiled_frame_generates_the_hosts_blades`] on `scene` tiled by `spec`, the
/// camera [`camera_at`] `at`.
fn tiled_frame_against_the_host(
    ctx: &std::sync::Arc<runner::vulkan::Context>,
    scene: &Scene,
    spec: &runner::tiles::TiledSpec,
    at: shared::glam::Vec2,
    impulses: &Impulses,
) {
    use shared::cull::tile::{tile_box, tile_in_view};
    use shared::gpu::counters::{
        COUNTER_COUNT, COUNTER_TILE_BLADES, COUNTER_TILES, COUNTER_TILES_SHORT,
    };
    use shared::gpu::layout::IDS_WORDS;
    use shared::gpu::layout::{TILE_WORDS, TILES_LIST};
    use shared::world::tiles::{blade_id, drawn_width, far_blade, far_count, pack_map_point};
    let params = spec.params;
    let map = &scene.paint;
    let size = (160, 120);
    let orbit = camera_at(at);
    let eye = orbit.viewpoint(size);
    let settings = scene.settings();
    // A frame of no time: the forces as the settings give them, at time 0.
    let forces = shared::sim::simulate::Environment {
        impulses: impulses.live(),
        ..settings.environment(0)
    };
    let (_, driver) = blown_frame(ctx, scene, &settings, &orbit, size, impulses);
    let r = &driver.renderer;
    let capacity = scene.blade_count() as usize;
    let blades: Vec<shared::Blade> = r.download(&r.field.blades, capacity).unwrap();
    let ids: Vec<u32> = r
        .download(r.field.ids.as_ref().unwrap(), IDS_WORDS * capacity)
        .unwrap();
    let words = spec.tile_words() as usize;
    let tiles: Vec<u32> = r.download(r.field.tiles.as_ref().unwrap(), words).unwrap();
    let counters: Vec<u32> = r.download(&r.field.counters, COUNTER_COUNT).unwrap();
    let held = r.tiles.as_ref().unwrap().held();
    let camera = eye.position;
    let per_tile = spec.tile_blades();

    // The far list against the host's selection.
    let listed = counters[COUNTER_TILES] as usize;
    let mut gpu_tiles = Vec::new();
    let mut far_blades = 0;
    let (mut differ, mut largest) = (0, 0.0f32);
    let (mut moved, mut farthest) = (0, 0.0f32);
    let mut blown = 0;
    for t in 0..listed {
        let at = TILES_LIST + TILE_WORDS * t;
        let tile = IVec2::new(tiles[at] as i32, tiles[at + 1] as i32);
        let (first, count) = (tiles[at + 2] as usize, tiles[at + 3]);
        gpu_tiles.push(tile);
        let span = tile_box(tile, &params, spec.ground, map);
        assert_eq!(count, far_count(tile, camera, &params, span, map), "{tile}");
        far_blades += count;
        for k in 0..count {
            let g = &blades[first + k as usize];
            // A frame of no time: the wind's pose at time 0.
            let h = far_blade(tile, k, camera, &params, map, &forces, impulses.slots());
            let calm = far_blade(tile, k, camera, &params, map, &forces, &NO_IMPULSES);
            blown += usize::from((h.tip() - calm.tip()).length() > 1e-3);
            assert_eq!(ids[IDS_WORDS * (first + k as usize)], blade_id(tile, k));
            // A decision at a threshold may fall either way: whether a blade is kept.
            if kept(g) != kept(&h) {
                differ += 1;
                continue;
            }
            // On a mesh, the part of a piece a root falls in (`surface::in_triangle`,
            // from the share of the piece's area: the GPU's division may round it
            // otherwise, and the point jumps by a cell where a digit carries).
            let off = (g.root() - h.root()).length();
            if off > 1e-5 {
                moved += 1;
                farthest = farthest.max(off);
                continue;
            }
            // Where it reads the maps, within a step of the packing.
            let (word, host) = (
                ids[IDS_WORDS * (first + k as usize) + 1],
                pack_map_point(tile, k, &h, &params, map),
            );
            let step = |w: u32| shared::glam::IVec2::new((w & 0xffff) as i32, (w >> 16) as i32);
            assert!(
                (step(word) - step(host)).abs().max_element() <= 1,
                "{tile} {k}: map point {} on the GPU, {} on the host; root {} and {}",
                step(word),
                step(host),
                g.root(),
                h.root()
            );
            for (a, b) in [(g.v0, h.v0), (g.v1, h.v1), (g.v2, h.v2), (g.up, h.up)] {
                let d = (a - b).abs() / b.abs().max(shared::glam::Vec4::ONE);
                largest = largest.max(d.max_element());
            }
        }
    }
    assert_eq!(counters[COUNTER_TILES_SHORT], 0);
    assert_eq!(counters[COUNTER_TILE_BLADES], far_blades);
    let reach_tiles = (spec.reach / params.size).ceil() as i32 + 1;
    let centre = (shared::glam::Vec2::new(camera.x, camera.z) / params.size)
        .floor()
        .as_ivec2();
    let mut host_tiles: Vec<IVec2> = Vec::new();
    for z in -reach_tiles..=reach_tiles {
        for x in -reach_tiles..=reach_tiles {
            let tile = centre + IVec2::new(x, z);
            let pooled = held.iter().any(|&(t, _)| t == tile);
            let span = tile_box(tile, &params, spec.ground, map);
            let seen = tile_in_view(tile, eye.view_proj, camera, &params, span, spec.reach);
            if seen && !pooled {
                host_tiles.push(tile);
            }
        }
    }
    gpu_tiles.sort_by_key(|t| (t.x, t.y));
    host_tiles.sort_by_key(|t| (t.x, t.y));
    println!(
        "{}: {listed} far tiles ({far_blades} blades), {} pool tiles, {differ} blades decided \
         differently, {moved} rooted elsewhere in their piece (at most {farthest:e} away), \
         largest difference {largest:e}",
        scene.name,
        held.len()
    );
    assert!(listed > 20, "{listed} far tiles");
    assert_eq!(gpu_tiles, host_tiles);
    assert!(
        differ * 500 <= far_blades as usize,
        "{differ} decided differently"
    );
    // Measured: none on lavapipe; on the NVIDIA H100 22 of the hills' 1,368 (1.6 %).
    assert!(moved * 40 <= far_blades, "{moved} rooted elsewhere");
    // Relative to the point's size: measured at most 6.4e-6 on lavapipe and 1.1e-4 on
    // the NVIDIA H100 (a far blade's settled pose on the textured square).
    assert!(largest <= 5e-4, "{largest}");
    if impulses.live() > 0 {
        println!("{blown} of {far_blades} far blades leaned by the wind impulses");
        // Measured: all 2,843; with the impulses starting after the frame, none.
        assert!(
            blown * 10 >= far_blades as usize * 9,
            "{blown} leaned by the impulses"
        );
    }

    // The pool's tiles, rooted as the far ones are (and as rarely elsewhere).
    assert!(!held.is_empty());
    let (mut pool_moved, mut widest) = (0, 0.0f32);
    for &(tile, slot) in &held {
        for k in 0..per_tile {
            let i = slot * per_tile as usize + k as usize;
            let (g, h) = (&blades[i], tile_blade(tile, k, camera, &params, map));
            assert_eq!(ids[IDS_WORDS * i], blade_id(tile, k));
            if (g.root() - h.root()).length() > 1e-5 {
                pool_moved += 1;
                continue;
            }
            assert!(
                same_height(g, &h),
                "{tile} {k}: {} against {}",
                g.height(),
                h.height()
            );
            if h.height() > 0.0 {
                let width = drawn_width(tile, k, h.root(), camera, &params, map);
                widest = widest.max((g.width() - width).abs() / width.max(1e-3));
            }
        }
    }
    let pool_blades = held.len() as u32 * per_tile;
    println!(
        "{pool_moved} of the pool's {pool_blades} blades rooted elsewhere in their piece; \
         widths within {widest:e}"
    );
    // Relative: measured at most 2.2e-4 on lavapipe and 1.1e-4 on the H100 (the hills).
    assert!(widest <= 5e-4, "widths {widest} apart");
    assert!(
        pool_moved * 40 <= pool_blades,
        "{pool_moved} rooted elsewhere"
    );
}

/// Blades of `tile`'s slot: their control points and collision strengths.
fn tile_state(
    renderer: &Renderer,
    tile: IVec2,
    per_tile: usize,
) -> Vec<(shared::glam::Vec3, shared::glam::Vec3, f32)> {
    let tiles = renderer.tiles.as_ref().unwrap();
    let slot = tiles.slot_of(tile).expect("the trampled tile in the pool");
    let count = renderer.field.blade_count as usize;
    let blades: Vec<shared::Blade> = renderer.download(&renderer.field.blades, count).unwrap();
    let strengths: Vec<f32> = renderer.download(&renderer.field.strengths, count).unwrap();
    (slot * per_tile..(slot + 1) * per_tile)
        .map(|i| (blades[i].guide(), blades[i].tip(), strengths[i]))
        .collect()
}

/// A ball tramples a tile for half a second, then the camera either stays or flies
/// 200 units away (the pool of 16 slots takes the tiles there, evicting the camera's
/// old ones, but not the ball's) for
/// two seconds and comes back: the trampled tile kept its slot, and its blades' state
/// (control points and collision strengths) is the same to the bit as if the camera
/// had stayed. Its strengths fell as the decay says: max(η − 0.25 · 2 s, 0) within
/// 1e-4 of each blade's at the ball's leaving. Planted fault: no pin for trails (the
/// trampled tile neither needed nor pinned) failed: the tile had lost its slot.
#[test]
fn a_trail_survives_the_camera_leaving_and_fades_as_the_decay_says() {
    use runner::app::driver::FrameDriver;
    use runner::app::headless::Offscreen;
    use shared::glam::{Vec2, Vec4};
    tests::with_device("a_trail_survives_the_camera_leaving", |ctx| {
        let (scene, spec) = small_world(16, 1000.0);
        let per_tile = spec.tile_blades() as usize;
        let settings = scene.settings();
        assert_eq!(settings.trample_decay, 0.25);
        let ball = Vec4::new(1.0, 0.6, 1.0, 1.0);
        let trail = shared::world::tiles::tile_of(Vec2::new(ball.x, ball.z), &spec.params);
        // The camera's own tiles (six) and the ball's (nine) apart.
        let home = Vec2::new(1.0, 20.0);
        let mut states = Vec::new();
        for leaves in [false, true] {
            let mut target = Offscreen::new(&ctx, 96, 64).unwrap();
            let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
            let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
            let mut frame = |driver: &mut FrameDriver, at: Vec2, balls: &[Vec4]| {
                let eye = camera_at(at).viewpoint(target.size());
                let request = settings.request(&eye, balls);
                driver
                    .run(&mut target, 1.0 / 60.0, |_| request.clone(), false)
                    .unwrap();
            };
            for _ in 0..30 {
                frame(&mut driver, home, &[ball]);
            }
            driver.finish().unwrap();
            let trampled = tile_state(&driver.renderer, trail, per_tile);
            let away = if leaves { Vec2::new(200.0, 2.0) } else { home };
            for _ in 0..120 {
                frame(&mut driver, away, &[]);
            }
            frame(&mut driver, home, &[]);
            driver.finish().unwrap();
            let pool = driver.renderer.tiles.as_ref().unwrap().stats;
            if leaves {
                assert!(pool.evictions >= 5, "{pool:?}: the pool never turned over");
            }
            let after = tile_state(&driver.renderer, trail, per_tile);
            // Two seconds and a frame without the ball (121 frames, 121 steps of 1/60 s
            // at 120 steps a second: 242 steps).
            let seconds = 121.0 / 60.0;
            let bent = trampled.iter().filter(|s| s.2 > 0.0).count();
            assert!(bent > per_tile / 20, "{bent} blades trampled");
            for (before, now) in trampled.iter().zip(&after) {
                let expected = (before.2 - 0.25 * seconds).max(0.0);
                assert!(
                    (now.2 - expected).abs() < 1e-4,
                    "{} against {expected}",
                    now.2
                );
            }
            states.push(after);
        }
        let differ = states[0]
            .iter()
            .zip(&states[1])
            .filter(|(a, b)| a != b)
            .count();
        println!("{differ} of {per_tile} trampled blades differ after the camera left");
        assert_eq!(differ, 0);
    });
}

/// Device memory of a tiled world does not depend on its size: the renderer's
/// allocations for worlds 2 and 32 km wide are the same, to the byte.
#[test]
fn a_larger_world_takes_no_more_device_memory() {
    use runner::app::driver::FrameDriver;
    use runner::app::headless::Offscreen;
    tests::with_device("a_larger_world_takes_no_more_device_memory", |ctx| {
        let mut used = Vec::new();
        for half in [1000.0, 16000.0] {
            let (scene, _) = small_world(8, half);
            let mut target = Offscreen::new(&ctx, 96, 64).unwrap();
            let before = ctx.device_memory().0;
            let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
            let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
            let eye = camera_at(shared::glam::Vec2::ZERO).viewpoint(target.size());
            let request = scene.settings().request(&eye, &[]);
            for _ in 0..3 {
                driver
                    .run(&mut target, 1.0 / 60.0, |_| request.clone(), false)
                    .unwrap();
            }
            driver.finish().unwrap();
            used.push(ctx.device_memory().0 - before);
        }
        println!("device memory: {used:?} bytes");
        assert_eq!(used[0], used[1]);
        assert!(used[0] > 0);
    });
}

/// Centre (x, z) of the painted disk.
const DISK: shared::glam::Vec2 = shared::glam::Vec2::new(-10.0, -8.0);

/// A density map with a disk in it (white within 16 units of (−10, −8), black beyond
/// 20, a 32-pixel map over a world 80 units wide): blades grow where the map says.
/// Counted per ring around the disk's centre, the GPU's blades of a frame seen from
/// above equal the host's (`tiles::tile_blade` with the same map); none beyond the
/// disk and its blending; and in the image (from 70 units, 46° down) grass covers the
/// disk and not the ground around it. Measured on lavapipe: 2,456, 3,418 and 0 blades
/// in the three rings on both; grass on 26 % of the disk's pixels (thin blades seen
/// from above), 0 % outside. Planted fault: the GPU reading the map's rows from +z
/// failed (GPU [1656, 2016, 2156] against the host's [2456, 3418, 0]).
#[test]
fn a_density_map_paints_where_grass_grows() {
    use runner::app::driver::FrameDriver;
    use runner::app::headless::Offscreen;
    use shared::gpu::counters::{COUNTER_COUNT, COUNTER_TILES};
    use shared::gpu::layout::{TILE_WORDS, TILES_LIST};
    tests::with_device("a_density_map_paints_where_grass_grows", |ctx| {
        let (mut scene, mut spec) = small_world(8, 40.0);
        spec.params.per_side = 8;
        spec.params.full_distance = 1e4;
        spec.reach = 200.0;
        scene.make_tiled(spec);
        let side = 32u32;
        let texels: Vec<u8> = (0..side * side)
            .map(|i| {
                let (x, y) = ((i % side) as f32 + 0.5, (i / side) as f32 + 0.5);
                // Pixels of 2.5 units: the disk's edge from 16 to 20 units around
                // (−10, −8) (pixel 16 is x = 0, row 16 is z = 0).
                let r = (shared::glam::Vec2::new(x, y) - 16.0) * 2.5 - DISK;
                let r = r.length();
                (255.0 * (1.0 - ((r - 16.0) / 4.0).clamp(0.0, 1.0))) as u8
            })
            .collect();
        let texels = shared::world::paint::grey(&texels);
        scene.paint =
            shared::world::paint::words(&[(shared::world::paint::DENSITY, side, side, &texels)]);
        let (width, height) = (128, 128);
        let mut target = Offscreen::new(&ctx, width, height).unwrap();
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
        let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
        let mut camera = runner::camera::OrbitCamera::framing(80.0);
        camera.target = Vec3::new(DISK.x, 0.0, DISK.y);
        camera.yaw = 0.0;
        camera.pitch = 0.8;
        camera.distance = 70.0;
        let eye = camera.viewpoint(target.size());
        let mut settings = scene.settings();
        settings.look.style = shared::settings::Look::Paper;
        settings.cull.tests = shared::settings::CullTests::NONE;
        let request = settings.request(&eye, &[]);
        driver
            .run(&mut target, 0.0, |_| request.clone(), true)
            .unwrap();
        driver.finish().unwrap();
        let image = image::RgbaImage::from_raw(width, height, target.pixels().unwrap()).unwrap();
        let r = &driver.renderer;
        let capacity = scene.blade_count() as usize;
        let blades: Vec<shared::Blade> = r.download(&r.field.blades, capacity).unwrap();
        let words = spec.tile_words() as usize;
        let tiles: Vec<u32> = r.download(r.field.tiles.as_ref().unwrap(), words).unwrap();
        let counters: Vec<u32> = r.download(&r.field.counters, COUNTER_COUNT).unwrap();
        let position = eye.position;
        // Rings 0-14, 14-24 (the edge and the map's blending), 24 on.
        let ring = |b: &shared::Blade| {
            let d = (shared::glam::Vec2::new(b.root().x, b.root().z) - DISK).length();
            usize::from(d >= 14.0) + usize::from(d >= 24.0)
        };
        let (mut gpu, mut host) = ([0u32; 3], [0u32; 3]);
        let mut seen = Vec::new();
        for t in 0..counters[COUNTER_TILES] as usize {
            let at = TILES_LIST + TILE_WORDS * t;
            let tile = IVec2::new(tiles[at] as i32, tiles[at + 1] as i32);
            let (first, count) = (tiles[at + 2] as usize, tiles[at + 3] as usize);
            seen.push(tile);
            for b in blades[first..first + count].iter().filter(|b| kept(b)) {
                gpu[ring(b)] += 1;
            }
        }
        let pool = r.tiles.as_ref().unwrap().held();
        let per_tile = spec.tile_blades();
        for &(tile, slot) in &pool {
            seen.push(tile);
            let range = slot * per_tile as usize..(slot + 1) * per_tile as usize;
            for b in blades[range].iter().filter(|b| kept(b)) {
                gpu[ring(b)] += 1;
            }
        }
        for &tile in &seen {
            for k in 0..per_tile {
                let b = tile_blade(tile, k, position, &spec.params, &scene.paint);
                if kept(&b) {
                    host[ring(&b)] += 1;
                }
            }
        }
        // Grass pixels whose ground point lies inside the disk (within 12 units) and
        // outside it (24 to 36 units).
        let clip_to_world = eye.view_proj.inverse();
        let (mut inside, mut inside_green, mut outside, mut outside_green) = (0, 0, 0, 0);
        for (x, y, p) in image.enumerate_pixels() {
            let ndc = shared::glam::Vec2::new(
                (x as f32 + 0.5) / width as f32 * 2.0 - 1.0,
                (y as f32 + 0.5) / height as f32 * 2.0 - 1.0,
            );
            let near = clip_to_world.project_point3(ndc.extend(0.0));
            let far = clip_to_world.project_point3(ndc.extend(1.0));
            if far.y >= near.y {
                continue;
            }
            let ground = near + (far - near) * (near.y / (near.y - far.y));
            let d = (shared::glam::Vec2::new(ground.x, ground.z) - DISK).length();
            let green = p[1] > p[0] && p[1] > p[2];
            if d < 12.0 {
                inside += 1;
                inside_green += u32::from(green);
            } else if d > 24.0 && d < 36.0 {
                outside += 1;
                outside_green += u32::from(green);
            }
        }
        let (inside, outside) = (
            f64::from(inside_green) / f64::from(inside),
            f64::from(outside_green) / f64::from(outside),
        );
        println!(
            "blades by ring (0-14, 14-24, 24+): GPU {gpu:?}, host {host:?}; grass on {:.0} % \
             of the disk's pixels, {:.0} % outside",
            100.0 * inside,
            100.0 * outside
        );
        assert_eq!(gpu, host);
        assert!(gpu[0] > 1000 && gpu[2] == 0, "{gpu:?}");
        image
            .save(tests::artifact_dir().join("density_map.png"))
            .ok();
        assert!(inside > 0.15 && outside < 0.02, "{inside} {outside}");
    });
}

/// A height map and a colour map, each split down x = 0 (8-pixel maps over a world
/// 80 units wide: the split blends from x = −5 to 5): the GPU's blades are as tall as
/// the host's `tile_blade` with the same maps, those left of −5 a quarter of those
/// right of 5 (grey 64 halves, white doubles); and in the natural look the colour map
/// (red on the left, white on the right) takes the green from the left quarter of the
/// image and leaves the right quarter as it was without the map. Measured on
/// lavapipe: heights equal to the bit, ratio 0.250; the left quarter's green 13 %
/// lower (the ground fills most pixels), the right quarter's pixels 0.04 apart (of 3 ×
/// 255). Planted fault: the colour map read
/// mirrored (at −x) failed (0 % lower, 21.9 apart).
#[test]
fn height_and_colour_maps_paint_the_blades() {
    use shared::world::paint::{COLOUR, HEIGHT, grey, words};
    tests::with_device("height_and_colour_maps_paint_the_blades", |ctx| {
        let (mut scene, spec) = open_world();
        let heights = grey(&[64, 64, 64, 64, 255, 255, 255, 255]);
        let colours = [[255u8, 0, 0, 255], [255, 255, 255, 255]];
        let colours: Vec<[u8; 4]> = (0..8).map(|i| colours[i / 4]).collect();
        let (width, height) = (192, 192);
        let mut camera = runner::camera::OrbitCamera::framing(80.0);
        camera.target = Vec3::ZERO;
        camera.yaw = 0.0;
        camera.pitch = 0.9;
        camera.distance = 25.0;
        let mut settings = scene.settings();
        settings.look.style = shared::settings::Look::Natural;
        settings.look.shadows = false;
        let mut images = Vec::new();
        let mut heights_by_side = [(0.0f64, 0u32); 2];
        for with_colour in [false, true] {
            let mut maps = vec![(HEIGHT, 8, 1, heights.as_slice())];
            if with_colour {
                maps.push((COLOUR, 8, 1, colours.as_slice()));
            }
            scene.paint = words(&maps);
            let (pixels, driver) = still_frame(&ctx, &scene, &settings, &camera, (width, height));
            let eye = camera.viewpoint((width, height));
            images.push(pixels);
            if with_colour {
                continue;
            }
            let r = &driver.renderer;
            let blades: Vec<shared::Blade> = r
                .download(&r.field.blades, scene.blade_count() as usize)
                .unwrap();
            let words_ = spec.tile_words() as usize;
            let tiles: Vec<u32> = r.download(r.field.tiles.as_ref().unwrap(), words_).unwrap();
            let counters: Vec<u32> = r
                .download(&r.field.counters, shared::gpu::counters::COUNTER_COUNT)
                .unwrap();
            use shared::gpu::counters::COUNTER_TILES;
            use shared::gpu::layout::{TILE_WORDS, TILES_LIST};
            for t in 0..counters[COUNTER_TILES] as usize {
                let at = TILES_LIST + TILE_WORDS * t;
                let tile = IVec2::new(tiles[at] as i32, tiles[at + 1] as i32);
                let first = tiles[at + 2] as usize;
                for k in 0..tiles[at + 3] {
                    let g = &blades[first + k as usize];
                    let h = tile_blade(tile, k, eye.position, &spec.params, &scene.paint);
                    assert!(
                        same_height(g, &h),
                        "{tile} {k}: {} against {}",
                        g.height(),
                        h.height()
                    );
                    let x = g.root().x;
                    if x.abs() > 5.0 {
                        let side = &mut heights_by_side[usize::from(x > 0.0)];
                        side.0 += f64::from(g.height());
                        side.1 += 1;
                    }
                }
            }
        }
        let mean = |s: (f64, u32)| s.0 / f64::from(s.1.max(1));
        let ratio = mean(heights_by_side[0]) / mean(heights_by_side[1]);
        // Grass pixels' green by quarter of the image (the camera looks along −z, so
        // image x follows world x), without and with the colour map.
        let (left_drop, right_diff) = red_on_the_left(&images[0], &images[1], width);
        println!(
            "heights left/right {ratio:.3}; left quarter's green {:.0} % lower, right \
             quarter's pixels {right_diff:.3} apart",
            100.0 * left_drop
        );
        assert!((ratio - 0.25).abs() < 0.03, "{ratio}");
        assert!(left_drop > 0.08, "{left_drop}");
        assert!(right_diff < 0.5, "{right_diff}");
    });
}

/// The natural look's frame `before` and `after` a colour map red on the left half
/// and white on the right, `width` pixels wide, the camera looking along −z (image x
/// follows world x): how much lower the left quarter's grass green is after (a share of
/// before's), and how far apart the right quarter's pixels are (the mean of 0..255 per
/// channel).
fn red_on_the_left(before: &[u8], after: &[u8], width: u32) -> (f64, f64) {
    let in_quarter = |i: usize, right: bool| {
        let x = (i % width as usize) as u32;
        if right {
            x >= 3 * width / 4
        } else {
            x < width / 4
        }
    };
    let green = |pixels: &[u8]| {
        let grass: Vec<f64> = pixels
            .chunks(4)
            .enumerate()
            .filter(|(i, p)| in_quarter(*i, false) && (p[1] > p[2] || p[0] > p[2]))
            .map(|(_, p)| f64::from(p[1]))
            .collect();
        grass.iter().sum::<f64>() / grass.len().max(1) as f64
    };
    let right: Vec<f64> = before
        .chunks(4)
        .zip(after.chunks(4))
        .enumerate()
        .filter(|(i, _)| in_quarter(*i, true))
        .map(|(_, (a, b))| {
            (0..3)
                .map(|c| (f64::from(a[c]) - f64::from(b[c])).abs())
                .sum::<f64>()
        })
        .collect();
    let apart = right.iter().sum::<f64>() / (3 * right.len().max(1)) as f64;
    (1.0 - green(after) / green(before), apart)
}

/// A type map: grey everywhere (dandelions) draws the field as the dandelion shape
/// draws it (the field's own shape quadratic), and black (bare) on the left half
/// leaves no blade there. Paper look, 160x160, 14 units from the centre. Measured on
/// lavapipe: the painted dandelions 0.000 (mean of 0..255 per channel) from the
/// dandelion-shaped field, 28.4 from the quadratic one; no blade left of x = −1 under
/// the bare half, 11,648 right of 1. Planted fault: the dandelion mark ignored by the
/// drawing stages (the field's shape used) failed (17.1 against 14.1).
#[test]
fn a_type_map_grows_dandelions_and_bare_ground() {
    use shared::settings::BladeShape;
    use shared::world::paint::{TYPE, grey, words};
    tests::with_device("a_type_map_grows_dandelions_and_bare_ground", |ctx| {
        let (mut scene, _) = open_world();
        let (width, height) = (160, 160);
        let mut camera = runner::camera::OrbitCamera::framing(80.0);
        camera.target = Vec3::ZERO;
        camera.yaw = 0.0;
        camera.pitch = 0.6;
        camera.distance = 14.0;
        let dandelions = grey(&[128]);
        let half_bare = grey(&[0, 0, 0, 0, 255, 255, 255, 255]);
        let mut render = |maps: Vec<u32>, shape: BladeShape| {
            scene.paint = maps;
            let mut settings = scene.settings();
            settings.look.style = shared::settings::Look::Paper;
            settings.shape = shape;
            let (pixels, driver) = still_frame(&ctx, &scene, &settings, &camera, (width, height));
            let r = &driver.renderer;
            let blades: Vec<shared::Blade> = r
                .download(&r.field.blades, scene.blade_count() as usize)
                .unwrap();
            (pixels, blades)
        };
        let (painted, _) = render(words(&[(TYPE, 1, 1, &dandelions)]), BladeShape::Quadratic);
        let (shaped, _) = render(Vec::new(), BladeShape::Dandelion);
        let (plain, _) = render(Vec::new(), BladeShape::Quadratic);
        let (_, blades) = render(words(&[(TYPE, 8, 1, &half_bare)]), BladeShape::Quadratic);
        let apart = |a: &[u8], b: &[u8]| {
            a.iter()
                .zip(b)
                .map(|(x, y)| (f64::from(*x) - f64::from(*y)).abs())
                .sum::<f64>()
                / a.len() as f64
        };
        let (same, other) = (apart(&painted, &shaped), apart(&painted, &plain));
        let bare_left = blades
            .iter()
            .filter(|b| kept(b) && b.root().x < -1.0)
            .count();
        let grass_right = blades
            .iter()
            .filter(|b| kept(b) && b.root().x > 1.0)
            .count();
        println!(
            "painted dandelions {same:.3} from the dandelion field, {other:.3} from the \
             quadratic one; {bare_left} blades left of −1, {grass_right} right of 1"
        );
        assert!(same < 0.2 * other, "{same} against {other}");
        assert_eq!(bare_left, 0);
        assert!(grass_right > 1000, "{grass_right}");
    });
}

/// A type map of the five bands of grey (bare, seed grass, dandelions, flowers, the
/// field's mix) over a tiled world: the pool's simulated blades, read back, carry the
/// species of the band they grow in (`shared::species::of`), at the species' heights
/// and stiffnesses: each blade is the host's `tiles::tile_blade` of its id within
/// 1e-4 (the simulation moves only v1 and v2); the white band grows the mix of
/// `--species` (seed grass and flowers, half and half within 10 %). Measured on
/// lavapipe: 4,992 blades checked, 639 flowers and 612 seed grass under white.
/// Planted fault: the mix ignored by the pool's tiles on the GPU
/// (`TileParams::species` left at 0) failed (grass where the host grows the mix).
#[test]
fn a_type_map_grows_every_species() {
    use shared::species::{self, Mix};
    use shared::world::paint::{TYPE, grey, words};
    tests::with_device("a_type_map_grows_every_species", |ctx| {
        // A world 20 units wide, its 25 tiles all in the pool.
        let (mut scene, mut spec) = small_world(64, 10.0);
        spec.pool_radius = 16.0;
        spec.params.full_distance = 1e4;
        scene.make_tiled(spec);
        scene.paint = words(&[(TYPE, 5, 1, &grey(&[0, 64, 128, 192, 255]))]);
        let mix = Mix::new([0, 0, 1, 1]);
        scene.set_species(mix);
        let mut camera = runner::camera::OrbitCamera::framing(20.0);
        camera.target = Vec3::ZERO;
        camera.pitch = 1.4;
        camera.distance = 3.0;
        let settings = scene.settings();
        let (_, driver) = still_frame(&ctx, &scene, &settings, &camera, (64, 64));
        let r = &driver.renderer;
        let spec = scene.tiles.expect("a tiled world");
        let blades: Vec<shared::Blade> = r
            .download(&r.field.blades, spec.pool_blades() as usize)
            .unwrap();
        let (half, params) = (spec.params.half_extent, spec.params);
        let band = |x: f32| ((x + half) / (0.4 * half)).floor() as usize;
        let expected = [
            None,
            Some(species::SEED_GRASS),
            Some(species::DANDELION),
            Some(species::FLOWER),
        ];
        let mut white = [0u32; species::COUNT as usize];
        let mut checked = 0;
        for (tile, slot) in r.tiles.as_ref().expect("tiles").held() {
            for index in 0..spec.tile_blades() {
                let b = &blades[slot * spec.tile_blades() as usize + index as usize];
                let host = tile_blade(tile, index, Vec3::ZERO, &params, &scene.paint);
                let x = b.root().x;
                // Texel borders may go either way.
                if !kept(b) || (x + half).rem_euclid(0.4 * half) < 0.01 * half {
                    continue;
                }
                assert_eq!(species::of(b), species::of(&host), "{tile} {index}");
                let (dh, ds) = (b.height() - host.height(), b.stiffness() - host.stiffness());
                assert!(dh.abs() < 1e-4 && ds.abs() < 1e-4, "{b:?} against {host:?}");
                match expected.get(band(x)) {
                    Some(None) => panic!("{tile} {index} on bare ground at x {x}"),
                    Some(Some(s)) => assert_eq!(species::of(b), *s, "{tile} {index} at x {x}"),
                    None => white[species::of(b) as usize] += 1,
                }
                checked += 1;
            }
        }
        println!(
            "{checked} blades checked; under white: {white:?} (grass, dandelion, flower, seed grass)"
        );
        assert!(checked > 1000, "{checked}");
        let (flowers, seeds) = (f64::from(white[2]), f64::from(white[3]));
        assert!(white[0] == 0 && white[1] == 0, "{white:?}");
        assert!(
            seeds > 100.0 && (flowers / seeds - 1.0).abs() < 0.1,
            "{white:?}"
        );
    });
}

/// The painted maps on a stored field (the paper's, every blade simulated): a type map
/// black on the left half leaves no blade there and grey on the right makes
/// dandelions; a height map scales the right half's blades by twice its grey
/// (`shared::world::paint::painted_blade`, host); a colour map red on the left half reddens
/// the natural look's blades there on the GPU and leaves the right half as it was
/// (read at each root over the ground's square, `Scene::paint_square`). Measured on
/// lavapipe: no blade left of −1 under the bare half, all 3,566 right of 1 dandelions
/// at 1.5 times their height; the left quarter's green 77 % lower, the right quarter
/// 0.000 apart (mean of 0..255). Planted fault: every stored blade reading the colour
/// map at the square's centre (the map point left at zero) failed (the right quarter
/// 14.5 apart).
#[test]
fn the_painted_maps_act_on_a_stored_field() {
    use shared::world::paint::{COLOUR, HEIGHT, KIND_DANDELION, TYPE, grey, kind, words};
    tests::with_device("the_painted_maps_act_on_a_stored_field", |ctx| {
        let grown = Scene::build(&SceneKind::Plane, None, BladeCount::Total(8192), 5, |_| {
            Ok(())
        })
        .unwrap();
        let (centre, half) = grown.paint_square();
        let types = grey(&[0, 0, 0, 0, 128, 128, 128, 128]);
        let heights = grey(&[191; 8]);
        let mut painted = Scene::build(&SceneKind::Plane, None, BladeCount::Total(8192), 5, |_| {
            Ok(())
        })
        .unwrap();
        painted.paint = words(&[(TYPE, 8, 1, &types), (HEIGHT, 8, 1, &heights)]);
        painted.apply_paint();
        let left = painted.blades.iter().filter(|b| b.root().x < -1.0).count();
        let right: Vec<_> = painted.blades.iter().filter(|b| b.root().x > 1.0).collect();
        let grown_right = grown.blades.iter().filter(|b| b.root().x > 1.0).count();
        println!(
            "{left} blades left of -1, {} of {grown_right} right of 1",
            right.len()
        );
        assert_eq!(left, 0);
        assert_eq!(right.len(), grown_right);
        for (b, g) in right
            .iter()
            .zip(grown.blades.iter().filter(|b| b.root().x > 1.0))
        {
            let p = b.root().xz() - centre;
            assert_eq!(kind(&painted.paint, p, half), KIND_DANDELION);
            assert!(
                shared::species::of(b) == shared::species::DANDELION,
                "{b:?}"
            );
            assert!((b.height() - g.height() * 2.0 * 191.0 / 255.0).abs() < 1e-5);
        }

        let mut scene = grown;
        let (width, height) = (192, 192);
        let mut camera = runner::camera::OrbitCamera::framing(20.0);
        camera.target = Vec3::ZERO;
        camera.yaw = 0.0;
        camera.pitch = 0.9;
        camera.distance = 7.0;
        let mut settings = scene.settings();
        settings.look.style = shared::settings::Look::Natural;
        settings.look.shadows = false;
        // Red on the left half, white on the right, blended over a 64th of the square.
        let red: Vec<[u8; 4]> = (0..64)
            .map(|i| if i < 32 { [255, 0, 0, 255] } else { [255; 4] })
            .collect();
        let mut images = Vec::new();
        for maps in [Vec::new(), words(&[(COLOUR, 64, 1, &red)])] {
            scene.paint = maps;
            images.push(still_frame(&ctx, &scene, &settings, &camera, (width, height)).0);
        }
        let (left_drop, right_diff) = red_on_the_left(&images[0], &images[1], width);
        println!(
            "colour map: the left quarter's green {:.0} % lower, the right quarter {right_diff:.3} apart",
            100.0 * left_drop
        );
        assert!(left_drop > 0.08, "{left_drop}");
        assert!(right_diff < 0.5, "{right_diff}");
    });
}

/// The border between simulated and far blades, and a pool tile nobody needs going
/// back to the far pose before it can leave. The camera's first tile, simulated for
/// 1 s under the breeze and gravity while the camera stands over it, is bent from
/// rest but stands where the far tiles' closed-form pose (`tiles::far_blade`) would
/// draw it at that time (the tip alone 0.035 of the height off on the host, the rest
/// pose 0.37, `sway`'s tests), guide and tip distances added, within 0.15 of the
/// height (mean); and it is in that pose exactly once the camera has been 200 units
/// away for 1.5 s (`passes::tiles::FADE_SECONDS` is 1 s). Measured on lavapipe: 0.63
/// from rest, 0.091 from the far pose while needed, 6e-7 after. Planted faults: the
/// fade ignored on the GPU failed (2.3 at most); the far pose at rest failed (0.61).
#[test]
fn a_simulated_tile_stands_as_the_far_pose_and_returns_to_it() {
    use runner::app::driver::FrameDriver;
    use runner::app::headless::Offscreen;
    use shared::glam::Vec2;
    tests::with_device("a_tile_nobody_needs_goes_back", |ctx| {
        let (scene, spec) = small_world(16, 1000.0);
        let per_tile = spec.tile_blades();
        let settings = scene.settings();
        let home = Vec2::new(1.0, 2.0);
        let mut target = Offscreen::new(&ctx, 96, 64).unwrap();
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
        let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
        let mut frame = |driver: &mut FrameDriver, at: Vec2| {
            let eye = camera_at(at).viewpoint(target.size());
            let request = settings.request(&eye, &[]);
            driver
                .run(&mut target, 1.0 / 60.0, |_| request.clone(), false)
                .unwrap();
        };
        let eye = camera_at(home).viewpoint((96, 64)).position;
        let tile = spec.needed(eye)[0];
        // Mean and largest distance of guide and tip from the pose `pose` gives, over
        // height, of the tile's blades.
        let from = |driver: &FrameDriver, pose: &dyn Fn(u32) -> shared::Blade| {
            let r = &driver.renderer;
            let slot = r.tiles.as_ref().unwrap().slot_of(tile).expect("still held");
            let count = r.field.blade_count as usize;
            let blades: Vec<shared::Blade> = r.download(&r.field.blades, count).unwrap();
            let (mut sum, mut most) = (0.0f32, 0.0f32);
            for k in 0..per_tile {
                let b = &blades[slot * per_tile as usize + k as usize];
                let p = pose(k);
                let d =
                    ((b.tip() - p.tip()).length() + (b.guide() - p.guide()).length()) / p.height();
                sum += d;
                most = most.max(d);
            }
            (sum / per_tile as f32, most)
        };
        // The far pose at the driver's time: the end of its last frame's steps.
        let far = |driver: &FrameDriver, k: u32| {
            let env = shared::sim::simulate::Environment {
                time: driver.clock.time(),
                ..settings.environment(0)
            };
            far_blade(tile, k, eye, &spec.params, &[], &env, &NO_IMPULSES)
        };
        for _ in 0..60 {
            frame(&mut driver, home);
        }
        driver.finish().unwrap();
        let (bent, _) = from(&driver, &|k| tile_blade(tile, k, eye, &spec.params, &[]));
        let (border, _) = from(&driver, &|k| far(&driver, k));
        for _ in 0..90 {
            frame(&mut driver, Vec2::new(200.0, 2.0));
        }
        driver.finish().unwrap();
        let (_, left) = from(&driver, &|k| far(&driver, k));
        println!(
            "tile {tile}: {bent} from rest, {border} from the far pose (mean) while \
             needed, {left} at most after"
        );
        assert!(bent > 0.05, "{bent}: the breeze did not bend it");
        assert!(
            border < 0.1,
            "{border}: the far pose is not the simulated one"
        );
        assert!(left < 1e-4, "{left}");
    });
}

/// A ball that cuts rolls over a tile by the camera for a sixth of a second; then the
/// camera flies 200 units off, on to eight places for eight seconds (the tile, no
/// longer held for a trail, leaves the pool as it turns over), looks at the tile from 10 units (a far tile,
/// generated), and comes back (the tile regenerated in the pool). The far blades and
/// the pool's blades of every cut cell stand at the regrowth formula's height for the
/// GPU's cut table, the others at their own: the cut survives the pool turning over
/// and reaches the far blades. Measured on lavapipe: 48 of the tile's 256 pool blades
/// cut, 10 of its 65 far blades drawn. (A planted fault in the far generation was tried but not seen through: the
/// changed shader's first compile on lavapipe outlasted the frame's one-minute wait.)
#[test]
fn a_cut_survives_the_pool_turning_over_and_reaches_the_far_blades() {
    use runner::app::driver::FrameDriver;
    use runner::app::headless::Offscreen;
    use shared::glam::Vec4;
    use shared::sim::collide::Collider;
    use shared::sim::cut::{CUT_SLOTS, CUT_WORDS, cell_key, find, regrown};
    use shared::sim::validate::paper_length;
    tests::with_device("a_cut_survives_the_pool_turning_over", |ctx| {
        let (scene, spec) = small_world(16, 1000.0);
        let per_tile = spec.tile_blades();
        let mut settings = scene.settings();
        // A trail held for a few seconds only; a slow regrowth.
        settings.trample_decay = 100.0;
        settings.regrow = 1000.0;
        let ball = Vec4::new(1.0, 0.5, 1.0, 1.0);
        let cutter = Collider::from_sphere(ball).cutting();
        let tile = shared::world::tiles::tile_of(Vec2::new(ball.x, ball.z), &spec.params);
        let mut target = Offscreen::new(&ctx, 96, 64).unwrap();
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
        let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
        let mut frame = |driver: &mut FrameDriver, at: Vec2, cutting: bool| {
            let eye = camera_at(at).viewpoint(target.size());
            let cutters: &[Collider] = if cutting { &[cutter] } else { &[] };
            let request = settings.request(&eye, &[]).with_colliders(cutters);
            driver
                .run(&mut target, 1.0 / 60.0, |_| request.clone(), false)
                .unwrap();
        };
        let (home, away, far) = (
            Vec2::new(1.0, -1.0),
            Vec2::new(200.0, 2.0),
            Vec2::new(1.0, 12.0),
        );
        for _ in 0..10 {
            frame(&mut driver, home, true);
        }
        // Eight places far apart: far more new tiles than the pool holds.
        for step in 0..480 {
            let spot = away + Vec2::X * (60 * (step / 60)) as f32;
            frame(&mut driver, spot, false);
        }
        driver.finish().unwrap();
        let tiles = driver.renderer.tiles.as_ref().unwrap();
        assert_eq!(tiles.slot_of(tile), None, "the cut tile still in the pool");
        // Each blade of the tile against its own and its cell's cut.
        let check = |driver: &FrameDriver, pool: bool| {
            let renderer = &driver.renderer;
            let now = renderer.block().forces.time;
            let table: Vec<u32> = renderer
                .download(&renderer.field.cuts, CUT_SLOTS as usize * CUT_WORDS)
                .unwrap();
            let count = renderer.field.blade_count as usize;
            let blades: Vec<shared::Blade> =
                renderer.download(&renderer.field.blades, count).unwrap();
            let ids = renderer.field.ids.as_ref().unwrap();
            let ids: Vec<u32> = renderer.download(ids, 2 * count).unwrap();
            let simulated = renderer.field.simulated as usize;
            let range = if pool { 0..simulated } else { simulated..count };
            let (mut cut, mut whole) = (0, 0);
            for k in 0..per_tile {
                let own = tile_blade(tile, k, Vec3::ZERO, &spec.params, &[]);
                let id = shared::world::tiles::blade_id(tile, k);
                let Some(i) = range
                    .clone()
                    .find(|&i| ids[2 * i] == id && kept(&blades[i]))
                else {
                    continue;
                };
                let g = &blades[i];
                // Pool blades keep their own height in the buffer: their length
                // (the paper's estimate) is the cut's; far blades are written cut.
                let height = if pool {
                    paper_length(g.root(), g.guide(), g.tip())
                } else {
                    g.height()
                };
                let expected = match find(&table, cell_key(own.root())) {
                    Some(c) => regrown(own.height(), c.stub, now - c.time, settings.regrow),
                    None => own.height(),
                };
                assert!(
                    (height - expected).abs() <= 1e-3 * expected,
                    "{} blade {k}: {height} against {expected}",
                    if pool { "pool" } else { "far" }
                );
                if expected < 0.5 * own.height() {
                    cut += 1;
                } else {
                    whole += 1;
                }
            }
            println!(
                "{}: {cut} blades of the tile cut, {whole} whole",
                if pool { "pool" } else { "far" }
            );
            assert!(cut > 3 && whole > 3, "{cut} cut, {whole} whole");
        };
        frame(&mut driver, far, false);
        driver.finish().unwrap();
        check(&driver, false);
        frame(&mut driver, home, false);
        driver.finish().unwrap();
        assert!(
            driver
                .renderer
                .tiles
                .as_ref()
                .unwrap()
                .slot_of(tile)
                .is_some()
        );
        check(&driver, true);
    });
}

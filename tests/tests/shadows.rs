//! Sun shadows that do not move with the camera: the shadow map of a frame (both
//! cascades) is the same, texel for texel, when only the direction the camera looks
//! in changes. Its casters come from the compute pass's own lists (every blade inside
//! the map and within the casters' reach of the camera, and those inside the near
//! cascade), not from the blades the camera keeps, which the frustum and orientation
//! tests choose by where it looks; both cascades are placed around the camera's
//! position, not ahead of it.

use glam::camera::rh;
use glam::{Mat4, Quat, Vec3};
use runner::app::driver::FrameDriver;
use runner::app::headless::{FORMAT, Offscreen};
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use runner::vulkan::Context;
use shared::gpu::counters::{COUNTER_CASTERS, COUNTER_COUNT};
use shared::settings::{Look, SHADOW_REACH, Viewpoint};
use std::sync::Arc;
use tests::with_device;

/// Degrees the camera turns about the vertical between the two frames.
const TURN: f32 = 10.0;

/// A camera at `eye` looking along `forward` turned by `degrees` about the vertical.
fn turned(eye: Vec3, forward: Vec3, degrees: f32, (width, height): (u32, u32)) -> Viewpoint {
    let forward = Quat::from_rotation_y(degrees.to_radians()) * forward;
    let fov_y = 50f32.to_radians();
    let view = rh::view::look_at_mat4(eye, eye + forward, Vec3::Y);
    let proj = rh::proj::vulkan::perspective(fov_y, width as f32 / height as f32, 0.1, 200.0);
    let view_proj: Mat4 = proj * view;
    Viewpoint {
        view_proj,
        position: eye,
        fov_y,
        height,
        forward,
    }
}

/// The natural look with shadows from one place, looking two ways `TURN` degrees
/// apart: the two frames' shadow maps are equal texel for texel (tolerance: none;
/// the same casters rasterize the same depths), while the frames' visible blades
/// differ (the turn is large enough for the camera's tests to keep other blades).
#[test]
fn the_shadow_map_does_not_turn_with_the_camera() {
    with_device("the_shadow_map_does_not_turn_with_the_camera", |ctx| {
        // A field inside the map's reach (the map covers the scene), and one larger
        // (the map covers a sphere around the camera).
        for (blades, larger) in [(8192, false), (196_608, true)] {
            let scene = Scene::build(
                &SceneKind::Hills,
                None,
                BladeCount::Total(blades),
                5,
                |_| Ok(()),
            )
            .expect("scene");
            assert_eq!(scene.bounds.1 > SHADOW_REACH, larger, "{blades} blades");
            turning_keeps_the_shadow_map(&ctx, &scene);
        }
    });
}

/// The frames of `scene` from one place, looking two ways [`TURN`] degrees apart.
fn turning_keeps_the_shadow_map(ctx: &Arc<Context>, scene: &Scene) {
    let mut settings = scene.settings();
    settings.look.style = Look::Natural;
    settings.look.shadows = true;
    let camera = scene.camera();
    // Inside the field, so that the frustum keeps part of it.
    let eye = camera.target + (camera.eye() - camera.target) * 0.4;
    let forward = (camera.target - eye).normalize();
    let mut target = Offscreen::new(ctx, 256, 160).expect("target");
    let renderer = Renderer::new(ctx, &scene.meshes(), FORMAT).expect("renderer");
    let mut driver = FrameDriver::new(ctx, renderer).expect("frame driver");
    let mut seen = Vec::new();
    for degrees in [0.0, TURN] {
        let eye = turned(eye, forward, degrees, target.size());
        let request = settings.request(&eye, &[]);
        // No time: the blades stand as they are.
        driver
            .run(&mut target, 0.0, |_| request.clone(), false)
            .expect("frame");
        driver.finish().expect("finish");
        let visible = driver.readback.visible().expect("visible count");
        let renderer = &driver.renderer;
        let counters: Vec<u32> = renderer
            .download(&renderer.field.counters, COUNTER_COUNT)
            .expect("counters");
        let map = renderer.shadow_map().expect("shadow map");
        seen.push((visible, counters[COUNTER_CASTERS], map));
    }
    let ((visible_a, casters_a, map_a), (visible_b, casters_b, map_b)) = (&seen[0], &seen[1]);
    assert_ne!(
        visible_a, visible_b,
        "the turn changed nothing the camera keeps"
    );
    assert!(*casters_a > 1000, "{casters_a} casters");
    let differing = map_a.iter().zip(map_b).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing,
        0,
        "{differing} of {} shadow-map texels changed when the camera turned {TURN} degrees",
        map_a.len()
    );
    assert_eq!(
        casters_a, casters_b,
        "the casters changed with the camera's direction"
    );
}

/// The grass in the shadow map is what the host draws of the same casters with the
/// same functions (`shadow_raster::raster_caster` over each caster's corners,
/// `clump::caster_blade`, `shape::surface_point`): on the plane, whose ground lies
/// behind every blade seen from the sun, each texel the host covers holds the host's
/// depth (tolerance 1e-5; texel centres on a triangle's edge may go either way: at
/// most 0.01 % of the covered texels, measured 10 of 612,768 on lavapipe), in both cascades (the plane larger than the
/// near one). Planted faults: the cascades swapped, the words' rows half as long.
#[test]
fn the_shadow_maps_grass_is_the_hosts() {
    with_device("the_shadow_maps_grass_is_the_hosts", |ctx| {
        use shared::draw::look::clump::{Clump, caster_blade};
        use shared::draw::look::shadow_raster::{caster_corners, raster_caster, texel_word};
        use shared::gpu::counters::COUNTER_NEAR_CASTERS;
        let mut scene = Scene::build(&SceneKind::Plane, None, BladeCount::Total(32768), 3, |_| {
            Ok(())
        })
        .expect("scene");
        // Every species, each casting its own outline.
        scene.set_species(shared::species::Mix::new([5, 1, 2, 2]));
        let mut settings = scene.settings();
        settings.look.style = Look::Natural;
        settings.look.shadows = true;
        let camera = scene.camera();
        let eye = camera.target + (camera.eye() - camera.target) * 0.4;
        let mut target = Offscreen::new(&ctx, 128, 96).expect("target");
        let view = turned(eye, (camera.target - eye).normalize(), 0.0, target.size());
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).expect("renderer");
        let mut driver = FrameDriver::new(&ctx, renderer).expect("frame driver");
        let request = settings.request(&view, &[]);
        driver
            .run(&mut target, 0.0, |_| request.clone(), false)
            .expect("frame");
        driver.finish().expect("finish");
        let renderer = &driver.renderer;
        let field = &renderer.field;
        let block = *renderer.block();
        assert_eq!(
            block.grass.tiled, 0,
            "a stored field: the casters' ids are their indices"
        );
        let n = field.blade_count as usize;
        let counters: Vec<u32> = renderer
            .download(&field.counters, COUNTER_COUNT)
            .expect("counters");
        let casters: Vec<u32> = renderer.download(&field.casters, 2 * n).expect("casters");
        let blades: Vec<shared::Blade> = renderer.download(&field.blades, n).expect("blades");
        let clumps: Vec<shared::glam::Vec4> = renderer.download(&field.clumps, n).expect("clumps");
        let map = renderer.shadow_map().expect("shadow map");
        // A plane larger than the near cascade, so the two cascades differ.
        assert_ne!(block.look.shadow_view_proj, block.look.near_view_proj);
        let side = block.look.shadow_size;
        let mut host = vec![1.0f32; map.len()];
        let lists = [
            (0, counters[COUNTER_CASTERS], block.look.shadow_view_proj, 1),
            (
                n,
                counters[COUNTER_NEAR_CASTERS],
                block.look.near_view_proj,
                0,
            ),
        ];
        for (first, count, view_proj, cascade) in lists {
            assert!(count > 100, "cascade {cascade}: {count} casters");
            for &index in &casters[first..first + count as usize] {
                let i = index as usize;
                let blade = caster_blade(
                    &blades[i],
                    &Clump::unpack(clumps[i]),
                    index,
                    block.look.seed,
                );
                let shape = (block.grass.shape, block.grass.tip_start);
                let corners = caster_corners(&blade, shape, view_proj, (side, cascade));
                raster_caster(corners, (side, cascade), &mut |x, y, d| {
                    let t = &mut host[texel_word(x, y, side)];
                    *t = t.min(d);
                });
            }
        }
        let covered = host.iter().filter(|&&d| d < 1.0).count();
        let differing = host
            .iter()
            .zip(&map)
            .filter(|&(&h, &g)| h < 1.0 && (h - g).abs() > 1e-5)
            .count();
        println!("{covered} texels covered by grass on the host, {differing} differ on the GPU");
        assert!(covered > 1000, "{covered} texels covered");
        assert!(
            differing * 10_000 <= covered,
            "{differing} of the {covered} texels the host's casters cover differ on the GPU"
        );
    });
}

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
            .run(&mut target, 0.0, |_| request, false)
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

//! The compute pass on a Vulkan device against the host running the same shared
//! functions: every blade after a few hundred steps, and the visible set.

use glam::Vec3;
use runner::app::render::FORMAT;
use runner::camera::OrbitCamera;
use runner::renderer::Renderer;
use runner::scene::{Scene, Settings};
use shared::Blade;
use shared::cull;
use shared::layout::{FrameUniforms, SimulatePush};
use shared::simulate::simulate;
use std::collections::HashSet;
use tests::with_device;

const BLADES: u32 = 2048;
const FRAMES: u32 = 30;
const STEPS_PER_FRAME: u32 = 10;

/// Largest difference allowed between a GPU and a host control point, in world units
/// (blades are 1.3 to 2.5 tall; lavapipe stays within 1e-5 of the host). The GPU's sin, cos, sqrt and division may differ from
/// the host's in the last bits (Vulkan allows a few ULP, sin/cos 2^-11 absolute), and
/// fused multiply-adds round differently; recovery pulls every tip towards its rest
/// position, so those differences do not grow over the steps.
const POSITION_TOLERANCE: f32 = 5e-4;

/// A blade within this of a cull threshold may fall either way on the two sides.
const THRESHOLD_EPSILON: f32 = 1e-3;

/// A camera low over the field's edge, so that every test removes blades.
fn setup() -> (Scene, FrameUniforms) {
    let scene = Scene::square(BLADES, 11);
    let mut settings = Settings::for_field(scene.side);
    settings.max_distance = scene.side * 0.9;
    settings.buckets = 4;
    let camera = OrbitCamera {
        target: Vec3::new(0.0, 0.5, 0.0),
        yaw: 0.3,
        pitch: 0.25,
        distance: scene.side * 0.6,
        fov_y: 40f32.to_radians(),
    };
    let uniforms = settings.uniforms(&camera, 1.0, &scene);
    (scene, uniforms)
}

/// True when `b` lies within [`THRESHOLD_EPSILON`] of a decision of an enabled test.
fn near_threshold(b: &Blade, u: &FrameUniforms) -> bool {
    let p = u.cull_params();
    let cam = u.camera_pos();
    let eps = THRESHOLD_EPSILON;
    let orientation = (cull::orientation_alignment(b, cam) - p.orientation_threshold).abs() < eps;
    let frustum = [b.root(), b.midpoint(), b.tip()].iter().any(|pt| {
        let c = u.view_proj * pt.extend(1.0);
        cull::clip_margin(c, p.frustum_tolerance).abs() < eps * c.w.abs().max(1.0)
    });
    let dproj = cull::projected_distance(b, cam);
    let limit = cull::distance_bucket_position(dproj, p.max_distance, p.buckets);
    let distance = (dproj - p.max_distance).abs() < eps * p.max_distance
        || (limit - limit.round()).abs() < eps * p.buckets as f32;
    orientation || frustum || distance
}

#[test]
fn compute_pass_matches_the_host() {
    with_device("compute_pass_matches_the_host", |ctx| {
        let (scene, uniforms) = setup();
        let mut renderer = Renderer::new(&ctx, &scene.blades, FORMAT).expect("renderer");
        let env = uniforms.environment();
        let mut host = scene.blades.clone();
        for frame in 0..FRAMES {
            let push = SimulatePush {
                first_step: frame * STEPS_PER_FRAME,
                steps: STEPS_PER_FRAME,
            };
            renderer
                .compute_frame(&uniforms, push)
                .expect("compute frame");
            for b in &mut host {
                *b = simulate(b, &env, push.first_step, push.steps);
            }
        }
        let gpu: Vec<Blade> = renderer
            .download(&renderer.field.blades, host.len())
            .unwrap();

        // Every blade, every control point.
        let mut worst: f32 = 0.0;
        for (i, (g, h)) in gpu.iter().zip(&host).enumerate() {
            assert_eq!(g.v0, h.v0, "blade {i}: the root must not move");
            assert_eq!(g.up, h.up, "blade {i}: up and stiffness must not change");
            let d = (g.guide() - h.guide())
                .length()
                .max((g.tip() - h.tip()).length());
            assert!(
                g.v1.is_finite() && g.v2.is_finite(),
                "blade {i} not finite: {g:?}"
            );
            assert!(
                d < POSITION_TOLERANCE,
                "blade {i}: GPU {g:?} host {h:?} differ by {d}"
            );
            worst = worst.max(d);
        }
        println!(
            "largest GPU/host control-point difference after {} steps: {worst:e}",
            FRAMES * STEPS_PER_FRAME
        );
        // The blades really moved (the comparison is not of two rest states).
        let moved = host
            .iter()
            .zip(&scene.blades)
            .filter(|(a, b)| (a.tip() - b.tip()).length() > 0.05)
            .count();
        assert!(moved > host.len() / 2, "only {moved} blades moved");

        // The visible set: the GPU's compacted survivors, named by their roots.
        let count = renderer.visible.expect("visible count") as usize;
        let visible: Vec<Blade> = renderer.download(&renderer.field.visible, count).unwrap();
        let key = |b: &Blade| b.v0.to_array().map(f32::to_bits);
        let gpu_set: HashSet<_> = visible.iter().map(key).collect();
        assert_eq!(gpu_set.len(), count, "a blade was appended twice");
        let p = uniforms.cull_params();
        let cam = uniforms.camera_pos();
        let (mut compared, mut skipped) = (0, 0);
        let mut removed = [0u32; 3];
        for (id, b) in host.iter().enumerate() {
            let id = id as u32;
            removed[0] += cull::cull_orientation(b, cam, p.orientation_threshold) as u32;
            removed[1] += cull::cull_frustum(b, uniforms.view_proj, p.frustum_tolerance) as u32;
            removed[2] += cull::cull_distance(b, id, cam, p.max_distance, p.buckets) as u32;
            if near_threshold(b, &uniforms) {
                skipped += 1;
                continue;
            }
            compared += 1;
            let host_visible = cull::is_visible(b, id, cam, uniforms.view_proj, &p);
            assert_eq!(
                gpu_set.contains(&key(b)),
                host_visible,
                "blade {id}: visible on the host: {host_visible}"
            );
        }
        println!(
            "visible {count} of {BLADES}; compared {compared}, {skipped} near a threshold; removed by orientation/frustum/distance {removed:?}"
        );
        assert!(
            removed.iter().all(|&r| r > 20),
            "each test must remove blades here: {removed:?}"
        );
        assert!(
            skipped < BLADES as usize / 20,
            "too many blades near a threshold: {skipped}"
        );
    });
}

//! The simulation on the device under extreme settings, over a whole field for
//! thousands of steps: no blade may become NaN or infinite, fall below its ground,
//! fold v1 under v0 or lose its length; then, the wind calmed and the balls gone,
//! every blade must come to rest (the host's property tests,
//! shared/tests/stability.rs, check the same on the shared functions).

use glam::Vec4;
use runner::app::driver::FrameDriver;
use runner::app::headless::FORMAT;
use runner::renderer::Renderer;
use runner::scene::Scene;
use shared::Blade;
use shared::gpu::layout::SimulatePush;
use shared::settings::WindField::{Breeze, Calm, Gusts, Vortex};
use shared::sim::simulate::MAX_STEPS_PER_FRAME;
use shared::sim::validate::{
    BENT_REACH, LENGTH_TOLERANCE_BENT, LENGTH_TOLERANCE_FOLDED, bezier_length,
};
use tests::with_device;

const BLADES: u32 = 2048;
/// Frames of the longest kind (2 s, [`MAX_STEPS_PER_FRAME`] steps each) per setting.
const FRAMES: u32 = 20;

/// Length error allowed for any blade: validation's bound for a folded blade
/// (`shared::sim::validate::LENGTH_TOLERANCE_FOLDED`) plus f32 rounding; bent blades are
/// held to `LENGTH_TOLERANCE_BENT`.
const LENGTH_TOLERANCE_ANY: f32 = LENGTH_TOLERANCE_FOLDED + 1e-3;

/// How far below its ground plane a tip may be found: f32 rounding of a tip lifted back
/// from far below (the host tests bound it by the throw; 1e-3 of a blade is ample).
const GROUND_TOLERANCE: f32 = 1e-3;

/// Frames of calm (2 s each) after the extreme ones, before the blades must be still.
const CALM_FRAMES: u32 = 5;

/// Most a tip may move in one step once the field has settled, as a share of its
/// blade's height (as in the host's settling property).
const SETTLED: f32 = 1e-4;

/// The largest move of any tip between `a` and `b`, as a share of its blade's height.
fn largest_move(a: &[Blade], b: &[Blade]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a.tip() - b.tip()).length() / a.height())
        .fold(0.0, f32::max)
}

/// The field's blades as the device holds them.
fn download(driver: &FrameDriver) -> Vec<Blade> {
    let renderer = &driver.renderer;
    renderer
        .download(&renderer.field.blades, BLADES as usize)
        .expect("download blades")
}

/// Checks every blade; returns the worst relative length error of bent blades.
fn check(blades: &[Blade], what: &str) -> f32 {
    let mut worst_bent: f32 = 0.0;
    for (i, b) in blades.iter().enumerate() {
        assert!(
            [b.v0, b.v1, b.v2, b.up].iter().all(|v| v.is_finite()),
            "{what}: blade {i} not finite: {b:?}"
        );
        let (v0, up, h) = (b.root(), b.up_dir(), b.height());
        assert!(
            up.dot(b.tip() - v0) >= -GROUND_TOLERANCE,
            "{what}: blade {i} below its ground: {b:?}"
        );
        assert!(
            up.dot(b.guide() - v0) > 0.0,
            "{what}: blade {i} v1 under v0: {b:?}"
        );
        let error = (bezier_length(v0, b.guide(), b.tip(), 64) - h).abs() / h;
        assert!(
            error <= LENGTH_TOLERANCE_ANY,
            "{what}: blade {i} length off by {error}: {b:?}"
        );
        if (b.tip() - v0).length() >= BENT_REACH * h {
            worst_bent = worst_bent.max(error);
        }
    }
    assert!(
        worst_bent <= LENGTH_TOLERANCE_BENT,
        "{what}: a bent blade's length is off by {worst_bent}"
    );
    worst_bent
}

/// Balls of radius `radius` jumping across the field each frame, through the blades.
fn balls(frame: u32, half: f32, radius: f32) -> Vec<Vec4> {
    (0..4)
        .map(|k| {
            let t = (frame * 4 + k) as f32 * 2.39996;
            let r = half * ((frame + k) % 5) as f32 / 4.0;
            Vec4::new(r * t.cos(), 0.5, r * t.sin(), radius)
        })
        .collect()
}

#[test]
fn extreme_settings_keep_every_blade_valid_on_the_device() {
    with_device("gpu stability", |ctx| {
        let scene = Scene::plane(BLADES, 5);
        let half = scene.bounds.1 / std::f32::consts::SQRT_2;
        let camera = scene.camera();
        // (what, wind kind, wind ×, gravity ×, stiffness factor, ball radius)
        let cases = [
            ("wind 100x, vortex", Vortex, 100.0, 1.0, 1.0, 1.5),
            ("gusts 100x, gravity 10x", Gusts, 100.0, 10.0, 1.0, 0.5),
            ("stiffness 100", Breeze, 1.0, 1.0, 100.0, 1.5),
            ("stiffness 0, gravity 10x", Breeze, 1.0, 10.0, 0.0, 3.0),
            ("everything at once", Vortex, 100.0, 10.0, 100.0, 8.0),
        ];
        for (what, kind, wind, gravity, stiffness, radius) in cases {
            let mut settings = scene.settings();
            settings.wind.field = kind;
            settings.wind.strength *= wind;
            settings.gravity.acceleration *= gravity;
            settings.stiffness = stiffness;
            let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).expect("renderer");
            let mut driver = FrameDriver::new(&ctx, renderer).expect("frame driver");
            let eye = camera.viewpoint((256, 256));
            for frame in 0..FRAMES {
                let balls = balls(frame, half, radius);
                let request = settings.request(&eye, &balls);
                let push = SimulatePush {
                    first_step: frame * MAX_STEPS_PER_FRAME,
                    steps: MAX_STEPS_PER_FRAME,
                    ..Default::default()
                };
                driver.compute_frame(&request, push).expect("compute frame");
            }
            let blades = download(&driver);
            let moved = blades
                .iter()
                .zip(&scene.blades)
                .filter(|(a, b)| (a.tip() - b.tip()).length() > 1e-3)
                .count();
            assert!(
                moved > BLADES as usize / 2,
                "{what}: only {moved} blades moved"
            );
            let worst = check(&blades, what);
            eprintln!(
                "{what}: {} steps, every blade valid, worst bent length error {worst:.4}",
                FRAMES * MAX_STEPS_PER_FRAME
            );

            // Calm: no wind, no ball; ten seconds, then one step at a time.
            settings.wind.field = Calm;
            let request = settings.request(&eye, &[]);
            let mut step = FRAMES * MAX_STEPS_PER_FRAME;
            for _ in 0..CALM_FRAMES {
                let push = SimulatePush {
                    first_step: step,
                    steps: MAX_STEPS_PER_FRAME,
                    ..Default::default()
                };
                driver.compute_frame(&request, push).expect("calm frame");
                step += MAX_STEPS_PER_FRAME;
            }
            let mut before = download(&driver);
            let mut worst_move: f32 = 0.0;
            for _ in 0..2 {
                let push = SimulatePush {
                    first_step: step,
                    steps: 1,
                    ..Default::default()
                };
                driver.compute_frame(&request, push).expect("one step");
                step += 1;
                let after = download(&driver);
                worst_move = worst_move.max(largest_move(&before, &after));
                before = after;
            }
            check(&before, what);
            eprintln!(
                "{what}: after {} s of calm the largest tip move in a step is {worst_move:.2e} of \
                 its blade's height",
                2 * CALM_FRAMES
            );
            assert!(
                worst_move < SETTLED,
                "{what}: not settled, a tip moved {worst_move} of its height in a step"
            );
        }
    });
}

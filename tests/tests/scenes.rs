//! Headless images against references: each built-in scene,
//! each blade shape, and the trail a collider ball leaves.

use glam::{Vec2, Vec3, Vec4Swizzles};
use image::RgbaImage;
use tests::{check_reference, device_available, difference, render_image, save_failure};

/// Small images: lavapipe draws about half a million triangles a second.
const SIZE: &str = "160";

/// Every built-in scene, rendered small, matches its reference and shows grass.
#[test]
fn each_built_in_scene_matches_its_reference() {
    let Some(_gpu) = device_available("each_built_in_scene_matches_its_reference") else {
        return;
    };
    for scene in ["plane", "hills", "planet", "meadow"] {
        let (report, image) = render_image(&format!(
            "--scene {scene} --blades 2048 --frames 20 --width {SIZE} --height {SIZE} --wind calm"
        ));
        let grass = share(&image, |[r, g, b]| g > r + 10 && g > b + 10);
        println!(
            "{scene}: {} of {} blades visible, grass share {grass:.3}",
            report.visible, report.blades
        );
        assert!(
            grass > 0.05 && report.visible > 200,
            "{scene}: too little grass ({grass:.3}, {} visible); {}",
            report.visible,
            save_failure(&format!("scene_{scene}"), &image, None)
        );
        check_reference(&format!("scene_{scene}"), &image);
    }
}

/// How far apart any two blade shapes' frames are at least: half the nearest pair
/// measured (triangle and triangle-tip: a mean of 5.84 with 4.0 % outliers on lavapipe
/// and the NVIDIA H100). Planted fault: the shape ignored by the drawing stages (every
/// blade quadratic) made every pair alike (0.000) and failed.
const SHAPES_APART: tests::Tolerance = tests::Tolerance {
    mean: 2.9,
    outliers: 0.02,
};

/// Each blade shape matches its reference, and every shape looks different from
/// every other one by at least [`SHAPES_APART`] (so the switch is seen).
#[test]
fn each_blade_shape_matches_its_reference_and_differs_from_the_others() {
    let Some(_gpu) = device_available("each_blade_shape_matches_its_reference") else {
        return;
    };
    let shapes = ["quad", "triangle", "quadratic", "triangle-tip", "dandelion"];
    let images: Vec<RgbaImage> = shapes
        .iter()
        .map(|shape| {
            let (_, image) = render_image(&format!(
                "--shape {shape} --blades 256 --frames 5 --width {SIZE} --height {SIZE} \
                 --wind calm --zoom 2.5 --tip-start 0.3"
            ));
            check_reference(&format!("shape_{shape}"), &image);
            image
        })
        .collect();
    for i in 0..shapes.len() {
        for j in i + 1..shapes.len() {
            let (d, _) = difference(&images[i], &images[j]);
            println!(
                "{} vs {}: mean {:.3}, outliers {:.4}",
                shapes[i], shapes[j], d.mean, d.outliers
            );
            assert!(
                d.beyond(SHAPES_APART),
                "{} and {} look alike: {d:?}",
                shapes[i],
                shapes[j]
            );
        }
    }
}

/// A ball rolled along a path leaves a trail: with the wind calm, the image with the
/// ball differs from the one without it in the grass (not just the ball itself), and
/// only near where the ball went: the screen rectangle around the path, widened by the
/// ball and the tallest blade. The path runs along the far side of the field, so the
/// near side must stay exactly as it was.
#[test]
fn a_collider_leaves_a_visible_trail_under_its_path() {
    let Some(_gpu) = device_available("a_collider_leaves_a_visible_trail_under_its_path") else {
        return;
    };
    let radius = 1.5;
    let base = format!(
        "--blades 2048 --frames 200 --width 192 --height 192 --wind calm --pitch 50 \
         --collider-speed 3 --collider-radius {radius}"
    );
    let (_, still) = render_image(&base);
    let (report, trail) = render_image(&format!("{base} --collider-path -5,-2;2,-2"));
    check_reference("trail", &trail);

    // Screen rectangle around the path: project a box around each point of it.
    let (reach, top) = (radius + 2.5, 1.6 * radius + 2.5);
    let (w, h) = (trail.width() as f32, trail.height() as f32);
    let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
    for i in 0..=70 {
        let centre = Vec3::new(-5.0 + 0.1 * i as f32, 0.0, -2.0);
        for corner in 0..8 {
            let sign = |bit: u32| if corner & bit == 0 { -1.0 } else { 1.0 };
            let offset = Vec3::new(
                sign(1) * reach,
                (0.5 + 0.5 * sign(2)) * top,
                sign(4) * reach,
            );
            let clip = report.view_proj * (centre + offset).extend(1.0);
            let ndc = clip.xy() / clip.w;
            let px = Vec2::new((ndc.x + 1.0) * 0.5 * w, (ndc.y + 1.0) * 0.5 * h);
            lo = lo.min(px);
            hi = hi.max(px);
        }
    }
    let ball = |p: &image::Rgba<u8>| i32::from(p[0]) > i32::from(p[1]) + 60;
    let (mut inside, mut outside) = (0u32, 0u32);
    for (x, y, p) in trail.enumerate_pixels() {
        let q = still.get_pixel(x, y);
        if (0..3).any(|c| p[c].abs_diff(q[c]) > 24) && !ball(p) && !ball(q) {
            let px = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            if px.cmpge(lo).all() && px.cmple(hi).all() {
                inside += 1;
            } else {
                outside += 1;
            }
        }
    }
    let band = (hi.min(Vec2::new(w, h)) - lo.max(Vec2::ZERO)).element_product();
    println!(
        "grass pixels changed by the ball: {inside} inside its screen band ({band:.0} px of {}), \
         {outside} outside",
        w * h
    );
    assert!(
        band < 0.9 * w * h && inside as f32 > 0.02 * band && outside <= inside / 50,
        "trail: {inside} changed inside the band, {outside} outside; {} / {}",
        save_failure("trail", &trail, None),
        save_failure("trail_without_ball", &still, None)
    );
}

fn share(image: &RgbaImage, pred: impl Fn([i32; 3]) -> bool) -> f64 {
    let n = image
        .pixels()
        .filter(|p| pred([p[0] as i32, p[1] as i32, p[2] as i32]))
        .count();
    n as f64 / f64::from(image.width() * image.height())
}

/// The walls scene's ground and stones meet without cracks: no pixel inside the
/// ground square's outline on screen may show the sky (the clear colour, read from the
/// top-left corner, above the horizon). Seen from above the field's corner, where the
/// walls' feet are in sight.
#[test]
fn the_walls_meet_the_ground_without_cracks() {
    let Some(_gpu) = device_available("the_walls_meet_the_ground_without_cracks") else {
        return;
    };
    // Few blades, so the ground and the walls' feet are in sight.
    let blades = 64;
    let args = format!(
        "--scene walls --blades {blades} --frames 2 --width 512 --height 288 --pitch 35 \
         --zoom 1.6 --yaw 30 --wind calm"
    );
    let (report, image) = render_image(&args);
    let kind = runner::scene::SceneKind::Walls;
    let count = runner::scene::BladeCount::Total(blades);
    let scene = runner::scene::Scene::build(&kind, None, count, 1, |_| Ok(())).unwrap();
    // The ground square: the mesh's bounds at y = 0.
    let (lo, hi) = scene.surface.bounds().unwrap();
    let corners = [
        Vec3::new(lo.x, 0.0, lo.z),
        Vec3::new(hi.x, 0.0, lo.z),
        Vec3::new(hi.x, 0.0, hi.z),
        Vec3::new(lo.x, 0.0, hi.z),
    ];
    let (w, h) = (image.width() as f32, image.height() as f32);
    let screen: Vec<Vec2> = corners
        .iter()
        .map(|c| {
            let clip = report.view_proj * c.extend(1.0);
            assert!(clip.w > 0.0, "a ground corner behind the camera");
            let ndc = clip.xy() / clip.w;
            Vec2::new((ndc.x + 1.0) * 0.5 * w, (ndc.y + 1.0) * 0.5 * h)
        })
        .collect();
    // Inside the convex outline, two pixels in from its edges.
    let inside = |p: Vec2| {
        let sign = |a: Vec2, b: Vec2| (b - a).perp_dot(p - a) / (b - a).length();
        let s: Vec<f32> = (0..4)
            .map(|i| sign(screen[i], screen[(i + 1) % 4]))
            .collect();
        s.iter().all(|&d| d > 2.0) || s.iter().all(|&d| d < -2.0)
    };
    let sky = *image.get_pixel(0, 0);
    let mut cracks = 0;
    let mut ground = 0;
    for (x, y, p) in image.enumerate_pixels() {
        if inside(Vec2::new(x as f32 + 0.5, y as f32 + 0.5)) {
            ground += 1;
            cracks += usize::from(*p == sky);
        }
    }
    println!("walls: {cracks} sky pixels among {ground} inside the ground's outline");
    assert!(
        ground > 20_000,
        "the ground covers too little of the image: {ground}"
    );
    assert!(
        cracks == 0,
        "{cracks} sky pixels inside the ground's outline; {}",
        save_failure("walls_cracks", &image, None)
    );
}

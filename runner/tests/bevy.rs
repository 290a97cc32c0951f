//! The Bevy example (`runner/examples/bevy/`, the `bevy` feature) run headless in
//! this process, three times: the ball walking across the field, the ball standing
//! at the end of its walk from the start, and that again in a field of flowers and
//! seed grass among the grass.
//!
//! Checked by content, with the ball's place projected by the host with Bevy's
//! camera: the grass covers much of the ground; the ball shows inside its silhouette
//! (Bevy drew it, and the grass, depth-tested against Bevy's reverse-Z depth, did not
//! cover it) but not all of it (the blades in front of it hide some); and the walk
//! left a trail: along the ball's path the two pictures differ far more than away
//! from it; and the species the example is given grow: the flowers' yellow heads show
//! in the mixed field and not in the grass alone.

#[path = "../examples/bevy/main.rs"]
#[allow(dead_code)]
mod example;

use glam::{Vec2, Vec3};
use runner::vulkan::probe::runs_here;

/// Red, as the ball is lit: red far above green and blue.
fn is_ball(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(f32::from);
    r > 1.6 * g + 20.0 && r > 1.6 * b + 20.0
}

/// A flower's yellow head (`shared::species::albedo`), as Bevy tone-maps it: red
/// and green high, blue low.
fn is_head(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(i32::from);
    r > 150 && g > 120 && b < 90 && r - b > 90
}

/// The grass's green: green above red and blue.
fn is_grass(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(i32::from);
    g > r + 8 && g > b + 8
}

/// `p` (world) in pixels on a `size` target, as Bevy's camera of the example sees it
/// (Bevy's matrices: reverse-Z, infinite far plane, clip space y up).
fn project(p: Vec3, (w, h): (u32, u32)) -> Vec2 {
    use bevy::math::{Mat4, Vec3 as BevyVec3};
    let view = Mat4::look_at_rh(example::EYE, example::LOOK_AT, BevyVec3::Y);
    let proj = Mat4::perspective_infinite_reverse_rh(example::FOV_Y, w as f32 / h as f32, 0.1);
    let clip = proj * view * BevyVec3::from_array(p.to_array()).extend(1.0);
    let ndc = clip.truncate().truncate() / clip.w;
    Vec2::new(
        (ndc.x + 1.0) / 2.0 * w as f32,
        (1.0 - ndc.y) / 2.0 * h as f32,
    )
}

/// The pixel at `(x, y)`.
fn pixel(shot: &example::Shot, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * shot.size.0 + x) * 4) as usize;
    [shot.rgba[i], shot.rgba[i + 1], shot.rgba[i + 2]]
}

#[test]
fn the_bevy_example_draws_grass_around_its_ball_and_a_trail() {
    if !runs_here("the bevy example", &[]) {
        return;
    }
    let args = |still| example::Args {
        out: "unused.png".into(),
        frames: 120,
        size: (320, 180),
        blades: 40_000,
        species: shared::species::Mix::GRASS,
        still,
        validation: false,
    };
    let run = |args: &example::Args| {
        example::render(args).unwrap_or_else(|e| panic!("bevy example: {e:#}"))
    };
    let (walked, stood) = (run(&args(false)), run(&args(true)));
    let meadow = run(&example::Args {
        frames: 10,
        species: "grass=2,flower=1,seed-grass=1".parse().expect("a mix"),
        ..args(true)
    });
    let heads = |shot: &example::Shot| {
        let (w, h) = shot.size;
        let n = (0..w * h)
            .filter(|&k| is_head(pixel(shot, k % w, k / w)))
            .count();
        n as f32 / (w * h) as f32
    };
    let (in_meadow, in_grass) = (heads(&meadow), heads(&stood));
    let size = walked.size;
    let (w, h) = size;
    assert_eq!(walked.rgba.len(), (w * h * 4) as usize);

    // The ball where the walk ended, and its radius in pixels.
    let total = 120.0 / 60.0;
    let end = Vec3::from_array(example::ball_at(total, total, false).to_array());
    let centre = project(end, size);
    // The silhouette's radius: the farthest of the sphere's points from its centre's
    // projection (perspective widens it off the axis).
    let radius = (0..64 * 32)
        .map(|k| {
            let (a, b) = ((k % 64) as f32 / 64.0, (k / 64) as f32 / 32.0);
            let (theta, phi) = (std::f32::consts::TAU * a, std::f32::consts::PI * b);
            let dir = Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin());
            project(end + dir * example::BALL, size).distance(centre)
        })
        .fold(0.0, f32::max);
    let (mut inside, mut ball_inside, mut ball_outside, mut grass) = (0, 0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let p = pixel(&walked, x, y);
            let d = Vec2::new(x as f32 + 0.5, y as f32 + 0.5).distance(centre);
            if d < radius - 1.0 {
                inside += 1;
                ball_inside += usize::from(is_ball(p));
            } else if d > radius + 2.0 {
                ball_outside += usize::from(is_ball(p));
            }
            grass += usize::from(is_grass(p));
        }
    }
    let ball_share = ball_inside as f32 / inside.max(1) as f32;
    let grass_share = grass as f32 / (w * h) as f32;
    // The trail: along the path behind the ball against the rest of the ground.
    let path = |x: f32| project(Vec3::new(x, 0.3, 1.5), size);
    let (mut on, mut on_n, mut off, mut off_n) = (0.0, 0, 0.0, 0);
    for y in 0..h {
        for x in 0..w {
            let at = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let (a, b) = (pixel(&walked, x, y), pixel(&stood, x, y));
            let diff: f32 = (0..3)
                .map(|k| (f32::from(a[k]) - f32::from(b[k])).abs())
                .sum::<f32>()
                / 3.0;
            let near_ball = at.distance(centre) < 2.5 * radius;
            let along = path_x(at, &path);
            let on_path = (-4.5..end.x - 2.5 * example::BALL).contains(&along)
                && (at.y - path(along).y).abs() < radius;
            if near_ball {
                continue;
            }
            if on_path {
                on += diff;
                on_n += 1;
            } else if at.y > h as f32 * 0.45 {
                off += diff;
                off_n += 1;
            }
        }
    }
    let (on, off) = (on / on_n.max(1) as f32, off / off_n.max(1) as f32);
    eprintln!(
        "bevy: yellow heads in {:.2} % of the meadow, {:.2} % of the grass",
        100.0 * in_meadow,
        100.0 * in_grass
    );
    assert!(
        in_meadow > 0.05,
        "heads in {:.2} % of the meadow",
        100.0 * in_meadow
    );
    assert!(
        in_grass < 0.001,
        "heads in {:.2} % of the grass",
        100.0 * in_grass
    );
    eprintln!(
        "bevy: ball {inside} px inside its silhouette, {:.1} % red, {ball_outside} red px \
         outside; grass {:.1} % of the picture; walk against still: {on:.2} on the path \
         ({on_n} px), {off:.2} off it ({off_n} px)",
        100.0 * ball_share,
        100.0 * grass_share
    );
    assert!(inside > 100, "the ball covers {inside} px");
    assert!(
        (0.3..0.97).contains(&ball_share),
        "the ball shows in {:.1} % of its silhouette",
        100.0 * ball_share
    );
    assert!(ball_outside < 20, "{ball_outside} red px outside the ball");
    assert!(
        grass_share > 0.3,
        "grass covers {:.1} % of the picture",
        100.0 * grass_share
    );
    assert!(on_n > 200, "the path covers {on_n} px");
    assert!(
        on > 4.0 * off && on > 5.0,
        "the walk's trail: {on:.2} on the path against {off:.2} off it"
    );
}

/// The world x on the ball's path whose projection is nearest `at` in x.
fn path_x(at: Vec2, path: &dyn Fn(f32) -> Vec2) -> f32 {
    (0..=200)
        .map(|k| -6.0 + 12.0 * k as f32 / 200.0)
        .min_by(|&a, &b| {
            (path(a).x - at.x)
                .abs()
                .total_cmp(&(path(b).x - at.x).abs())
        })
        .unwrap_or(0.0)
}

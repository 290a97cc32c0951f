//! Unit tests of `temporal`.

use super::*;
use spirv_std::glam::Vec3;

fn close(a: Vec2, b: Vec2) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn halton_by_hand() {
    assert_eq!(halton(1, 2), 0.5);
    assert_eq!(halton(2, 2), 0.25);
    assert_eq!(halton(3, 2), 0.75);
    assert!((halton(1, 3) - 1.0 / 3.0).abs() < 1e-6);
    assert!((halton(2, 3) - 2.0 / 3.0).abs() < 1e-6);
    assert!((halton(4, 3) - 4.0 / 9.0).abs() < 1e-6);
}

#[test]
fn the_jitter_stays_within_half_a_pixel_and_averages_near_the_centre() {
    let extent = (640, 360);
    let pixel = Vec2::new(2.0 / 640.0, 2.0 / 360.0);
    let mut sum = Vec2::ZERO;
    for frame in 0..JITTER_FRAMES {
        let j = jitter(frame, extent) / pixel;
        assert!(j.abs().max_element() < 0.5, "{j}");
        sum += j;
    }
    // Eight Halton points average within a sixteenth of a pixel of the centre.
    assert!((sum / JITTER_FRAMES as f32).abs().max_element() < 1.0 / 16.0);
    assert_eq!(jitter(3, extent), jitter(3 + JITTER_FRAMES, extent));
}

#[test]
fn a_jittered_projection_moves_every_point_by_the_jitter() {
    let vp = camera(Vec3::new(1.0, 2.0, 3.0));
    let j = Vec2::new(0.003, -0.002);
    for p in [
        Vec3::ZERO,
        Vec3::new(0.5, -0.2, 1.0),
        Vec3::new(-3.0, 0.0, -4.0),
    ] {
        let a = vp * p.extend(1.0);
        let b = jittered(vp, j) * p.extend(1.0);
        assert!(close(b.xy() / b.w - a.xy() / a.w, j));
        assert!((b.z / b.w - a.z / a.w).abs() < 1e-6);
    }
}

/// A camera at `eye` looking down −z: a perspective of focal length 1.5 and
/// aspect 1.5, depth 0..1 from 0.1 to 100.
fn camera(eye: Vec3) -> Mat4 {
    let (near, far) = (0.1, 100.0);
    let projection = Mat4::from_cols(
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.5, 0.0, 0.0),
        Vec4::new(0.0, 0.0, far / (near - far), -1.0),
        Vec4::new(0.0, 0.0, near * far / (near - far), 0.0),
    );
    projection * Mat4::from_translation(-eye)
}

#[test]
fn the_depth_motion_of_a_still_camera_is_nil_whatever_the_jitter() {
    let vp = camera(Vec3::new(1.0, 2.0, 3.0));
    let j = Vec2::new(0.004, 0.001);
    let params = TemporalParams::new(vp, j, Some(vp));
    let clip = jittered(vp, j) * Vec4::new(0.3, 0.1, -0.2, 1.0);
    let (ndc, depth) = (clip.xy() / clip.w, clip.z / clip.w);
    assert!(close(depth_motion(ndc, depth, &params), Vec2::ZERO));
}

/// The point (0.3, 0.1, −0.2) seen by a camera at `now` (eye) jittered by `jitter`
/// after one at (1, 2, 3): the frame's parameters, the point, its drawn device
/// position and depth, and its move on screen worked by hand (unjittered).
fn moved_point(now: Vec3, jitter: Vec2) -> (TemporalParams, Vec4, Vec2, f32, Vec2) {
    let (before, now) = (camera(Vec3::new(1.0, 2.0, 3.0)), camera(now));
    let params = TemporalParams::new(now, jitter, Some(before));
    let p = Vec4::new(0.3, 0.1, -0.2, 1.0);
    let drawn = jittered(now, jitter) * p;
    let (ndc, depth) = (drawn.xy() / drawn.w, drawn.z / drawn.w);
    let (a, b) = (now * p, before * p);
    (params, p, ndc, depth, a.xy() / a.w - b.xy() / b.w)
}

#[test]
fn the_depth_motion_of_a_moved_camera_is_the_points_move_on_screen() {
    let (params, p, ndc, depth, by_hand) =
        moved_point(Vec3::new(1.2, 2.0, 3.0), Vec2::new(-0.002, 0.003));
    assert!(close(depth_motion(ndc, depth, &params), by_hand));
    // A point that did not move has no motion of its own.
    let before = camera(Vec3::new(1.0, 2.0, 3.0));
    assert!(close(object_motion(p.xyz(), p.xyz(), before), Vec2::ZERO));
}

#[test]
fn a_surface_over_the_depth_buffer_moves_as_itself() {
    // A far blade's point, composited over the ground after the depth was written:
    // the resolve adds the camera's motion of the ground's depth to what it wrote.
    let (params, _, ndc, depth, by_hand) =
        moved_point(Vec3::new(1.2, 2.1, 2.5), Vec2::new(0.001, -0.003));
    for behind in [depth + 0.001, 0.999, 1.0] {
        let wrote = motion_over(ndc, depth, behind, &params);
        assert!(close(pixel_motion(ndc, behind, wrote, &params), by_hand));
    }
    // Over its own depth it writes nothing; the ground's motion differs from it.
    assert!(close(motion_over(ndc, depth, depth, &params), Vec2::ZERO));
    assert!(!close(depth_motion(ndc, 0.999, &params), by_hand));
}

#[test]
fn the_sky_moves_with_the_cameras_turn() {
    // An infinite projection (depth 1 at infinity, where w is 0), turned by a
    // small angle: the sky's pixels (depth 1) still move with the turn.
    let infinite = |yaw: f32| {
        let projection = Mat4::from_cols(
            Vec4::new(1.0, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 1.5, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -1.0, -1.0),
            Vec4::new(0.0, 0.0, -0.1, 0.0),
        );
        projection * Mat4::from_rotation_y(yaw)
    };
    let params = TemporalParams::new(infinite(0.01), Vec2::ZERO, Some(infinite(0.0)));
    let m = depth_motion(Vec2::ZERO, 1.0, &params);
    assert!(m.is_finite() && m.x.abs() > 1e-3 && m.y.abs() < 1e-6, "{m}");
}

#[test]
fn a_moving_point_adds_its_own_motion_to_the_cameras() {
    let (before, now) = (
        camera(Vec3::new(1.0, 2.0, 3.0)),
        camera(Vec3::new(1.2, 2.0, 3.0)),
    );
    let params = TemporalParams::new(now, Vec2::ZERO, Some(before));
    // The point is at p now and was at q: its whole motion, by hand.
    let (p, q) = (Vec3::new(0.3, 0.1, -0.2), Vec3::new(0.25, 0.12, -0.2));
    let (a, b) = (now * p.extend(1.0), before * q.extend(1.0));
    let by_hand = a.xy() / a.w - b.xy() / b.w;
    let (ndc, depth) = (a.xy() / a.w, a.z / a.w);
    let own = object_motion(p, q, params.previous_view_proj);
    assert!(close(pixel_motion(ndc, depth, own, &params), by_hand));
}

#[test]
fn a_blade_point_moves_with_its_control_points() {
    let now = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.3, 1.0, 0.1, 1.0);
    let mut before = BladeMotion::of(&now);
    // Root: still; tip: the whole of the tip's move; middle: half of v1's, a
    // quarter of v2's.
    before.guide += Vec4::new(0.2, 0.0, 0.0, 0.0);
    before.tip += Vec4::new(0.0, 0.0, 0.4, 0.0);
    let p = Vec3::new(1.0, 2.0, 3.0);
    assert_eq!(previous_point(p, 0.0, &now, &before), p);
    assert!(
        (previous_point(p, 1.0, &now, &before) - (p + Vec3::new(0.0, 0.0, 0.4))).length() < 1e-6
    );
    let mid = previous_point(p, 0.5, &now, &before) - p;
    assert!((mid - Vec3::new(0.1, 0.0, 0.1)).length() < 1e-6);
}

#[test]
fn ycocg_round_trips() {
    for c in [
        Vec3::new(0.2, 0.5, 0.9),
        Vec3::new(3.0, 0.0, 1.0),
        Vec3::ZERO,
    ] {
        assert!((from_ycocg(to_ycocg(c)) - c).length() < 1e-6);
    }
    assert_eq!(to_ycocg(Vec3::ONE), Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn the_history_is_clipped_towards_the_box_centre() {
    let (low, high) = (Vec4::ZERO, Vec4::ONE);
    let inside = Vec4::splat(0.3);
    assert_eq!(clip_to_box(inside, low, high), inside);
    // Twice as far out as the box's half in x: halfway back to the centre.
    let out = Vec4::new(1.5, 0.5, 0.5, 0.5);
    assert!((clip_to_box(out, low, high) - Vec4::new(1.0, 0.5, 0.5, 0.5)).length() < 1e-6);
}

#[test]
fn a_neighbourhood_gathered_one_by_one_has_the_box_of_its_sums() {
    let (a, b) = (Vec4::ZERO, Vec4::splat(2.0));
    let n = Neighbourhood::of(a).with(b);
    assert_eq!(
        n.bounds(1.0),
        neighbourhood_box((a + b, b * b), a, b, 2.0, 1.0)
    );
    // Gathered in the resolve's space.
    let y = resolve_space(b);
    assert_eq!(neighbourhood_3x3(|_, _| b).bounds(1.0), (y, y));
}

#[test]
fn the_box_is_the_spread_within_the_extremes() {
    // Samples 0 and 2 in every channel: mean 1, deviation 1.
    let (sum, squares) = (Vec4::splat(2.0), Vec4::splat(4.0));
    let sums = (sum, squares);
    let (low, high) = neighbourhood_box(sums, Vec4::ZERO, Vec4::splat(2.0), 2.0, 1.0);
    assert_eq!((low, high), (Vec4::ZERO, Vec4::splat(2.0)));
    // A narrower extreme wins; half a deviation is half as wide.
    let (_, high) = neighbourhood_box(sums, Vec4::ZERO, Vec4::splat(1.5), 2.0, 1.0);
    assert_eq!(high, Vec4::splat(1.5));
    let half = neighbourhood_box(sums, Vec4::ZERO, Vec4::splat(2.0), 2.0, 0.5);
    assert_eq!(half, (Vec4::splat(0.5), Vec4::splat(1.5)));
}

#[test]
fn the_blend_takes_a_tenth_of_the_frame() {
    let (c, h) = (Vec4::new(0.5, 0.1, 0.0, 1.0), Vec4::new(9.0, 0.0, 0.1, 1.0));
    let out = blend(c, h, 0.1);
    assert!((out - (0.1 * c + 0.9 * h)).length() < 1e-5);
}

#[test]
fn a_resolved_pixel_keeps_a_history_that_fits_and_drops_one_that_does_not() {
    let grey = Vec4::new(0.5, 0.5, 0.5, 1.0);
    let flat = neighbourhood_3x3(|_, _| grey);
    // No history: the frame as it is.
    assert_eq!(resolve(grey, &flat, (false, Vec4::ONE)), grey);
    // A neighbourhood of two greys: a history between them stays, blended.
    let dark = Vec4::new(0.3, 0.3, 0.3, 1.0);
    let mixed = neighbourhood_3x3(|dx, _| if dx < 0 { dark } else { grey });
    let between = Vec4::new(0.45, 0.45, 0.45, 1.0);
    let out = resolve(grey, &mixed, (true, between));
    assert!((out - between).length() < 0.02, "{out}");
    // A history of what is no longer there (red where all is grey) goes.
    let red = Vec4::new(1.0, 0.0, 0.0, 1.0);
    let out = resolve(grey, &flat, (true, red));
    assert!((out - grey).length() < 1e-3, "{out}");
}

#[test]
fn a_pixels_centre_by_hand() {
    let (uv, ndc) = pixel_centre(UVec2::new(0, 3), UVec2::new(4, 4));
    assert_eq!((uv, ndc), (Vec2::new(0.125, 0.875), Vec2::new(-0.75, 0.75)));
}

#[test]
fn the_history_lies_back_along_the_motion() {
    assert_eq!(
        history_uv(Vec2::splat(0.5), Vec2::new(0.2, 0.0)),
        (true, Vec2::new(0.4, 0.5))
    );
    assert!(!history_uv(Vec2::new(0.05, 0.5), Vec2::new(0.2, 0.0)).0);
}

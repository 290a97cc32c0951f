//! Temporal anti-aliasing: each frame's projection moves by a sub-pixel jitter, every
//! pixel says where its surface was the frame before (its motion), and the tone map
//! blends the frame into a history reprojected along that motion, the history first
//! clipped to the colours of the pixel's neighbourhood so that what is no longer there
//! does not linger.
//!
//! The method is Brian Karis's *High Quality Temporal Supersampling* (Unreal Engine 4,
//! SIGGRAPH 2014): a Halton (2, 3) jitter, the history clipped (not clamped) to the
//! neighbourhood's box in YCoCg, a tenth of each frame blended in (plainly: Karis's
//! weighting by luma measured worse here, [`blend`]); the box is Marco Salvi's
//! variance clip (*An Excursion in Temporal Supersampling*, GDC 2016) within the
//! neighbourhood's extremes, the clip towards the box's centre Lasse Jon Fuglsang
//! Pedersen's (*Temporal Reprojection Anti-Aliasing in INSIDE*, GDC 2016).
//!
//! Motion is in normalized device coordinates: this frame's unjittered position of a
//! surface point minus its position the frame before. The resolve finds the camera's
//! part of every pixel's motion from the depth ([`depth_motion`]). A blade's points
//! also move with the wind: the compute pass keeps each visible blade's previous
//! control points beside it ([`BladeMotion`]), its geometry stages give every vertex
//! that part of its motion ([`object_motion`]), and its fragments write it to the
//! motion target (two half floats a pixel); the ground, stones and far blades write
//! none, and the target's clear value is no motion of their own.

use crate::Blade;
use spirv_std::glam::{Mat4, UVec2, Vec2, Vec3, Vec4, Vec4Swizzles};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Frames of the jitter sequence before it repeats.
pub const JITTER_FRAMES: u32 = 8;

/// Weight of this frame in the history (the rest is the reprojected history): 1/10,
/// Karis's figure, so about ten frames make a pixel.
pub const CURRENT_WEIGHT: f32 = 0.1;

/// Standard deviations the neighbourhood's box reaches from its mean (Salvi 2016
/// suggests 1 to 1.25).
pub const CLIP_GAMMA: f32 = 1.0;

/// Frames after which a still camera's history has settled: the first frame's share
/// of it is 0.9^32, about 3 %, and every jitter position has been drawn four times.
pub const SETTLE_FRAMES: u32 = 32;

/// Element `index` (from 1) of the van der Corput sequence in `base`: the Halton
/// sequence's coordinate.
pub fn halton(mut index: u32, base: u32) -> f32 {
    let mut result = 0.0;
    let mut f = 1.0;
    while index > 0 {
        f /= base as f32;
        result += f * (index % base) as f32;
        index /= base;
    }
    result
}

/// Frame `frame`'s jitter for a target of `extent` pixels, in normalized device
/// coordinates: the Halton (2, 3) point `frame mod JITTER_FRAMES + 1`, centred on the
/// pixel (each coordinate within half a pixel of its centre).
pub fn jitter(frame: u32, (width, height): (u32, u32)) -> Vec2 {
    let k = frame % JITTER_FRAMES + 1;
    let pixel = Vec2::new(halton(k, 2) - 0.5, halton(k, 3) - 0.5);
    2.0 * pixel / Vec2::new(width.max(1) as f32, height.max(1) as f32)
}

/// `view_proj` moved on screen by `jitter` (normalized device coordinates): every
/// clip position gains `jitter · w`, so every point lands `jitter` further on.
pub fn jittered(view_proj: Mat4, jitter: Vec2) -> Mat4 {
    Mat4::from_translation(jitter.extend(0.0)) * view_proj
}

/// The temporal anti-aliasing's part of the frame block.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TemporalParams {
    /// World to the previous frame's clip space, unjittered (this frame's own,
    /// unjittered, where there is no history).
    pub previous_view_proj: Mat4,
    /// This frame's clip space (jittered) to the previous frame's (unjittered):
    /// `previous_view_proj · view_proj⁻¹`, for [`depth_motion`].
    pub to_previous: Mat4,
    /// This frame's jitter (normalized device coordinates).
    pub jitter: Vec2,
    /// 1 while temporal anti-aliasing is on.
    pub on: u32,
    /// 1 when the history holds nothing to blend (the first frame, a new size or look).
    pub reset: u32,
}

impl TemporalParams {
    /// The block for a frame whose unjittered view-projection is `view_proj`, drawn
    /// with `jitter`, after a frame of `previous` (unjittered; `None`: no history).
    pub fn new(view_proj: Mat4, jitter: Vec2, previous: Option<Mat4>) -> Self {
        let drawn = jittered(view_proj, jitter);
        let previous_view_proj = previous.unwrap_or(view_proj);
        Self {
            previous_view_proj,
            to_previous: previous_view_proj * drawn.inverse(),
            jitter,
            on: 1,
            reset: u32::from(previous.is_none()),
        }
    }
}

/// What the compute pass keeps of a visible blade for its motion: its guide and tip
/// (v1, v2) as drawn the frame before (w unused).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BladeMotion {
    /// The previous frame's v1.
    pub guide: Vec4,
    /// The previous frame's v2.
    pub tip: Vec4,
}

impl BladeMotion {
    /// The control points of `before`, the blade as drawn the frame before.
    pub fn of(before: &Blade) -> Self {
        Self {
            guide: before.v1,
            tip: before.v2,
        }
    }
}

/// Where the point at height `v` of blade `now` was the frame before, given its
/// previous control points `before`: the Bézier point moves by
/// 2v(1 − v)·Δv1 + v²·Δv2 (the root stays, and the width direction follows the
/// orientation, which does not change), so the point moves by as much.
pub fn previous_point(point: Vec3, v: f32, now: &Blade, before: &BladeMotion) -> Vec3 {
    let d1 = before.guide.xyz() - now.guide();
    let d2 = before.tip.xyz() - now.tip();
    point + 2.0 * v * (1.0 - v) * d1 + v * v * d2
}

/// A point's own motion, beyond the camera's: where the previous camera
/// (`previous_view_proj`) saw it now, less where it saw it then (at `previous`).
/// Added to the camera's motion of the same point ([`depth_motion`]) it is the point's
/// whole motion.
pub fn object_motion(point: Vec3, previous: Vec3, previous_view_proj: Mat4) -> Vec2 {
    let ndc = |p: Vec3| {
        let c = previous_view_proj * p.extend(1.0);
        c.xy() / c.w.max(1e-6)
    };
    ndc(point) - ndc(previous)
}

/// The own motion of the point `point` at height `v` of blade `now`, whose control
/// points the frame before were `before` ([`previous_point`], [`object_motion`]).
pub fn blade_point_motion(
    params: &TemporalParams,
    point: Vec3,
    v: f32,
    now: &Blade,
    before: &BladeMotion,
) -> Vec2 {
    let previous = previous_point(point, v, now, before);
    object_motion(point, previous, params.previous_view_proj)
}

/// The motion of the surface at normalized device position `ndc` with `depth` (this
/// frame's depth buffer) when only the camera moved: where `params.to_previous` puts
/// it the frame before, against where it is now unjittered. Nothing drawn (the sky,
/// depth 1) is taken at [`FARTHEST_DEPTH`]: at the far plane of an infinite
/// projection w is 0, and the sky's pixels at the edges of blades would lose their
/// history every frame a jittered sample missed the blade.
pub fn depth_motion(ndc: Vec2, depth: f32, params: &TemporalParams) -> Vec2 {
    let depth = depth.min(FARTHEST_DEPTH);
    let before = params.to_previous * Vec4::new(ndc.x, ndc.y, depth, 1.0);
    (ndc - params.jitter) - before.xy() / before.w
}

/// The depth the resolve takes for nothing drawn: ten thousand times the near plane's
/// distance under an infinite projection, where a camera's move shifts a point by a
/// ten-thousandth of what it shifts one at the near plane.
pub const FARTHEST_DEPTH: f32 = 0.9999;

/// A pixel's motion: the camera's motion of the depth buffer's surface plus the
/// motion of its own that a blade `wrote` to the motion target (none elsewhere).
pub fn pixel_motion(ndc: Vec2, depth: f32, wrote: Vec2, params: &TemporalParams) -> Vec2 {
    depth_motion(ndc, depth, params) + wrote
}

/// RGB to YCoCg (luma, orange and green chroma), where the neighbourhood's box hugs
/// the colours more tightly than in RGB (Karis 2014).
pub fn to_ycocg(c: Vec3) -> Vec3 {
    Vec3::new(
        0.25 * c.x + 0.5 * c.y + 0.25 * c.z,
        0.5 * c.x - 0.5 * c.z,
        -0.25 * c.x + 0.5 * c.y - 0.25 * c.z,
    )
}

/// YCoCg back to RGB.
pub fn from_ycocg(c: Vec3) -> Vec3 {
    Vec3::new(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z)
}

/// The colour of a pixel in the space the resolve works in: YCoCg, with the share of
/// the pixel the scene covers (alpha) as a fourth channel.
pub fn resolve_space(rgba: Vec4) -> Vec4 {
    to_ycocg(rgba.xyz()).extend(rgba.w)
}

/// Back from [`resolve_space`].
pub fn from_resolve_space(c: Vec4) -> Vec4 {
    from_ycocg(c.xyz()).extend(c.w)
}

/// The neighbourhood's box: its mean ± `gamma` standard deviations in each channel
/// (Salvi's variance clip), within its extremes; from the sums of the samples
/// (`sum`), of their squares (`squares`), their least and most, over `count` samples.
pub fn neighbourhood_box(
    (sum, squares): (Vec4, Vec4),
    least: Vec4,
    most: Vec4,
    count: f32,
    gamma: f32,
) -> (Vec4, Vec4) {
    let mean = sum / count;
    let spread = (squares / count - mean * mean).max(Vec4::ZERO);
    let sigma = Vec4::new(
        spread.x.sqrt(),
        spread.y.sqrt(),
        spread.z.sqrt(),
        spread.w.sqrt(),
    );
    (
        (mean - gamma * sigma).max(least),
        (mean + gamma * sigma).min(most),
    )
}

/// `history` clipped to the box (`low`, `high`) along the line to the box's centre
/// (Pedersen 2016): unchanged inside, else the point where that line leaves the box.
pub fn clip_to_box(history: Vec4, low: Vec4, high: Vec4) -> Vec4 {
    let centre = 0.5 * (low + high);
    let half = (0.5 * (high - low)).max(Vec4::splat(1e-5));
    let offset = history - centre;
    let units = (offset / half).abs();
    let most = units.x.max(units.y).max(units.z).max(units.w);
    if most > 1.0 {
        centre + offset / most
    } else {
        history
    }
}

/// This frame's `current` colour blended into the clipped `history`: weights
/// `weight` and its rest. Karis's weights divided by 1 + luma (against fireflies) bias
/// the mean towards the dark: on the NVIDIA H100 at 1920x1080 they left the paper
/// look's still frame 2.95 from the supersampled reference against 1.84 without
/// (`grass quality`; 4x MSAA: 2.16).
pub fn blend(current: Vec4, history: Vec4, weight: f32) -> Vec4 {
    current * weight + history * (1.0 - weight)
}

/// The colours of a pixel's neighbourhood, gathered one by one (in [`resolve_space`]):
/// their sum, the sum of their squares, their least and their most.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Neighbourhood {
    sum: Vec4,
    squares: Vec4,
    least: Vec4,
    most: Vec4,
    count: f32,
}

impl Neighbourhood {
    /// The neighbourhood of one colour, `c`.
    pub fn of(c: Vec4) -> Self {
        Self {
            sum: c,
            squares: c * c,
            least: c,
            most: c,
            count: 1.0,
        }
    }

    /// With the colour `c` too. (The shaders gather the 3x3 neighbourhood by eight
    /// explicit calls: a loop over it took the NVIDIA H100 3.3 ms more at 1920x1080
    /// than no neighbourhood, the explicit calls 0.1 ms.)
    pub fn with(self, c: Vec4) -> Self {
        Self {
            sum: self.sum + c,
            squares: self.squares + c * c,
            least: self.least.min(c),
            most: self.most.max(c),
            count: self.count + 1.0,
        }
    }

    /// Its box of `gamma` standard deviations ([`neighbourhood_box`]).
    pub fn bounds(&self, gamma: f32) -> (Vec4, Vec4) {
        let sums = (self.sum, self.squares);
        neighbourhood_box(sums, self.least, self.most, self.count, gamma)
    }
}

/// One pixel resolved: its `current` colour (premultiplied RGBA, alpha the share the
/// scene covers) blended into its `history` (reprojected; where there is none,
/// `(false, _)`), the history first clipped to the box of [`CLIP_GAMMA`] deviations of
/// its neighbourhood `around` (in [`resolve_space`]; [`clip_to_box`]), then
/// [`CURRENT_WEIGHT`] of the frame blended in ([`blend`]). (Flags rather than options:
/// rust-gpu cannot make an `Option<Vec4>` constant.)
pub fn resolve(
    current: Vec4,
    around: &Neighbourhood,
    (has_history, history): (bool, Vec4),
) -> Vec4 {
    if !has_history {
        return current;
    }
    let (low, high) = around.bounds(CLIP_GAMMA);
    let clipped = clip_to_box(resolve_space(history), low, high);
    from_resolve_space(blend(resolve_space(current), clipped, CURRENT_WEIGHT))
}

/// The 3x3 neighbourhood of a pixel whose colours `at(dx, dy)` gives, in
/// [`resolve_space`], gathered by explicit calls (see [`Neighbourhood::with`]).
pub fn neighbourhood_3x3(at: impl Fn(i32, i32) -> Vec4) -> Neighbourhood {
    let s = |dx, dy| resolve_space(at(dx, dy));
    Neighbourhood::of(s(0, 0))
        .with(s(-1, -1))
        .with(s(0, -1))
        .with(s(1, -1))
        .with(s(-1, 0))
        .with(s(1, 0))
        .with(s(-1, 1))
        .with(s(0, 1))
        .with(s(1, 1))
}

/// The centre of pixel `texel` of a target of `size` pixels: its texture coordinates
/// and its normalized device coordinates.
pub fn pixel_centre(texel: UVec2, size: UVec2) -> (Vec2, Vec2) {
    let uv = (texel.as_vec2() + Vec2::splat(0.5)) / size.as_vec2();
    (uv, 2.0 * uv - 1.0)
}

/// Where the history of the pixel at texture coordinates `uv` with `motion` lies:
/// `uv` less the motion in texture units, and whether that is on the screen (else
/// there is nothing to blend).
pub fn history_uv(uv: Vec2, motion: Vec2) -> (bool, Vec2) {
    let before = uv - 0.5 * motion;
    let inside = before.x >= 0.0 && before.y >= 0.0 && before.x <= 1.0 && before.y <= 1.0;
    (inside, before)
}

#[cfg(test)]
mod tests {
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

    #[test]
    fn the_depth_motion_of_a_moved_camera_is_the_points_move_on_screen() {
        let (before, now) = (
            camera(Vec3::new(1.0, 2.0, 3.0)),
            camera(Vec3::new(1.2, 2.0, 3.0)),
        );
        let j = Vec2::new(-0.002, 0.003);
        let params = TemporalParams::new(now, j, Some(before));
        let p = Vec4::new(0.3, 0.1, -0.2, 1.0);
        let drawn = jittered(now, j) * p;
        let (ndc, depth) = (drawn.xy() / drawn.w, drawn.z / drawn.w);
        let (a, b) = (now * p, before * p);
        let by_hand = a.xy() / a.w - b.xy() / b.w;
        assert!(close(depth_motion(ndc, depth, &params), by_hand));
        // A point that did not move has no motion of its own.
        assert!(close(object_motion(p.xyz(), p.xyz(), before), Vec2::ZERO));
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
            (previous_point(p, 1.0, &now, &before) - (p + Vec3::new(0.0, 0.0, 0.4))).length()
                < 1e-6
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
}

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

/// The motion that a surface at `depth`, drawn where the depth buffer holds `behind`
/// (it did not write its depth), gives the motion target, so that the resolve's
/// camera motion of `behind` plus it ([`pixel_motion`]) is the camera's motion of the
/// surface itself: the shading's far blades, composited after the depth was written.
pub fn motion_over(ndc: Vec2, depth: f32, behind: f32, params: &TemporalParams) -> Vec2 {
    depth_motion(ndc, depth, params) - depth_motion(ndc, behind, params)
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
mod tests;

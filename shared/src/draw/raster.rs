//! The compute rasterizer for far blades: blades a few pixels tall skip the
//! fixed-function pipeline. Each is drawn by one compute thread into a visibility
//! buffer of one 64-bit value per pixel taken with an atomic minimum: the depth in the
//! high 32 bits (a positive `f32`'s bits order as the float does), the blade's slot and
//! the position along it in the low 32. A narrow blade is drawn as its Bezier curve in
//! a few straight segments, one pixel wide ([`raster_line`]); a wider one as its
//! surface, each pixel whose centre it covers ([`raster_wide`]). A resolve pass shades
//! each pixel's winner with the fragment stages' functions and writes its depth, so the
//! depth test composites it with what the hardware drew. After Nanite's visibility
//! buffer (Karis et al., *Nanite: a deep dive*, SIGGRAPH 2021), drawn for grass.
//!
//! Blades narrower than a pixel keep their expected coverage: a blade whose width is a
//! fraction f of a pixel is drawn with probability f, by a hash of its index (the same
//! every frame: no shimmer), and left out otherwise.
//!
//! The rasterizer runs once the hardware has drawn the near grass and the ground: each
//! pixel is tested against their depth ([`in_front`]) and against the value the pixel
//! holds, and only a sample in front of both takes the atomic.
//!
//! Every function here runs on the GPU and on the host: [`raster_blade`] with a
//! closure that takes the atomic minimum on the GPU and a plain minimum on the host.

use crate::Blade;
use crate::cull::lod::screen_height;
use crate::draw::shape::{shape_tau, shape_width, surface_point};
use crate::noise::hash_unit;
use spirv_std::glam::{Mat4, Vec3, Vec4Swizzles};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// A pixel no far blade covers.
pub const EMPTY: u64 = u64::MAX;
/// Bits of the position along the blade in a packed value.
pub const V_BITS: u32 = 8;
/// Bits of the far blade's slot in a packed value: 2^24 slots, 16,777,216 blades.
pub const SLOT_BITS: u32 = 24;
/// Widest x of the rasterizer's dispatch ([`raster_dispatch`]); the smallest
/// `maxComputeWorkGroupCount[0]` Vulkan allows is 65,535.
pub const RASTER_GRID_WIDTH: u32 = 32_768;
/// Most straight segments a far blade is drawn with as a line.
pub const MAX_SEGMENTS: u32 = 4;
/// Most segments a wide blade is drawn with as its surface ([`WIDE_PX`]).
pub const MAX_WIDE_SEGMENTS: u32 = 8;
/// A blade at least this wide on screen where it is widest (pixels) is drawn as its
/// surface, quad by quad, each pixel whose centre it covers, as the hardware samples
/// it; a narrower one as a line with its expected coverage ([`Coverage::draws`]).
pub const WIDE_PX: f32 = 1.5;
/// Screen pixels of blade height per segment of a wide blade, as the hardware path's
/// level of detail spaces them (`lod::LodSettings::pixels_per_segment`'s default).
pub const WIDE_PIXELS_PER_SEGMENT: f32 = 16.0;

/// What the rasterizer needs of the frame (`FrameUniforms::raster`).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RasterParams {
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// Blades shorter than this on screen (pixels) are drawn by the compute
    /// rasterizer; 0 turns it off.
    pub below: f32,
    /// Straight segments along a far blade, 1 to [`MAX_SEGMENTS`].
    pub segments: u32,
}

/// Whether `blade`, seen from `camera` with focal length `focal`, is drawn by the
/// compute rasterizer under `params`.
pub fn is_far(blade: &Blade, camera: Vec3, focal: f32, params: &RasterParams) -> bool {
    let distance = (blade.v0.xyz() - camera).length();
    params.below > 0.0 && screen_height(blade.height(), distance, focal) < params.below
}

/// The visibility buffer's value of a sample at `depth` (0 near to 1 far) of far slot
/// `slot` at `v` along the blade (0 root, 1 tip): smaller is nearer.
pub fn pack(depth: f32, slot: u32, v: f32) -> u64 {
    let v_max = ((1u32 << V_BITS) - 1) as f32;
    let quantised = (v.clamp(0.0, 1.0) * v_max + 0.5) as u32;
    let low = ((slot & ((1 << SLOT_BITS) - 1)) << V_BITS) | quantised;
    ((depth.max(0.0).to_bits() as u64) << 32) | low as u64
}

/// [`pack`]'s inverse: (depth, slot, v), v to 1/255.
pub fn unpack(value: u64) -> (f32, u32, f32) {
    let depth = packed_depth(value);
    let low = value as u32;
    let v_max = ((1u32 << V_BITS) - 1) as f32;
    (
        depth,
        low >> V_BITS,
        (low & ((1 << V_BITS) - 1)) as f32 / v_max,
    )
}

/// The value [`pack`] made, read as its two 32-bit words (low first, as a buffer of
/// `u32` holds it, for a stage without 64-bit integers): (depth, slot, v) as
/// [`unpack`] gives them, or `None` where the pixel holds [`EMPTY`].
pub fn unpack_words(low: u32, high: u32) -> Option<(f32, u32, f32)> {
    if low == u32::MAX && high == u32::MAX {
        return None;
    }
    let v_max = ((1u32 << V_BITS) - 1) as f32;
    Some((
        f32::from_bits(high),
        low >> V_BITS,
        (low & ((1 << V_BITS) - 1)) as f32 / v_max,
    ))
}

/// Whether a far blade's sample at `depth` is in front of `hardware`, the depth the
/// fixed-function pipeline left at its pixel: the resolve's depth test
/// (`LESS_OR_EQUAL`, as every pipeline's), taken before the atomic, so a pixel the
/// hardware's grass or ground hides costs the rasterizer a load rather than an atomic.
pub fn in_front(depth: f32, hardware: f32) -> bool {
    depth <= hardware
}

/// The depth of a packed value ([`pack`]).
pub fn packed_depth(value: u64) -> f32 {
    f32::from_bits((value >> 32) as u32)
}

/// Whether a blade `width_px` pixels wide is drawn at all: always from a pixel up, with
/// probability `width_px` below (by the hash of its `index`).
pub fn covers(width_px: f32, index: u32) -> bool {
    width_px >= 1.0 || hash_unit(index ^ 0x5bd1_e995) < width_px
}

/// A point of a far blade on screen: pixel coordinates, depth, v.
#[derive(Copy, Clone, Debug, PartialEq)]
struct ScreenPoint {
    x: f32,
    y: f32,
    depth: f32,
    v: f32,
}

/// The curve point at `v` (De Casteljau on v0, v1, v2, paper section 6.2), on screen;
/// `None` behind the camera.
fn curve_on_screen(
    blade: &Blade,
    v: f32,
    view_proj: Mat4,
    params: &RasterParams,
) -> Option<ScreenPoint> {
    let (v0, v1, v2) = (blade.root(), blade.guide(), blade.tip());
    let a = v0 + v * (v1 - v0);
    let b = v1 + v * (v2 - v1);
    let c = a + v * (b - a);
    on_screen(c, v, view_proj, params)
}

/// World point `p` (at `v` along its blade) on screen; `None` behind the camera or
/// nearer than its near plane (a depth below 0, never drawn), where the projection
/// would throw the point arbitrarily far off the target.
fn on_screen(p: Vec3, v: f32, view_proj: Mat4, params: &RasterParams) -> Option<ScreenPoint> {
    let clip = view_proj * p.extend(1.0);
    if clip.w <= 1e-6 || clip.z < 0.0 {
        return None;
    }
    let ndc = clip.xyz() / clip.w;
    Some(ScreenPoint {
        x: (ndc.x * 0.5 + 0.5) * params.width as f32,
        y: (ndc.y * 0.5 + 0.5) * params.height as f32,
        depth: ndc.z,
        v,
    })
}

/// Most samples one straight segment of a far blade is stepped in
/// (`segment_samples`): far more than a target's diagonal.
pub const MAX_SEGMENT_STEPS: f32 = 65_536.0;

/// Samples segment `from` → `to` is stepped in: one a pixel along its longer axis
/// (sample i at t = i / samples), at least 1, at most [`MAX_SEGMENT_STEPS`].
fn segment_samples(from: ScreenPoint, to: ScreenPoint) -> u32 {
    let (dx, dy) = ((to.x - from.x).abs(), (to.y - from.y).abs());
    dx.max(dy).ceil().clamp(1.0, MAX_SEGMENT_STEPS) as u32
}

/// The samples of segment `from` → `to` ([`segment_samples`]: `samples` of them)
/// that may lie on the target and within the depth range, as (first, last); `None`
/// where none does. The segment is clipped against x in [0, width], y in
/// [0, height] and depth in [0, 1] by Liang and Barsky's parametric test (*A new
/// concept and method for line clipping*, ACM TOG 1984), so a segment reaching far off
/// the target costs its pixels on it, not its length. A sample either side is kept
/// for the rounding; the per-sample test keeps those off the target out.
fn samples_on_target(
    from: ScreenPoint,
    to: ScreenPoint,
    samples: u32,
    params: &RasterParams,
) -> Option<(u32, u32)> {
    let (dx, dy, dz) = (to.x - from.x, to.y - from.y, to.depth - from.depth);
    let (w, h) = (params.width as f32, params.height as f32);
    // Each side keeps the t where t·p ≤ q.
    let mut range = (0.0f32, 1.0f32);
    let inside = clip_side(-dx, from.x, &mut range)
        && clip_side(dx, w - from.x, &mut range)
        && clip_side(-dy, from.y, &mut range)
        && clip_side(dy, h - from.y, &mut range)
        && clip_side(-dz, from.depth, &mut range)
        && clip_side(dz, 1.0 - from.depth, &mut range);
    if !inside || range.0 > range.1 {
        return None;
    }
    let n = samples as f32;
    let first = (range.0 * n).floor().max(0.0) as u32;
    let last = ((range.1 * n).ceil() as u32).min(samples);
    Some((first, last))
}

/// One side of Liang and Barsky's test ([`samples_on_target`]): narrows `range` to
/// the t where t·p ≤ q; false where no t is (parallel to the side and outside it).
fn clip_side(p: f32, q: f32, range: &mut (f32, f32)) -> bool {
    if p == 0.0 {
        q >= 0.0
    } else {
        let r = q / p;
        if p < 0.0 {
            range.0 = range.0.max(r);
        } else {
            range.1 = range.1.min(r);
        }
        true
    }
}

/// Twice the signed area of the triangle (a, b, p): which side of a→b the point p is.
fn edge(a: ScreenPoint, b: ScreenPoint, (x, y): (f32, f32)) -> f32 {
    (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)
}

/// Whether pixel centre `p` lies in triangle (a, b, c), either winding.
fn in_triangle(a: ScreenPoint, b: ScreenPoint, c: ScreenPoint, p: (f32, f32)) -> bool {
    let (e0, e1, e2) = (edge(a, b, p), edge(b, c, p), edge(c, a, p));
    (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0)
}

/// The edges of a wide blade at `v`: its surface at u = 0 and u = 1 on screen (the
/// shape's width there, `shape::surface_point`), and its centre line.
fn edges_on_screen(
    blade: &Blade,
    v: f32,
    coverage: &Coverage,
    view_proj: Mat4,
    params: &RasterParams,
) -> Option<(ScreenPoint, ScreenPoint, ScreenPoint)> {
    let (shape, k) = (coverage.shape, coverage.tip_start);
    let left = surface_point(blade, 0.0, v, shape, k).position;
    let right = surface_point(blade, 1.0, v, shape, k).position;
    let centre = curve_on_screen(blade, v, view_proj, params)?;
    Some((
        on_screen(left, v, view_proj, params)?,
        on_screen(right, v, view_proj, params)?,
        centre,
    ))
}

/// Whether a blade of `coverage` is drawn as its surface ([`raster_wide`]) rather than
/// as a line.
pub fn is_wide(coverage: &Coverage) -> bool {
    coverage.width_px >= WIDE_PX
}

/// Draws a wide blade ([`is_wide`]) as its surface: a strip of quads between its edges
/// at `segments` + 1 heights, each pixel whose centre a quad covers (its two triangles)
/// plotted once per quad with the depth and v of its nearest point on the quad's
/// centre line. `tile`² threads share the work, this one `lane` of them: the bounding
/// box of each quad is walked in tiles of `tile` by `tile` pixels, each lane taking
/// its pixel of every tile (a workgroup of 64 drawing one blade together in 8 by 8
/// tiles, its lanes in step and each pixel's place found without a division; the host
/// draws it alone, lane 0 of tiles of 1). Returns the pixels this lane plotted.
// As in `raster_line`, the depth is compared by hand.
#[allow(clippy::manual_range_contains, clippy::too_many_arguments)]
pub fn raster_wide(
    blade: &Blade,
    slot: u32,
    coverage: &Coverage,
    view_proj: Mat4,
    params: &RasterParams,
    (lane, tile): (u32, u32),
    mut plot: impl FnMut(u32, u32, u64),
) -> u32 {
    let segments = ((coverage.height_px / WIDE_PIXELS_PER_SEGMENT).ceil() as u32).clamp(
        params.segments.clamp(1, MAX_WIDE_SEGMENTS),
        MAX_WIDE_SEGMENTS,
    );
    let Some((mut l0, mut r0, mut c0)) = edges_on_screen(blade, 0.0, coverage, view_proj, params)
    else {
        return 0;
    };
    let (w, h) = (params.width as f32, params.height as f32);
    let (lane_x, lane_y) = (lane % tile, lane / tile);
    let mut plotted = 0;
    let mut s = 1;
    while s <= segments {
        let v = s as f32 / segments as f32;
        let Some((l1, r1, c1)) = edges_on_screen(blade, v, coverage, view_proj, params) else {
            return plotted;
        };
        // The quad's pixels: every centre in its bounding box, on the target.
        let x_min = l0.x.min(r0.x).min(l1.x).min(r1.x).max(0.0).floor() as u32;
        let y_min = l0.y.min(r0.y).min(l1.y).min(r1.y).max(0.0).floor() as u32;
        let x_end = l0.x.max(r0.x).max(l1.x).max(r1.x).min(w).ceil() as u32;
        let y_end = l0.y.max(r0.y).max(l1.y).max(r1.y).min(h).ceil() as u32;
        let axis = (c1.x - c0.x, c1.y - c0.y);
        let length2 = (axis.0 * axis.0 + axis.1 * axis.1).max(1e-12);
        let mut ty = y_min;
        while ty < y_end {
            let mut tx = x_min;
            while tx < x_end {
                let (x, y) = (tx + lane_x, ty + lane_y);
                let p = (x as f32 + 0.5, y as f32 + 0.5);
                if x < x_end
                    && y < y_end
                    && (in_triangle(l0, r0, r1, p) || in_triangle(l0, r1, l1, p))
                {
                    let t =
                        (((p.0 - c0.x) * axis.0 + (p.1 - c0.y) * axis.1) / length2).clamp(0.0, 1.0);
                    let depth = c0.depth + t * (c1.depth - c0.depth);
                    if depth >= 0.0 && depth <= 1.0 {
                        plot(x, y, pack(depth, slot, c0.v + t * (c1.v - c0.v)));
                        plotted += 1;
                    }
                }
                tx += tile;
            }
            ty += tile;
        }
        (l0, r0, c0) = (l1, r1, c1);
        s += 1;
    }
    plotted
}

/// How much of a pixel row a blade covers at each v: its width on screen in pixels
/// (`width_px`, its shape's full width), narrowed by its shape function (`shape`,
/// `tip_start`: `shape::shape_tau`), and the blade's index for the coverage hash.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Width on screen in pixels where the shape is widest.
    pub width_px: f32,
    /// One of `shape::SHAPE_*`.
    pub shape: u32,
    /// k of the triangle-tip shape.
    pub tip_start: f32,
    /// The blade's index (its hash decides the thin parts).
    pub index: u32,
    /// Height on screen in pixels.
    pub height_px: f32,
}

impl Coverage {
    /// The coverage of `blade` seen from `camera` (`focal` in pixels) in `shape`.
    pub fn of(
        blade: &Blade,
        index: u32,
        (shape, tip_start): (u32, f32),
        camera: Vec3,
        focal: f32,
    ) -> Self {
        let shape = crate::draw::shape::blade_shape(blade, shape);
        let distance = (blade.v0.xyz() - camera).length();
        let width = blade.width() * shape_width(shape);
        Self {
            width_px: screen_height(width, distance, focal),
            shape,
            tip_start,
            index,
            height_px: screen_height(blade.height(), distance, focal),
        }
    }

    /// Whether step `step` of the blade's line, at `v`, is drawn: [`covers`] for the
    /// width the shape leaves there, hashed per blade and step, so a tapering blade
    /// covers fewer pixels towards its tip, as the triangles it stands for would.
    pub fn draws(&self, v: f32, step: u32) -> bool {
        let (shape, k) = (self.shape, self.tip_start);
        let taper = (shape_tau(shape, 1.0, v, k) - shape_tau(shape, 0.0, v, k)).abs();
        covers(
            self.width_px * taper,
            self.index.wrapping_mul(0x9e37_79b1) ^ step,
        )
    }
}

/// Draws far blade `blade` (far slot `slot`) alone: [`raster_wide`] where it is wide,
/// else [`raster_line`]. Returns the pixels plotted.
pub fn raster_blade(
    blade: &Blade,
    slot: u32,
    coverage: &Coverage,
    view_proj: Mat4,
    params: &RasterParams,
    plot: impl FnMut(u32, u32, u64),
) -> u32 {
    if is_wide(coverage) {
        raster_wide(blade, slot, coverage, view_proj, params, (0, 1), plot)
    } else {
        raster_line(blade, slot, coverage, view_proj, params, plot)
    }
}

/// Draws a narrow far blade `blade` (far slot `slot`): calls `plot(x, y, packed)` for
/// each pixel its curve crosses, in `params.segments` straight segments, one pixel
/// wide, where its `coverage` draws. Pixels off the target and depths outside 0..1 are
/// skipped. Returns the pixels plotted.
// `(0.0..=1.0).contains(&depth)` makes rust-gpu emit a load through a pointer that is
// not logical (spirv-val rejects it): the depth is compared by hand.
#[allow(clippy::manual_range_contains)]
pub fn raster_line(
    blade: &Blade,
    slot: u32,
    coverage: &Coverage,
    view_proj: Mat4,
    params: &RasterParams,
    mut plot: impl FnMut(u32, u32, u64),
) -> u32 {
    let segments = params.segments.clamp(1, MAX_SEGMENTS);
    let Some(mut from) = curve_on_screen(blade, 0.0, view_proj, params) else {
        return 0;
    };
    let mut plotted = 0;
    let mut step = 0;
    let mut s = 1;
    while s <= segments {
        let Some(to) = curve_on_screen(blade, s as f32 / segments as f32, view_proj, params) else {
            return plotted;
        };
        // One step a pixel along the longer axis, only over the part on the target;
        // the first segment takes its start. `step` counts every sample, on the
        // target or not, so where the target's edge cuts a blade does not change
        // which of its samples the coverage's hash draws.
        let start = if s == 1 { 0 } else { 1 };
        let steps = segment_samples(from, to);
        if let Some((first, last)) = samples_on_target(from, to, steps, params) {
            let mut i = first.max(start);
            while i <= last {
                let t = i as f32 / steps as f32;
                let x = from.x + t * (to.x - from.x);
                let y = from.y + t * (to.y - from.y);
                let depth = from.depth + t * (to.depth - from.depth);
                let inside = x >= 0.0
                    && y >= 0.0
                    && x < params.width as f32
                    && y < params.height as f32
                    && depth >= 0.0
                    && depth <= 1.0;
                let v = from.v + t * (to.v - from.v);
                if inside && coverage.draws(v, step + i - start) {
                    plot(x as u32, y as u32, pack(depth, slot, v));
                    plotted += 1;
                }
                i += 1;
            }
        }
        step += steps + 1 - start;
        from = to;
        s += 1;
    }
    plotted
}

/// The rasterizer's dispatch for `far` blades, one thread each in workgroups of
/// `workgroup` threads, as (x, y) workgroups no wider than `width` (x · workgroup
/// threads a row, as `layout::flat_index` counts them); (0, 1) for none.
pub fn raster_dispatch(far: u32, workgroup: u32, width: u32) -> (u32, u32) {
    let groups = far.div_ceil(workgroup);
    let x = groups.min(width);
    (x, if x == 0 { 1 } else { groups.div_ceil(x) })
}

/// The rasterizer's preparation's dispatch (one thread per pixel of a `width` by
/// `height` target in workgroups of `side`²) when `far` blades are far; (0, 1), none,
/// without, so a frame with no far blade neither copies the depth nor clears the
/// visibility buffer.
pub fn prepare_dispatch(far: u32, (width, height): (u32, u32), side: u32) -> (u32, u32) {
    if far == 0 {
        (0, 1)
    } else {
        (width.div_ceil(side), height.div_ceil(side))
    }
}

/// Index of pixel (x, y) in the visibility buffer of a target `width` wide.
pub fn pixel_index(x: u32, y: u32, width: u32) -> usize {
    (y * width + x) as usize
}

#[cfg(test)]
mod tests;

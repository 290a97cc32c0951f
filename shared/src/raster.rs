//! The compute rasterizer for far blades (issue 18): blades a few pixels tall skip the
//! fixed-function pipeline. Each is drawn by one compute thread as its Bezier curve in
//! a few straight segments, one pixel wide, into a visibility buffer of one 64-bit
//! value per pixel taken with an atomic minimum: the depth in the high 32 bits (a
//! positive `f32`'s bits order as the float does), the blade's slot and the position
//! along it in the low 32. A resolve pass shades each pixel's winner with the fragment
//! stages' functions and writes its depth, so the depth test composites it with what
//! the hardware drew. After Nanite's visibility buffer (Karis et al., *Nanite: a deep
//! dive*, SIGGRAPH 2021), drawn for grass.
//!
//! Blades narrower than a pixel keep their expected coverage: a blade whose width is a
//! fraction f of a pixel is drawn with probability f, by a hash of its index (the same
//! every frame: no shimmer), and left out otherwise.
//!
//! Every function here runs on the GPU and on the host: [`raster_blade`] with a
//! closure that takes the atomic minimum on the GPU and a plain minimum on the host.

use crate::Blade;
use crate::lod::screen_height;
use crate::look::hash_unit;
use crate::shape::{shape_tau, shape_width};
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
/// Most straight segments a far blade is drawn with.
pub const MAX_SEGMENTS: u32 = 4;

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
    let depth = f32::from_bits((value >> 32) as u32);
    let low = value as u32;
    let v_max = ((1u32 << V_BITS) - 1) as f32;
    (
        depth,
        low >> V_BITS,
        (low & ((1 << V_BITS) - 1)) as f32 / v_max,
    )
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
    let clip = view_proj * c.extend(1.0);
    if clip.w <= 1e-6 {
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
        let distance = (blade.v0.xyz() - camera).length();
        let width = blade.width() * shape_width(shape);
        Self {
            width_px: screen_height(width, distance, focal),
            shape,
            tip_start,
            index,
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

/// Draws far blade `blade` (far slot `slot`): calls `plot(x, y, packed)` for each pixel
/// its curve crosses, in `params.segments` straight segments, one pixel wide, where its
/// `coverage` draws. Pixels off the target and depths outside 0..1 are skipped.
/// Returns the pixels plotted.
// `(0.0..=1.0).contains(&depth)` makes rust-gpu emit a load through a pointer that is
// not logical (spirv-val rejects it): the depth is compared by hand.
#[allow(clippy::manual_range_contains)]
pub fn raster_blade(
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
        // One step a pixel along the longer axis; the first segment takes its start.
        let steps = (to.x - from.x)
            .abs()
            .max((to.y - from.y).abs())
            .ceil()
            .max(1.0) as u32;
        let mut i = if s == 1 { 0 } else { 1 };
        while i <= steps {
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
            if inside && coverage.draws(v, step) {
                plot(x as u32, y as u32, pack(depth, slot, v));
                plotted += 1;
            }
            step += 1;
            i += 1;
        }
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

/// Index of pixel (x, y) in the visibility buffer of a target `width` wide.
pub fn pixel_index(x: u32, y: u32, width: u32) -> usize {
    (y * width + x) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use spirv_std::glam::Vec3;

    #[test]
    fn packing_orders_by_depth_and_round_trips() {
        let a = pack(0.25, 7, 0.5);
        let b = pack(0.5, 3, 0.0);
        assert!(a < b, "nearer is smaller");
        let (depth, slot, v) = unpack(a);
        assert_eq!((depth, slot), (0.25, 7));
        assert!((v - 0.5).abs() <= 0.5 / 255.0 + 1e-6, "{v}");
        // The largest slot and the ends of the blade survive.
        let (_, slot, v) = unpack(pack(1.0, (1 << SLOT_BITS) - 1, 1.0));
        assert_eq!((slot, v), ((1 << SLOT_BITS) - 1, 1.0));
        assert!(pack(1.0, (1 << SLOT_BITS) - 1, 1.0) < EMPTY);
        assert_eq!(unpack(pack(0.75, 0, 0.0)).2, 0.0);
    }

    #[test]
    fn thin_blades_keep_their_expected_coverage() {
        // Over many blades a quarter-pixel blade is drawn about a quarter of the time,
        // and the same blade always alike.
        let drawn = (0..10_000).filter(|&i| covers(0.25, i)).count();
        assert!((2_300..2_700).contains(&drawn), "{drawn}");
        assert!((0..100).all(|i| covers(1.0, i) && covers(3.0, i)));
        assert_eq!(covers(0.25, 42), covers(0.25, 42));
        assert!((0..100).all(|i| !covers(0.0, i)));
    }

    #[test]
    fn a_blade_is_drawn_as_its_curve_a_pixel_wide() {
        // An upright blade 2 units tall 10 units ahead, seen by a camera looking down
        // -z: its curve is a vertical run of pixels from the root to the tip.
        let params = RasterParams {
            width: 64,
            height: 64,
            below: 16.0,
            segments: 2,
        };
        use spirv_std::glam::camera::rh;
        let eye = Vec3::new(0.0, 1.0, 10.0);
        let view = rh::view::look_at_mat4(eye, Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
        let view_proj = rh::proj::vulkan::perspective(1.0, 1.0, 0.1, 100.0) * view;
        // Wide enough to be drawn whatever the hash says.
        let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 2.0, 10.0);
        let focal = crate::lod::focal_pixels(1.0, 64.0);
        let camera = Vec3::new(0.0, 1.0, 10.0);
        let mut pixels = Vec::new();
        let quad = (crate::shape::SHAPE_QUAD, 0.5);
        let coverage = Coverage::of(&blade, 9, quad, camera, focal);
        let n = raster_blade(&blade, 5, &coverage, view_proj, &params, |x, y, packed| {
            pixels.push((x, y, packed))
        });
        assert_eq!(n as usize, pixels.len());
        // About its height on screen in pixels, in one column at the centre.
        let tall = screen_height(2.0, 10.0, focal);
        assert!((n as f32 - tall).abs() <= 3.0, "{n} pixels for {tall}");
        assert!(
            pixels.iter().all(|&(x, _, _)| x == 31 || x == 32),
            "{pixels:?}"
        );
        // The slot, and v from the root (0) to the tip (1) along the run.
        let vs: Vec<f32> = pixels.iter().map(|&(_, _, p)| unpack(p).2).collect();
        assert!(pixels.iter().all(|&(_, _, p)| unpack(p).1 == 5));
        assert_eq!(vs.first(), Some(&0.0));
        assert_eq!(vs.last(), Some(&1.0));
        assert!(vs.windows(2).all(|w| w[1] >= w[0]), "{vs:?}");
        // Behind the camera: nothing.
        let behind = Blade::at_rest(Vec3::new(0.0, 0.0, 20.0), Vec3::Y, 0.0, 2.0, 2.0, 10.0);
        assert_eq!(
            raster_blade(&behind, 0, &coverage, view_proj, &params, |_, _, _| {}),
            0
        );
    }

    #[test]
    fn a_tapering_blade_covers_less_towards_its_tip() {
        // A triangle blade half a pixel wide at the root: about half of its root's
        // steps are drawn, and none at the tip, where it closes.
        let c = Coverage {
            width_px: 0.5,
            shape: crate::shape::SHAPE_TRIANGLE,
            tip_start: 0.5,
            index: 3,
        };
        let root = (0..4000).filter(|&s| c.draws(0.0, s)).count();
        let middle = (0..4000).filter(|&s| c.draws(0.5, s)).count();
        assert!((1_800..2_200).contains(&root), "{root}");
        assert!((800..1_200).contains(&middle), "{middle}");
        assert_eq!((0..4000).filter(|&s| c.draws(1.0, s)).count(), 0);
        // A quad blade wider than a pixel draws every step.
        let wide = Coverage {
            width_px: 1.5,
            shape: crate::shape::SHAPE_QUAD,
            ..c
        };
        assert!((0..100).all(|s| wide.draws(0.9, s)));
    }

    #[test]
    fn the_dispatch_covers_every_far_blade() {
        assert_eq!(raster_dispatch(0, 64, 32_768), (0, 1));
        assert_eq!(raster_dispatch(1, 64, 32_768), (1, 1));
        assert_eq!(raster_dispatch(65, 64, 32_768), (2, 1));
        let (x, y) = raster_dispatch(16_777_216, 64, 32_768);
        assert!(x <= 32_768 && x * y * 64 >= 16_777_216 && (x * (y - 1)) * 64 < 16_777_216);
    }

    #[test]
    fn far_means_shorter_on_screen_than_the_threshold() {
        let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 1.0, 0.1, 10.0);
        let params = |below| RasterParams {
            below,
            ..Default::default()
        };
        // 1 unit at 10 units with a focal length of 100 pixels: 10 pixels tall.
        let camera = Vec3::new(0.0, 0.0, 10.0);
        assert!(is_far(&blade, camera, 100.0, &params(12.0)));
        assert!(!is_far(&blade, camera, 100.0, &params(8.0)));
        assert!(
            !is_far(&blade, camera, 100.0, &params(0.0)),
            "0 turns it off"
        );
    }
}

//! Occlusion culling, the paper's fourth test (section 4.2), with a hierarchical depth
//! buffer (Hi-Z): the occluders' depth of this frame, reduced level by level to the
//! farthest depth of each 2×2 block, and a blade removed only when its nearest point
//! is behind the farthest occluder depth over every pixel it could cover.
//!
//! The pyramid lives in one `f32` storage buffer, level after level, row-major. The
//! same functions build it (host tests) and read it (compute pass and host tests).

use crate::Blade;
use spirv_std::glam::{Mat4, Vec2, Vec3, Vec3Swizzles, Vec4Swizzles};

/// Most levels of a pyramid: level 15 of a 65,536-pixel-wide screen is 2 pixels wide.
pub const MAX_LEVELS: u32 = 16;

/// Depth slack of the test: a blade is occluded only when its nearest depth exceeds
/// the occluders' farthest by more than this (rasterised and computed depths may
/// differ in the last bits).
pub const DEPTH_BIAS: f32 = 1e-6;

/// Pixels added around a blade's projected bounds before the test.
pub const MARGIN_PIXELS: f32 = 1.0;

/// Where each level of the pyramid lies in its buffer, as the uniform block carries
/// it. All zero: no pyramid, and the test keeps every blade.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct HiZLayout {
    /// Width of level 0 (the screen), in pixels.
    pub width: u32,
    /// Height of level 0, in pixels.
    pub height: u32,
    /// Number of levels; 0 when there is no pyramid.
    pub levels: u32,
    /// Floats in the whole pyramid.
    pub len: u32,
    /// Offset in floats of each level.
    pub offsets: [u32; MAX_LEVELS as usize],
}

/// Size of `level` of a `width` × `height` pyramid: ⌈width / 2^level⌉ × ⌈height / 2^level⌉,
/// so texel (x, y) of level k covers the pixels [x·2^k, (x + 1)·2^k) × [y·2^k, (y + 1)·2^k).
pub fn level_size(width: u32, height: u32, level: u32) -> (u32, u32) {
    (
        ((width.max(1) - 1) >> level) + 1,
        ((height.max(1) - 1) >> level) + 1,
    )
}

impl HiZLayout {
    /// The layout of the pyramid of a `width` × `height` screen: levels down to 1×1.
    #[cfg(not(target_arch = "spirv"))]
    pub fn new(width: u32, height: u32) -> Self {
        let mut layout = Self::default();
        let mut offset = 0;
        let mut level = 0;
        while level < MAX_LEVELS {
            layout.offsets[level as usize] = offset;
            let (w, h) = level_size(width, height, level);
            offset += w * h;
            level += 1;
            if w == 1 && h == 1 {
                break;
            }
        }
        layout.width = width;
        layout.height = height;
        layout.levels = level;
        layout.len = offset;
        layout
    }
    /// True when there is no pyramid.
    pub fn is_empty(&self) -> bool {
        self.levels == 0
    }
    /// Offset in floats of `level`.
    pub fn offset(&self, level: u32) -> u32 {
        self.offsets[level as usize]
    }
}

/// Texel (x, y) of `level` (≥ 1): the farthest of the 2×2 texels of the level below
/// that lie inside it (one or two at an odd edge).
pub fn reduce(pyramid: &[f32], hiz: &HiZLayout, level: u32, x: u32, y: u32) -> f32 {
    let (w, h) = level_size(hiz.width, hiz.height, level - 1);
    let base = hiz.offset(level - 1);
    let (x0, y0) = (2 * x, 2 * y);
    let x1 = (x0 + 1).min(w - 1);
    let y1 = (y0 + 1).min(h - 1);
    let at = |px: u32, py: u32| pyramid[(base + py * w + px) as usize];
    at(x0, y0).max(at(x1, y0)).max(at(x0, y1)).max(at(x1, y1))
}

/// The pyramid of a depth image (row-major, `width` × `height`), built on the host
/// with the same [`reduce`] the GPU runs.
#[cfg(not(target_arch = "spirv"))]
pub fn build(depth: &[f32], width: u32, height: u32) -> (HiZLayout, Vec<f32>) {
    let hiz = HiZLayout::new(width, height);
    let mut pyramid = vec![0.0; hiz.len as usize];
    pyramid[..depth.len()].copy_from_slice(depth);
    for level in 1..hiz.levels {
        let (w, h) = level_size(width, height, level);
        for y in 0..h {
            for x in 0..w {
                let value = reduce(&pyramid, &hiz, level, x, y);
                pyramid[(hiz.offset(level) + y * w + x) as usize] = value;
            }
        }
    }
    (hiz, pyramid)
}

/// A blade's extent on screen: pixel bounds and nearest depth.
#[derive(Copy, Clone, Debug)]
pub struct ScreenBounds {
    /// Smallest pixel coordinates (x right, y down).
    pub min: Vec2,
    /// Largest pixel coordinates.
    pub max: Vec2,
    /// Smallest depth (0 near … 1 far).
    pub nearest: f32,
    /// False when part of the blade is at or behind the camera's plane: then the
    /// projection says nothing and the blade must be kept.
    pub in_front: bool,
}

/// The screen bounds of the box around v0, v1 and v2 grown by half the width: the
/// Bezier curve lies in the hull of its control points and the blade within ½w of
/// the curve, so the box holds every point the blade can draw.
pub fn screen_bounds(blade: &Blade, view_proj: Mat4, screen: Vec2) -> ScreenBounds {
    let half = Vec3::splat(0.5 * blade.width());
    let lo = blade.root().min(blade.guide()).min(blade.tip()) - half;
    let hi = blade.root().max(blade.guide()).max(blade.tip()) + half;
    box_bounds(lo, hi, view_proj, screen)
}

/// The screen bounds of the box from `lo` to `hi` (its eight corners).
pub fn box_bounds(lo: Vec3, hi: Vec3, view_proj: Mat4, screen: Vec2) -> ScreenBounds {
    let mut bounds = ScreenBounds {
        min: Vec2::splat(f32::MAX),
        max: Vec2::splat(f32::MIN),
        nearest: f32::MAX,
        in_front: true,
    };
    let mut corner = 0u32;
    while corner < 8 {
        let pick = |bit: u32, a: f32, b: f32| if corner & bit == 0 { a } else { b };
        let p = Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        let clip = view_proj * p.extend(1.0);
        // A NaN must also keep the blade, so `in_front` stays true only for a
        // finite w clearly in front.
        bounds.in_front &= clip.w > 1e-6;
        let ndc = clip.xyz() / clip.w;
        let pixel = (ndc.xy() * 0.5 + 0.5) * screen;
        bounds.min = bounds.min.min(pixel);
        bounds.max = bounds.max.max(pixel);
        bounds.nearest = bounds.nearest.min(ndc.z);
        corner += 1;
    }
    bounds
}

/// True when every pixel of the rectangle [x0, x1] × [y0, y1] (inclusive, on screen)
/// has occluder depth nearer than `nearest`: the farthest depth over the rectangle,
/// read from the finest level where it spans at most `span` × `span` texels (the
/// first level, going up from the screen, where it does): 2 for a blade (four reads),
/// more for a tile, whose box is wide on screen and would otherwise be read at a
/// level so coarse that its texels take in the sky beside it.
pub fn rect_occluded(
    pyramid: &[f32],
    hiz: &HiZLayout,
    (x0, y0): (u32, u32),
    (x1, y1): (u32, u32),
    nearest: f32,
    span: u32,
) -> bool {
    let (mut a0, mut a1, mut b0, mut b1) = (x0, x1, y0, y1);
    let mut level = 0;
    while level + 1 < hiz.levels && (a1 - a0 >= span || b1 - b0 >= span) {
        level += 1;
        a0 >>= 1;
        a1 >>= 1;
        b0 >>= 1;
        b1 >>= 1;
    }
    let (w, _) = level_size(hiz.width, hiz.height, level);
    let base = hiz.offset(level);
    let mut farthest = 0.0f32;
    let mut y = b0;
    while y <= b1 {
        let mut x = a0;
        while x <= a1 {
            farthest = farthest.max(pyramid[(base + y * w + x) as usize]);
            x += 1;
        }
        y += 1;
    }
    nearest > farthest + DEPTH_BIAS
}

/// Texels a side a tile's rectangle is read over ([`box_occluded`]): at most 64
/// reads.
pub const TILE_SPAN: u32 = 8;

/// Occlusion test: true when the blade is certainly hidden behind the occluders.
/// Conservative: a blade partly off screen, crossing the camera plane, or not finite
/// is kept, and so is every blade when there is no pyramid.
pub fn occluded(blade: &Blade, view_proj: Mat4, pyramid: &[f32], hiz: &HiZLayout) -> bool {
    if hiz.is_empty() {
        return false;
    }
    let screen = Vec2::new(hiz.width as f32, hiz.height as f32);
    bounds_occluded(screen_bounds(blade, view_proj, screen), pyramid, hiz, 2)
}

/// [`occluded`] for the box from `lo` to `hi` (a tile of the tiled field and the
/// blades it can hold: the tile-level test).
pub fn box_occluded(lo: Vec3, hi: Vec3, view_proj: Mat4, pyramid: &[f32], hiz: &HiZLayout) -> bool {
    if hiz.is_empty() {
        return false;
    }
    let screen = Vec2::new(hiz.width as f32, hiz.height as f32);
    bounds_occluded(
        box_bounds(lo, hi, view_proj, screen),
        pyramid,
        hiz,
        TILE_SPAN,
    )
}

/// Whether everything within `b` is hidden (kept when off screen, crossing the
/// camera plane or not finite).
fn bounds_occluded(b: ScreenBounds, pyramid: &[f32], hiz: &HiZLayout, span: u32) -> bool {
    let screen = Vec2::new(hiz.width as f32, hiz.height as f32);
    let min = b.min - MARGIN_PIXELS;
    let max = b.max + MARGIN_PIXELS;
    // Written so that NaN keeps the blade; also bounds the conversions below.
    let on_screen = min.x >= 0.0 && min.y >= 0.0 && max.x < screen.x && max.y < screen.y;
    if !b.in_front || !on_screen {
        return false;
    }
    rect_occluded(
        pyramid,
        hiz,
        (min.x as u32, min.y as u32),
        (max.x as u32, max.y as u32),
        b.nearest,
        span,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_of_an_odd_screen() {
        let hiz = HiZLayout::new(5, 3);
        // 5×3, 3×2, 2×1, 1×1.
        assert_eq!(hiz.levels, 4);
        assert_eq!(level_size(5, 3, 1), (3, 2));
        assert_eq!(level_size(5, 3, 2), (2, 1));
        assert_eq!(
            (0..4).map(|l| hiz.offset(l)).collect::<Vec<_>>(),
            vec![0, 15, 21, 23]
        );
        assert_eq!(hiz.len, 24);
        let full_hd = HiZLayout::new(1920, 1080);
        assert_eq!(full_hd.levels, 12);
        assert_eq!(level_size(1920, 1080, 11), (1, 1));
    }

    #[test]
    fn levels_hold_the_farthest_depth_below() {
        // A 5×3 image with one far texel in the odd last column.
        let mut depth = vec![0.2; 15];
        depth[2 * 5 + 4] = 0.9;
        depth[0] = 0.5;
        let (hiz, pyramid) = build(&depth, 5, 3);
        let level = |l: u32| {
            let (w, h) = level_size(5, 3, l);
            let o = hiz.offset(l) as usize;
            pyramid[o..o + (w * h) as usize].to_vec()
        };
        assert_eq!(level(1), vec![0.5, 0.2, 0.2, 0.2, 0.2, 0.9]);
        assert_eq!(level(2), vec![0.5, 0.9]);
        assert_eq!(level(3), vec![0.9]);
    }

    /// A 64×64 screen, camera at (0, 1, 10) looking down −Z.
    const SIZE: u32 = 64;

    fn view_proj() -> Mat4 {
        use spirv_std::glam::camera::rh;
        let eye = Vec3::new(0.0, 1.0, 10.0);
        let view = rh::view::look_at_mat4(eye, Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
        rh::proj::vulkan::perspective(60f32.to_radians(), 1.0, 0.1, 100.0) * view
    }

    /// The depth image of a wall in the plane z = 0 spanning x0..x1 and y0..y1,
    /// rasterised at pixel centres (far plane, 1.0, elsewhere).
    fn wall_depth(x0: f32, x1: f32, y0: f32, y1: f32) -> Vec<f32> {
        let vp = view_proj();
        let inverse = vp.inverse();
        let mut depth = vec![1.0; (SIZE * SIZE) as usize];
        for py in 0..SIZE {
            for px in 0..SIZE {
                let ndc = (Vec2::new(px as f32, py as f32) + 0.5) / SIZE as f32 * 2.0 - 1.0;
                let near = inverse.project_point3(ndc.extend(0.0));
                let far = inverse.project_point3(ndc.extend(1.0));
                let t = near.z / (near.z - far.z);
                let hit = near + (far - near) * t;
                if (x0..=x1).contains(&hit.x) && (y0..=y1).contains(&hit.y) && t > 0.0 {
                    depth[(py * SIZE + px) as usize] = vp.project_point3(hit).z;
                }
            }
        }
        depth
    }

    fn upright(x: f32, z: f32, height: f32) -> Blade {
        Blade::at_rest(Vec3::new(x, 0.0, z), Vec3::Y, 0.3, height, 0.1, 10.0)
    }

    fn is_occluded(blade: &Blade, depth: &[f32]) -> bool {
        let (hiz, pyramid) = build(depth, SIZE, SIZE);
        occluded(blade, view_proj(), &pyramid, &hiz)
    }

    #[test]
    fn a_blade_fully_behind_a_wall_is_removed() {
        let depth = wall_depth(-3.0, 3.0, -1.0, 4.0);
        assert!(is_occluded(&upright(0.0, -3.0, 1.5), &depth));
    }

    #[test]
    fn a_blade_half_behind_a_wall_is_kept() {
        let depth = wall_depth(-3.0, 3.0, -1.0, 4.0);
        // Seen from the camera the wall's edge x = 3 lies at x = 3.9 three units
        // behind it: a blade there is half hidden.
        assert!(!is_occluded(&upright(3.9, -3.0, 1.5), &depth));
        // Well inside the silhouette at the same distance: removed.
        assert!(is_occluded(&upright(3.3, -3.0, 1.5), &depth));
        // Taller than the wall's silhouette: the top shows.
        assert!(!is_occluded(&upright(0.0, -3.0, 6.0), &depth));
        // In front of the wall.
        assert!(!is_occluded(&upright(0.0, 2.0, 1.5), &depth));
    }

    #[test]
    fn a_blade_at_the_screen_edge_is_kept() {
        // A wall filling the whole screen.
        let depth = wall_depth(-100.0, 100.0, -100.0, 100.0);
        assert!(is_occluded(&upright(0.0, -3.0, 1.5), &depth));
        // The screen's left edge three units behind the wall is at x ≈ −7.5: a blade
        // across it is partly off screen, where the pyramid knows nothing.
        assert!(!is_occluded(&upright(-7.5, -3.0, 1.5), &depth));
        // Crossing the camera's plane.
        assert!(!is_occluded(&upright(0.0, 10.0, 1.5), &depth));
    }

    #[test]
    fn no_pyramid_or_no_finite_blade_keeps_it() {
        let blade = upright(0.0, -3.0, 1.5);
        assert!(!occluded(&blade, view_proj(), &[], &HiZLayout::default()));
        let depth = wall_depth(-3.0, 3.0, -1.0, 4.0);
        let mut broken = blade;
        broken.v2.x = f32::NAN;
        assert!(!is_occluded(&broken, &depth));
    }

    /// Independent of the bounds and the pyramid: a removed blade must have every
    /// point of its drawn surface behind the wall's depth at the pixel it lands on.
    #[test]
    fn removed_blades_are_hidden_at_every_surface_point() {
        let depth = wall_depth(-2.0, 2.5, -1.0, 3.0);
        let vp = view_proj();
        let mut rng = crate::world::generate::SplitMix64::new(7);
        let mut removed = 0;
        for _ in 0..2000 {
            let root = Vec3::new(rng.range(-6.0, 6.0), 0.0, rng.range(-8.0, 4.0));
            let height = rng.range(0.5, 4.0);
            let rest = Blade::at_rest(
                root,
                Vec3::Y,
                rng.range(0.0, std::f32::consts::TAU),
                height,
                0.15,
                10.0,
            );
            let lean = Vec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0));
            let blade = rest.with_curve(rest.guide() + 0.3 * lean, rest.tip() + lean);
            if !is_occluded(&blade, &depth) {
                continue;
            }
            removed += 1;
            for i in 0..=8 {
                for j in 0..=16 {
                    let (u, v) = (i as f32 / 8.0, j as f32 / 16.0);
                    let p = crate::draw::shape::surface_point(&blade, u, v, 0, 0.5).position;
                    let clip = vp * p.extend(1.0);
                    let ndc = clip.xyz() / clip.w;
                    let pixel = ((ndc.xy() * 0.5 + 0.5) * SIZE as f32).floor();
                    let (px, py) = (pixel.x as usize, pixel.y as usize);
                    let wall = depth[py * SIZE as usize + px];
                    assert!(ndc.z > wall, "blade {blade:?} shows at ({u}, {v})");
                }
            }
        }
        // The case is not vacuous: a good share is hidden.
        assert!(removed > 200, "only {removed} blades removed");
    }
}

//! Level of detail of the tessellation control stage: a continuous tessellation level
//! along the blade from its height on screen, so a segment covers about the same
//! number of pixels near and far; the width is always one segment.
//!
//! The evaluation stage uses fractional-odd spacing: a level between two odd numbers
//! splits the blade into the higher odd count with two shorter segments that grow as
//! the level rises, so detail fades in and out without popping.

use crate::camera::CameraParams;
use crate::draw::shape::{SHAPE_DANDELION, SHAPE_FLOWER, SHAPE_SEED_HEAD, blade_shape};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Highest tessellation level along a blade.
pub const MAX_LEVEL: f32 = 9.0;

/// Most vertical segments a blade can get: [`MAX_LEVEL`] rounded up to odd.
pub const MAX_SEGMENTS: u32 = 9;

/// Default screen pixels per segment along a blade: coarse, because the tessellator
/// turns each segment into six triangles (`reference::triangles_per_patch`); chosen
/// by measurement (docs/performance-notes.md).
pub const PIXELS_PER_SEGMENT: f32 = 16.0;

/// The level-of-detail thresholds, as the frame block carries them (the focal length
/// comes with the camera).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LodParams {
    /// Screen pixels per segment along a blade.
    pub pixels_per_segment: f32,
    /// Most segments (near the camera).
    pub most: f32,
    /// Fewest segments (far away); equal to `most` with LOD off.
    pub fewest: f32,
}

/// Focal length in pixels of a perspective projection with vertical field of view
/// `fov_y` (radians) on a target `height` pixels tall: an object of size s at
/// distance d covers s · focal / d pixels.
pub fn focal_pixels(fov_y: f32, height: f32) -> f32 {
    0.5 * height / (0.5 * fov_y).tan()
}

/// Height on screen in pixels of something `height` tall at `distance` from a camera
/// of focal length `focal` ([`focal_pixels`]): the measure of the level of detail and of
/// the compute rasterizer's threshold (`raster`).
pub fn screen_height(height: f32, distance: f32, focal: f32) -> f32 {
    height * focal / distance.max(1e-6)
}

/// Tessellation level along a blade of `height` at `distance` from the camera: its
/// height on screen (`focal` from [`focal_pixels`]) over `pixels` per segment, between
/// `fewest` and `most`, not rounded (continuous LOD), within 1..=[`MAX_LEVEL`]. With
/// `fewest` = `most` every blade gets `most` (LOD off).
pub fn screen_level(
    height: f32,
    distance: f32,
    focal: f32,
    pixels: f32,
    most: f32,
    fewest: f32,
) -> f32 {
    let on_screen = screen_height(height, distance, focal);
    let level = clamp_unchecked(on_screen / pixels.max(1e-6), fewest.min(most), most);
    clamp_unchecked(level, 1.0, MAX_LEVEL)
}

/// The level of detail of `blade` in this frame (both pipelines, and the compute
/// pass that bins blades for the mesh path): its height on screen over the pixels
/// per segment ([`screen_level`]), at least what its shape (`shape`, the field's
/// setting) needs.
pub fn blade_level(
    blade: &crate::Blade,
    lod: &LodParams,
    camera: &CameraParams,
    shape: u32,
) -> f32 {
    use spirv_std::glam::Vec4Swizzles;
    let distance = (blade.v0.xyz() - camera.position).length();
    screen_level(
        blade.height(),
        distance,
        camera.focal_pixels,
        lod.pixels_per_segment,
        lod.most,
        lod.fewest,
    )
    .max(shape_min_level(blade_shape(blade, shape)))
}

/// `x` within `lo..=hi` (for `lo <= hi`) without `f32::clamp`'s check of its bounds:
/// that check is a panic path (rust-gpu turns a panic into an early return), which
/// the shader code that calls this (`crate::meshlet`) has no use for.
#[allow(clippy::manual_clamp)]
pub fn clamp_unchecked(x: f32, lo: f32, hi: f32) -> f32 {
    x.max(lo).min(hi)
}

/// Segments fractional-odd spacing makes of `level`: the level rounded up to the next
/// odd whole number.
pub fn odd_segments(level: f32) -> u32 {
    let n = level.clamp(1.0, MAX_LEVEL).ceil() as u32;
    n + 1 - n % 2
}

/// Tessellation levels of a quad patch with u across the width and v along the
/// height: (outer, inner). Outer 0 and 2 are the edges u = 0 and u = 1 (they run
/// along v), outer 1 and 3 the edges v = 0 and v = 1; inner 0 runs along u, inner 1
/// along v.
pub fn tess_levels(segments: f32) -> ([f32; 4], [f32; 2]) {
    ([segments, 1.0, segments, 1.0], [1.0, segments])
}

/// [`tess_levels`], or outer levels of 0 when the patch is not to be drawn: the
/// tessellator then drops it.
pub fn tess_levels_if(segments: f32, keep: bool) -> ([f32; 4], [f32; 2]) {
    let (outer, inner) = tess_levels(segments);
    if keep {
        (outer, inner)
    } else {
        ([0.0; 4], inner)
    }
}

/// Vertices one blade produces at `segments` vertical segments: a 2 × (segments + 1)
/// grid.
pub fn vertices_per_blade(segments: u32) -> u32 {
    2 * (segments + 1)
}

/// Most vertices one draw may produce: lavapipe (Mesa 22.3) wraps a 16-bit vertex
/// index inside its tessellation path past 65,536 and draws broken sheets.
pub const MAX_VERTICES_PER_DRAW: u32 = 65_536;

/// Blades per indirect draw so that no draw exceeds [`MAX_VERTICES_PER_DRAW`] at the
/// highest level, with a factor of two to spare for how a driver counts vertices.
pub fn blades_per_chunk() -> u32 {
    MAX_VERTICES_PER_DRAW / 2 / vertices_per_blade(MAX_SEGMENTS)
}

/// The slice of the visible blades that draw command `chunk` covers:
/// (first blade, number of blades); empty chunks past the end draw nothing.
pub fn chunk_range(visible: u32, chunk: u32, chunk_size: u32) -> (u32, u32) {
    let first = chunk * chunk_size;
    let count = if visible > first {
        (visible - first).min(chunk_size)
    } else {
        0
    };
    (first, count)
}

/// Ways the tessellation path deals the visible list out in ([`dealt_slot`]).
pub const DRAW_WAYS: u32 = 256;

/// The slot of the visible list (of `visible` blades) that the tessellation path's
/// vertex `vertex` draws: the list read as [`DRAW_WAYS`] columns, row by row, and
/// drawn column by column (the columns of the last, short row one longer), a
/// bijection of 0..`visible`. The blades lie in Z order of their roots
/// (`world::mesh::spatial_order`), so the visible list's neighbours stand together on
/// screen; drawn in that order, a burst of patches falls on one screen tile and the one
/// raster unit that owns it. Dealt out, consecutive patches are a column's
/// `visible / DRAW_WAYS` slots apart, over the whole view.
pub fn dealt_slot(vertex: u32, visible: u32) -> u32 {
    let (rows, short) = (visible / DRAW_WAYS, visible % DRAW_WAYS);
    // The first `short` columns hold rows + 1 slots, the rest `rows`.
    let long = short * (rows + 1);
    let (column, row) = if vertex < long {
        (vertex / (rows + 1), vertex % (rows + 1))
    } else {
        let v = vertex - long;
        (short + v / rows.max(1), v % rows.max(1))
    };
    row * DRAW_WAYS + column
}

/// The fewest segments along a leaf of `shape` whatever its size on screen: the
/// dandelion's lobes and the flower's head (the last fifth of its length) need every
/// segment there is ([`MAX_LEVEL`]), the seed head 5; other shapes 1.
pub fn shape_min_level(shape: u32) -> f32 {
    if shape == SHAPE_DANDELION || shape == SHAPE_FLOWER {
        MAX_LEVEL
    } else if shape == SHAPE_SEED_HEAD {
        5.0
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::shape::SHAPE_QUAD;

    #[test]
    fn the_dandelion_needs_every_segment() {
        assert_eq!(shape_min_level(SHAPE_DANDELION), MAX_LEVEL);
        assert_eq!(shape_min_level(SHAPE_QUAD), 1.0);
        // The flower's head has four rows inside it (its rows crowd there,
        // `species::row_v`); the seed head two.
        use crate::species::{FLOWER, FLOWER_HEAD_FROM, SEED_GRASS, SEED_HEAD_FROM, row_v};
        let rows = |level: f32, species: u32| {
            let n = odd_segments(level);
            (0..=n).map(move |k| row_v(species, k as f32 / n as f32))
        };
        let inside = |level: f32, species: u32, from: f32| {
            rows(level, species)
                .filter(|&v| v > from + 1e-6 && v < 1.0)
                .count()
        };
        let flower = shape_min_level(SHAPE_FLOWER);
        assert_eq!(inside(flower, FLOWER, FLOWER_HEAD_FROM), 4);
        let seed = shape_min_level(SHAPE_SEED_HEAD);
        assert!(inside(seed, SEED_GRASS, SEED_HEAD_FROM) >= 2);
    }

    #[test]
    fn a_patch_not_kept_has_no_outer_levels() {
        assert_eq!(tess_levels_if(5.0, true), tess_levels(5.0));
        let (outer, inner) = tess_levels_if(5.0, false);
        assert_eq!(outer, [0.0; 4]);
        assert_eq!(inner, tess_levels(5.0).1);
    }

    #[test]
    fn focal_length_by_hand() {
        // 90 degrees: half the height at distance 1 covers half the target.
        let f = focal_pixels(90f32.to_radians(), 1000.0);
        assert!((f - 500.0).abs() < 1e-3, "{f}");
    }

    #[test]
    fn level_follows_the_height_on_screen() {
        // A 1-unit blade at 10 units with a 1,200-pixel focal length is 120 pixels
        // tall: 20 pixels per segment make 6, continuous.
        assert_eq!(screen_level(1.0, 10.0, 1200.0, 20.0, 9.0, 1.0), 6.0);
        assert_eq!(screen_level(1.0, 16.0, 1200.0, 20.0, 9.0, 1.0), 3.75);
        // Twice as far, half the level; never below the fewest or above the most.
        assert_eq!(screen_level(1.0, 20.0, 1200.0, 20.0, 9.0, 1.0), 3.0);
        assert_eq!(screen_level(1.0, 1e4, 1200.0, 20.0, 9.0, 2.0), 2.0);
        assert_eq!(screen_level(1.0, 0.5, 1200.0, 20.0, 7.0, 1.0), 7.0);
        assert_eq!(screen_level(1.0, 0.0, 1200.0, 20.0, 7.0, 1.0), 7.0);
        // LOD off: fewest = most.
        assert_eq!(screen_level(1.0, 1e4, 1200.0, 20.0, 7.0, 7.0), 7.0);
        // Clamped to what the chunks are sized for.
        assert_eq!(screen_level(1.0, 1.0, 1200.0, 1.0, 64.0, 1.0), MAX_LEVEL);
        assert_eq!(screen_level(1.0, 1e9, 1200.0, 20.0, 7.0, 0.0), 1.0);
    }

    #[test]
    fn fractional_odd_rounds_up_to_odd() {
        let cases = [
            (1.0, 1),
            (1.2, 3),
            (3.0, 3),
            (3.01, 5),
            (6.5, 7),
            (9.0, 9),
            (20.0, 9),
        ];
        for (level, segments) in cases {
            assert_eq!(odd_segments(level), segments, "level {level}");
        }
        assert_eq!(odd_segments(MAX_LEVEL), MAX_SEGMENTS);
    }

    #[test]
    fn chunks_cover_the_visible_blades_once() {
        assert_eq!(chunk_range(2500, 0, 1000), (0, 1000));
        assert_eq!(chunk_range(2500, 2, 1000), (2000, 500));
        assert_eq!(chunk_range(2500, 3, 1000), (3000, 0));
        assert_eq!(chunk_range(0, 0, 1000), (0, 0));
    }

    #[test]
    fn chunks_stay_under_the_vertex_limit() {
        let n = blades_per_chunk();
        assert!(n * vertices_per_blade(MAX_SEGMENTS) * 2 <= MAX_VERTICES_PER_DRAW);
        assert!(n > 1000);
    }
    #[test]
    fn the_dealt_slots_are_each_slot_once_and_neighbours_far_apart() {
        for visible in [0, 1, 5, 255, 256, 257, 1000, 4096, 70_001] {
            let mut seen = vec![false; visible as usize];
            for v in 0..visible {
                let slot = dealt_slot(v, visible);
                assert!(slot < visible, "{v} of {visible} to {slot}");
                assert!(!seen[slot as usize], "{slot} twice of {visible}");
                seen[slot as usize] = true;
            }
        }
        // Hand-worked: 1,000 slots are 3 rows of 256 and 232 over; vertex 0 is slot 0,
        // vertex 1 the next row's (256), vertex 4 column 1's first (1); past the 232
        // long columns (928 vertices) the short ones, three each: 928 → slot 232.
        assert_eq!(dealt_slot(1, 1000), 256);
        assert_eq!(dealt_slot(4, 1000), 1);
        assert_eq!(dealt_slot(928, 1000), 232);
        assert_eq!(dealt_slot(931, 1000), 233);
    }
}

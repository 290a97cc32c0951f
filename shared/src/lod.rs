//! Level of detail of the tessellation control stage: fewer vertical segments far
//! away; the width is always one segment.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Most vertical segments a blade gets (near the camera).
pub const MAX_SEGMENTS: u32 = 8;

/// Vertical segments at `distance`: `most` up to `near`, falling linearly to `fewest`
/// at `far` and beyond, rounded to a whole number so neighbouring blades match.
pub fn vertical_segments(distance: f32, near: f32, far: f32, most: f32, fewest: f32) -> f32 {
    let t = ((distance - near) / (far - near).max(1e-6)).clamp(0.0, 1.0);
    (most + (fewest - most) * t)
        .round()
        .clamp(1.0, MAX_SEGMENTS as f32)
}

/// Tessellation levels of a quad patch with u across the width and v along the
/// height: (outer, inner). Outer 0 and 2 are the edges u = 0 and u = 1 (they run
/// along v), outer 1 and 3 the edges v = 0 and v = 1; inner 0 runs along u, inner 1
/// along v.
pub fn tess_levels(segments: f32) -> ([f32; 4], [f32; 2]) {
    ([segments, 1.0, segments, 1.0], [1.0, segments])
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_fall_with_distance_and_stay_whole() {
        assert_eq!(vertical_segments(0.0, 5.0, 45.0, 8.0, 2.0), 8.0);
        assert_eq!(vertical_segments(25.0, 5.0, 45.0, 8.0, 2.0), 5.0);
        assert_eq!(vertical_segments(45.0, 5.0, 45.0, 8.0, 2.0), 2.0);
        assert_eq!(vertical_segments(1e9, 5.0, 45.0, 8.0, 2.0), 2.0);
        assert_eq!(vertical_segments(10.0, 5.0, 5.0, 8.0, 2.0), 2.0);
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
}

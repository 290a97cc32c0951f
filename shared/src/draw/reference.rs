//! The triangle-throughput reference: patches shaped like a blade's tessellated quad but
//! with nothing to compute, laid on a grid of small screen cells, so that timing them
//! measures how fast this device tessellates and sets up triangles.

use crate::gpu::layout::ThroughputPush;
use spirv_std::glam::{Vec2, Vec4};

/// Size of one cell in pixels (wide, tall): about the footprint of a distant blade.
pub const CELL_PIXELS: (u32, u32) = (2, 8);

/// The grid of cells over a `width` × `height` target.
pub fn push(level: f32, width: u32, height: u32) -> ThroughputPush {
    let cell = CELL_PIXELS;
    ThroughputPush {
        level,
        columns: (width / cell.0).max(1),
        rows: (height / cell.1).max(1),
        pad: 0,
    }
}

/// The cell of patch `index` in clip space, (corner x, corner y, width, height):
/// patches fill the cells row by row and start over when the grid is full, so every
/// patch lands on screen.
pub fn patch_cell(index: u32, push: &ThroughputPush) -> Vec4 {
    let (columns, rows) = (push.columns.max(1), push.rows.max(1));
    let cell = index % (columns * rows);
    let size = Vec2::new(2.0 / columns as f32, 2.0 / rows as f32);
    let corner = Vec2::new((cell % columns) as f32, (cell / columns) as f32) * size - 1.0;
    Vec4::new(corner.x, corner.y, size.x, size.y)
}

/// Clip-space position of (u, v) of a patch in `cell` (from [`patch_cell`]).
pub fn cell_point(cell: Vec4, u: f32, v: f32) -> Vec4 {
    Vec4::new(cell.x + u * cell.z, cell.y + v * cell.w, 0.5, 1.0)
}

/// Triangles the tessellator makes of one blade's quad patch at `level`: two at
/// level 1 (every level 1: the quad is not subdivided); otherwise the inner level 1
/// across the blade counts as 1 + ε and fractional-odd spacing rounds it up to 3, so
/// N segments along give an inner grid of 1 × (N − 2) quads (2N − 4 triangles) and a
/// ring joining the outer edges' 2N + 2 segments to the inner ones' 2N − 2 (4N
/// triangles): 6N − 4, three times the 2N a blade needs.
pub fn triangles_per_patch(level: f32) -> u32 {
    match crate::cull::lod::odd_segments(level) {
        1 => 2,
        n => 6 * n - 4,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patches_tile_the_screen_then_wrap() {
        let p = push(1.0, 8, 16);
        assert_eq!((p.columns, p.rows), (4, 2));
        let patch_point = |i, u, v, p| cell_point(patch_cell(i, p), u, v);
        assert_eq!(
            patch_point(0, 0.0, 0.0, &p),
            Vec4::new(-1.0, -1.0, 0.5, 1.0)
        );
        assert_eq!(patch_point(0, 1.0, 1.0, &p), Vec4::new(-0.5, 0.0, 0.5, 1.0));
        assert_eq!(patch_point(5, 0.0, 0.0, &p), Vec4::new(-0.5, 0.0, 0.5, 1.0));
        assert_eq!(patch_point(7, 1.0, 1.0, &p), Vec4::new(1.0, 1.0, 0.5, 1.0));
        // The ninth patch starts the grid again.
        assert_eq!(patch_point(8, 0.3, 0.7, &p), patch_point(0, 0.3, 0.7, &p));
        // A target smaller than a cell still has one.
        let tiny = push(1.0, 1, 1);
        assert_eq!((tiny.columns, tiny.rows), (1, 1));
    }

    #[test]
    fn triangles_follow_the_odd_segments() {
        assert_eq!(triangles_per_patch(1.0), 2);
        // 3 segments: a 1 × 1 inner quad (2) and a ring of 8 + 4 segments (12).
        assert_eq!(triangles_per_patch(3.0), 14);
        assert_eq!(triangles_per_patch(4.0), 26);
        assert_eq!(triangles_per_patch(9.0), 50);
    }
}

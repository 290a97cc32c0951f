//! Rectangles of pixels (`vk::Rect2D`): from their corners, and one less another, for
//! the passes that leave out the overlay's opaque part.

use ash::vk;

/// `outer` less `hole` (inside it): at most four rectangles, the rows above and
/// below the hole, then the columns left and right of it.
pub fn around(outer: vk::Rect2D, hole: vk::Rect2D) -> Vec<vk::Rect2D> {
    let (x0, y0, x1, y1) = (outer.offset.x, outer.offset.y, right(outer), bottom(outer));
    let (hx0, hy0, hx1, hy1) = (hole.offset.x, hole.offset.y, right(hole), bottom(hole));
    [
        rect(x0, y0, x1, hy0),
        rect(x0, hy1, x1, y1),
        rect(x0, hy0, hx0, hy1),
        rect(hx1, hy0, x1, hy1),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The column after `r`'s last.
pub fn right(r: vk::Rect2D) -> i32 {
    r.offset.x + r.extent.width as i32
}

/// The row after `r`'s last.
pub fn bottom(r: vk::Rect2D) -> i32 {
    r.offset.y + r.extent.height as i32
}

/// The pixels from (`x0`, `y0`) up to (`x1`, `y1`); `None` when empty.
pub fn rect(x0: i32, y0: i32, x1: i32, y1: i32) -> Option<vk::Rect2D> {
    (x1 > x0 && y1 > y0).then_some(vk::Rect2D {
        offset: vk::Offset2D { x: x0, y: y0 },
        extent: vk::Extent2D {
            width: (x1 - x0) as u32,
            height: (y1 - y0) as u32,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pixel of `outer` is in exactly one of `around`'s rectangles or in the hole,
    /// for a hole in the middle, at a corner, along a whole side and equal to `outer`.
    #[test]
    fn around_covers_the_rest_once() {
        let outer = rect(2, 3, 12, 10).unwrap();
        let holes = [
            rect(4, 5, 8, 7).unwrap(),
            rect(2, 3, 5, 6).unwrap(),
            rect(2, 3, 6, 10).unwrap(),
            outer,
        ];
        let inside = |r: vk::Rect2D, x: i32, y: i32| {
            x >= r.offset.x && x < right(r) && y >= r.offset.y && y < bottom(r)
        };
        for hole in holes {
            let parts = around(outer, hole);
            assert!(parts.len() <= 4);
            for y in 0..14 {
                for x in 0..14 {
                    let n = parts.iter().filter(|&&p| inside(p, x, y)).count();
                    let want = usize::from(inside(outer, x, y) && !inside(hole, x, y));
                    assert_eq!(n, want, "pixel ({x}, {y}) with hole {hole:?}");
                }
            }
        }
        assert!(around(outer, outer).is_empty());
        assert_eq!(rect(3, 3, 3, 5), None);
    }
}

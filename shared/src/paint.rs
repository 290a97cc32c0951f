//! Painted maps (issue 19): an 8-bit image laid over the world's square, read where a
//! blade grows. A map is `u32` words: its width and height, then its texels row by row
//! (the image's top row at −z), four to a word, lowest byte first: the same words in a
//! storage buffer on the GPU and in a `Vec` on the host. A map of no texels (fewer
//! than two words, or a width of 0) reads 1 everywhere.

use spirv_std::glam::Vec2;

/// Words before the texels.
pub const HEADER_WORDS: usize = 2;

/// Texel (x, y) of `map`, 0..1.
fn texel(map: &[u32], width: u32, x: u32, y: u32) -> f32 {
    let at = (y * width + x) as usize;
    let word = map[HEADER_WORDS + at / 4];
    ((word >> (8 * (at % 4) as u32)) & 0xff) as f32 / 255.0
}

/// `map` at ground point `p` (x, z), the map laid over the square from −`half` to
/// `half`: bilinear between texel centres, clamped at the edges; 1 without a map.
pub fn sample(map: &[u32], p: Vec2, half: f32) -> f32 {
    if map.len() < HEADER_WORDS {
        return 1.0;
    }
    let (width, height) = (map[0], map[1]);
    if width == 0 || height == 0 {
        return 1.0;
    }
    let uv = (p + Vec2::splat(half)) / (2.0 * half).max(1e-6);
    let x = (uv.x * width as f32 - 0.5).clamp(0.0, (width - 1) as f32);
    let y = (uv.y * height as f32 - 0.5).clamp(0.0, (height - 1) as f32);
    let (x0, y0) = (x as u32, y as u32);
    let (x1, y1) = ((x0 + 1).min(width - 1), (y0 + 1).min(height - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let top = texel(map, width, x0, y0) * (1.0 - fx) + texel(map, width, x1, y0) * fx;
    let bottom = texel(map, width, x0, y1) * (1.0 - fx) + texel(map, width, x1, y1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The words of a map `width` × `height` of `texels` (row by row).
#[cfg(not(target_arch = "spirv"))]
pub fn words(width: u32, height: u32, texels: &[u8]) -> Vec<u32> {
    let mut words = vec![width, height];
    words.extend(texels.chunks(4).map(|c| {
        c.iter()
            .enumerate()
            .fold(0u32, |w, (i, &b)| w | (u32::from(b) << (8 * i)))
    }));
    words
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_reads_its_texels_at_their_centres_and_blends_between() {
        // 3 x 2: top row 0, 255, 0; bottom row 255, 255, 51.
        let map = words(3, 2, &[0, 255, 0, 255, 255, 51]);
        let half = 3.0;
        // Texel centres: x at −2, 0, 2; z at −1.5, 1.5.
        assert_eq!(sample(&map, Vec2::new(-2.0, -1.5), half), 0.0);
        assert_eq!(sample(&map, Vec2::new(0.0, -1.5), half), 1.0);
        assert!((sample(&map, Vec2::new(2.0, 1.5), half) - 0.2).abs() < 1e-6);
        // Halfway between the first two of the top row; clamped beyond the edge.
        assert!((sample(&map, Vec2::new(-1.0, -1.5), half) - 0.5).abs() < 1e-6);
        assert_eq!(sample(&map, Vec2::new(-50.0, -50.0), half), 0.0);
        assert_eq!(sample(&[], Vec2::ZERO, half), 1.0);
        assert_eq!(sample(&[0, 0], Vec2::ZERO, half), 1.0);
    }
}

//! Painted maps: 8-bit images laid over the world's square, read where a
//! blade grows: how dense the grass is ([`DENSITY`]), how tall ([`HEIGHT`]), what
//! colour ([`COLOUR`]) and what grows there ([`TYPE`]: a species, the field's mix of them, or nothing). The maps travel in one set of `u32` words: a header of
//! [`MAPS`] word offsets (0: no such map) and the loaded scene's surface table's
//! ([`SURFACE`], `surface`), then each map as its width, its height
//! and its texels row by row (the image's top row at −z), one RGBA texel a word
//! (red in the lowest byte): the same words in a storage buffer on the GPU and in a
//! `Vec` on the host. A missing map reads white everywhere.

use spirv_std::glam::{Vec2, Vec4};

/// The density map: its red channel (grey images have it in all three) is the share
/// of blades that grow, 0 to 1.
pub const DENSITY: usize = 0;
/// The height map: each blade's height times twice its red channel (mid grey keeps
/// the heights, white doubles them, black leaves a twentieth).
pub const HEIGHT: usize = 1;
/// The colour map: the natural look's blade colours times its RGB (white keeps them).
pub const COLOUR: usize = 2;
/// The type map, read at the nearest texel, in five bands of grey ([`kind`]): black
/// (below 32) bare ground, dark grey (32 to 95, 64 at its middle) seed grass, mid grey
/// (96 to 159, 128) dandelions, light grey (160 to 223, 192) flowers, white (224 and
/// up) the field's mix of species (`species::Mix`, grass unless set).
pub const TYPE: usize = 3;
/// Maps a set can hold.
pub const MAPS: usize = 4;
/// The header word after the maps': where a loaded scene's surface table starts
/// (`surface`; 0: none).
pub const SURFACE: usize = MAPS;

/// What grows at a point of the type map: the field's mix of species (grass unless
/// set).
pub const KIND_MIX: u32 = 0;
/// Dandelions (the paper's fifth shape, whatever the field's).
pub const KIND_DANDELION: u32 = 1;
/// Nothing.
pub const KIND_BARE: u32 = 2;
/// Flowers (`species::FLOWER`).
pub const KIND_FLOWER: u32 = 3;
/// Seed grass (`species::SEED_GRASS`).
pub const KIND_SEED_GRASS: u32 = 4;
/// Words of the set's header.
pub const HEADER_WORDS: usize = MAPS + 1;

/// Texel (x, y) of the map at `base`, 0..1 per channel.
fn texel(set: &[u32], base: usize, width: u32, x: u32, y: u32) -> Vec4 {
    let word = set[base + 2 + (y * width + x) as usize];
    Vec4::new(
        (word & 0xff) as f32,
        ((word >> 8) & 0xff) as f32,
        ((word >> 16) & 0xff) as f32,
        (word >> 24) as f32,
    ) / 255.0
}

/// Map `which` of `set` at ground point `p` (x, z), laid over the square from
/// −`half` to `half`: bilinear between texel centres, clamped at the edges; white
/// where the set has no such map.
pub fn sample(set: &[u32], which: usize, p: Vec2, half: f32) -> Vec4 {
    if set.len() < HEADER_WORDS {
        return Vec4::ONE;
    }
    let base = set[which] as usize;
    if base == 0 {
        return Vec4::ONE;
    }
    let (width, height) = (set[base], set[base + 1]);
    if width == 0 || height == 0 {
        return Vec4::ONE;
    }
    let uv = (p + Vec2::splat(half)) / (2.0 * half).max(1e-6);
    let x = (uv.x * width as f32 - 0.5).clamp(0.0, (width - 1) as f32);
    let y = (uv.y * height as f32 - 0.5).clamp(0.0, (height - 1) as f32);
    let (x0, y0) = (x as u32, y as u32);
    let (x1, y1) = ((x0 + 1).min(width - 1), (y0 + 1).min(height - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let top = texel(set, base, width, x0, y0) * (1.0 - fx) + texel(set, base, width, x1, y0) * fx;
    let bottom =
        texel(set, base, width, x0, y1) * (1.0 - fx) + texel(set, base, width, x1, y1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The share of blades that grow at `p` ([`DENSITY`]).
pub fn density(set: &[u32], p: Vec2, half: f32) -> f32 {
    sample(set, DENSITY, p, half).x
}

/// Whether `set` holds map `which`.
pub fn has(set: &[u32], which: usize) -> bool {
    set.len() >= HEADER_WORDS && set[which] != 0
}

/// The factor on a blade's height at `p` ([`HEIGHT`]): twice the map, at least 0.05;
/// 1 without a height map.
pub fn height_factor(set: &[u32], p: Vec2, half: f32) -> f32 {
    if !has(set, HEIGHT) {
        return 1.0;
    }
    (2.0 * sample(set, HEIGHT, p, half).x).max(0.05)
}

/// How many times the course's tallest blade (`blade::HEIGHT`) the tallest blade of a
/// field under the maps of `set` and the species `mix` can grow: the tallest species
/// the type map or the mix can grow (`species::height_factor`), twice that under a
/// height map ([`height_factor`]).
pub fn tallest_factor(set: &[u32], mix: crate::species::Mix) -> f32 {
    let species = if has(set, TYPE) {
        crate::species::TALLEST
    } else {
        mix.tallest()
    };
    let painted = if has(set, HEIGHT) { 2.0 } else { 1.0 };
    species * painted
}

/// Whether a field under the maps of `set` and the species `mix` may grow a species
/// other than grass: a type map, or a mix with one.
pub fn mixed(set: &[u32], mix: crate::species::Mix) -> bool {
    has(set, TYPE) || mix != crate::species::Mix::GRASS
}

/// The tallest blade, at the course's size, a field under the maps of `set` and the
/// species `mix` can grow: the course's tallest (`blade::HEIGHT`) times
/// [`tallest_factor`].
pub fn tallest(set: &[u32], mix: crate::species::Mix) -> f32 {
    crate::blade::HEIGHT.1 * tallest_factor(set, mix)
}

/// What grows at `p` ([`TYPE`]): the nearest texel's red, classed; the field's mix
/// without a type map. Nearest rather than blended, so no band of another kind lines
/// the border between two.
pub fn kind(set: &[u32], p: Vec2, half: f32) -> u32 {
    if !has(set, TYPE) {
        return KIND_MIX;
    }
    let base = set[TYPE] as usize;
    let (width, height) = (set[base], set[base + 1]);
    if width == 0 || height == 0 {
        return KIND_MIX;
    }
    let uv = (p + Vec2::splat(half)) / (2.0 * half).max(1e-6);
    let x = (uv.x * width as f32).clamp(0.0, (width - 1) as f32) as u32;
    let y = (uv.y * height as f32).clamp(0.0, (height - 1) as f32) as u32;
    let grey = texel(set, base, width, x, y).x * 255.0;
    if grey < 32.0 {
        KIND_BARE
    } else if grey < 96.0 {
        KIND_SEED_GRASS
    } else if grey < 160.0 {
        KIND_DANDELION
    } else if grey < 224.0 {
        KIND_FLOWER
    } else {
        KIND_MIX
    }
}

/// The species a blade grows as at `p`, `unit` its own uniform draw (0..1): the type
/// map's where it paints one, else `mix`'s pick; on bare ground the grass (the caller
/// leaves such a blade out).
pub fn species_at(set: &[u32], p: Vec2, half: f32, mix: crate::species::Mix, unit: f32) -> u32 {
    let kind = kind(set, p, half);
    if kind == KIND_DANDELION {
        crate::species::DANDELION
    } else if kind == KIND_FLOWER {
        crate::species::FLOWER
    } else if kind == KIND_SEED_GRASS {
        crate::species::SEED_GRASS
    } else if kind == KIND_MIX {
        mix.pick(unit)
    } else {
        crate::species::GRASS
    }
}

/// A stored field's `blade` as the maps of `set` and the field's `mix` have it at its
/// map point `p`, `unit` its own uniform draw: `None` where the type map leaves the
/// ground bare; else grown as the species there ([`species_at`],
/// `species::grown_as`), its height times the height map, as `tiles::tile_blade` makes
/// a tile's blade.
pub fn painted_blade(
    blade: &crate::blade::Blade,
    set: &[u32],
    p: Vec2,
    half: f32,
    (mix, unit): (crate::species::Mix, f32),
) -> Option<crate::blade::Blade> {
    if kind(set, p, half) == KIND_BARE {
        return None;
    }
    let species = species_at(set, p, half, mix, unit);
    let grown = crate::species::grown_as(blade, species);
    Some(crate::blade::Blade::at_rest(
        grown.root(),
        grown.up_dir(),
        grown.orientation(),
        grown.height() * height_factor(set, p, half),
        grown.width(),
        grown.stiffness(),
    ))
}

/// A set of maps, each `(which, width, height, RGBA texels row by row)`, as words.
#[cfg(not(target_arch = "spirv"))]
pub fn words(maps: &[(usize, u32, u32, &[[u8; 4]])]) -> Vec<u32> {
    let mut words = vec![0u32; HEADER_WORDS];
    for &(which, width, height, texels) in maps {
        words[which] = words.len() as u32;
        words.extend([width, height]);
        words.extend(texels.iter().map(|&t| u32::from_le_bytes(t)));
    }
    words
}

/// `set` (a set of maps, or none) with the surface table `surface` after it.
#[cfg(not(target_arch = "spirv"))]
pub fn with_surface(mut set: Vec<u32>, surface: &[u32]) -> Vec<u32> {
    set.resize(set.len().max(HEADER_WORDS), 0);
    // A table set before is the last thing in the set: replaced.
    if set[SURFACE] != 0 {
        set.truncate(set[SURFACE] as usize);
    }
    set[SURFACE] = set.len() as u32;
    set.extend_from_slice(surface);
    set
}

/// Grey texels as RGBA (the grey in red, green and blue, alpha 255).
#[cfg(not(target_arch = "spirv"))]
pub fn grey(texels: &[u8]) -> Vec<[u8; 4]> {
    texels.iter().map(|&g| [g, g, g, 255]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_reads_its_texels_at_their_centres_and_blends_between() {
        // A 3 x 2 density map: top row 0, 255, 0; bottom row 255, 255, 51; and a
        // 1 x 1 colour map.
        let density_texels = grey(&[0, 255, 0, 255, 255, 51]);
        let set = words(&[
            (DENSITY, 3, 2, &density_texels),
            (COLOUR, 1, 1, &[[255, 0, 51, 255]]),
        ]);
        let half = 3.0;
        // Texel centres: x at −2, 0, 2; z at −1.5, 1.5.
        assert_eq!(density(&set, Vec2::new(-2.0, -1.5), half), 0.0);
        assert_eq!(density(&set, Vec2::new(0.0, -1.5), half), 1.0);
        assert!((density(&set, Vec2::new(2.0, 1.5), half) - 0.2).abs() < 1e-6);
        // Halfway between the first two of the top row; clamped beyond the edge.
        assert!((density(&set, Vec2::new(-1.0, -1.5), half) - 0.5).abs() < 1e-6);
        assert_eq!(density(&set, Vec2::new(-50.0, -50.0), half), 0.0);
        // The colour map's channels; no height map: white.
        let c = sample(&set, COLOUR, Vec2::ZERO, half);
        assert!((c - Vec4::new(1.0, 0.0, 0.2, 1.0)).abs().max_element() < 1e-6);
        assert_eq!(height_factor(&set, Vec2::ZERO, half), 1.0);
        assert!(!has(&set, HEIGHT) && has(&set, COLOUR));
        assert_eq!(density(&[], Vec2::ZERO, half), 1.0);
        // A type map of three texels: bare, dandelion, grass (nearest, no blending).
        let types = grey(&[0, 128, 255]);
        let set = words(&[(TYPE, 3, 1, &types)]);
        assert_eq!(kind(&set, Vec2::new(-2.5, 0.0), half), KIND_BARE);
        assert_eq!(kind(&set, Vec2::new(-0.9, 0.0), half), KIND_DANDELION);
        assert_eq!(kind(&set, Vec2::new(0.9, 0.0), half), KIND_DANDELION);
        assert_eq!(kind(&set, Vec2::new(1.1, 0.0), half), KIND_MIX);
        assert_eq!(kind(&[], Vec2::ZERO, half), KIND_MIX);
        // The five bands at their middles and edges.
        let bands = grey(&[31, 32, 64, 95, 96, 159, 160, 192, 223, 224]);
        let set = words(&[(TYPE, 10, 1, &bands)]);
        let kinds: Vec<u32> = (0..10)
            .map(|i| kind(&set, Vec2::new(-2.7 + 0.6 * i as f32, 0.0), half))
            .collect();
        let (s, d, f) = (KIND_SEED_GRASS, KIND_DANDELION, KIND_FLOWER);
        assert_eq!(kinds, [KIND_BARE, s, s, s, d, d, f, f, f, KIND_MIX]);
        assert_eq!(density(&[0, 0, 0], Vec2::ZERO, half), 1.0);
    }

    /// A stored blade under a type and a height map: gone on bare ground, a dandelion
    /// among dandelions (two turns more), its height twice the height map's grey, the
    /// rest kept; on white, the field's mix.
    #[test]
    fn a_stored_blade_takes_the_maps_at_its_root() {
        use crate::blade::Blade;
        use spirv_std::glam::Vec3;
        let half = 3.0;
        let types = grey(&[0, 128, 255]);
        let heights = grey(&[255, 255, 64]);
        let set = words(&[(TYPE, 3, 1, &types), (HEIGHT, 3, 1, &heights)]);
        let at = |x: f32| Blade::at_rest(Vec3::new(x, 0.5, 0.0), Vec3::Y, 1.0, 0.8, 0.05, 2.0);
        let map_point = |b: &Blade| Vec2::new(b.root().x, b.root().z);
        let grass_only = (crate::species::Mix::GRASS, 0.5);
        let bare = at(-2.0);
        assert!(painted_blade(&bare, &set, map_point(&bare), half, grass_only).is_none());
        let dandelion = at(0.0);
        let painted = painted_blade(&dandelion, &set, map_point(&dandelion), half, grass_only);
        let painted = painted.unwrap();
        assert!((painted.orientation() - (1.0 + crate::species::TURNS)).abs() < 1e-5);
        assert!((painted.height() - 1.6).abs() < 1e-5);
        let grass = at(2.0);
        let painted = painted_blade(&grass, &set, map_point(&grass), half, grass_only).unwrap();
        assert!((painted.orientation() - 1.0).abs() < 1e-5);
        assert!((painted.height() - 0.8 * 2.0 * 64.0 / 255.0).abs() < 1e-5);
        assert_eq!(painted.root(), grass.root());
        assert_eq!((painted.width(), painted.stiffness()), (0.05, 2.0));
        // No maps: the blade as it was.
        assert_eq!(
            painted_blade(&grass, &[], map_point(&grass), half, grass_only),
            Some(grass)
        );
        // White under a mix of seed grass only: seed grass, taller and softer.
        let seeds = (crate::species::Mix::new([0, 0, 0, 1]), 0.5);
        let painted = painted_blade(&grass, &set, map_point(&grass), half, seeds).unwrap();
        assert_eq!(crate::species::of(&painted), crate::species::SEED_GRASS);
        assert!((painted.height() - 1.5 * 0.8 * 2.0 * 64.0 / 255.0).abs() < 1e-5);
        assert_eq!(painted.stiffness(), 2.0 * 0.75);
    }
}

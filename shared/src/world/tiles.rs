//! Blades from tiles: the world is cut into square tiles, and a
//! tile's blades are a function of the tile's coordinates, the blade's index in it and
//! a seed, so nothing per blade has to be stored for a tile nobody simulates. After the
//! generated grass of Ghost of Tsushima (Eric Wohllaib, *Procedural Grass in Ghost of
//! Tsushima*, GDC 2021) and Fan et al., *Simulation and Rendering for Millions of
//! Grass Blades* (I3D 2015).
//!
//! - **Stratified roots.** A tile of `per_side`² blades is cut into as many cells and
//!   each blade is jittered inside its own cell, so blades never crowd at a tile's
//!   border: a border cell is as full as an inner one, and neighbouring tiles meet
//!   without a seam.
//! - **Density that falls with distance, without popping.** Blade `index` has rank
//!   (index + jitter) / count and is kept while its rank is below the share
//!   [`kept_share`] leaves at its distance: as the camera recedes blades leave one by
//!   one in a fixed order, and a blade kept at some distance is kept at every nearer
//!   one. A blade thins to nothing over the last [`FADE`] of its share before it
//!   leaves, and the kept ones widen by the inverse of the share (up to
//!   [`MAX_WIDENING`]), so the field's coverage (blades × width) stays.
//! - **Every prefix stratified.** Blades are numbered in rank order and blade `index`
//!   takes the cell whose Morton code is `index` with its bits reversed (a (0, 2)
//!   sequence's order, after Hammersley): the first 4^j blades hold one cell of each
//!   of the tile's 2^j × 2^j blocks, so a far tile's few kept blades still spread
//!   over it, and the GPU generates a far tile's first [`far_count`] blades rather
//!   than testing every one.
//!
//! Every function here runs on the GPU and on the host (the host tests below run the
//! same functions the GPU pass will).

use crate::Blade;
use crate::blade::{HEIGHT, STIFFNESS, WIDTH};
use crate::noise::{hash_u32, hash_unit};
use crate::world::terrain;
use spirv_std::glam::{IVec2, UVec2, Vec2, Vec3};

/// The share of its rank's range over which a blade thins before it leaves.
pub const FADE: f32 = 0.1;
/// The kept blades widen by the inverse of the share kept, at most this much.
pub const MAX_WIDENING: f32 = 4.0;

/// How the world's blades are laid out and thinned.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TileParams {
    /// Side of a tile in world units.
    pub size: f32,
    /// Blades along a side of a tile: `per_side`² in all; a power of two (the
    /// stratified order, [`root_of`]).
    pub per_side: u32,
    /// Names the world: the same seed gives the same blades.
    pub seed: u32,
    /// Up to this distance from the camera every blade is kept.
    pub full_distance: f32,
    /// The ground the blades stand on: [`TERRAIN_FLAT`] or [`TERRAIN_VALLEY`].
    pub terrain: u32,
    /// The world is the square from −`half_extent` to `half_extent` in x and z around
    /// `centre`: no blade grows outside it, and the painted maps lie over it.
    pub half_extent: f32,
    /// The world's square's centre (x, z): 0 for the plane and the valley, a loaded
    /// scene's own.
    pub centre: Vec2,
    /// The blades' size: heights, widths and tile sizes are the course's times this,
    /// stiffnesses over it (`mesh::scatter_scaled`'s rule: the same bend under the same
    /// forces).
    pub blade_scale: f32,
    /// How the species mix where the type map leaves it to the field
    /// (`crate::species::Mix`'s weights; 0: grass only).
    pub species: u32,
    /// Padding to 48 bytes (no arrays in push constants: the reflection tests read
    /// scalars and vectors).
    pub pad: UVec2,
}

/// Blades on the plane y = 0, up +Y.
pub const TERRAIN_FLAT: u32 = 0;
/// Blades on the valley (`terrain::valley_height`), up its normal, none on the bare
/// path.
pub const TERRAIN_VALLEY: u32 = 1;
/// Blades on a loaded scene's surface, by area (`surface`: its table in the world's
/// set), up its interpolated normal.
pub const TERRAIN_MESH: u32 = 2;

impl Default for TileParams {
    /// Tiles of 32/3 units at the course's density (36 blades a square unit: 64
    /// along a side), every blade kept within 16 units, a world 2,000 units wide.
    fn default() -> Self {
        Self {
            size: 32.0 / 3.0,
            per_side: 64,
            seed: 1,
            full_distance: 16.0,
            terrain: TERRAIN_FLAT,
            half_extent: 1000.0,
            centre: Vec2::ZERO,
            blade_scale: 1.0,
            species: 0,
            pad: UVec2::ZERO,
        }
    }
}

/// Uniform in 0..1 for blade `index` of `tile`, attribute `k`, in world `seed`
/// (`look::hash_unit` of the four mixed).
fn blade_unit(tile: IVec2, index: u32, seed: u32, k: u32) -> f32 {
    hash_unit(
        (tile.x as u32).wrapping_mul(0x8da6_b343)
            ^ (tile.y as u32).wrapping_mul(0xd816_3841)
            ^ hash_u32(index ^ hash_u32(seed.wrapping_add(k.wrapping_mul(0x9e37_79b9)))),
    )
}

/// The tile holding world point `p` (x, z).
pub fn tile_of(p: Vec2, params: &TileParams) -> IVec2 {
    (p / params.size).floor().as_ivec2()
}

/// The cell (x, z) of a `per_side` × `per_side` grid (a power of two) that blade
/// `index` takes: the Morton code `index` with its 2·log2(`per_side`) bits reversed,
/// so the first 4^j indices take one cell in each 2^j × 2^j block.
pub fn cell_of(index: u32, per_side: u32) -> UVec2 {
    let bits = 2 * per_side.max(1).trailing_zeros();
    if bits == 0 {
        return UVec2::ZERO;
    }
    let code = index.reverse_bits() >> (32 - bits);
    UVec2::new(compact_bits(code), compact_bits(code >> 1))
}

/// The even bits of `v`, packed (Morton decoding of one axis).
pub fn compact_bits(v: u32) -> u32 {
    let mut x = v & 0x5555_5555;
    x = (x | (x >> 1)) & 0x3333_3333;
    x = (x | (x >> 2)) & 0x0f0f_0f0f;
    x = (x | (x >> 4)) & 0x00ff_00ff;
    (x | (x >> 8)) & 0x0000_ffff
}

/// Blade `index`'s root of `tile` on the ground plane (x, z): its own cell of the
/// tile's `per_side` × `per_side` grid ([`cell_of`]), jittered anywhere inside it.
pub fn root_of(tile: IVec2, index: u32, params: &TileParams) -> Vec2 {
    let n = params.per_side.max(1);
    let cell = cell_of(index, n).as_vec2();
    let jitter = Vec2::new(
        blade_unit(tile, index, params.seed, 0),
        blade_unit(tile, index, params.seed, 1),
    );
    (tile.as_vec2() + (cell + jitter) / n as f32) * params.size
}

/// How many times the blades a pixel needs the tiles hold at `distance` from the
/// camera: `full_distance`² / distance², above 1 nearer than `full_distance` (a tile's
/// blades cover a screen area that falls as the square of the distance), so the kept
/// blades per pixel stay about even. The share kept is this, at most 1
/// ([`kept_share`]).
pub fn density(distance: f32, params: &TileParams) -> f32 {
    let ratio = params.full_distance / distance.max(1e-6);
    ratio * ratio
}

/// The share of blades kept at `distance` from the camera: all within
/// `full_distance`, then falling as the square of the distance ([`density`]).
pub fn kept_share(distance: f32, params: &TileParams) -> f32 {
    density(distance, params).min(1.0)
}

/// A blade's rank, (index + jitter) / count, count the tile's blades
/// ([`tile_count`]): it is kept while [`kept_share`] at its distance is above this, so
/// the kept blades of a tile are always its first ones.
pub fn rank_of(tile: IVec2, index: u32, params: &TileParams, map: &[u32]) -> f32 {
    let count = tile_count(tile, params, map).max(1) as f32;
    (index as f32 + blade_unit(tile, index, params.seed, 2)) / count
}

/// The blades `tile` grows at full density: `per_side`², or on a loaded scene its
/// share of the surface's (`surface::SurfaceTile::blades`, from the world's set
/// `map`).
pub fn tile_count(tile: IVec2, params: &TileParams, map: &[u32]) -> u32 {
    if params.terrain == TERRAIN_MESH {
        crate::world::surface::tile(map, tile).blades
    } else {
        params.per_side * params.per_side
    }
}

/// Where a blade rooted at `root` reads the painted maps: its x and z from the
/// world's centre.
pub fn map_point(root: Vec3, params: &TileParams) -> Vec2 {
    Vec2::new(root.x, root.z) - params.centre
}

/// Where a blade at texture coordinates `uv` reads the painted maps: the maps laid
/// over the texture's unit square (v down the image, as glTF has it; the OBJ loader
/// turns its v round), clamped at its edges, in the map's own measure (the world's
/// square, `half_extent` around 0).
pub fn uv_map_point(uv: Vec2, params: &TileParams) -> Vec2 {
    (uv - Vec2::splat(0.5)) * (2.0 * params.half_extent)
}

/// Blade `index` of `tile`'s map point ([`blade_map_point`]) as the field's ids
/// buffer keeps it next to its name (`layout::IDS_WORDS`), for the passes that know
/// a blade but not its tile: x and z over the map's square, 16 bits each.
pub fn pack_map_point(
    tile: IVec2,
    index: u32,
    blade: &Blade,
    params: &TileParams,
    map: &[u32],
) -> u32 {
    let at = blade_map_point(tile, index, blade.root(), params, map);
    let unit =
        (at / (2.0 * params.half_extent.max(1e-6)) + Vec2::splat(0.5)).clamp(Vec2::ZERO, Vec2::ONE);
    let q = (unit * 65535.0 + Vec2::splat(0.5)).as_uvec2();
    q.x | (q.y << 16)
}

/// [`pack_map_point`]'s inverse (within 1/65535 of the map's side).
pub fn unpack_map_point(word: u32, params: &TileParams) -> Vec2 {
    let unit = Vec2::new((word & 0xffff) as f32, (word >> 16) as f32) / 65535.0;
    (unit - Vec2::splat(0.5)) * (2.0 * params.half_extent)
}

/// Where blade `index` of `tile`, rooted at `root`, reads the painted maps: on a
/// loaded scene with texture coordinates at its own ([`uv_map_point`], found again
/// by [`mesh_root`]), elsewhere over the world's square ([`map_point`]).
pub fn blade_map_point(
    tile: IVec2,
    index: u32,
    root: Vec3,
    params: &TileParams,
    map: &[u32],
) -> Vec2 {
    if params.terrain == TERRAIN_MESH && crate::world::surface::has_uvs(map) {
        let surface = crate::world::surface::tile(map, tile);
        spot_map_point(&mesh_root(tile, index, params, map, &surface), params, map)
    } else {
        map_point(root, params)
    }
}

/// Where a blade rooted at `spot` reads the painted maps: at its texture coordinates
/// on a loaded scene that has them ([`uv_map_point`]), else over the world's square
/// ([`map_point`]).
fn spot_map_point(spot: &crate::world::surface::Spot, params: &TileParams, map: &[u32]) -> Vec2 {
    if params.terrain == TERRAIN_MESH && crate::world::surface::has_uvs(map) {
        uv_map_point(spot.uv, params)
    } else {
        map_point(spot.position, params)
    }
}

/// A name for blade `index` of `tile` that stays with it wherever it is generated
/// (a far tile's list or a pool slot): what the cull's buckets and the look's
/// per-blade hashes read in place of a stored field's index.
pub fn blade_id(tile: IVec2, index: u32) -> u32 {
    hash_u32(
        (tile.x as u32).wrapping_mul(0x8da6_b343)
            ^ (tile.y as u32).wrapping_mul(0xd816_3841)
            ^ index.wrapping_mul(0x9e37_79b9),
    )
}

/// The square `tile` covers on the ground plane: its (x, z) corners, low and high.
pub fn tile_square(tile: IVec2, params: &TileParams) -> (Vec2, Vec2) {
    let lo = tile.as_vec2() * params.size;
    (lo, lo + Vec2::splat(params.size))
}

/// Whether any of `tile`'s square lies inside the world (`half_extent` around
/// `centre`).
pub fn tile_in_world(tile: IVec2, params: &TileParams) -> bool {
    let (lo, hi) = tile_square(tile, params);
    let (lo, hi) = (lo - params.centre, hi - params.centre);
    let half = params.half_extent;
    hi.x > -half && hi.y > -half && lo.x < half && lo.y < half
}

/// The point of `tile`'s box (its square, from `bottom` to `top` in height) nearest
/// `camera`.
pub fn nearest_point(
    tile: IVec2,
    camera: Vec3,
    params: &TileParams,
    (bottom, top): (f32, f32),
) -> Vec3 {
    let (lo, hi) = tile_square(tile, params);
    Vec3::new(
        camera.x.clamp(lo.x, hi.x),
        camera.y.clamp(bottom, top),
        camera.z.clamp(lo.y, hi.y),
    )
}

/// How many of `tile`'s first blades can be kept seen from `camera`: every blade
/// whose rank is below the share at the nearest point of the tile's box (its square
/// over the height range `span`, [`tile_box`](crate::cull::tile::tile_box)), at most all of them ([`tile_count`]; `map` the world's
/// set). A far tile's blades beyond this are never kept, so they need not be
/// generated.
pub fn far_count(
    tile: IVec2,
    camera: Vec3,
    params: &TileParams,
    span: (f32, f32),
    map: &[u32],
) -> u32 {
    let nearest = nearest_point(tile, camera, params, span);
    let count = tile_count(tile, params, map);
    let share = kept_share((nearest - camera).length(), params);
    ((share * count as f32) as u32 + 1).min(count)
}

/// How wide a blade of `rank` is drawn at `density` ([`density`]): 0 once its rank
/// has left it (rank at or above the density); rising over the last [`FADE`] of the
/// density below its rank to the widening the share kept asks (its inverse, at most
/// [`MAX_WIDENING`]), so it comes and goes without popping, and near the camera
/// (density above 1 / (1 − FADE)) every blade at its own width.
pub fn width_scale(rank: f32, density: f32) -> f32 {
    painted_scale(rank, density, 1.0)
}

/// [`width_scale`] where a painted density map reads `paint` (0..1): a blade is kept
/// while its rank is below `density` · `paint` and fades over the last [`FADE`] of
/// that share, widening only for the distance (the map takes blades and coverage
/// away together).
pub fn painted_scale(rank: f32, density: f32, paint: f32) -> f32 {
    let share = density * paint;
    if rank >= share {
        return 0.0;
    }
    let fade = ((share - rank) / (FADE * share)).min(1.0);
    fade * (1.0 / density.min(1.0)).min(MAX_WIDENING)
}

/// Blade `index` of `tile` at rest on its ground (`params.terrain`: the plane y = 0,
/// up +Y; the valley, up its normal; or a loaded scene's surface, up its normal, from
/// the world's set `map`: [`mesh_root`]), seen from `camera`, its width carrying
/// [`width_scale`]: 0 (not [`kept`]) when its rank has left it at that distance or it
/// stands on bare ground. `map` holds the painted maps (`paint`: the density thins the
/// blades as the distance does, the height map scales their heights, the type map
/// picks species or bare ground, `paint::species_at`, else `params.species` mixes
/// them; `&[]` for none). On a loaded scene, a blade past
/// the tile's count ([`tile_count`]) is empty (all zero: height 0).
pub fn tile_blade(
    tile: IVec2,
    index: u32,
    camera: Vec3,
    params: &TileParams,
    map: &[u32],
) -> Blade {
    let mut spot = crate::world::surface::Spot::default();
    if params.terrain == TERRAIN_MESH {
        let surface = crate::world::surface::tile(map, tile);
        if index >= surface.blades {
            return Blade::default();
        }
        spot = mesh_root(tile, index, params, map, &surface);
    } else {
        let at = root_of(tile, index, params);
        spot.position = Vec3::new(at.x, 0.0, at.y);
        spot.normal = Vec3::Y;
        if params.terrain == TERRAIN_VALLEY {
            spot.position.y = terrain::valley_height(at);
            spot.normal = terrain::valley_normal(at);
        }
    }
    let (root, up) = (spot.position, spot.normal);
    let root2 = spot_map_point(&spot, params, map);
    let pick =
        |k: u32, (lo, hi): (f32, f32)| lo + (hi - lo) * blade_unit(tile, index, params.seed, k);
    let species = crate::world::paint::species_at(
        map,
        root2,
        params.half_extent,
        crate::species::Mix {
            weights: params.species,
        },
        blade_unit(tile, index, params.seed, 7),
    );
    let orientation = crate::species::mark(pick(3, (0.0, core::f32::consts::TAU)), species);
    let scale = params.blade_scale;
    let height = pick(4, HEIGHT)
        * scale
        * crate::species::height_factor(species)
        * crate::world::paint::height_factor(map, root2, params.half_extent);
    let width = drawn_width(tile, index, root, camera, params, map);
    let stiffness = pick(6, STIFFNESS) / scale * crate::species::stiffness_factor(species);
    Blade::at_rest(root, up, orientation, height, width, stiffness)
}

/// Blade `index`'s root (its position, up and texture coordinates) on a loaded
/// scene's `surface` part of `tile`: at the share u = (index's bits reversed + jitter) / per_side² of
/// the tile's area (`surface::point`, which runs through the pieces in Morton order
/// and through each piece in Morton order too), so that, as [`cell_of`] does on a
/// square, every prefix of the tile's blades is spread over all of it; up the
/// surface's normal there.
pub fn mesh_root(
    tile: IVec2,
    index: u32,
    params: &TileParams,
    map: &[u32],
    surface: &crate::world::surface::SurfaceTile,
) -> crate::world::surface::Spot {
    let room = params.per_side * params.per_side;
    let bits = room.max(2).trailing_zeros();
    let stratum = index.reverse_bits() >> (32 - bits);
    let unit = |k: u32| blade_unit(tile, index, params.seed, k);
    let u = (stratum as f32 + unit(0)) / room as f32;
    crate::world::surface::point(map, surface, u)
}

/// How wide blade `index` of `tile`, rooted at `root`, is drawn seen from `camera`:
/// its own width (drawn from [`WIDTH`]) times [`width_scale`] at its rank and
/// distance and the painted maps' density (`map`, [`painted_scale`],
/// `paint::density`; `&[]` for none); 0 outside the world and, on the valley, on the bare path. The pool's
/// simulated blades take theirs from here every frame, so they thin with distance
/// exactly as the far tiles' generated ones do.
pub fn drawn_width(
    tile: IVec2,
    index: u32,
    root: Vec3,
    camera: Vec3,
    params: &TileParams,
    map: &[u32],
) -> f32 {
    let root2 = blade_map_point(tile, index, root, params, map);
    // A loaded scene's blades grow where its surface is.
    let inside = params.terrain == TERRAIN_MESH
        || map_point(root, params).abs().max_element() < params.half_extent;
    let valley = params.terrain == TERRAIN_VALLEY;
    let painted_bare =
        crate::world::paint::kind(map, root2, params.half_extent) == crate::world::paint::KIND_BARE;
    if !inside || (valley && terrain::bare(root2)) || painted_bare {
        return 0.0;
    }
    let scale = painted_scale(
        rank_of(tile, index, params, map),
        density((root - camera).length(), params),
        crate::world::paint::density(map, root2, params.half_extent),
    );
    let (lo, hi) = WIDTH;
    (lo + (hi - lo) * blade_unit(tile, index, params.seed, 5)) * scale * params.blade_scale
}

/// Blade `index` of `tile` as the far tiles draw it and as a tile entering the pool
/// starts: [`tile_blade`] in the pose the frame's gravity and wind (`env`, at
/// `env.time`, with the first `env.impulses` of `impulses`) settle it into
/// (`sway::settled`), so that it sways with the simulated blades around it; at rest
/// where `env.far_sway` is 0.
pub fn far_blade(
    tile: IVec2,
    index: u32,
    camera: Vec3,
    params: &TileParams,
    map: &[u32],
    env: &crate::sim::simulate::Environment,
    impulses: &[crate::sim::impulse::Impulse; crate::sim::impulse::MAX_IMPULSES],
) -> Blade {
    let blade = tile_blade(tile, index, camera, params, map);
    if blade.height() <= 0.0 || env.far_sway == 0 {
        return blade;
    }
    crate::sim::sway::settled(&blade, env, impulses, env.time)
}

/// A pool blade `fade` (0..1) of the way to `far`, its pose as a far blade
/// ([`far_blade`]): how a tile nobody needs returns to the pose the far tiles draw
/// before its slot is given away, so it leaves the pool without a jump (its root,
/// scalars and width as they are).
pub fn fade_to_far(blade: &Blade, far: &Blade, fade: f32) -> Blade {
    blade.with_curve(
        blade.guide().lerp(far.guide(), fade),
        blade.tip().lerp(far.tip(), fade),
    )
}

/// Whether a generated blade is drawn: its rank has not left it ([`tile_blade`]).
pub fn kept(blade: &Blade) -> bool {
    blade.width() > 0.0
}

#[cfg(test)]
mod tests;

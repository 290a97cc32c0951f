//! Whether a tile of the tiled world can show a blade: its box over the ground, the
//! view volume, the occluders' depth pyramid and the reach of the far field.

use crate::world::terrain;
use crate::world::tiles::tile_in_world;
use crate::world::tiles::{TERRAIN_MESH, TERRAIN_VALLEY, TileParams, nearest_point, tile_square};
use spirv_std::glam::{IVec2, Mat4, Vec3};

/// The lowest and highest ground under `tile` (within `ground`, the world's): the
/// plane's 0, the valley's height at the tile's centre ± its steepest slope over
/// the half diagonal (`terrain::VALLEY_MAX_SLOPE`), or a loaded scene's lowest and
/// highest point in the tile (`surface`, from the world's set `map`).
pub fn tile_ground(
    tile: IVec2,
    params: &TileParams,
    ground: (f32, f32),
    map: &[u32],
) -> (f32, f32) {
    if params.terrain == TERRAIN_MESH {
        return crate::world::surface::tile(map, tile).ground;
    }
    if params.terrain != TERRAIN_VALLEY {
        return ground;
    }
    let (lo, hi) = tile_square(tile, params);
    let centre = 0.5 * (lo + hi);
    let h = terrain::valley_height(centre);
    let reach = terrain::VALLEY_MAX_SLOPE * params.size * core::f32::consts::FRAC_1_SQRT_2;
    (
        (h - reach).max(ground.0).min(ground.1),
        (h + reach).min(ground.1).max(ground.0),
    )
}

/// The height range of `tile`'s box: its ground ([`tile_ground`]) up to the tallest
/// blade it can grow (the course's tallest times the blade scale and
/// `paint::tallest_factor`: the species and the height map).
pub fn tile_box(tile: IVec2, params: &TileParams, ground: (f32, f32), map: &[u32]) -> (f32, f32) {
    let (low, high) = tile_ground(tile, params, ground, map);
    let mix = crate::species::Mix {
        weights: params.species,
    };
    (
        low,
        high + crate::world::paint::tallest(map, mix) * params.blade_scale,
    )
}

/// Whether every blade `tile` can hold is hidden behind the occluders' depth
/// pyramid (`hiz::box_occluded` on its box: its square, over the height range `span`,
/// [`tile_box`]).
pub fn tile_occluded(
    tile: IVec2,
    params: &TileParams,
    span: (f32, f32),
    view_proj: Mat4,
    pyramid: &[f32],
    hiz: &crate::cull::hiz::HiZLayout,
) -> bool {
    let (lo, hi) = tile_square(tile, params);
    let low = Vec3::new(lo.x, span.0, lo.y);
    let high = Vec3::new(hi.x, span.1, hi.y);
    crate::cull::hiz::box_occluded(low, high, view_proj, pyramid, hiz)
}

/// Whether `tile` can show a blade to a camera at `camera` with `view_proj`: inside
/// the world (`half_extent`), its box (the tile's square over the height range
/// `span`, [`tile_box`]) not wholly outside one plane of the view volume (the eight corners in clip space),
/// and its nearest point within `reach` of the camera (beyond, [`density`](crate::world::tiles::density) has left
/// too few blades to draw: the caller's choice).
pub fn tile_in_view(
    tile: IVec2,
    view_proj: Mat4,
    camera: Vec3,
    params: &TileParams,
    span: (f32, f32),
    reach: f32,
) -> bool {
    if !tile_in_world(tile, params) {
        return false;
    }
    let (lo, hi) = tile_square(tile, params);
    let (bottom, top) = span;
    let nearest = nearest_point(tile, camera, params, (bottom, top));
    if (nearest - camera).length() > reach {
        return false;
    }
    let low = Vec3::new(lo.x, bottom, lo.y);
    let high = Vec3::new(hi.x, top, hi.y);
    box_in_view(low, high, view_proj)
}

/// Whether the box from `lo` to `hi` is not wholly outside one plane of the view
/// volume of `view_proj`: outside a plane when every one of its eight corners is
/// beyond it (x < −w, x > w, y < −w, y > w, z < 0, z > w in clip space).
pub fn box_in_view(lo: Vec3, hi: Vec3, view_proj: Mat4) -> bool {
    // One bit per plane, cleared by a corner inside it (rust-gpu cannot fill a bool
    // array).
    let mut outside = 0b11_1111u32;
    let mut corner = 0;
    while corner < 8 {
        let p = Vec3::new(
            if corner & 1 == 0 { lo.x } else { hi.x },
            if corner & 2 == 0 { lo.y } else { hi.y },
            if corner & 4 == 0 { lo.z } else { hi.z },
        );
        let c = view_proj * p.extend(1.0);
        let beyond = [
            c.x < -c.w,
            c.x > c.w,
            c.y < -c.w,
            c.y > c.w,
            c.z < 0.0,
            c.z > c.w,
        ];
        let mut plane = 0;
        while plane < 6 {
            if !beyond[plane] {
                outside &= !(1 << plane);
            }
            plane += 1;
        }
        corner += 1;
    }
    outside == 0
}

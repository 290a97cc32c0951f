//! The pool of simulated tiles as the compute pass reads it: which tile a pool
//! blade's slot holds, whether the blade grows there, how wide this frame draws it,
//! and how far its tile has gone back to the far pose. The pool itself is kept by the
//! runner (`passes::tiles`); its table is `gpu::layout::TILES_POOL` on.

use crate::Blade;
use crate::gpu::layout::{EMPTY_SLOT, POOL_WORDS, TILES_POOL};
use crate::world::tiles::{TileParams, drawn_width};
use spirv_std::glam::{IVec2, Vec3};

/// A pool blade as this frame draws it.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct PoolBlade {
    /// It grows: its slot holds a tile, it is not empty (height above 0), and its
    /// tile grows it at its root (drawn width above 0 seen from there).
    pub grows: bool,
    /// The tile its slot holds.
    pub tile: IVec2,
    /// Its index in the tile.
    pub index: u32,
    /// Its width seen from the camera ([`drawn_width`]): 0 where its rank has left
    /// it (it is still simulated, so its trail decays as if seen, but not drawn).
    pub width: f32,
    /// How far its tile has gone back to its far pose (0..1, `tiles::fade_to_far`).
    pub fade: f32,
}

/// Pool blade `index` (below the pool's blade count), whose stored state is `blade`,
/// with the pool's table `tiles`, the world's `params` and set `map`, seen from
/// `camera`.
pub fn pool_blade(
    index: u32,
    blade: &Blade,
    tiles: &[u32],
    params: &TileParams,
    map: &[u32],
    camera: Vec3,
) -> PoolBlade {
    let per_tile = params.per_side * params.per_side;
    let slot = TILES_POOL + POOL_WORDS * (index / per_tile) as usize;
    let tile = IVec2::new(tiles[slot] as i32, tiles[slot + 1] as i32);
    let root = blade.root();
    let k = index % per_tile;
    let grows = tile.x != EMPTY_SLOT
        && blade.height() > 0.0
        && drawn_width(tile, k, root, root, params, map) > 0.0;
    if !grows {
        return PoolBlade::default();
    }
    PoolBlade {
        grows,
        tile,
        index: k,
        width: drawn_width(tile, k, root, camera, params, map),
        fade: f32::from_bits(tiles[slot + 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::tiles::tile_blade;

    /// A table of `slots`: (tile, fade) or `None` for an empty slot.
    fn table(slots: &[Option<(IVec2, f32)>]) -> Vec<u32> {
        let mut t = vec![0u32; TILES_POOL + POOL_WORDS * slots.len()];
        for (i, s) in slots.iter().enumerate() {
            let at = TILES_POOL + POOL_WORDS * i;
            let (tile, fade) = s.unwrap_or((IVec2::new(EMPTY_SLOT, 0), 0.0));
            t[at] = tile.x as u32;
            t[at + 1] = tile.y as u32;
            t[at + 2] = fade.to_bits();
        }
        t
    }

    #[test]
    fn a_pool_blade_is_its_slot_s_tile_s_blade() {
        let params = TileParams {
            full_distance: 20.0,
            ..TileParams::default()
        };
        let per_tile = params.per_side * params.per_side;
        let (near, far) = (IVec2::new(0, 0), IVec2::new(3, -2));
        let tiles = table(&[Some((near, 0.0)), None, Some((far, 0.25))]);
        let camera = Vec3::new(1.0, 1.5, 1.0);
        for (slot, tile) in [(0u32, near), (2, far)] {
            for k in [0, 1, per_tile / 2, per_tile - 1] {
                let blade = tile_blade(tile, k, camera, &params, &[]);
                let p = pool_blade(slot * per_tile + k, &blade, &tiles, &params, &[], camera);
                assert!(p.grows, "slot {slot} blade {k}");
                assert_eq!((p.tile, p.index), (tile, k));
                let root = blade.root();
                assert_eq!(p.width, drawn_width(tile, k, root, camera, &params, &[]));
                assert_eq!(p.fade, if slot == 0 { 0.0 } else { 0.25 });
            }
        }
        // An empty slot, an empty blade: nothing grows.
        let blade = tile_blade(near, 0, camera, &params, &[]);
        assert!(!pool_blade(per_tile, &blade, &tiles, &params, &[], camera).grows);
        assert!(!pool_blade(0, &Blade::default(), &tiles, &params, &[], camera).grows);
        // Seen from far away, a blade still grows but is drawn at width 0.
        let away = Vec3::new(5_000.0, 1.5, 0.0);
        let p = pool_blade(0, &blade, &tiles, &params, &[], away);
        assert!(p.grows && p.width == 0.0, "{p:?}");
    }
}

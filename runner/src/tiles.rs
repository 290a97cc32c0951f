//! The tiled field's host side: its layout and budget ([`TiledSpec`]),
//! and which tiles hold simulated state. A fixed number of slots, each the state of one tile's blades (the paper's
//! v1, v2 and collision strength), so device memory depends on the pool, not on the
//! world. A tile keeps its slot while it is needed (near the camera) or pinned (a
//! collider trampled it and its strength has not decayed); a needed tile without a
//! slot takes a free one, else the least recently needed unpinned tile's, else it is
//! dropped for the frame (drawn in the far tiles' pose) and counted.

use shared::glam::{IVec2, Vec2, Vec3};
use shared::gpu::layout::{MAX_POOL_TILES, TILE_WORDS, TILES_LIST};
use shared::sim::collide::Collider;
use shared::world::tiles::TileParams;
use std::collections::HashMap;

/// A tiled field's layout and budget: the world's tiles, the pool's size and reach,
/// the room for far blades and how far tiles are drawn.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TiledSpec {
    /// The world's tiles (`shared::tiles`).
    pub params: TileParams,
    /// Slots of simulated tiles.
    pub pool_tiles: u32,
    /// Tiles whose square comes within this distance of the camera (on the ground
    /// plane) are simulated.
    pub pool_radius: f32,
    /// Room for the far tiles' blades each frame.
    pub far_blades: u32,
    /// Tiles beyond this distance are not drawn.
    pub reach: f32,
    /// The ground's lowest and highest points (the tiles' boxes).
    pub ground: (f32, f32),
    /// The world's surface area: its square's, or a loaded scene's triangles'.
    pub area: f64,
}

impl TiledSpec {
    /// A flat world of `params` for the tests: `pool_tiles` slots within 3 units of
    /// the camera, room for `far_blades`, drawn to 20 units, its area its square's.
    #[cfg(test)]
    pub(crate) fn flat_for_tests(params: TileParams, pool_tiles: u32, far_blades: u32) -> Self {
        let side = 2.0 * f64::from(params.half_extent);
        Self {
            params,
            pool_tiles,
            pool_radius: 3.0,
            far_blades,
            reach: 20.0,
            ground: (0.0, 0.0),
            area: side * side,
        }
    }

    /// Blades of one tile.
    pub fn tile_blades(&self) -> u32 {
        self.params.per_side * self.params.per_side
    }

    /// Blades of the pool's slots (the simulated part of the field, first).
    pub fn pool_blades(&self) -> u32 {
        self.pool_tiles * self.tile_blades()
    }

    /// Blades the field holds: the pool's, then room for the far ones.
    pub fn capacity(&self) -> u32 {
        self.pool_blades() + self.far_blades
    }

    /// Blades the world could grow at full density (every tile, every blade): what
    /// a stored field of the same world would hold.
    pub fn potential_blades(&self) -> f64 {
        self.area * f64::from(self.per_area())
    }

    /// Blades a square unit grows at full density: a tile's over its square, on a
    /// loaded scene a share of that (`shared::world::surface::per_area`: room for slopes).
    pub fn per_area(&self) -> f32 {
        if self.params.terrain == shared::world::tiles::TERRAIN_MESH {
            return shared::world::surface::per_area(self.params.size, self.tile_blades());
        }
        let per_unit = self.params.per_side as f32 / self.params.size;
        per_unit * per_unit
    }

    /// The tiles inside the world whose square comes within `radius` of `at` on the
    /// ground plane (x, z), nearest first.
    pub fn tiles_within(&self, at: Vec2, radius: f32) -> Vec<IVec2> {
        use shared::world::tiles::{tile_in_world, tile_of};
        let params = &self.params;
        let lo = tile_of(at - Vec2::splat(radius), params);
        let hi = tile_of(at + Vec2::splat(radius), params);
        let mut near: Vec<(f32, IVec2)> = Vec::new();
        for z in lo.y..=hi.y {
            for x in lo.x..=hi.x {
                let tile = IVec2::new(x, z);
                let distance = self.distance(tile, at);
                if tile_in_world(tile, params) && distance <= radius {
                    near.push((distance, tile));
                }
            }
        }
        nearest_first(near)
    }

    /// How far `tile`'s square lies from `at` on the ground plane (0 inside it).
    fn distance(&self, tile: IVec2, at: Vec2) -> f32 {
        let (min, max) = shared::world::tiles::tile_square(tile, &self.params);
        at.clamp(min, max).distance(at)
    }

    /// The tiles the pool should hold for a camera at `camera`: those within
    /// [`TiledSpec::pool_radius`], nearest first (not only those in view, so a tile
    /// keeps its state while the camera turns).
    pub fn needed(&self, camera: Vec3) -> Vec<IVec2> {
        self.tiles_within(Vec2::new(camera.x, camera.z), self.pool_radius)
    }

    /// The tiles the pool should hold ([`Self::needed`]), then the trampled tiles
    /// `trails` names that are not among them, nearest the camera first: in an order
    /// that does not depend on the order the trails are kept in (a hash map's), so
    /// that every run places the same tiles in the same slots.
    pub fn needed_with_trails(
        &self,
        camera: Vec3,
        trails: impl IntoIterator<Item = IVec2>,
    ) -> Vec<IVec2> {
        let mut needed = self.needed(camera);
        let at = Vec2::new(camera.x, camera.z);
        let trampled: Vec<(f32, IVec2)> = trails
            .into_iter()
            .filter(|t| !needed.contains(t))
            .map(|t| (self.distance(t, at), t))
            .collect();
        needed.extend(nearest_first(trampled));
        needed
    }

    /// The tiles a collider can bend blades in: those its bounding sphere's ground
    /// shadow, grown by `reach`, touches: how far the field's blades reach from
    /// their roots (`Field::reach`: the tallest its species mix and painted maps
    /// grow, `shared::world::paint::tallest`, times `sim::grid::REACH_MARGIN`).
    pub fn touched(&self, collider: &Collider, reach: f32) -> Vec<IVec2> {
        let (lo, hi) = collider.bounds();
        let centre = (lo + hi) * 0.5;
        let radius = 0.5 * (hi - lo).length() + reach;
        self.tiles_within(Vec2::new(centre.x, centre.z), radius)
    }

    /// Tiles from the camera's tile to the edge of the far tiles' candidate square:
    /// enough to reach [`TiledSpec::reach`], and one more.
    pub fn reach_tiles(&self) -> i32 {
        (self.reach / self.params.size).ceil() as i32 + 1
    }

    /// Tiles along a side of the candidate square (the camera's tile at its centre).
    pub fn candidate_side(&self) -> u32 {
        (2 * self.reach_tiles() + 1) as u32
    }

    /// Words of the tile buffer for this layout: the header, the pool's table and the
    /// list of far tiles (every candidate of the selection's square at most).
    pub fn tile_words(&self) -> u32 {
        let side = self.candidate_side() as usize;
        (TILES_LIST + TILE_WORDS * side * side) as u32
    }

    /// Checks the layout against the pool table's room.
    pub fn check(&self) -> anyhow::Result<()> {
        if self.pool_tiles as usize > MAX_POOL_TILES || self.pool_tiles == 0 {
            anyhow::bail!(
                "a tiled field's pool holds 1 to {MAX_POOL_TILES} tiles, not {}",
                self.pool_tiles
            );
        }
        if !self.params.per_side.is_power_of_two() {
            anyhow::bail!(
                "tiles need a power of two blades a side, not {}",
                self.params.per_side
            );
        }
        Ok(())
    }
}

/// The tiles of `tiles` (each with its distance) nearest first, then by x and z.
fn nearest_first(mut tiles: Vec<(f32, IVec2)>) -> Vec<IVec2> {
    tiles.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(a.1.x.cmp(&b.1.x))
            .then(a.1.y.cmp(&b.1.y))
    });
    tiles.into_iter().map(|(_, t)| t).collect()
}

/// How long a trampled tile keeps its slot after a collider last touched it: until
/// its collision strength has decayed (η falls linearly from at most
/// `collide::MAX_STRENGTH` at `decay` a second) and its blades stood up again (a few
/// seconds of recovery); for ever without decay.
pub fn trail_hold(decay: f32) -> f32 {
    if decay > 0.0 {
        shared::sim::collide::MAX_STRENGTH / decay + RECOVERY_SECONDS
    } else {
        f32::INFINITY
    }
}

/// Seconds a blade takes to stand up again once its collision strength is gone (the
/// recovery force at the default stiffness brings it within a few per cent in about
/// this: `shared/tests/stability.rs`).
pub const RECOVERY_SECONDS: f32 = 3.0;

/// One slot's tile and when it was last needed (in [`TilePool::update`] calls).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Slot {
    tile: IVec2,
    last_needed: u64,
}

/// What one [`TilePool::update`] decided.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PoolUpdate {
    /// Slots given to tiles this frame, (slot, tile): their blades start from the
    /// far tiles' pose (`shared::world::tiles::far_blade`).
    pub placed: Vec<(usize, IVec2)>,
    /// Tiles that lost their slot to a needed one (their state is gone).
    pub evicted: Vec<IVec2>,
    /// Needed tiles that found no slot (every slot needed or pinned).
    pub dropped: usize,
}

/// The slots of simulated tiles.
#[derive(Clone, Debug)]
pub struct TilePool {
    slots: Vec<Option<Slot>>,
    by_tile: HashMap<IVec2, usize>,
    frame: u64,
    /// Tiles evicted since the pool was made (the overlay's count).
    pub evictions: u64,
}

impl TilePool {
    /// A pool of `slots` tiles, all free.
    pub fn new(slots: usize) -> Self {
        Self {
            slots: vec![None; slots],
            by_tile: HashMap::new(),
            frame: 0,
            evictions: 0,
        }
    }

    /// The slot of `tile`, if it holds one.
    pub fn slot_of(&self, tile: IVec2) -> Option<usize> {
        self.by_tile.get(&tile).copied()
    }

    /// The tiles held and their slots.
    pub fn held(&self) -> impl Iterator<Item = (IVec2, usize)> + '_ {
        self.by_tile.iter().map(|(&tile, &slot)| (tile, slot))
    }

    /// One frame: `needed` tiles, most needed first, and `pinned` saying which held
    /// tiles must keep their state (trampled, not yet recovered). Needed tiles keep or
    /// take slots in that order; see the module's text for who gives way.
    pub fn update(&mut self, needed: &[IVec2], pinned: impl Fn(IVec2) -> bool) -> PoolUpdate {
        self.frame += 1;
        let frame = self.frame;
        let mut update = PoolUpdate::default();
        // First mark every needed tile that holds a slot, so none of them is evicted
        // for a tile later in the list.
        for tile in needed {
            if let Some(s) = self
                .by_tile
                .get(tile)
                .and_then(|&slot| self.slots[slot].as_mut())
            {
                s.last_needed = frame;
            }
        }
        for &tile in needed {
            if self.by_tile.contains_key(&tile) {
                continue;
            }
            let free = self.slots.iter().position(Option::is_none);
            let slot = free.or_else(|| {
                // The least recently needed slot not needed now and not pinned.
                self.slots
                    .iter()
                    .enumerate()
                    .filter_map(|(i, s)| s.map(|s| (i, s)))
                    .filter(|(_, s)| s.last_needed < frame && !pinned(s.tile))
                    .min_by_key(|&(i, s)| (s.last_needed, i))
                    .map(|(i, s)| {
                        self.by_tile.remove(&s.tile);
                        update.evicted.push(s.tile);
                        self.evictions += 1;
                        i
                    })
            });
            match slot {
                Some(slot) => {
                    self.slots[slot] = Some(Slot {
                        tile,
                        last_needed: frame,
                    });
                    self.by_tile.insert(tile, slot);
                    update.placed.push((slot, tile));
                }
                None => update.dropped += 1,
            }
        }
        update
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiles(range: std::ops::Range<i32>) -> Vec<IVec2> {
        range.map(|x| IVec2::new(x, 0)).collect()
    }

    /// A flat world of unit tiles, 32 a side, with 64 slots.
    fn unit_tiles() -> TiledSpec {
        let params = shared::world::tiles::TileParams {
            size: 1.0,
            per_side: 4,
            half_extent: 16.0,
            ..Default::default()
        };
        TiledSpec::flat_for_tests(params, 64, 1 << 10)
    }

    #[test]
    fn a_needed_tile_keeps_its_slot() {
        let mut pool = TilePool::new(8);
        let first = pool.update(&tiles(0..5), |_| false);
        assert_eq!(first.placed.len(), 5);
        let slots: Vec<_> = tiles(0..5).iter().map(|&t| pool.slot_of(t)).collect();
        // The camera moves on by one tile: four stay where they were, one is placed.
        let next = pool.update(&tiles(1..6), |_| false);
        assert_eq!(next.placed, vec![(5, IVec2::new(5, 0))]);
        assert!(next.evicted.is_empty());
        for (t, s) in tiles(0..5).iter().zip(&slots).skip(1) {
            assert_eq!(pool.slot_of(*t), *s);
        }
    }

    /// Planted fault: the most recently needed giving way instead failed.
    #[test]
    fn the_least_recently_needed_gives_way_and_no_slot_is_shared() {
        let mut pool = TilePool::new(4);
        pool.update(&tiles(0..4), |_| false);
        pool.update(&tiles(2..4), |_| false);
        pool.update(&tiles(1..4), |_| false);
        // Tile 0 was needed longest ago: it goes first, then tile 1.
        let update = pool.update(&tiles(2..6), |_| false);
        assert_eq!(update.evicted, vec![IVec2::new(0, 0), IVec2::new(1, 0)]);
        assert_eq!(pool.evictions, 2);
        let mut held: Vec<usize> = tiles(2..6)
            .iter()
            .filter_map(|&t| pool.slot_of(t))
            .collect();
        held.sort_unstable();
        assert_eq!(held, vec![0, 1, 2, 3]);
        assert_eq!(pool.slot_of(IVec2::new(0, 0)), None);
    }

    #[test]
    fn a_trampled_tile_keeps_its_state_until_it_recovers() {
        let mut pool = TilePool::new(3);
        let trail = IVec2::new(0, 0);
        pool.update(&tiles(0..3), |_| false);
        // The camera turns away: three other tiles needed, the trampled one pinned.
        let away = [IVec2::new(7, 7), IVec2::new(8, 7), IVec2::new(9, 7)];
        let update = pool.update(&away, |t| t == trail);
        assert_eq!(pool.slot_of(trail), Some(0));
        assert_eq!(update.placed.len(), 2);
        assert_eq!(update.dropped, 1, "no slot for the third");
        // Back again: it is still there with its state.
        let back = pool.update(&tiles(0..1), |t| t == trail);
        assert!(back.placed.is_empty());
        assert_eq!(pool.slot_of(trail), Some(0));
        // Recovered (no longer pinned) and not needed: it gives way.
        pool.update(&away, |_| false);
        assert_eq!(pool.slot_of(trail), None);
    }

    /// A collider pins the tiles within its bounding sphere's ground shadow grown by
    /// the reach it is given: seed grass painted by a type map (half as tall again
    /// as grass) pins a ring of tiles more than grass alone. Planted fault: the
    /// reach of grass whatever the field grows (as before) failed.
    #[test]
    fn a_collider_pins_the_tiles_its_fields_tallest_blades_reach() {
        let spec = unit_tiles();
        let ball = Collider::sphere(Vec3::new(0.5, 0.5, 0.5), 0.5);
        let radius = 0.5 * 3f32.sqrt();
        let tallest = shared::blade::HEIGHT.1;
        for reach in [tallest, 1.5 * tallest] {
            let touched = spec.touched(&ball, reach);
            let centre = Vec2::splat(0.5);
            for tile in spec.tiles_within(centre, 8.0) {
                let (min, max) = shared::world::tiles::tile_square(tile, &spec.params);
                let within = centre.clamp(min, max).distance(centre) <= radius + reach;
                assert_eq!(touched.contains(&tile), within, "{tile} at reach {reach}");
            }
        }
        let grass = spec.touched(&ball, tallest).len();
        let seed = spec.touched(&ball, 1.5 * tallest).len();
        assert!(seed > grass, "{seed} against {grass} tiles");
    }

    /// The trampled tiles come after the camera's, nearest it first, whatever order
    /// the trails are kept in. Planted fault: taken in the trails' order (as a hash
    /// map gives them, differently in every run) failed.
    #[test]
    fn trampled_tiles_are_needed_in_one_order() {
        let spec = unit_tiles();
        let camera = Vec3::new(0.5, 1.0, 0.5);
        let near = spec.needed(camera);
        let trails: Vec<IVec2> = [(9, 2), (-6, 0), (5, 5), (0, 0), (2, -9), (-6, 1)]
            .into_iter()
            .map(|(x, z)| IVec2::new(x, z))
            .collect();
        let forward = spec.needed_with_trails(camera, trails.iter().copied());
        let backward = spec.needed_with_trails(camera, trails.iter().rev().copied());
        assert_eq!(forward, backward);
        // The camera's own tile is needed already; the rest follow it, nearest first.
        assert_eq!(forward[..near.len()], near[..]);
        // From (0.5, 0.5) to the squares: 5.5, √30.5, √40.5, then √74.5 twice (x
        // decides).
        let trampled: Vec<IVec2> = [(-6, 0), (-6, 1), (5, 5), (2, -9), (9, 2)]
            .into_iter()
            .map(|(x, z)| IVec2::new(x, z))
            .collect();
        assert_eq!(forward[near.len()..], trampled[..]);
    }

    #[test]
    fn needed_tiles_are_served_in_order_when_slots_run_out() {
        let mut pool = TilePool::new(3);
        let update = pool.update(&tiles(0..5), |_| false);
        assert_eq!(update.placed.len(), 3);
        assert_eq!(update.dropped, 2);
        // The first three (the nearest) hold the slots.
        assert!(tiles(0..3).iter().all(|&t| pool.slot_of(t).is_some()));
        assert!(tiles(3..5).iter().all(|&t| pool.slot_of(t).is_none()));
    }
}

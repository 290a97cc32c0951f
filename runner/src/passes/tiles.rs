//! The tiled field's generation, first in a tiled frame: the host decides
//! which tiles the pool of simulated tiles holds ([`TilePool`]: the tiles near the
//! camera and the ones a collider trampled), and the GPU generates a tile entering the
//! pool into its slot; then a compute pass picks the far tiles in view, each taking
//! room for the blades its distance keeps, and one workgroup per far tile generates
//! them. The simulate-and-cull pass that follows simulates the pool's blades and
//! culls both. A pool tile nobody needs any more goes back to the far tiles' pose over
//! [`FADE_SECONDS`], so that it leaves the pool as the far tiles draw it.

use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::tiles::{TilePool, TiledSpec, trail_hold};
use crate::vulkan::pipeline::{Pipeline, ShaderModules};
use crate::vulkan::{Context, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use shared::glam::{IVec2, UVec2, UVec4, Vec2};
use shared::gpu::layout::{
    EMPTY_SLOT, FrameUniforms, POOL_WORDS, SIMULATE_WORKGROUP, SPEC_IMPULSES, SelectPush,
    TILES_DISPATCH, TILES_POOL, TilePush,
};
use shared::sim::collide::Collider;
use std::collections::HashMap;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// What the host's side of the tiles did in the last frame (the overlay's and the
/// log's; the GPU's side is in the counters).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct PoolStats {
    /// Tiles the pool holds.
    pub held: u32,
    /// Its slots.
    pub slots: u32,
    /// Tiles placed (generated into a slot) this frame.
    pub placed: u32,
    /// Tiles evicted since the field was made.
    pub evictions: u64,
    /// Needed tiles that found no slot this frame.
    pub dropped: u32,
    /// Tiles pinned by a trail.
    pub pinned: u32,
}

/// Seconds a pool tile nobody needs takes to go back to the far tiles' pose
/// (`shared::world::tiles::fade_to_far`): by then it can leave the pool without a jump, and
/// the least recently needed, which leave first, have.
pub const FADE_SECONDS: f32 = 1.0;

/// The tiled field's pipelines and pool.
pub struct TilesPass {
    ctx: Arc<Context>,
    spec: TiledSpec,
    /// The pool's and the far tiles' generation, without and with the frame's wind
    /// impulses (`layout::SPEC_IMPULSES`).
    pool_tile: [Pipeline; 2],
    select: Pipeline,
    generate: [Pipeline; 2],
    pool: TilePool,
    /// Trampled tiles and the seconds left before they may leave the pool.
    trails: HashMap<IVec2, f32>,
    /// Seconds each slot's tile has gone unneeded (0 while needed or trampled).
    idle: Vec<f32>,
    /// The last frame's host side.
    pub stats: PoolStats,
}

impl TilesPass {
    /// The pipelines for a field laid out by `spec` (the field made with
    /// `FieldBlades::Tiled`).
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        spec: TiledSpec,
    ) -> Result<Self> {
        let layout = &field.layout;
        let blowing = |entry, on: bool| {
            let constants = [(SPEC_IMPULSES, u32::from(on))];
            Pipeline::compute_specialised(ctx, layout, module, entry, &constants)
        };
        let both = |entry| -> Result<[Pipeline; 2]> {
            Ok([blowing(entry, false)?, blowing(entry, true)?])
        };
        Ok(Self {
            ctx: ctx.clone(),
            spec,
            pool_tile: both(shaders::GENERATE_POOL_TILE)?,
            select: Pipeline::compute(ctx, layout, module, shaders::SELECT_FAR_TILES)?,
            generate: both(shaders::GENERATE_FAR)?,
            pool: TilePool::new(spec.pool_tiles as usize),
            trails: HashMap::new(),
            idle: vec![0.0; spec.pool_tiles as usize],
            stats: PoolStats::default(),
        })
    }

    /// The field's layout.
    pub fn spec(&self) -> &TiledSpec {
        &self.spec
    }

    /// Every blade kept within `distance` of the camera from the next frame on (the
    /// overlay's control): the far tiles and the pool's thinning follow at once.
    pub fn set_full_distance(&mut self, distance: f32) {
        self.spec.params.full_distance = distance.max(1.0);
    }

    /// Tiles grown with the species `mix` from the next frame on (the overlay's
    /// control): the pool starts empty, so every tile is made again, trails and cuts
    /// with it.
    pub fn set_species(&mut self, mix: shared::species::Mix) {
        self.spec.params.species = mix.weights;
        self.pool = TilePool::new(self.spec.pool_tiles as usize);
        self.trails.clear();
    }

    /// The pool's slot holding `tile`, if any.
    pub fn slot_of(&self, tile: IVec2) -> Option<usize> {
        self.pool.slot_of(tile)
    }

    /// The tiles the pool holds and their slots.
    pub fn held(&self) -> Vec<(IVec2, usize)> {
        self.pool.held().collect()
    }

    /// Records the frame's tile work, `seconds` after the last frame: the pool's
    /// update and its new tiles, the pool's table, the far tiles' selection and
    /// generation. The uniform update and the counters' reset must come before, with
    /// their barrier; this leaves the blades, ids and clumps ready for the compute
    /// pass.
    pub fn record(
        &mut self,
        rec: &Recorder,
        field: &Field,
        (uniforms, colliders): (&FrameUniforms, &[Collider]),
        seconds: f32,
    ) -> Result<()> {
        let spec = self.spec;
        let camera = uniforms.camera.position;
        // Trails: a tile a ball touches is held for as long as its blades take to
        // recover; the others count down.
        for hold in self.trails.values_mut() {
            *hold -= seconds;
        }
        self.trails.retain(|_, hold| *hold > 0.0);
        let hold = trail_hold(uniforms.forces.strength_decay);
        for collider in colliders {
            for tile in spec.touched(collider, field.reach) {
                self.trails.insert(tile, hold);
            }
        }
        // A trampled tile out of the pool's reach is needed too (after the near ones).
        let needed = spec.needed_with_trails(camera, self.trails.keys().copied());
        let trails = &self.trails;
        let update = self.pool.update(&needed, |t| trails.contains_key(&t));

        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let blowing = usize::from(uniforms.forces.impulses > 0);
        let tiles = field
            .tiles
            .as_ref()
            .context("a tiled field's tile buffer")?;
        // The far generation's dispatch (x by the selection), the pool's table.
        let mut words = vec![0u32; TILES_POOL + POOL_WORDS * spec.pool_tiles as usize];
        words[TILES_DISPATCH..TILES_DISPATCH + 3].copy_from_slice(&[0, 1, 1]);
        for slot in 0..spec.pool_tiles as usize {
            words[TILES_POOL + POOL_WORDS * slot] = EMPTY_SLOT as u32;
        }
        for &(slot, _) in &update.placed {
            self.idle[slot] = 0.0;
        }
        for (tile, slot) in self.pool.held() {
            let at = TILES_POOL + POOL_WORDS * slot;
            self.idle[slot] = if needed.contains(&tile) {
                0.0
            } else {
                self.idle[slot] + seconds
            };
            let fade = (self.idle[slot] / FADE_SECONDS).min(1.0);
            words[at..at + POOL_WORDS].copy_from_slice(&[
                tile.x as u32,
                tile.y as u32,
                fade.to_bits(),
            ]);
        }
        rec.update_buffer(tiles.buffer, bytemuck::cast_slice(&words));

        if !update.placed.is_empty() {
            rec.bind_pipeline(compute, self.pool_tile[blowing].pipeline, layout, set);
            let mut params = spec.params;
            // Every blade of a pool tile kept, at its own width.
            params.full_distance = 1e6;
            for &(slot, tile) in &update.placed {
                let push = TilePush {
                    params,
                    tile,
                    slot: UVec2::new(slot as u32 * spec.tile_blades(), 0),
                    camera: camera.extend(0.0),
                };
                rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
                rec.dispatch((spec.tile_blades().div_ceil(SIMULATE_WORKGROUP), 1));
            }
        }
        rec.memory_barrier(
            (S::COPY, A::TRANSFER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
        );

        // The far tiles in view: a square of candidates around the camera's tile.
        let centre = shared::world::tiles::tile_of(Vec2::new(camera.x, camera.z), &spec.params);
        let (reach_tiles, side) = (spec.reach_tiles(), spec.candidate_side());
        let push = SelectPush {
            view_proj: uniforms.camera.view_proj,
            camera: camera.extend(spec.reach),
            first: centre - IVec2::splat(reach_tiles),
            count: UVec2::splat(side),
            ground: shared::glam::Vec4::new(spec.ground.0, spec.ground.1, 0.0, 0.0),
            params: spec.params,
            far: UVec4::new(spec.pool_tiles, spec.far_blades, spec.pool_blades(), 0),
        };
        rec.bind_pipeline(compute, self.select.pipeline, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        rec.dispatch(self.ctx.workgroups(side * side, SIMULATE_WORKGROUP));
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (
                S::COMPUTE_SHADER | S::DRAW_INDIRECT,
                A::SHADER_READ | A::INDIRECT_COMMAND_READ,
            ),
        );
        rec.bind_pipeline(compute, self.generate[blowing].pipeline, layout, set);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        rec.dispatch_indirect(tiles.buffer, (TILES_DISPATCH * 4) as u64);
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
        );

        self.stats = PoolStats {
            held: self.pool.held().count() as u32,
            slots: spec.pool_tiles,
            placed: update.placed.len() as u32,
            evictions: self.pool.evictions,
            dropped: update.dropped as u32,
            pinned: self.trails.len() as u32,
        };
        Ok(())
    }
}

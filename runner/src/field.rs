//! The field on the GPU: blade, collision strength, visible, counter, draw and uniform
//! buffers, and the one descriptor set and pipeline layout every pass uses.

use crate::vulkan::commands::CommandPool;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::PipelineLayout;
use crate::vulkan::{Buffer, Context};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::Blade;
use shared::cull::lod::blades_per_chunk;
use shared::draw::look::clump::DressedBlade;
use shared::draw::meshlet::{MESH_DRAWS, StripBlade};
use shared::draw::temporal::BladeMotion;
use shared::gpu::counters;
use shared::gpu::layout;
use shared::gpu::layout::{
    ChunkPush, CopyPush, FrameUniforms, HiZPush, PreparePush, SimulatePush, SurfacePush,
    ThroughputPush,
};
use shared::gpu::layout::{SelectPush, TilePush};
use shared::sim;
use shared::sim::collide::{Collider, MAX_COLLIDERS};
use shared::sim::cut::{CUT_SLOTS, CUT_WORDS};
use shared::sim::grid::ColliderGrid;
use std::sync::Arc;

mod limits;
mod resize;
pub use limits::DEVICE_BYTES_PER_BLADE;
use resize::{root_range, stored_growth, tiled_growth};
use vk::ShaderStageFlags as Stage;

/// Stages that read the frame's uniform block (a storage buffer: see
/// `shared::gpu::layout::BINDING_UNIFORMS`).
const UNIFORM_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::COMPUTE.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION.as_raw()
        | vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw()
        | vk::ShaderStageFlags::MESH_EXT.as_raw(),
);

const fn storage(binding: u32) -> BindingSpec {
    storage_in(binding, vk::ShaderStageFlags::empty())
}

/// A storage buffer read by the compute passes and the `graphics` stages.
const fn storage_in(binding: u32, graphics: vk::ShaderStageFlags) -> BindingSpec {
    BindingSpec {
        binding,
        ty: vk::DescriptorType::STORAGE_BUFFER,
        stages: vk::ShaderStageFlags::from_raw(
            vk::ShaderStageFlags::COMPUTE.as_raw() | graphics.as_raw(),
        ),
    }
}

/// The one descriptor set layout of every pipeline (but the overlay's).
pub const BINDINGS: [BindingSpec; 30] = [
    BindingSpec {
        binding: layout::BINDING_UNIFORMS,
        ty: vk::DescriptorType::STORAGE_BUFFER,
        stages: UNIFORM_STAGES,
    },
    // The paper look's tessellation and mesh stages read the blades through their
    // index, and so does the compute rasterizer's resolve (a fragment stage).
    storage_in(layout::BINDING_BLADES, GEOMETRY_OR_RESOLVE),
    storage_in(layout::BINDING_VISIBLE, VERTEX_FRAGMENT),
    // The mesh stages read how many blades have strips of each length, the
    // tessellation path's vertex stage how many are visible.
    storage_in(layout::BINDING_COUNTERS, MESH_VERTEX),
    storage(layout::BINDING_DRAWS),
    storage(layout::BINDING_STRENGTH),
    storage(layout::BINDING_PYRAMID),
    // The bandwidth reference's destination, also the mesh-vertex capture's
    // (`GrassPass::capture`).
    storage_in(layout::BINDING_SCRATCH, vk::ShaderStageFlags::MESH_EXT),
    // The sun's shadow map (`passes::shadow`), read by the lit fragment stages and
    // the natural look's shading after the draw (`passes::shade`).
    BindingSpec {
        binding: layout::BINDING_SHADOW_MAP,
        ty: vk::DescriptorType::SAMPLED_IMAGE,
        stages: FRAGMENT_OR_SHADE,
    },
    // The visible blades as the natural look draws them, read by its tessellation
    // stages.
    storage_in(layout::BINDING_DRESSED, GEOMETRY_OR_RESOLVE),
    // The shadow map's comparison sampler.
    BindingSpec {
        binding: layout::BINDING_SHADOW_SAMPLER,
        ty: vk::DescriptorType::SAMPLER,
        stages: FRAGMENT_OR_SHADE,
    },
    // Each blade's clump, made by the clump pass, read by the compute pass and by the
    // shadow map's casters.
    storage(layout::BINDING_CLUMPS),
    // The mesh path's indirect draws and the shadow casters' dispatches, written by
    // the compute pass.
    storage(layout::BINDING_MESH_DRAW),
    // The shadow map's grass depth, drawn by the casters' compute threads.
    storage(layout::BINDING_SHADOW_DEPTH),
    // The mesh path's binned blades, written by the compute pass.
    storage_in(layout::BINDING_BINNED, vk::ShaderStageFlags::MESH_EXT),
    // The compute rasterizer's visibility buffer (`passes::raster`), read by its
    // resolve.
    storage_in(layout::BINDING_VISIBILITY, vk::ShaderStageFlags::FRAGMENT),
    // The compute rasterizer's indirect dispatch and resolve, written by the compute
    // pass.
    storage(layout::BINDING_RASTER_ARGS),
    // The hardware's depth, copied for the compute rasterizer's depth test.
    storage(layout::BINDING_HARDWARE_DEPTH),
    // The depth targets it is copied from, single-sample and multisampled (written
    // when the draw targets are made).
    BindingSpec {
        binding: layout::BINDING_DEPTH_IMAGE,
        ty: vk::DescriptorType::SAMPLED_IMAGE,
        stages: vk::ShaderStageFlags::COMPUTE,
    },
    BindingSpec {
        binding: layout::BINDING_DEPTH_IMAGE_MS,
        ty: vk::DescriptorType::SAMPLED_IMAGE,
        stages: vk::ShaderStageFlags::COMPUTE,
    },
    // A tiled field's tile words and blade ids (placeholders in a stored field).
    // (The ids name the shadow map's casters too.)
    storage(layout::BINDING_TILES),
    storage(layout::BINDING_IDS),
    // The painted density map (`shared::paint`).
    storage(layout::BINDING_PAINT),
    // The shadow casters, read by the shadow map's compute rasterizer.
    storage(layout::BINDING_CASTERS),
    // The visible blades' previous control points (temporal anti-aliasing), read by
    // the grass's geometry stages.
    storage_in(layout::BINDING_MOTION, GEOMETRY_OR_RESOLVE),
    // The frame's colliders and their grid, built each frame that has colliders.
    storage(layout::BINDING_COLLIDERS),
    storage(layout::BINDING_COLLIDER_GRID),
    // The blades handed to the compute pass's collision pass, and its dispatch.
    storage(layout::BINDING_NEAR),
    // The cut table (`shared::sim::cut`), kept for the field's life.
    storage(layout::BINDING_CUTS),
    // The frame's questions, answers and contacts (`shared::query`).
    storage(layout::BINDING_QUERIES),
];

/// The fragment stages and the compute stage (the natural look shaded after the
/// draw, `passes::shade`).
const FRAGMENT_OR_SHADE: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::FRAGMENT.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

/// Stages `a` and `b`.
const fn either(a: Stage, b: Stage) -> Stage {
    Stage::from_raw(a.as_raw() | b.as_raw())
}
/// The vertex and fragment stages; the mesh and vertex stages.
const VERTEX_FRAGMENT: Stage = either(Stage::VERTEX, Stage::FRAGMENT);
const MESH_VERTEX: Stage = either(Stage::MESH_EXT, Stage::VERTEX);

/// Both tessellation stages, the mesh stage, and the fragment stage (the compute
/// rasterizer's resolve).
const GEOMETRY_OR_RESOLVE: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION.as_raw()
        | vk::ShaderStageFlags::MESH_EXT.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

/// Push-constant range of the pipeline layout: one range covering the compute push
/// blocks, the surface draw's model matrix and the throughput references' grid (a
/// vertex or a mesh stage), so every push names these stages.
pub const PUSH_CONSTANTS: (vk::ShaderStageFlags, u32) = (
    vk::ShaderStageFlags::from_raw(
        vk::ShaderStageFlags::COMPUTE.as_raw()
            | vk::ShaderStageFlags::VERTEX.as_raw()
            | vk::ShaderStageFlags::MESH_EXT.as_raw(),
    ),
    max(
        max(
            max(size_of::<SimulatePush>(), size_of::<ChunkPush>()),
            max(
                max(size_of::<HiZPush>(), size_of::<CopyPush>()),
                max(
                    size_of::<PreparePush>(),
                    max(size_of::<TilePush>(), size_of::<SelectPush>()),
                ),
            ),
        ),
        max(size_of::<SurfacePush>(), size_of::<ThroughputPush>()),
    ) as u32,
);

const fn max(a: usize, b: usize) -> usize {
    if a > b { a } else { b }
}

/// Where a field's blades come from.
#[derive(Copy, Clone, Debug)]
pub enum FieldBlades<'a> {
    /// These blades, uploaded once and simulated in place, and the painted maps'
    /// words (`shared::paint`; empty for none: the colour map is read on the GPU).
    Stored {
        /// The blades at rest.
        blades: &'a [Blade],
        /// The maps' words.
        paint: &'a [u32],
    },
    /// A tiled field: room for `simulated` pool blades, simulated in
    /// place, then for `far` blades generated every frame, `tile_words` words of
    /// tile lists (`layout::BINDING_TILES`), and the painted density map's words
    /// (`shared::paint`; empty for none).
    Tiled {
        /// The density map's words.
        paint: &'a [u32],
        /// Blades of the pool's slots.
        simulated: u32,
        /// Room for the far tiles' blades.
        far: u32,
        /// Words of the tile buffer.
        tile_words: u32,
        /// The ground's lowest and highest points (`TiledSpec::ground`).
        ground: (f32, f32),
        /// How the tiles mix their species (`TileParams::species`).
        species: shared::species::Mix,
    },
}

impl FieldBlades<'_> {
    /// Blades the field holds.
    pub fn count(&self) -> u64 {
        match *self {
            Self::Stored { blades, .. } => blades.len() as u64,
            Self::Tiled { simulated, far, .. } => u64::from(simulated) + u64::from(far),
        }
    }
}

/// The field's buffers and their bindings.
pub struct Field {
    /// Number of blades.
    pub blade_count: u32,
    /// Blades simulated: all of a stored field, the pool's of a tiled one.
    pub simulated: u32,
    /// A tiled field's tile words (`layout::BINDING_TILES`).
    pub tiles: Option<Buffer>,
    /// A tiled field's blade ids (`layout::BINDING_IDS`).
    pub ids: Option<Buffer>,
    /// The painted density map's words (`layout::BINDING_PAINT`).
    pub paint: Buffer,
    /// Blades per indirect draw command.
    pub chunk_size: u32,
    /// Number of indirect draw commands.
    pub chunk_count: u32,
    /// The blades, simulated in place.
    pub blades: Buffer,
    /// Collision strength η per blade, simulated in place.
    pub strengths: Buffer,
    /// This frame's visible blades' indices (`u32`), compacted; read by the grass
    /// draw's vertex stage.
    pub visible: Buffer,
    /// The counters (`layout::COUNTER_*`).
    pub counters: Buffer,
    /// One `VkDrawIndirectCommand` per chunk.
    pub draws: Buffer,
    /// The shadow casters' indices (`u32`), compacted: all of them, then from the
    /// blade count on the near cascade's; read by the shadow map's compute
    /// rasterizer.
    pub casters: Buffer,
    /// The mesh path's indirect draws: one mesh grid per strip length
    /// (`meshlet::BUCKETS`) and the spill's; then the shadow casters' dispatches
    /// ([`Field::caster_dispatches`]).
    pub mesh_draw: Buffer,
    /// The compute rasterizer's indirect dispatch and resolve draw
    /// (`layout::RASTER_DISPATCH`, `layout::RASTER_DRAW`, `layout::RASTER_PREPARE`).
    pub raster_args: Buffer,
    /// The mesh path's visible blades binned by strip length (`meshlet::StripBlade`):
    /// a slot per blade for the buckets, as many again for the blades that spill
    /// (`meshlet::BinLayout`).
    pub binned: Buffer,
    /// The visible blades as the natural look draws them (`clump::DressedBlade`).
    pub dressed: Buffer,
    /// Each blade's clump (`clump::Clump::pack`).
    pub clumps: Buffer,
    /// The visible blades' control points the frame before
    /// (`temporal::BladeMotion`), by visible slot (natural look) or blade index
    /// (paper look), written while temporal anti-aliasing is on.
    pub motion: Buffer,
    /// The frame's uniform block, updated by a transfer at the start of each frame.
    pub uniforms: Buffer,
    /// The frame's colliders (`sim::collide::Collider`), updated by a transfer at
    /// the start of each frame that has any.
    pub colliders: Buffer,
    /// The colliders' grid (`sim::grid`), cleared and built each frame that has
    /// colliders.
    pub collider_grid: Buffer,
    /// The blades handed to the compute pass's collision pass, after its indirect
    /// dispatch (`layout::BINDING_NEAR`).
    pub near: Buffer,
    /// The cut table (`shared::sim::cut`: `CUT_SLOTS` slots, 4 MiB), empty at first.
    pub cuts: Buffer,
    /// The frame's questions, answers and contacts (`shared::query::QUERY_WORDS`),
    /// uploaded at each frame's start.
    pub queries: Buffer,
    /// How far a blade reaches from its root (`sim::grid::ColliderGrid::reach`): the
    /// tallest blade times `sim::grid::REACH_MARGIN`; a tiled field's tallest is the
    /// tallest a tile grows, twice that under a painted height map (which doubles at
    /// most).
    pub reach: f32,
    /// A blade may be of a species other than grass (`GrassParams::mixed`).
    pub mixed: bool,
    /// The lowest and highest height of the roots (`FrameFacts::roots`): a stored
    /// field's own, a tiled field's ground's with a unit to spare (its blades stand on
    /// the analytic ground its mesh follows within a fifth of a unit).
    pub roots: Option<(f32, f32)>,
    /// The occluders' depth pyramid (`shared::hiz`), sized for the target.
    pub pyramid: Buffer,
    /// Descriptor set over the buffers above.
    pub descriptors: DescriptorSet,
    /// Pipeline layout shared by every pipeline.
    pub layout: PipelineLayout,
}

impl Field {
    /// Uploads the blades (or makes room for a tiled field's) and creates the rest,
    /// checking the device's limits first.
    pub fn new(ctx: &Arc<Context>, pool: &CommandPool, source: FieldBlades) -> Result<Self> {
        Self::check_limits(ctx, source.count())?;
        let count = source.count() as u32;
        let chunk_size = blades_per_chunk();
        let chunk_count = count.div_ceil(chunk_size);

        use vk::BufferUsageFlags as U;
        let device_buffer =
            |name, size, usage| Buffer::new(ctx, name, size, usage, MemoryLocation::GpuOnly);
        let blade_usage = U::STORAGE_BUFFER | U::TRANSFER_SRC;
        let no_map = [0u32; shared::world::paint::HEADER_WORDS];
        let paint_words = match source {
            FieldBlades::Tiled { paint, .. } | FieldBlades::Stored { paint, .. }
                if !paint.is_empty() =>
            {
                paint
            }
            _ => &no_map[..],
        };
        let paint = Buffer::upload(ctx, pool, "painted maps", paint_words, U::STORAGE_BUFFER)?;
        let (reach, mixed) = match source {
            FieldBlades::Stored { blades, .. } => stored_growth(blades),
            FieldBlades::Tiled { paint, species, .. } => tiled_growth(paint, species),
        };
        let roots = match source {
            FieldBlades::Stored { blades, .. } => root_range(blades),
            FieldBlades::Tiled { ground, .. } => Some((ground.0 - 1.0, ground.1 + 1.0)),
        };
        let (blade_buffer, simulated, tiles, ids) = match source {
            FieldBlades::Stored { blades, .. } => {
                let buffer = Buffer::upload(ctx, pool, "blades", blades, blade_usage)?;
                (buffer, count, None, None)
            }
            FieldBlades::Tiled {
                simulated,
                tile_words,
                ..
            } => {
                let size = u64::from(count) * size_of::<Blade>() as u64;
                let blades = device_buffer("blades", size, blade_usage | U::TRANSFER_DST)?;
                let ids = device_buffer(
                    "blade ids",
                    u64::from(count) * 4 * layout::IDS_WORDS as u64,
                    U::STORAGE_BUFFER | U::TRANSFER_SRC,
                )?;
                let tiles = device_buffer(
                    "tiles",
                    u64::from(tile_words) * 4,
                    U::STORAGE_BUFFER | U::INDIRECT_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
                )?;
                // Every slot empty (width 0) until a tile fills it.
                pool.one_shot(|rec| rec.fill_buffer(blades.buffer, 0))?;
                (blades, simulated, Some(tiles), Some(ids))
            }
        };
        let strengths = device_buffer(
            "collision strengths",
            u64::from(count) * 4,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
        )?;
        let visible = device_buffer(
            "visible",
            u64::from(count) * 4,
            U::STORAGE_BUFFER | U::TRANSFER_SRC,
        )?;
        // All of them, then the near cascade's.
        // Read back by the test of the shadow map's grass.
        let casters = device_buffer(
            "shadow casters",
            u64::from(count) * 8,
            U::STORAGE_BUFFER | U::TRANSFER_SRC,
        )?;
        let dressed = device_buffer(
            "dressed blades",
            u64::from(count) * size_of::<DressedBlade>() as u64,
            U::STORAGE_BUFFER,
        )?;
        // Read back, as the casters are, by the test of the shadow map's grass.
        let clumps = device_buffer(
            "clumps",
            u64::from(count) * 16,
            U::STORAGE_BUFFER | U::TRANSFER_SRC,
        )?;
        let motion = device_buffer(
            "previous control points",
            u64::from(count) * size_of::<BladeMotion>() as u64,
            // Read back by the test of what it holds.
            U::STORAGE_BUFFER | U::TRANSFER_SRC,
        )?;
        let counters = device_buffer(
            "counters",
            (counters::COUNTER_WORDS * 4) as u64,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
        )?;
        // No layout of the binned list yet: the first frame's blades all spill.
        pool.one_shot(|rec| rec.fill_buffer(counters.buffer, 0))?;
        let draws = device_buffer(
            "draws",
            u64::from(chunk_count) * size_of::<vk::DrawIndirectCommand>() as u64,
            U::STORAGE_BUFFER | U::INDIRECT_BUFFER,
        )?;
        // One grid per bucket and the spill's, then the shadow casters' dispatch and
        // the near ones'.
        let mesh_draw = device_buffer(
            "mesh draws",
            u64::from(MESH_DRAWS + 2) * size_of::<vk::DrawMeshTasksIndirectCommandEXT>() as u64,
            U::STORAGE_BUFFER | U::INDIRECT_BUFFER,
        )?;
        let raster_args = device_buffer(
            "raster arguments",
            (layout::RASTER_ARGS_WORDS * 4) as u64,
            U::STORAGE_BUFFER | U::INDIRECT_BUFFER,
        )?;
        let binned = device_buffer(
            "binned blades",
            2 * u64::from(count) * size_of::<StripBlade>() as u64,
            U::STORAGE_BUFFER | U::TRANSFER_SRC,
        )?;
        let uniforms = device_buffer(
            "uniforms",
            size_of::<FrameUniforms>() as u64,
            U::STORAGE_BUFFER | U::TRANSFER_DST,
        )?;
        let colliders = device_buffer(
            "colliders",
            (MAX_COLLIDERS * size_of::<Collider>()) as u64,
            U::STORAGE_BUFFER | U::TRANSFER_DST,
        )?;
        let near_size = (layout::NEAR_LIST as u64 + u64::from(simulated)) * 4;
        let near_usage = U::STORAGE_BUFFER | U::INDIRECT_BUFFER | U::TRANSFER_DST;
        let near = device_buffer("blades near colliders", near_size, near_usage)?;
        let collider_grid = device_buffer(
            "collider grid",
            ColliderGrid::largest().words() as u64 * 4,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
        )?;
        let cuts = device_buffer(
            "cut table",
            u64::from(CUT_SLOTS) * CUT_WORDS as u64 * 4,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
        )?;

        let queries = device_buffer(
            "queries",
            (shared::query::QUERY_WORDS * 4) as u64,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
        )?;
        // A placeholder until a frame sizes it: no occlusion test without a target.
        let pyramid = Self::pyramid_buffer(ctx, 1)?;

        pool.one_shot(|rec| {
            rec.fill_buffer(strengths.buffer, 0);
            rec.fill_buffer(cuts.buffer, sim::cut::NO_CELL);
        })?;

        let descriptors = DescriptorSet::new(ctx, &BINDINGS)?;
        // In the order of BINDINGS.
        let bound = [
            &uniforms,
            &blade_buffer,
            &visible,
            &counters,
            &draws,
            &strengths,
            &pyramid,
            // The bandwidth reference binds its own while it runs.
            &visible,
        ];
        for (spec, buffer) in BINDINGS.iter().zip(bound) {
            descriptors.write_buffer(spec.binding, spec.ty, buffer.buffer);
        }
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        descriptors.write_buffer(layout::BINDING_DRESSED, storage, dressed.buffer);
        descriptors.write_buffer(layout::BINDING_CASTERS, storage, casters.buffer);
        descriptors.write_buffer(layout::BINDING_CLUMPS, storage, clumps.buffer);
        descriptors.write_buffer(layout::BINDING_MOTION, storage, motion.buffer);
        descriptors.write_buffer(layout::BINDING_COLLIDERS, storage, colliders.buffer);
        let grid = collider_grid.buffer;
        descriptors.write_buffer(layout::BINDING_COLLIDER_GRID, storage, grid);
        descriptors.write_buffer(layout::BINDING_NEAR, storage, near.buffer);
        descriptors.write_buffer(layout::BINDING_CUTS, storage, cuts.buffer);
        descriptors.write_buffer(layout::BINDING_QUERIES, storage, queries.buffer);
        descriptors.write_buffer(layout::BINDING_MESH_DRAW, storage, mesh_draw.buffer);
        descriptors.write_buffer(layout::BINDING_RASTER_ARGS, storage, raster_args.buffer);
        descriptors.write_buffer(layout::BINDING_BINNED, storage, binned.buffer);
        // A placeholder until the compute rasterizer sizes its own for the target.
        descriptors.write_buffer(layout::BINDING_VISIBILITY, storage, visible.buffer);
        descriptors.write_buffer(layout::BINDING_HARDWARE_DEPTH, storage, visible.buffer);
        let (tile_words, blade_ids) = match (&tiles, &ids) {
            (Some(t), Some(i)) => (t.buffer, i.buffer),
            // Never read in a stored field (`GrassParams::tiled` is 0).
            _ => (visible.buffer, visible.buffer),
        };
        descriptors.write_buffer(layout::BINDING_TILES, storage, tile_words);
        descriptors.write_buffer(layout::BINDING_IDS, storage, blade_ids);
        descriptors.write_buffer(layout::BINDING_PAINT, storage, paint.buffer);
        let layout = PipelineLayout::new(ctx, descriptors.layout, PUSH_CONSTANTS)?;

        Ok(Self {
            blade_count: count,
            simulated,
            tiles,
            ids,
            paint,
            chunk_size,
            chunk_count,
            blades: blade_buffer,
            strengths,
            visible,
            counters,
            draws,
            casters,
            mesh_draw,
            raster_args,
            binned,
            dressed,
            clumps,
            motion,
            uniforms,
            colliders,
            collider_grid,
            near,
            cuts,
            queries,
            reach,
            mixed,
            roots,
            pyramid,
            descriptors,
            layout,
        })
    }

    /// Where in the mesh draws buffer the shadow casters' dispatches are (the near
    /// cascade's, then all casters' for the far one): after the grass's draws. A mesh
    /// grid and a dispatch are the same three words.
    pub fn caster_dispatches(&self) -> [u64; 2] {
        let size = size_of::<vk::DrawMeshTasksIndirectCommandEXT>() as u64;
        [
            u64::from(MESH_DRAWS + 1) * size,
            u64::from(MESH_DRAWS) * size,
        ]
    }
}

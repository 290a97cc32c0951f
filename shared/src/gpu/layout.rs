//! The interface between the runner and the shaders: descriptor set/binding numbers,
//! the uniform block and the push constants. Both sides use these definitions, and a
//! test compares them with what the compiled SPIR-V declares.

use crate::camera::CameraParams;
use crate::cull::blade::CullParams;
use crate::cull::hiz::HiZLayout;
use crate::cull::lod::LodParams;
use crate::draw::look::LookParams;
use crate::draw::raster::RasterParams;
use crate::draw::shade::Light;
use crate::draw::temporal::TemporalParams;
use crate::sim::grid::ColliderGrid;
use crate::sim::impulse::{Impulse, MAX_IMPULSES};
use crate::sim::simulate::Environment;
use crate::world::tiles::TileParams;
use spirv_std::glam::{IVec2, Mat4, UVec2, UVec3, UVec4, Vec4};

/// Threads per workgroup of the per-blade compute passes but the cull
/// ([`CULL_WORKGROUP`]).
pub const SIMULATE_WORKGROUP: u32 = 64;
/// Threads per workgroup of the simulate-and-cull pass and the mesh path's binning,
/// each of whose workgroups counts its blades in workgroup memory and takes its places
/// with one device atomic per counter: at 4 M blades on the NVIDIA H100, 128 threads
/// took simulate + cull from 0.349 to 0.325 ms (the paper look) and 0.529 to 0.486
/// (the natural look) against 64; 256 took 0.351 and 0.526.
pub const CULL_WORKGROUP: u32 = 128;
/// Threads per workgroup of the pass writing one draw command per chunk.
pub const CHUNK_WORKGROUP: u32 = 64;
/// Threads per workgroup of the bandwidth reference (a plain copy of the blades).
pub const COPY_WORKGROUP: u32 = 256;
/// Threads per workgroup (8 × 8) of the temporal resolve, one per pixel.
pub const TEMPORAL_WORKGROUP: u32 = 8;
/// Threads per workgroup (8 × 8) of the depth-pyramid reduction.
pub const HIZ_WORKGROUP: u32 = 8;

/// The flat thread index of a dispatch of (x, y, 1) workgroups of `workgroup_size`
/// threads: x alone cannot hold 2^22 blades (65,535 workgroups at most on many
/// devices), so larger dispatches spill into y.
pub fn flat_index(global_id: UVec3, workgroups: UVec3, workgroup_size: u32) -> u32 {
    global_id.x + global_id.y * workgroups.x * workgroup_size
}

/// Specialisation constant of the simulate-and-cull pass: its wind field (one of
/// `sim::wind::WIND_*`). Each field gets its own pipeline, made when a frame first
/// needs it, so the pass's compiled code holds one field: a branch to a field the
/// frame never takes still costs the pass its registers (the turbulent field's noise
/// made every field's pass 0.018 ms slower at 4 M blades on the NVIDIA H100).
pub const SPEC_WIND_FIELD: u32 = 0;
/// [`SPEC_WIND_FIELD`]: the frame's field (`Environment::wind_kind`), every field's
/// code in one pipeline. Software devices take it: there a pipeline's first compile
/// costs 8 to 24 s (lavapipe, LLVM 15), five times over for one field each.
pub const WIND_FROM_FRAME: u32 = u32::MAX;
/// Specialisation constant of the simulate-and-cull pass: 1 on the mesh path, whose
/// pass also bins the visible blades by strip length (`draw::meshlet`), 0 on the
/// tessellation path, whose pipeline then holds none of that code (the binning's
/// registers made the tessellation path's pass 0.009 ms slower at 4 M blades on the
/// NVIDIA H100). It must agree with the frame's `GrassParams::pipeline`.
pub const SPEC_MESH_PATH: u32 = 1;
/// Specialisation constant of the simulate-and-cull pass: 1 where the frame has wind
/// impulses (`Environment::impulses` above 0), 0 where it has none, whose pipeline
/// then holds none of their code (with it compiled in, the pass took 0.013 ms more at
/// 4 M blades on the NVIDIA H100, no impulse blowing).
pub const SPEC_IMPULSES: u32 = 2;
/// Specialisation constant of the simulate-and-cull pass: what it does with the
/// frame's colliders (`Environment::colliders`): [`COLLIDERS_NONE`] where it has
/// none, else [`COLLIDERS_HAND_OVER`] for the pass over every blade and
/// [`COLLIDERS_NEAR`] for its collision pass. Only the collision pass holds the
/// collisions' code: in the pass over every blade it took the NVIDIA H100 from 64
/// registers to 96, and simulate + cull at 4 M blades from 0.237 ms to 0.401 with a
/// single collider in the frame.
pub const SPEC_COLLIDERS: u32 = 3;
/// [`SPEC_COLLIDERS`]: no colliders; every blade simulated without them.
pub const COLLIDERS_NONE: u32 = 0;
/// [`SPEC_COLLIDERS`]: the pass over every blade simulates each blade without the
/// colliders and hands one they may have touched (`sim::grid::Nearby::
/// may_have_touched`) to the collision pass ([`BINDING_NEAR`],
/// `counters::COUNTER_NEAR`).
pub const COLLIDERS_HAND_OVER: u32 = 1;
/// [`SPEC_COLLIDERS`]: the collision pass, a thread a handed blade (an indirect
/// dispatch, [`NEAR_DISPATCH`]): the same steps and tests, with the colliders.
pub const COLLIDERS_NEAR: u32 = 2;
/// [`SPEC_COLLIDERS`]: [`COLLIDERS_HAND_OVER`] with the roots looked up: in a frame
/// where a cut may be growing back (`sim::simulate::Environment::cutting`), a blade a
/// cutter reaches (its root's slot, `sim::grid::Nearby::reaches`) is handed over
/// before its steps, and in a frame the watch is not for (`sim::simulate::watches`),
/// a blade any collider reaches. Only
/// this pipeline holds that look-up: without it the other has no local memory on the
/// NVIDIA H200 (natural look, 1,024 walkers, 4 M blades: 0.468 ms against 0.475).
pub const COLLIDERS_HAND_OVER_ROOTS: u32 = 3;

/// Whether a pipeline made for `colliders` ([`SPEC_COLLIDERS`]) is the pass over
/// every blade that hands blades to the collision pass.
pub fn hands_over(colliders: u32) -> bool {
    colliders == COLLIDERS_HAND_OVER || colliders == COLLIDERS_HAND_OVER_ROOTS
}
/// Specialisation constant of the simulate-and-cull pass: 1 where the frame's gravity
/// pulls towards a centre (`Environment::centre_blend` above 0), 0 where it does not,
/// whose pipeline then holds none of that code (0.004 ms of the paper look's pass at 4
/// M blades on the NVIDIA H100, 0.021 of the natural look's).
pub const SPEC_GRAVITY_CENTRE: u32 = 4;
/// Specialisation constant of the simulate-and-cull pass: 1 where the field is tiled
/// (`GrassParams::tiled`), 0 where it is stored, whose pipeline then holds none of the
/// tiled field's code (0.014 ms of the paper look's pass on the mesh path at 4 M
/// blades on the NVIDIA H100, 0.032 of the natural look's).
pub const SPEC_TILED: u32 = 5;
/// Specialisation constant of the simulate-and-cull pass: 1 where its blades take
/// their places in the lists through a workgroup's tally (one device atomic a counter
/// a workgroup, between workgroup barriers), 0 where each takes its place from the
/// device counter and the pass has no barrier. 0 on software devices only: lavapipe
/// runs a workgroup's invocations as coroutines that switch at every barrier, which
/// made the pass three times slower there (docs/culling.md, "Counters"). GPUs keep
/// the tally: one device atomic a counter a workgroup rather than one a blade.
pub const SPEC_WORKGROUP_TALLY: u32 = 6;

/// Descriptor set of every pipeline (each pipeline has exactly one).
pub const SET: u32 = 0;
/// Binding of [`FrameUniforms`], in every pipeline: a read-only storage buffer rather
/// than a uniform buffer, because lavapipe (Mesa 22.3) keeps host memory for every
/// new set of uniform values its shaders see (about 0.7 MB a frame), and the frame's
/// values change every frame. The layout is the same in both (vec4-aligned fields).
pub const BINDING_UNIFORMS: u32 = 0;
/// Binding of the blade buffer (storage): simulated in place by the compute pass,
/// read by the grass draw's tessellation stages.
pub const BINDING_BLADES: u32 = 1;
/// Binding of the visible blades' indices, compacted (storage, `u32`: written by the
/// compute pass, read by the grass draw's vertex stage).
pub const BINDING_VISIBLE: u32 = 2;
/// Binding of the counters (storage, `u32` array; [`COUNTER_VISIBLE`](crate::gpu::counters::COUNTER_VISIBLE) first).
pub const BINDING_COUNTERS: u32 = 3;
/// Binding of the indirect draw commands (storage): one per chunk of the visible
/// list, then the shadow casters' ([`BINDING_CASTERS`]).
pub const BINDING_DRAWS: u32 = 4;
/// Binding of the per-blade collision strength η (storage, `f32` per blade): the
/// paper's "force map", kept per blade.
pub const BINDING_STRENGTH: u32 = 5;
/// Binding of the occluders' depth pyramid (storage, `f32`, laid out by
/// [`HiZLayout`]), built and read by the compute pipelines.
pub const BINDING_PYRAMID: u32 = 6;
/// Binding of the bandwidth reference's destination (storage, one blade per blade),
/// bound only while the reference runs.
pub const BINDING_SCRATCH: u32 = 7;

/// Binding of the sun's shadow map (sampled depth image), read by the lit fragment
/// stages of the natural look.
pub const BINDING_SHADOW_MAP: u32 = 8;
/// Binding of the shadow map's comparison sampler (the depth test and the bilinear
/// weights of `look::shadow_factor` in the texture unit, one fetch).
pub const BINDING_SHADOW_SAMPLER: u32 = 10;

/// Binding of the visible blades as the natural look draws them (storage,
/// `look::DressedBlade` per slot of the visible list): written by the compute pass,
/// read by the natural look's grass stages.
pub const BINDING_DRESSED: u32 = 9;

/// Binding of the blades' clumps (storage, `vec4` per blade, `look::Clump::pack`):
/// written by the clump pass when the field, the seed or the clump size changes, read
/// by the compute pass.
pub const BINDING_CLUMPS: u32 = 11;
/// Binding of the mesh path's indirect draws (storage and indirect, one
/// `VkDrawMeshTasksIndirectCommandEXT` per draw: `meshlet::mesh_grid` of each
/// bucket and of the spill, `meshlet::MESH_DRAWS`, then the shadow casters'
/// dispatches: `shadow::caster_grid` of all casters, then of the near cascade's, the
/// same three words as a dispatch's), written by the compute pass.
pub const BINDING_MESH_DRAW: u32 = 12;
/// Binding of the visible blades binned by strip length (storage,
/// `meshlet::StripBlade` per slot, twice the field's blades: `meshlet::BinLayout`):
/// written by the compute pass, read by the mesh stages.
pub const BINDING_BINNED: u32 = 14;
/// Binding of the shadow map's grass depth (storage, one `u32` word a texel of the
/// map's two cascades, rows of twice the cascade's side: `f32` depth bits): the
/// casters drawn by compute threads (`look::shadow_raster`), then copied into the
/// map's depth image.
pub const BINDING_SHADOW_DEPTH: u32 = 13;
/// Binding of the compute rasterizer's visibility buffer (storage, `u64` per pixel of
/// the target, `raster::pack`): written by the compute pass, read by the resolve.
pub const BINDING_VISIBILITY: u32 = 15;
/// Binding of the hardware's depth for the compute rasterizer (storage, `f32` per
/// pixel of the target, row by row): the grass and ground the fixed-function pipeline
/// drew, copied from [`BINDING_DEPTH_IMAGE`] (or the farthest sample of
/// [`BINDING_DEPTH_IMAGE_MS`]) once they are done, so a far blade's pixel behind them
/// costs a load instead of an atomic.
pub const BINDING_HARDWARE_DEPTH: u32 = 17;
/// Binding of the single-sample depth target as a sampled image, read by texel by the
/// rasterizer's preparation, which copies it into [`BINDING_HARDWARE_DEPTH`] (SPIR-V
/// for Vulkan lets no closure or struct hold an image, and the rasterizer's pixels
/// come through a closure; a transfer copy cost the NVIDIA H100 0.1 ms at 1920x1080).
pub const BINDING_DEPTH_IMAGE: u32 = 18;
/// Binding of the multisampled depth target (MSAA) as a sampled image, read sample by
/// sample by the rasterizer's preparation, which keeps the farthest: a far blade is
/// hidden in that pixel only where every sample hides it (the resolve's depth test
/// decides the rest per sample). Read in place, where a `MAX` depth resolve, which
/// lavapipe lacks, would have left CI without the path.
pub const BINDING_DEPTH_IMAGE_MS: u32 = 19;
/// Threads of the rasterizer's preparation's workgroups along x and y (one per
/// pixel).
pub const PREPARE_WORKGROUP: u32 = 8;

/// Binding of the tiled field's tile words (storage and indirect, `u32`):
/// the far blades' generation dispatch at [`TILES_DISPATCH`], the pool's tiles from
/// [`TILES_POOL`] (x, z each; written by the host every frame), and the far tiles in
/// view from [`TILES_LIST`] (x, z, first blade, blade count each), written by
/// `compute::select_far_tiles`.
pub const BINDING_TILES: u32 = 20;
/// Binding of the blades' names (storage, `u32` per blade, `tiles::blade_id`) in a
/// tiled field: what the cull's buckets and the look's hashes read in place of the
/// index, which changes as a tile moves between the far list and the pool. A stored
/// field reads its index and binds a placeholder.
pub const BINDING_IDS: u32 = 21;
/// Words a blade has in the ids buffer: its name (`tiles::blade_id`) and where it
/// reads the painted maps (`tiles::pack_map_point`).
pub const IDS_WORDS: usize = 2;
/// Binding of the painted density map (storage, `u32` words: `paint`'s layout),
/// read where a tiled field's blades grow; a map of no texels in a field without one.
pub const BINDING_PAINT: u32 = 22;
/// Binding of the shadow casters' lists (storage, `u32` blade indices, twice as many
/// as the field's blades): the blades inside the sun's map and within the casters'
/// reach of the camera from the start, those of them inside the near cascade from
/// the field's blade count on; written by the compute pass and read by the shadow
/// map's compute rasterizer (`look::shadow_raster`), so the map does not depend on
/// where the camera looks. Their dispatches (far cascade, then near) follow the mesh
/// draws ([`BINDING_MESH_DRAW`]).
pub const BINDING_CASTERS: u32 = 23;
/// Binding of the visible blades' previous control points (storage,
/// `draw::temporal::BladeMotion`, a slot per slot of the visible list): written by the
/// compute pass while temporal anti-aliasing is on, read by the grass's geometry
/// stages for each vertex's motion.
pub const BINDING_MOTION: u32 = 24;
/// Binding of the frame's colliders (storage, `sim::collide::Collider`, the first
/// `Environment::colliders` used): written by the renderer each frame that has any,
/// read by the grid's build and the compute pass.
pub const BINDING_COLLIDERS: u32 = 25;
/// Binding of the colliders' grid (storage, `sim::grid::GRID_SLOTS` slots of
/// `GRID_WORDS` words, then as many of the watch's of `WATCH_WORDS`): cleared, then
/// built on the GPU each frame that has colliders (`compute::grid`), read by the
/// compute pass.
pub const BINDING_COLLIDER_GRID: u32 = 26;
/// Binding of the blades handed to the collision pass (storage): its indirect
/// dispatch at [`NEAR_DISPATCH`], then the blades' indices from [`NEAR_LIST`].
pub const BINDING_NEAR: u32 = 27;
/// Binding of the cut table (storage, `sim::cut::CUT_SLOTS` slots of
/// `sim::cut::CUT_WORDS` words): a cut left pending by the collision pass and
/// committed after it, read by the compute pass and the far tiles' generation while
/// `Environment::cutting` is set.
pub const BINDING_CUTS: u32 = 28;
/// Binding of the query buffer (storage, `u32` words laid out by `query::ASKED`,
/// `query::CONTACTS`, `query::ANSWERS` and `query::QUESTIONS`): the frame's
/// questions, uploaded with the answers cleared at its start; the colliders touching
/// the collision pass's blades are marked after it, and the query pass adds each
/// blade's part to each answer.
pub const BINDING_QUERIES: u32 = 29;
/// Word of the collision pass's `VkDispatchIndirectCommand` in [`BINDING_NEAR`]:
/// (0, 0, 1) at the frame's start, grown by the pass over every blade
/// ([`near_groups`]).
pub const NEAR_DISPATCH: usize = 0;
/// Workgroups along x every Vulkan device can dispatch.
pub const MAX_GROUPS_X: u32 = 65535;

/// The collision pass's dispatch (x, y) that holds the handed blade at `place` of
/// its list: its workgroups of [`CULL_WORKGROUP`] up to that blade's, at most
/// [`MAX_GROUPS_X`] along x and spilling into y as [`flat_index`] reads them. Each
/// grows only with `place`, so the first blade of each of the pass's workgroups
/// takes the maximum of each word with its own, and the last leaves the dispatch
/// every handed blade needs, with no pass to count them first.
pub fn near_groups(place: u32) -> (u32, u32) {
    let groups = place / CULL_WORKGROUP + 1;
    (groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X))
}
/// First word of the handed blades' indices in [`BINDING_NEAR`].
pub const NEAR_LIST: usize = 4;
/// Word of the far blades' generation's `VkDispatchIndirectCommand` (one workgroup
/// per far tile in view).
pub const TILES_DISPATCH: usize = 0;
/// First word of the pool's tiles: (x, z, fade) per slot ([`POOL_WORDS`]),
/// [`EMPTY_SLOT`] in x where the slot holds none; the fade (`f32` bits, 0..1) is how
/// far a tile nobody needs has gone back to its far pose (`tiles::fade_to_far`).
pub const TILES_POOL: usize = 4;
/// Words per pool slot in the table.
pub const POOL_WORDS: usize = 3;
/// Slots the pool's table can hold.
pub const MAX_POOL_TILES: usize = 1024;
/// x of a pool slot that holds no tile.
pub const EMPTY_SLOT: i32 = i32::MIN;
/// First word of the far tiles in view: (x, z, first blade, blade count) per tile.
pub const TILES_LIST: usize = TILES_POOL + POOL_WORDS * MAX_POOL_TILES;
/// Words per far tile in the list.
pub const TILE_WORDS: usize = 4;
/// Threads per workgroup of the far blades' generation (one workgroup per tile).
pub const GENERATE_WORKGROUP: u32 = 256;

/// What the GPU's tile selection pushes: the camera, the square of candidate tiles
/// (`first`, `count` along x and z), the layout, the ground's height range and the
/// reach (`tiles::tile_in_view`), read by `compute::select_tiles`.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SelectPush {
    /// The camera's view-projection.
    pub view_proj: Mat4,
    /// The camera's position (xyz) and the reach (w).
    pub camera: Vec4,
    /// The first candidate tile.
    pub first: IVec2,
    /// Candidates along x and z.
    pub count: UVec2,
    /// The ground's lowest and highest points, and padding.
    pub ground: Vec4,
    /// The world's tiles.
    pub params: TileParams,
    /// The tiled frame's far generation (`compute::select_far_tiles`): the pool's
    /// slots (x), the far blades the field holds (y), and the first far blade's index
    /// (z, after the pool's); unused by `compute::select_tiles`.
    pub far: UVec4,
}

/// What the GPU's tile generation pushes (`compute::generate_tile`, `tiles::tile_blade`):
/// the layout, the tile and the camera.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TilePush {
    /// The world's tiles.
    pub params: TileParams,
    /// The tile generated.
    pub tile: IVec2,
    /// The first blade's index in the field (`compute::generate_pool_tile`; unused by
    /// `compute::generate_tile`), and padding to the camera's 16-byte alignment.
    pub slot: UVec2,
    /// The camera's position (w unused).
    pub camera: Vec4,
}

/// Push constants of the rasterizer's preparation under MSAA.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PreparePush {
    /// Samples per pixel of the multisampled depth target.
    pub samples: u32,
}
/// Binding of the compute rasterizer's indirect arguments (storage and indirect, `u32`
/// words: its dispatch at [`RASTER_DISPATCH`], the resolve's draw at
/// [`RASTER_DRAW`]), written by the compute pass from the far count, so a frame
/// without far blades neither rasterizes nor resolves anything.
pub const BINDING_RASTER_ARGS: u32 = 16;
/// Word of the rasterizer's `VkDispatchIndirectCommand` in its arguments.
pub const RASTER_DISPATCH: usize = 0;
/// Word of the resolve's `VkDrawIndirectCommand` in the rasterizer's arguments.
pub const RASTER_DRAW: usize = 4;
/// Word of the rasterizer's preparation's `VkDispatchIndirectCommand` (the hardware's
/// depth copied, the visibility buffer cleared: `raster::prepare_dispatch`).
pub const RASTER_PREPARE: usize = 8;
/// Words of the rasterizer's arguments.
pub const RASTER_ARGS_WORDS: usize = 12;

/// The field and how its blades are drawn.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GrassParams {
    /// Blades in the field.
    pub blades: u32,
    /// Blade shape, one of `shape::SHAPE_*` (paper section 6.1).
    pub shape: u32,
    /// Tip start k of the triangle-tip shape, 0 (root) to 1 (tip).
    pub tip_start: f32,
    /// Grass view, one of `shade::VIEW_*`.
    pub view: u32,
    /// How the grass is drawn, [`PIPELINE_TESS`] or [`PIPELINE_MESH`] (read by the
    /// renderer, which picks its pipelines from it).
    pub pipeline: u32,
    /// Blades below this index are simulated (all of a stored field; a tiled field's
    /// pool, filled by the renderer).
    pub simulated: u32,
    /// 1 in a tiled field (the renderer's): blades from `simulated` on are the far
    /// tiles', as many as [`COUNTER_TILE_BLADES`](crate::gpu::counters::COUNTER_TILE_BLADES) says, generated this frame and not
    /// simulated, and every blade's name is at [`BINDING_IDS`].
    pub tiled: u32,
    /// 1 where a blade may be of a species other than grass (`species`): the
    /// geometry stages then read each blade's species and draw it in its own shape;
    /// 0: every blade is grass, in the field's shape (`shape::row_point`).
    pub mixed: u32,
}

/// Grass drawn through the tessellator: one patch per blade.
pub const PIPELINE_TESS: u32 = 0;
/// Grass drawn by mesh stages: blade strips, binned by length in the compute pass.
pub const PIPELINE_MESH: u32 = 1;

/// Per-frame values, one block read by every stage (a read-only storage buffer, std430
/// layout: every member that holds a vector starts on 16 bytes, and the SPIR-V
/// reflection test compares each offset with this struct's). Built in one place,
/// `settings::Settings::uniforms`, beside the frame's plan (`plan::FramePlan`); the
/// renderer fills in `hiz`, a tiled field's part, the time and the target's size.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    /// The camera.
    pub camera: CameraParams,
    /// The sun.
    pub light: Light,
    /// Gravity, wind, recovery and collision decay (paper section 5).
    pub forces: Environment,
    /// The colliders' grid (`sim::grid`); the first `forces.colliders` of the
    /// collider buffer ([`BINDING_COLLIDERS`]) are used.
    pub collider_grid: ColliderGrid,
    /// Wind impulses (`sim::impulse`); the first `forces.impulses` are used.
    pub impulses: [Impulse; MAX_IMPULSES],
    /// This frame's occluder depth pyramid; empty when there is none.
    pub hiz: HiZLayout,
    /// Level of detail.
    pub lod: LodParams,
    /// The field and how it is drawn.
    pub grass: GrassParams,
    /// The culling tests and their thresholds (paper section 4.2).
    pub cull: CullParams,
    /// The natural look: shadows, fog, clumps.
    pub look: LookParams,
    /// The compute rasterizer of far blades; the renderer fills in the target's size.
    pub raster: RasterParams,
    /// Temporal anti-aliasing: the jitter and the previous frame's camera.
    pub temporal: TemporalParams,
}

/// Push constants of the simulate-and-cull dispatch: which fixed steps to run.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SimulatePush {
    /// Index of the first fixed step of this frame.
    pub first_step: u32,
    /// Number of fixed steps this frame.
    pub steps: u32,
    /// Padding to the tiles' 8-byte alignment.
    pub pad: UVec2,
    /// A tiled field's layout (its pool's blades thin with distance as the far ones:
    /// `tiles::drawn_width`); unused in a stored field.
    pub tiles: TileParams,
}

/// Push constants of one level of the depth-pyramid reduction.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct HiZPush {
    /// The level written (≥ 1); it reads the level below.
    pub level: u32,
}

/// Push constants of the overlay draw: the screen size in egui points.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct OverlayPush {
    /// Width and height in points.
    pub screen: spirv_std::glam::Vec2,
}

impl OverlayPush {
    /// An overlay position in points (origin top left, y down) in clip space.
    pub fn to_clip(&self, points: spirv_std::glam::Vec2) -> Vec4 {
        (2.0 * points / self.screen - spirv_std::glam::Vec2::ONE)
            .extend(0.0)
            .extend(1.0)
    }
}

/// One vertex of a drawn surface (ground meshes and the collider ball).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SurfaceVertex {
    /// Position (xyz) and material (w, one of `shade::MATERIAL_*`).
    pub position: Vec4,
    /// Unit normal (xyz).
    pub normal: Vec4,
}

/// Push constants of the surface draws: the model matrix (identity for the ground,
/// placement and size for the collider ball, the camera's place for the valley's
/// grid) and whether the vertices are a terrain grid.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SurfacePush {
    /// Model to world.
    pub model: Mat4,
    /// x: [`GROUND_GRID`] where the vertices are the valley's ground grid around the
    /// camera (`terrain::grid_offset`: each placed on the valley's height field, x and
    /// z clamped to ± y, the world's half extent), else [`GROUND_MESH`]; z, w unused.
    pub terrain: Vec4,
}

/// A surface draw of mesh vertices as they are.
pub const GROUND_MESH: f32 = 0.0;
/// A surface draw of the valley's ground grid (`SurfacePush::terrain`).
pub const GROUND_GRID: f32 = 1.0;

/// Push constants of the triangle-throughput reference: the tessellation level of
/// every patch and the grid of screen cells the patches are laid on.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ThroughputPush {
    /// Tessellation level along each patch (odd: that many segments, two triangles
    /// each).
    pub level: f32,
    /// Cells across the screen.
    pub columns: u32,
    /// Cells down the screen.
    pub rows: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}

/// Push constants of the bandwidth reference: `vec4`s to copy (4 per blade).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CopyPush {
    /// Number of `vec4`.
    pub count: u32,
}

/// The tone map's grid of cells over the screen (columns, rows): the sky and the
/// meadow beyond the field are evaluated at the cells' corners and interpolated, the
/// sun disc and the tone map per pixel.
pub const TONEMAP_GRID: (u32, u32) = (32, 18);

/// Vertices of the tone map's draw: two triangles per cell of [`TONEMAP_GRID`].
pub const TONEMAP_VERTICES: u32 = 6 * TONEMAP_GRID.0 * TONEMAP_GRID.1;

/// Push constants of the tone-map pass: what it needs to draw the sky behind the
/// scene and to expose the image.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ToneMapPush {
    /// Clip space to world (the inverse of the camera's view-projection).
    pub clip_to_world: Mat4,
    /// Camera position (xyz) and exposure (w).
    pub camera: Vec4,
    /// Unit direction towards the sun (xyz); w: 1 where the frame is shown as drawn
    /// (the paper look resolved by the temporal anti-aliasing: no sky, no tone map).
    pub sun: Vec4,
    /// The meadow beyond the field: the ground plane's height (x), fog density (y),
    /// clump size (z), and 1 to draw it or 0 (w); see `look::meadow_to_horizon`.
    pub ground: Vec4,
    /// The source image's pixels per output pixel across (x) and down (y): 1, or
    /// less where the scene was drawn smaller (`LookSettings::render_scale`); z, w 0.
    pub source: Vec4,
}

/// Push constants of the chunk pass: how the visible blades split into draws.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ChunkPush {
    /// Blades per draw command.
    pub chunk_size: u32,
    /// Number of draw commands written.
    pub chunk_count: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest of [`near_groups`] over the first blade of each workgroup of `n`
    /// handed blades: the dispatch the pass over every blade leaves.
    fn grown(n: u32) -> (u32, u32) {
        (0..n)
            .step_by(CULL_WORKGROUP as usize)
            .map(near_groups)
            .fold((0, 0), |(x, y), (a, b)| (x.max(a), y.max(b)))
    }

    /// The dispatch grown blade by blade covers every handed blade with whole
    /// workgroups, and no workgroup holds none, also past 65,535 along x.
    #[test]
    fn the_grown_dispatch_covers_the_handed_blades_and_no_more() {
        let w = CULL_WORKGROUP;
        assert_eq!(grown(0), (0, 0));
        assert_eq!(grown(1), (1, 1));
        assert_eq!(grown(w), (1, 1));
        assert_eq!(grown(w + 1), (2, 1));
        assert_eq!(grown(MAX_GROUPS_X * w), (MAX_GROUPS_X, 1));
        assert_eq!(grown(MAX_GROUPS_X * w + 1), (MAX_GROUPS_X, 2));
        for n in [
            1,
            77,
            4096,
            81_685,
            MAX_GROUPS_X * w + 5000,
            3 * MAX_GROUPS_X * w,
        ] {
            let (x, y) = grown(n);
            let threads = u64::from(x) * u64::from(y) * u64::from(w);
            // Every blade has a thread (`flat_index`), and a row less would not do.
            assert!(threads >= u64::from(n), "{n}: {x} x {y}");
            let rows_short = u64::from(x) * u64::from(y - 1) * u64::from(w);
            assert!(rows_short < u64::from(n), "{n}: {x} x {y}");
            if y == 1 {
                assert!(u64::from(x - 1) * u64::from(w) < u64::from(n));
            }
        }
    }
}

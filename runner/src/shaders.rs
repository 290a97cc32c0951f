//! The SPIR-V modules of `shaders-rs`, one per entry point (`build.rs`: those kept
//! in `runner/spirv`, or with the `rebuild-shaders` feature compiled by this build),
//! and the entry points' names.

include!(env!("GRASS_SHADER_MODULES"));

/// The SPIR-V module of `entry`, if there is one.
pub fn module(entry: &str) -> Option<&'static [u8]> {
    MODULES
        .iter()
        .find(|(name, _)| *name == entry)
        .map(|(_, spirv)| *spirv)
}

/// Compute: simulate, cull and compact.
pub const SIMULATE_CULL: &str = "compute::simulate::simulate_cull";
/// Compute: simulate, cull and compact, and dress the visible blades (natural look).
pub const SIMULATE_CULL_NATURAL: &str = "compute::simulate::simulate_cull_natural";
/// Compute: the bandwidth reference, a plain copy of every blade.
pub const COPY_BLADES: &str = "compute::reference::copy_blades";
/// Compute: one level of the occluders' depth pyramid.
pub const BUILD_HIZ: &str = "compute::hiz::build_hiz";
/// Compute: the tiles in view around the camera (`shared::tiles`), into the scratch
/// binding.
pub const SELECT_TILES: &str = "compute::tiles::select_tiles";
/// Compute: one tile's blades (`shared::tiles`), into the scratch binding.
pub const GENERATE_TILE: &str = "compute::tiles::generate_tile";
/// Compute: a tile entering the tiled field's pool (`shared::tiles`).
pub const GENERATE_POOL_TILE: &str = "compute::tiles::generate_pool_tile";
/// Compute: the far tiles in view of a tiled frame, listed for their generation.
pub const SELECT_FAR_TILES: &str = "compute::tiles::select_far_tiles";
/// Compute: the far tiles' blades of a tiled frame, one workgroup per tile.
pub const GENERATE_FAR: &str = "compute::tiles::generate_far";
/// Compute: the temporal resolve, one thread per pixel.
pub const RESOLVE_TAA: &str = "compute::temporal::resolve_taa";
/// Compute: the natural look shaded after the draw, one thread per pixel
/// (`shared::draw::look::visibility`).
pub const SHADE_NATURAL: &str = "compute::shade::shade_natural";
/// Compute: the colliders' grid, each frame that has colliders (`shared::sim::grid`).
pub const BUILD_COLLIDER_GRID: &str = "compute::grid::build_collider_grid";
/// Compute: a frame's cuts committed to the cut table after its collision pass
/// (`shared::sim::cut::commit`).
pub const COMMIT_CUTS: &str = "compute::cut::commit_cuts";
/// Compute: the frame's questions answered over every simulated blade
/// (`shared::query`).
pub const ANSWER_QUESTIONS: &str = "compute::query::answer_questions";
/// Compute: the colliders touching the collision pass's blades, marked after it
/// (`shared::query::CONTACTS`).
pub const MARK_CONTACTS: &str = "compute::query::mark_contacts";
/// Compute: each blade's clump, when the field or the clumps' settings change.
pub const CLUMP_BLADES: &str = "compute::clumps::clump_blades";
/// Compute: the compute rasterizer of far blades (paper look).
pub const RASTER_FAR: &str = "compute::raster::raster_far";
/// The shadow map's grass, far cascade: a caster a compute thread
/// (`shared::draw::look::shadow_raster`).
pub const RASTER_CASTERS: &str = "compute::shadow::raster_casters";
/// [`RASTER_CASTERS`] into the near cascade.
pub const RASTER_NEAR_CASTERS: &str = "compute::shadow::raster_near_casters";
/// Compute: the compute rasterizer of far blades (natural look, dressed blades).
pub const RASTER_FAR_NATURAL: &str = "compute::raster::raster_far_natural";
/// Compute: the compute rasterizer's preparation (the hardware's depth copied, the
/// visibility buffer cleared).
pub const RASTER_PREPARE: &str = "compute::raster::raster_prepare";
/// Compute: the preparation under MSAA (the farthest sample of the hardware's depth).
pub const RASTER_PREPARE_MS: &str = "compute::raster::raster_prepare_ms";
/// The compute rasterizer's resolve: the full-screen triangle.
pub const RESOLVE_VS: &str = "raster::resolve_vs";
/// The resolve's fragment stage, paper look.
pub const RESOLVE_PAPER_FS: &str = "raster::resolve_paper_fs";
/// The resolve's fragment stage, LOD view (what the compute rasterizer drew).
pub const RESOLVE_LOD_FS: &str = "raster::resolve_lod_fs";
/// The resolve's fragment stage, natural look.
pub const RESOLVE_NATURAL_FS: &str = "raster::resolve_natural_fs";
/// Compute: one indirect draw command per chunk of visible blades.
pub const WRITE_DRAWS: &str = "compute::draws::write_draws";
/// Grass vertex stage.
pub const GRASS_VS: &str = "grass::grass_vs";
/// Grass tessellation control stage (LOD).
pub const GRASS_TCS: &str = "grass::grass_tcs";
/// Grass tessellation evaluation stage (blade shape).
pub const GRASS_TES: &str = "grass::grass_tes";
/// Tessellation evaluation: [`GRASS_TES`] with each vertex's motion (temporal
/// anti-aliasing).
pub const GRASS_TAA_TES: &str = "grass::grass_taa_tes";
/// The mesh path's triangle-throughput reference: mesh stage.
pub const THROUGHPUT_MESH: &str = "throughput::throughput_mesh";
/// Grass fragment stage (shaded and wireframe views).
pub const GRASS_FS: &str = "grass::grass_fs";
/// Fragment: [`GRASS_FS`] writing the motion target too (temporal anti-aliasing).
pub const GRASS_TAA_FS: &str = "grass::grass_taa_fs";
/// Grass fragment stage of the LOD view.
pub const GRASS_LOD_FS: &str = "grass::grass_lod_fs";
/// The natural look's grass: vertex stage (the visible slot).
pub const NATURAL_VS: &str = "grass::natural_vs";
/// The natural look's grass: tessellation control (LOD of the dressed blade).
pub const NATURAL_TCS: &str = "grass::natural_tcs";
/// The natural look's grass: tessellation evaluation (the dressed blade's surface).
pub const NATURAL_TES: &str = "grass::natural_tes";
/// The natural look's grass: fragment stage.
pub const NATURAL_FS: &str = "grass::natural_fs";
/// The natural look's grass at one sample: tessellation evaluation for shading after
/// the draw (surface coordinates and slot).
pub const NATURAL_VIS_TES: &str = "grass::natural_vis_tes";
/// Fragment: the blade and the place on it, packed for [`SHADE_NATURAL`].
pub const NATURAL_VIS_FS: &str = "grass::natural_vis_fs";
/// The natural look's grass: fragment stage of the LOD and wireframe views.
pub const NATURAL_VIEW_FS: &str = "grass::natural_view_fs";
/// The paper look's mesh path: mesh stage (the blade strips of one length).
pub const PAPER_MESH: &str = "mesh::paper_mesh";
/// Mesh: [`PAPER_MESH`] with each vertex's motion (temporal anti-aliasing).
pub const PAPER_TAA_MESH: &str = "mesh::paper_taa_mesh";
/// The paper look's mesh stage writing each vertex's clip position to the scratch
/// binding (tests).
pub const PAPER_MESH_CAPTURE: &str = "mesh::paper_mesh_capture";
/// The natural look's mesh path: mesh stage.
pub const NATURAL_MESH: &str = "mesh::natural_mesh";
/// Mesh: [`NATURAL_MESH`] for shading after the draw (surface coordinates and slot).
pub const NATURAL_VIS_MESH: &str = "mesh::natural_vis_mesh";
/// The tone map's full-screen triangle.
pub const TONEMAP_VS: &str = "tonemap::tonemap_vs";
/// Sky and tone map.
pub const TONEMAP_FS: &str = "tonemap::tonemap_fs";
/// The embedding example's cube, vertex stage (`shared::cube`).
pub const CUBE_VS: &str = "example::cube_vs";
/// The embedding example's cube, fragment stage.
pub const CUBE_FS: &str = "example::cube_fs";
/// The surfaces from the sun (shadow map): vertex stage.
pub const SHADOW_SURFACE_VS: &str = "ground::shadow_surface_vs";
/// A surface from the sun into the near cascade.
pub const SHADOW_SURFACE_NEAR_VS: &str = "ground::shadow_surface_near_vs";
/// Ground vertex stage.
pub const GROUND_VS: &str = "ground::ground_vs";
/// Ground fragment stage.
pub const GROUND_FS: &str = "ground::ground_fs";
/// Overlay vertex stage.
pub const OVERLAY_VS: &str = "overlay::overlay_vs";
/// Overlay fragment stage.
pub const OVERLAY_FS: &str = "overlay::overlay_fs";
/// Triangle-throughput reference, vertex stage.
pub const THROUGHPUT_VS: &str = "throughput::throughput_vs";
/// Triangle-throughput reference, tessellation control stage.
pub const THROUGHPUT_TCS: &str = "throughput::throughput_tcs";
/// Triangle-throughput reference, tessellation evaluation stage.
pub const THROUGHPUT_TES: &str = "throughput::throughput_tes";
/// Triangle-throughput reference, fragment stage.
pub const THROUGHPUT_FS: &str = "throughput::throughput_fs";

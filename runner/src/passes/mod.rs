//! The passes of a frame, in the order the renderer records them, with what each reads
//! and writes:
//!
//! 0. [`tiles`]: in a tiled field, generates the tiles entering the pool of simulated
//!    tiles and the far tiles' blades in view (reads the frame block and the pool's
//!    table; writes the blades, their ids and clumps, the tile list and counters).
//! 1. [`occlusion`]: draws the scene's surfaces depth-only and reduces the depth to a
//!    pyramid (reads the surfaces and the camera; writes the depth image and the
//!    pyramid buffer). Only with the occlusion test and something that can hide grass.
//! 2. [`simulate`]: simulates, culls and compacts every blade, then writes one draw
//!    command per chunk (reads the frame block and the pyramid; writes the blades,
//!    their collision strengths, the visible indices, the counters and the draws).
//! 3. [`shadow`]: the sun's shadow map (natural look, shadows on): surfaces, balls and
//!    the visible grass at its fewest segments (reads what `ground` and `grass` read;
//!    writes the shadow map).
//! 4. [`ground`]: the surfaces and the collider ball (reads the surface meshes and
//!    the frame block; writes colour and depth).
//! 5. [`grass`]: the visible blades as tessellated patches (reads the visible
//!    indices, the blades, the draws and the frame block; writes colour and depth).
//!    In the natural look both draw into a linear HDR target (multisampled with
//!    `--msaa`, resolved when the scope ends).
//! 6. [`tonemap`]: the natural look's sky and tone map (reads the resolved HDR
//!    image; writes the target).
//! 7. [`overlay`]: the viewer's egui panel (reads egui's meshes and textures; writes
//!    colour).
//!
//! [`throughput`] is no part of a frame: the benchmark's triangle reference.

pub mod by_target;
pub mod grass;
pub mod ground;
pub mod occlusion;
pub mod overlay;
pub mod raster;
pub mod shadow;
pub mod simulate;
pub mod throughput;
pub mod tiles;
pub mod tonemap;

/// Depth format of every pass.
pub const DEPTH_FORMAT: ash::vk::Format = ash::vk::Format::D32_SFLOAT;

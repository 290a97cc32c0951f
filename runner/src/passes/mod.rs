//! The passes of a frame, in the order the renderer records them, with what each reads
//! and writes:
//!
//! 1. [`occlusion`]: draws the scene's surfaces depth-only and reduces the depth to a
//!    pyramid (reads the surfaces and the camera; writes the depth image and the
//!    pyramid buffer). Only with the occlusion test and something that can hide grass.
//! 2. [`simulate`]: simulates, culls and compacts every blade, then writes one draw
//!    command per chunk (reads the frame block and the pyramid; writes the blades,
//!    their collision strengths, the visible indices, the counters and the draws).
//! 3. [`ground`]: the surfaces and the collider ball (reads the surface meshes and
//!    the frame block; writes colour and depth).
//! 4. [`grass`]: the visible blades as tessellated patches (reads the visible
//!    indices, the blades, the draws and the frame block; writes colour and depth).
//! 5. [`overlay`]: the viewer's egui panel (reads egui's meshes and textures; writes
//!    colour).
//!
//! [`throughput`] is no part of a frame: the benchmark's triangle reference.

pub mod grass;
pub mod ground;
pub mod occlusion;
pub mod overlay;
pub mod simulate;
pub mod throughput;

/// Depth format of every pass.
pub const DEPTH_FORMAT: ash::vk::Format = ash::vk::Format::D32_SFLOAT;

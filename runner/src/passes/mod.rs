//! The passes of a frame, in order: simulate-and-cull (compute), then ground and grass
//! (graphics).

pub mod grass;
pub mod ground;
pub mod occlusion;
pub mod overlay;
pub mod simulate;
pub mod throughput;

/// Depth format of every pass.
pub const DEPTH_FORMAT: ash::vk::Format = ash::vk::Format::D32_SFLOAT;

//! The low Vulkan layer: the only place with raw `unsafe` ash calls. One Vulkan
//! object (or close family) per module; each owns its destruction.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod descriptors;
pub mod fault;
pub mod features;
pub mod image;
pub mod pipeline;
pub mod probe;
pub mod query;
pub mod recorder;
pub mod sampler;
pub mod swapchain;

pub use buffer::Buffer;
pub use context::{Context, ContextOptions, DeviceParts, ValidationChecks};
pub use features::{DeviceFeatures, Missing};
pub use image::Image;
pub use recorder::{Attachments, Recorder};

/// True when `GRASS_REQUIRE_GPU=1` (as in CI): tests that need a Vulkan device then
/// fail instead of skipping. The one place every test asks.
pub fn gpu_required() -> bool {
    std::env::var("GRASS_REQUIRE_GPU").is_ok_and(|v| v.trim() == "1")
}

//! The ash renderer of the grass field.
//!
//! The file tree reads like the frame: [`vulkan`] is the low layer (the only raw
//! Vulkan calls), [`field`] the GPU buffers of the blades, [`passes`] the passes of a
//! frame in order, [`renderer`] one frame start to end, and [`app`] the shells
//! (window viewer, headless render).

pub mod app;
pub mod camera;
pub mod cli;
pub mod collider;
pub mod field;
pub mod passes;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod vulkan;

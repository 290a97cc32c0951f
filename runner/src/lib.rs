//! The ash renderer of the grass field.
//!
//! The file tree reads like the frame: [`vulkan`] is the low layer (the only raw
//! Vulkan calls), [`field`] the GPU buffers of the blades, [`passes`] the passes of a
//! frame in order, [`renderer`] records one frame start to end, and [`app`] the
//! frame driver (`app::driver`: slots, submission, presentation or capture, the
//! simulation clock, read-back) and the shells that use it (window viewer, `render`,
//! `bench`, `soak`); [`tiles`] the tiled field's host side (issue 19) and [`paint`]
//! its painted maps.
//! The settings are typed (`shared::settings`) and become the
//! shaders' numbers in one place, `Settings::uniforms`.

pub mod app;
pub mod camera;
pub mod cli;
pub mod collider;
pub mod config;
pub mod field;
pub mod paint;
pub mod parse;
pub mod passes;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod tiles;
pub mod vulkan;

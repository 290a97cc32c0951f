//! The grass model of Jahrmann & Wimmer, *Responsive Real-Time Grass Rendering for
//! General 3D Scenes* (I3D 2017), as pure functions shared by the GPU and the host.
//!
//! The same code runs in the rust-gpu shaders (`shaders-rs`) and in the host tests, so
//! a formula lives exactly once: change it here and both sides follow.
//!
//! The modules by concern: `sim` (the simulation), `cull` (what is drawn), `draw` (how
//! it is drawn), `world` (where grass grows), `gpu` (the frame's block and counters the
//! runner and the shaders share), with `blade`, `species`, `camera` and `noise` under
//! them all and `settings` (host only) over them all, the one place settings become the
//! GPU block.
#![cfg_attr(target_arch = "spirv", no_std)]

pub mod blade;
pub mod camera;
pub mod cull;
pub mod draw;
pub mod example;
pub mod gpu;
pub mod noise;
#[cfg(not(target_arch = "spirv"))]
pub mod plan;
pub mod query;
#[cfg(not(target_arch = "spirv"))]
pub mod settings;
pub mod sim;
pub mod species;
pub mod world;

pub use blade::Blade;
pub use spirv_std::glam;

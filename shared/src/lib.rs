//! The grass model of Jahrmann & Wimmer, *Responsive Real-Time Grass Rendering for
//! General 3D Scenes* (I3D 2017), as pure functions shared by the GPU and the host.
//!
//! The same code runs in the rust-gpu shaders (`shaders-rs`) and in the host tests, so
//! a formula lives exactly once: change it here and both sides follow.
#![cfg_attr(target_arch = "spirv", no_std)]

pub mod blade;
pub mod collide;
pub mod cube;
pub mod cull;
pub mod forces;
#[cfg(not(target_arch = "spirv"))]
pub mod generate;
pub mod hiz;
pub mod layout;
pub mod lod;
pub mod look;
#[cfg(not(target_arch = "spirv"))]
pub mod mesh;
pub mod meshlet;
pub mod paint;
pub mod raster;
pub mod reference;
#[cfg(not(target_arch = "spirv"))]
pub mod settings;
pub mod shade;
pub mod shape;
pub mod simulate;
pub mod surface;
pub mod sway;
pub mod terrain;
pub mod tiles;
pub mod validate;
pub mod wind;

pub use blade::Blade;
pub use spirv_std::glam;

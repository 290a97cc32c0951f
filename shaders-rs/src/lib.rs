//! Shader entry points of the grass renderer, compiled to SPIR-V by rust-gpu.
//!
//! Each entry point only reads its inputs, calls the grass model in `shared`, and
//! writes its outputs. Descriptor bindings are literals here (rust-gpu attributes take
//! no constants); the numbers are `shared::layout::BINDING_*`, and a test reflects
//! the compiled module to check that they agree with the runner's layouts.
#![cfg_attr(target_arch = "spirv", no_std)]

pub mod compute;
pub mod grass;
pub mod ground;
pub mod overlay;
pub mod throughput;

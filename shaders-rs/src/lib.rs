//! Shader entry points of the grass renderer, compiled to SPIR-V by rust-gpu.
//!
//! Each entry point only reads its inputs, calls the grass model in `shared`, and
//! writes its outputs. Descriptor bindings are literals here (rust-gpu attributes take
//! no constants); the numbers are `shared::gpu::layout::BINDING_*`, and a test reflects
//! the compiled module to check that they agree with the runner's layouts.
#![cfg_attr(target_arch = "spirv", no_std)]

pub mod compute;
pub mod example;
pub mod grass;
pub mod ground;
pub mod mesh;
pub mod overlay;
pub mod raster;
pub mod throughput;
pub mod tonemap;

use shared::draw::look::shadow::{cascade_coord, shadow_bias};
use shared::gpu::layout::FrameUniforms;
use spirv_std::Sampler;
use spirv_std::glam::Vec3;

/// The shadow map as the fragment stages declare it: a sampled depth image.
pub type ShadowMap = spirv_std::Image!(2D, type=f32, sampled, depth);

/// The depth target as the depth copy and the temporal resolve read it: a sampled
/// image fetched by texel, with no sampler (`shared::gpu::layout::BINDING_DEPTH_IMAGE`).
pub type DepthImage = spirv_std::Image!(2D, type=f32, sampled);

/// The multisampled depth target as the preparation reads it, sample by sample
/// (`shared::gpu::layout::BINDING_DEPTH_IMAGE_MS`).
pub type DepthImageMs = spirv_std::Image!(2D, type=f32, sampled, multisampled);

/// The sun's light reaching `world`: 1 lit, 0 in shadow, from one fetch of the shadow
/// map's cascade that holds it (`shared::draw::look::shadow::cascade_coord`) through
/// its comparison sampler (the texture unit tests the four nearest texels and weighs
/// them bilinearly: `shared::draw::look::shadow::shadow_factor`); 1 with shadows off.
pub fn sun_shadow(frame: &FrameUniforms, map: &ShadowMap, sampler: &Sampler, world: Vec3) -> f32 {
    let look = &frame.look;
    if look.shadows == 0 {
        return 1.0;
    }
    let (on, coord) = cascade_coord(
        look.near_view_proj,
        look.shadow_view_proj,
        world,
        look.shadow_size,
    );
    if !on {
        return 1.0;
    }
    let reference = coord.z - shadow_bias(look.shadow_size);
    map.sample_depth_reference_by_lod(*sampler, coord.truncate(), reference, 0.0)
}

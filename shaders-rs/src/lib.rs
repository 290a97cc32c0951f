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
pub mod tonemap;

use shared::layout::FrameUniforms;
use shared::look::{shadow_coord, shadow_factor};
use spirv_std::glam::{Vec2, Vec4};
use spirv_std::image::SampledImage;
use spirv_std::Image;

/// The sun's light reaching `world`: 1 lit, 0 in shadow, from the shadow map (four
/// texels, bilinear weights: `shared::look::shadow_factor`); 1 with shadows off.
pub fn sun_shadow(
    frame: &FrameUniforms,
    map: &SampledImage<Image!(2D, type=f32, sampled)>,
    world: spirv_std::glam::Vec3,
) -> f32 {
    let look = &frame.look;
    if look.shadows == 0 {
        return 1.0;
    }
    let coord = shadow_coord(look.shadow_view_proj, world);
    let size = look.shadow_size;
    let texel = |x: i32, y: i32| {
        let uv = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32;
        let d: Vec4 = map.sample_by_lod(uv, 0.0);
        d.x
    };
    // Two texels of depth: the map's depth range is 4 radii deep.
    shadow_factor(coord, size, 2.0 / size as f32, texel)
}

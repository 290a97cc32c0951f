//! The temporal resolve (`shared::draw::temporal`): one thread per pixel blends the
//! frame into the history that its motion finds, and writes the next history, which
//! the tone map then shows.

use crate::DepthImage;
use shared::draw::temporal::{history_uv, neighbourhood_3x3, pixel_centre, pixel_motion, resolve};
use shared::gpu::layout::FrameUniforms;
use spirv_std::glam::{IVec2, UVec2, UVec3, Vec4, Vec4Swizzles};
use spirv_std::{Image, Sampler, spirv};

/// One thread per pixel: the pixel's motion (the camera's, from the depth, and a
/// blade's own from the motion target) finds its history, which is clipped to the 3x3
/// neighbourhood's box and blended with the frame; the result goes to `out`. In a
/// compute stage rather than the tone map's fragment stage: on the NVIDIA H100, which
/// shades pixels on few of its SMs, the fragment stage took 1.45 ms at 1920x1080.
/// Workgroups of `layout::TEMPORAL_WORKGROUP` squared.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn resolve_taa(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(descriptor_set = 0, binding = 0)] hdr: &Image!(2D, type=f32, sampled),
    #[spirv(descriptor_set = 0, binding = 1)] motion: &Image!(2D, type=f32, sampled),
    #[spirv(descriptor_set = 0, binding = 2)] depth: &DepthImage,
    #[spirv(descriptor_set = 0, binding = 3)] history: &Image!(2D, type=f32, sampled),
    #[spirv(descriptor_set = 0, binding = 4)] sampler: &Sampler,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 6)] out: &Image!(2D, format = rgba16f, sampled = false),
) {
    let size = UVec2::new(frame.raster.width, frame.raster.height);
    let texel = id.truncate();
    if texel.x >= size.x || texel.y >= size.y {
        return;
    }
    let current: Vec4 = hdr.fetch(texel);
    let (uv, ndc) = pixel_centre(texel, size);
    let z: Vec4 = depth.fetch(texel);
    let written: Vec4 = motion.fetch(texel);
    let temporal = &frame.temporal;
    let moved = pixel_motion(ndc, z.x, written.xy(), temporal);
    let (inside, at) = history_uv(uv, moved);
    let has_history = inside && temporal.reset == 0;
    let before: Vec4 = if has_history {
        history.sample_by_lod(*sampler, at, 0.0)
    } else {
        Vec4::ZERO
    };
    let top = size.as_ivec2() - 1;
    let around = neighbourhood_3x3(|dx, dy| {
        let at = (texel.as_ivec2() + IVec2::new(dx, dy)).clamp(IVec2::ZERO, top);
        let c: Vec4 = hdr.fetch(at.as_uvec2());
        c
    });
    let resolved = resolve(current, &around, (has_history, before));
    unsafe { out.write(texel, resolved) };
}

//! The natural look's last pass: the sky behind the scene, then the tone map from the
//! linear HDR image to the sRGB target (`shared::look::tone_map`).

use shared::layout::ToneMapPush;
use shared::look::{meadow_to_horizon, sky, tone_map};
use spirv_std::glam::{UVec2, Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::{Image, spirv};

/// One triangle over the whole screen, with the view ray from the camera through
/// each corner (on the far plane): linear across the screen, so the fragment stage
/// gets each pixel's ray by interpolation instead of a matrix product.
#[spirv(vertex)]
pub fn tonemap_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(push_constant)] push: &ToneMapPush,
    #[spirv(position)] out_position: &mut Vec4,
    out_ray: &mut Vec3,
) {
    let uv = Vec2::new(((vertex << 1) & 2) as f32, (vertex & 2) as f32);
    let clip = (uv * 2.0 - Vec2::ONE).extend(0.0).extend(1.0);
    *out_position = clip;
    let far = push.clip_to_world * Vec4::new(clip.x, clip.y, 1.0, 1.0);
    *out_ray = far.xyz() / far.w - push.camera.xyz();
}

/// The HDR pixel over the sky, or below the horizon over the meadow beyond the field
/// (its alpha is the share of the pixel the scene covers; the rest shows what is
/// behind), exposed and tone-mapped. The HDR image has the target's size: each pixel
/// fetches its own texel (no sampler, which a software rasteriser pays dearly for).
#[spirv(fragment)]
pub fn tonemap_fs(
    #[spirv(frag_coord)] frag: Vec4,
    ray: Vec3,
    #[spirv(push_constant)] push: &ToneMapPush,
    #[spirv(descriptor_set = 0, binding = 0)] hdr: &Image!(2D, type=f32, sampled),
    out_color: &mut Vec4,
) {
    let texel = UVec2::new(frag.x as u32, frag.y as u32);
    let pixel: Vec4 = hdr.fetch(texel);
    let open = (1.0 - pixel.w).max(0.0);
    let mut radiance = pixel.xyz();
    if open > 0.0 {
        let dir = ray.normalize_or_zero();
        let sun = push.sun.xyz();
        let behind = match meadow_to_horizon(push.camera.xyz(), dir, sun, push.ground) {
            Some(meadow) => meadow,
            None => sky(dir, sun),
        };
        radiance += open * behind;
    }
    *out_color = tone_map(radiance, push.camera.w).extend(1.0);
}

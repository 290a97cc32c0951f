//! The overlay (egui's triangles): positions in points, a texture (egui's font atlas
//! and images, sRGB, premultiplied alpha) times the vertex colour.

use shared::draw::shade::srgb_to_linear;
use shared::gpu::layout::OverlayPush;
use spirv_std::glam::{Vec2, Vec4};
use spirv_std::image::SampledImage;
use spirv_std::{Image, spirv};

/// egui's vertex: points to clip space; the sRGB vertex colour made linear for the
/// sRGB target (alpha stays as it is).
#[spirv(vertex)]
pub fn overlay_vs(
    position: Vec2,
    uv: Vec2,
    color: Vec4,
    #[spirv(push_constant)] push: &OverlayPush,
    #[spirv(position)] out_position: &mut Vec4,
    out_uv: &mut Vec2,
    out_color: &mut Vec4,
) {
    *out_position = push.to_clip(position);
    *out_uv = uv;
    *out_color = Vec4::new(
        srgb_to_linear(color.x),
        srgb_to_linear(color.y),
        srgb_to_linear(color.z),
        color.w,
    );
}

/// Texture times colour, premultiplied (blended with ONE, ONE_MINUS_SRC_ALPHA).
#[spirv(fragment)]
pub fn overlay_fs(
    uv: Vec2,
    color: Vec4,
    #[spirv(descriptor_set = 0, binding = 0)] texture: &SampledImage<Image!(2D, type=f32, sampled)>,
    out_color: &mut Vec4,
) {
    let texel: Vec4 = texture.sample(uv);
    *out_color = texel * color;
}

//! The natural look's last pass: the sky behind the scene, then the tone map from the
//! linear HDR image to the sRGB target (`shared::draw::look::sky::tone_map`). With
//! temporal anti-aliasing it shows the resolved history, in either look (the paper
//! look's as drawn).

use shared::draw::look::ground::meadow_to_horizon;
use shared::draw::look::sky::{sky_gradient, sun_disc, tone_map};
use shared::gpu::layout::TONEMAP_GRID;
use shared::gpu::layout::ToneMapPush;
use spirv_std::glam::{UVec2, Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::{Image, spirv};

/// One vertex of the grid over the screen (`layout::TONEMAP_GRID`): its view ray
/// (from the camera to the far plane; linear across the screen, so interpolation
/// gives each pixel its own) and what lies behind the scene there, the sky's gradient
/// or the meadow beyond the field (smooth enough to interpolate over a cell).
#[spirv(vertex)]
pub fn tonemap_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(push_constant)] push: &ToneMapPush,
    #[spirv(position)] out_position: &mut Vec4,
    out_ray: &mut Vec3,
    out_behind: &mut Vec3,
) {
    let (columns, rows) = TONEMAP_GRID;
    let cell = vertex / 6;
    let corner = [(0, 0), (1, 0), (0, 1), (0, 1), (1, 0), (1, 1)][(vertex % 6) as usize];
    let x = (cell % columns + corner.0) as f32 / columns as f32;
    let y = (cell / columns + corner.1) as f32 / rows as f32;
    let clip = Vec2::new(2.0 * x - 1.0, 2.0 * y - 1.0);
    *out_position = clip.extend(0.0).extend(1.0);
    let far = push.clip_to_world * clip.extend(1.0).extend(1.0);
    let ray = far.xyz() / far.w - push.camera.xyz();
    let dir = ray.normalize_or_zero();
    let sun = push.sun.xyz();
    *out_ray = ray;
    *out_behind = match meadow_to_horizon(push.camera.xyz(), dir, sun, push.ground) {
        Some(meadow) => meadow,
        None => sky_gradient(dir, sun),
    };
}

/// The HDR pixel over what lies behind it (its alpha is the share of the pixel the
/// scene covers; the rest shows the sky or the meadow, with the sun disc), exposed and
/// tone-mapped. Each pixel fetches the texel under it (no sampler, which a software
/// rasteriser pays dearly for): its own, or where the scene was drawn smaller
/// (`push.source`) the nearest.
#[spirv(fragment)]
pub fn tonemap_fs(
    #[spirv(frag_coord)] frag: Vec4,
    ray: Vec3,
    behind: Vec3,
    #[spirv(push_constant)] push: &ToneMapPush,
    #[spirv(descriptor_set = 0, binding = 0)] hdr: &Image!(2D, type=f32, sampled),
    out_color: &mut Vec4,
) {
    // The source's pixel under this one (nearest: a scaled frame's pixels grow).
    let texel = UVec2::new(
        (frag.x * push.source.x) as u32,
        (frag.y * push.source.y) as u32,
    );
    let pixel: Vec4 = hdr.fetch(texel);
    *out_color = finish(pixel, ray, behind, push);
}

/// The pixel `pixel` (premultiplied, alpha the share the scene covers) over the sky or
/// the meadow `behind` with the sun disc, exposed and tone-mapped; as it is where
/// `push` says the frame is shown as drawn (the paper look).
fn finish(pixel: Vec4, ray: Vec3, behind: Vec3, push: &ToneMapPush) -> Vec4 {
    if push.sun.w != 0.0 {
        return pixel.xyz().extend(1.0);
    }
    let open = (1.0 - pixel.w).max(0.0);
    let mut radiance = pixel.xyz();
    if open > 0.0 {
        let disc = sun_disc(ray.normalize_or_zero(), push.sun.xyz());
        radiance += open * (behind + disc);
    }
    tone_map(radiance, push.camera.w).extend(1.0)
}

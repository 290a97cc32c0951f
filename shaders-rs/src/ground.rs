//! The surfaces: the scene's ground mesh (soil and rock) and the collider ball, lit,
//! with the soil texture generated in the fragment stage.

use crate::{ShadowMap, sun_shadow};
use shared::draw::look::LOOK_NATURAL;
use shared::draw::look::ground::natural_ground;
use shared::draw::look::ground::shade_ground;
use shared::draw::look::sky::fog;
use shared::draw::shade::{lambert, surface_albedo};
use shared::gpu::layout::{FrameUniforms, GROUND_GRID, SurfacePush};
use shared::world::terrain::{valley_height, valley_normal};
use spirv_std::Sampler;
use spirv_std::glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::spirv;

/// One surface vertex, placed by the push constant's model matrix.
#[allow(clippy::too_many_arguments)]
#[spirv(vertex)]
pub fn ground_vs(
    position: Vec4,
    normal: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SurfacePush,
    #[spirv(position)] out_position: &mut Vec4,
    out_world: &mut Vec3,
    out_normal: &mut Vec3,
    #[spirv(flat)] out_material: &mut u32,
) {
    let (world, n) = place(push, position, normal);
    *out_position = frame.camera.view_proj * world;
    *out_world = world.xyz();
    *out_normal = n;
    *out_material = position.w as u32;
}

/// A surface vertex in the world and its normal: through the model matrix, or on
/// the valley's height field for its ground grid (`SurfacePush::terrain`).
fn place(push: &SurfacePush, position: Vec4, normal: Vec4) -> (Vec4, Vec3) {
    let world = push.model * position.xyz().extend(1.0);
    if push.terrain.x == GROUND_GRID {
        let half = Vec2::splat(push.terrain.y);
        let p = world.xz().clamp(-half, half);
        return (Vec4::new(p.x, valley_height(p), p.y, 1.0), valley_normal(p));
    }
    // Models are rotations, translations and uniform scales: no inverse transpose.
    (world, (push.model * normal.xyz().extend(0.0)).xyz())
}

/// The surface's material, lit by the sun. In the natural look: soil under grass
/// takes the roots' colour and, far away, the field's; sky light and the sun with its
/// shadow; fog.
#[spirv(fragment)]
pub fn ground_fs(
    world: Vec3,
    normal: Vec3,
    #[spirv(flat)] material: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &ShadowMap,
    #[spirv(descriptor_set = 0, binding = 10)] shadow_sampler: &Sampler,
    out_color: &mut Vec4,
) {
    let n = normal.normalize_or_zero();
    if frame.look.style != LOOK_NATURAL {
        let albedo = surface_albedo(material, world, n);
        *out_color = lambert(albedo, n, frame.light).extend(1.0);
        return;
    }
    let to_camera = frame.camera.position - world;
    let distance = to_camera.length();
    let look = &frame.look;
    let (albedo, occlusion) = natural_ground(material, world, n, distance, look);
    let to_light = frame.light.direction;
    let sun = sun_shadow(frame, shadow_map, shadow_sampler, world);
    // Under the canopy the blades hold back the sun as they hold back the sky.
    let lit = shade_ground(albedo, n, to_light, occlusion, sun * occlusion);
    let dir = -to_camera / distance.max(1e-6);
    *out_color = fog(lit, distance, dir, to_light, look.fog_density).extend(1.0);
}

/// One surface vertex seen from the sun: the shadow map's far cascade (depth only).
#[spirv(vertex)]
pub fn shadow_surface_vs(
    position: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SurfacePush,
    #[spirv(position)] out_position: &mut Vec4,
) {
    let (world, _) = place(push, position, Vec4::ZERO);
    *out_position = frame.look.shadow_view_proj * world;
}

/// [`shadow_surface_vs`] into the near cascade.
#[spirv(vertex)]
pub fn shadow_surface_near_vs(
    position: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(push_constant)] push: &SurfacePush,
    #[spirv(position)] out_position: &mut Vec4,
) {
    let (world, _) = place(push, position, Vec4::ZERO);
    *out_position = frame.look.near_view_proj * world;
}

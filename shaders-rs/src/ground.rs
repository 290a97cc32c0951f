//! The surfaces: the scene's ground mesh (soil and rock) and the collider ball, lit,
//! with the soil texture generated in the fragment stage.

use shared::layout::{FrameUniforms, SurfacePush};
use shared::shade::{lambert, surface_albedo};
use spirv_std::glam::{Vec3, Vec4, Vec4Swizzles};
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
    let world = push.model * position.xyz().extend(1.0);
    *out_position = frame.camera.view_proj * world;
    *out_world = world.xyz();
    // Models are rotations, translations and uniform scales: no inverse transpose.
    *out_normal = (push.model * normal.xyz().extend(0.0)).xyz();
    *out_material = position.w as u32;
}

/// The surface's material, lit by the sun.
#[spirv(fragment)]
pub fn ground_fs(
    world: Vec3,
    normal: Vec3,
    #[spirv(flat)] material: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    let n = normal.normalize_or_zero();
    let albedo = surface_albedo(material, world, n);
    *out_color = lambert(albedo, n, frame.light).extend(1.0);
}

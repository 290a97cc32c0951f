//! The ground: a square under the field, drawn from the vertex index alone, with a
//! texture generated in the fragment stage.

use shared::layout::FrameUniforms;
use shared::shade::{ground_albedo, ground_corner, lambert};
use spirv_std::glam::{Vec3, Vec3Swizzles, Vec4};
use spirv_std::spirv;

/// Corner `vertex_index` of the two triangles of the ground.
#[spirv(vertex)]
pub fn ground_vs(
    #[spirv(vertex_index)] vertex_index: u32,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(position)] out_position: &mut Vec4,
    out_world: &mut Vec3,
) {
    let p = ground_corner(vertex_index, frame.ground.x);
    *out_position = frame.view_proj * p.extend(1.0);
    *out_world = p;
}

/// The generated soil texture, lit from above.
#[spirv(fragment)]
pub fn ground_fs(
    world: Vec3,
    #[spirv(uniform, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    *out_color = lambert(ground_albedo(world.xz()), Vec3::Y, frame.light).extend(1.0);
}

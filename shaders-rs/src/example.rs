//! The embedding example's own object (`runner/examples/embed/`): the cube of
//! `shared::cube`, drawn from the vertex index. It stands for a caller's scene.

use shared::example::cube::{CubePush, cube_shade, cube_vertex};
use spirv_std::glam::{Vec3, Vec4, Vec4Swizzles};
use spirv_std::spirv;

/// One of the cube's 36 vertices, to clip space; its normal to world space.
#[spirv(vertex)]
pub fn cube_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(push_constant)] push: &CubePush,
    #[spirv(position)] out_position: &mut Vec4,
    out_normal: &mut Vec3,
) {
    let (position, normal) = cube_vertex(vertex);
    *out_position = push.model_view_proj * position.extend(1.0);
    *out_normal = (push.model * normal.extend(0.0)).xyz();
}

/// The face's flat colour.
#[spirv(fragment)]
pub fn cube_fs(normal: Vec3, #[spirv(push_constant)] push: &CubePush, out_color: &mut Vec4) {
    *out_color = cube_shade(push, normal).extend(1.0);
}

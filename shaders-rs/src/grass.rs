//! The grass pipeline: one visible blade is one patch of one control point.
//!
//! The draw has no vertex buffer: vertex k reads the k-th visible blade's index, and
//! the tessellation stages read that blade from the blade buffer (vertex pulling), so
//! only the index and the level travel between stages. rust-gpu has no `patch`
//! decoration for user outputs, so they go from the control to the evaluation stage as
//! per-vertex arrays of length 1. The tessellation levels get their `Patch`
//! decoration from the runner's build script.

use shared::Blade;
use shared::layout::FrameUniforms;
use shared::lod::{screen_level, tess_levels};
use shared::shade::blade_colour;
use shared::shape::surface_point;
use spirv_std::glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::spirv;

/// The index of the visible blade this vertex stands for.
#[spirv(vertex)]
pub fn grass_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    out_blade: &mut u32,
) {
    *out_blade = visible[vertex as usize];
}

/// Level of detail: a continuous tessellation level along the blade from its height
/// on screen (fractional-odd spacing in the evaluation stage), passed on for the LOD
/// view.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_control(output_vertices = 1))]
pub fn grass_tcs(
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    in_blade: [u32; 1],
    out_blade: &mut [u32; 1],
    out_level: &mut [f32; 1],
    #[spirv(tess_level_outer)] outer: &mut [f32; 4],
    #[spirv(tess_level_inner)] inner: &mut [f32; 2],
) {
    out_blade[0] = in_blade[0];
    let blade = &blades[in_blade[0] as usize];
    let distance = (blade.v0.xyz() - frame.camera.position).length();
    let lod = &frame.lod;
    let focal = frame.camera.focal_pixels;
    let level = screen_level(
        blade.height(),
        distance,
        focal,
        lod.pixels_per_segment,
        lod.most,
        lod.fewest,
    );
    out_level[0] = level;
    let (o, i) = tess_levels(level);
    *outer = o;
    *inner = i;
}

/// Blade shape: the surface point at (u, v) of the tessellated quad, in clip space.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn grass_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    in_blade: [u32; 1],
    in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_normal: &mut Vec3,
    out_world: &mut Vec3,
    out_uv: &mut Vec2,
    out_level: &mut f32,
) {
    let blade = &blades[in_blade[0] as usize];
    let grass = &frame.grass;
    let p = surface_point(blade, coord.x, coord.y, grass.shape, grass.tip_start);
    *out_position = frame.camera.view_proj * p.position.extend(1.0);
    *out_normal = p.normal;
    *out_world = p.position;
    *out_uv = coord.truncate();
    *out_level = in_level[0];
}

/// Lambert plus ambient with the base-to-tip gradient, both faces lit; or the
/// tessellation level's colour in the LOD view.
#[spirv(fragment)]
pub fn grass_fs(
    normal: Vec3,
    world: Vec3,
    uv: Vec2,
    level: f32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    let n = normal.normalize_or_zero();
    let (view, camera) = (frame.grass.view, frame.camera.position);
    *out_color = blade_colour(view, n, world, camera, frame.light, uv.y, level).extend(1.0);
}

//! The grass pipeline: one visible blade is one patch of one control point.
//!
//! The draw has no vertex buffer: vertex k reads the k-th visible blade (vertex
//! pulling) and, in the natural look, dresses it (clump, fades, thin-blade coverage)
//! once per blade; the blade then travels to the tessellation stages as varyings.
//! rust-gpu has no `patch` decoration for user outputs, so they go from the control to
//! the evaluation stage as per-vertex arrays of length 1. The tessellation levels get
//! their `Patch` decoration from the runner's build script.

use crate::sun_shadow;
use shared::Blade;
use shared::layout::FrameUniforms;
use shared::look::{
    LOOK_NATURAL, ambient_occlusion, blade_albedo, fog, rounded_normal, shade_leaf,
    unpack_coverage,
};
use shared::lod::{screen_level, tess_levels};
use shared::shade::blade_colour;
use shared::shape::{shape_min_level, surface_point};
use spirv_std::glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::image::SampledImage;
use spirv_std::{Image, spirv};

/// The blade this vertex stands for, as drawn: stored, or dressed by the natural look
/// (`shared::look::dress`), with its tint, coverage and local density.
#[allow(clippy::too_many_arguments)]
#[spirv(vertex)]
pub fn grass_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    out_v0: &mut Vec4,
    out_v1: &mut Vec4,
    out_v2: &mut Vec4,
    out_up: &mut Vec4,
    out_tint: &mut Vec4,
) {
    let id = visible[vertex as usize];
    let blade = blades[id as usize];
    let (drawn, tint) = if frame.look.style == LOOK_NATURAL {
        shared::look::dress(&blade, id, frame.camera.position, &frame.cull, &frame.look)
    } else {
        (blade, Vec4::ONE)
    };
    *out_v0 = drawn.v0;
    *out_v1 = drawn.v1;
    *out_v2 = drawn.v2;
    *out_up = drawn.up;
    *out_tint = tint;
}

fn blade_of(v0: Vec4, v1: Vec4, v2: Vec4, up: Vec4) -> Blade {
    Blade { v0, v1, v2, up }
}

/// Level of detail: a continuous tessellation level along the blade from its height
/// on screen (fractional-odd spacing in the evaluation stage), passed on for the LOD
/// view.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_control(output_vertices = 1))]
pub fn grass_tcs(
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    in_v0: [Vec4; 1],
    in_v1: [Vec4; 1],
    in_v2: [Vec4; 1],
    in_up: [Vec4; 1],
    in_tint: [Vec4; 1],
    out_v0: &mut [Vec4; 1],
    out_v1: &mut [Vec4; 1],
    out_v2: &mut [Vec4; 1],
    out_up: &mut [Vec4; 1],
    out_tint: &mut [Vec4; 1],
    out_level: &mut [f32; 1],
    #[spirv(tess_level_outer)] outer: &mut [f32; 4],
    #[spirv(tess_level_inner)] inner: &mut [f32; 2],
) {
    let blade = blade_of(in_v0[0], in_v1[0], in_v2[0], in_up[0]);
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
    )
    .max(shape_min_level(frame.grass.shape));
    out_v0[0] = in_v0[0];
    out_v1[0] = in_v1[0];
    out_v2[0] = in_v2[0];
    out_up[0] = in_up[0];
    out_tint[0] = in_tint[0];
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
    in_v0: [Vec4; 1],
    in_v1: [Vec4; 1],
    in_v2: [Vec4; 1],
    in_up: [Vec4; 1],
    in_tint: [Vec4; 1],
    in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_normal: &mut Vec3,
    out_world: &mut Vec3,
    out_uv: &mut Vec2,
    out_level: &mut f32,
    out_tint: &mut Vec4,
    out_width_dir: &mut Vec3,
) {
    let blade = blade_of(in_v0[0], in_v1[0], in_v2[0], in_up[0]);
    let grass = &frame.grass;
    let p = surface_point(&blade, coord.x, coord.y, grass.shape, grass.tip_start);
    *out_position = frame.camera.view_proj * p.position.extend(1.0);
    *out_normal = p.normal;
    *out_world = p.position;
    *out_uv = coord.truncate();
    *out_level = in_level[0];
    *out_tint = in_tint[0];
    *out_width_dir = blade.width_dir();
}

/// The paper look: Lambert plus ambient with the base-to-tip gradient, both faces
/// lit, or the tessellation level's colour in the LOD view. The natural look: the
/// blade's tint and drier tip, its leaf rounded across the width, sky light with
/// ambient occlusion, the sun (direct, through the leaf, specular) with its shadow,
/// fog; blades thinner than a pixel cover part of its samples.
#[allow(clippy::too_many_arguments)]
#[spirv(fragment)]
pub fn grass_fs(
    normal: Vec3,
    world: Vec3,
    uv: Vec2,
    level: f32,
    tint: Vec4,
    width_dir: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &SampledImage<
        Image!(2D, type=f32, sampled),
    >,
    out_color: &mut Vec4,
    #[spirv(sample_mask)] out_mask: &mut [u32; 1],
) {
    let n = normal.normalize_or_zero();
    let (view, camera) = (frame.grass.view, frame.camera.position);
    if frame.look.style != LOOK_NATURAL || view != shared::shade::VIEW_SHADED {
        *out_color = blade_colour(view, n, world, camera, frame.light, uv.y, level).extend(1.0);
        out_mask[0] = !0;
        return;
    }
    // The thin-blade coverage (`shared::look::coverage_mask`), made in the vertex stage.
    let (mask, density) = unpack_coverage(tint.w);
    out_mask[0] = mask;
    let to_camera = camera - world;
    let distance = to_camera.length();
    let to_eye = to_camera / distance.max(1e-6);
    let facing = if n.dot(to_eye) < 0.0 { -n } else { n };
    let rounded = rounded_normal(facing, width_dir, uv.x);
    let albedo = blade_albedo(tint.xyz(), uv.y);
    let occlusion = ambient_occlusion(uv.y, density);
    let sun = sun_shadow(frame, shadow_map, world);
    let to_light = frame.light.direction;
    let lit = shade_leaf(albedo, rounded, to_light, to_eye, occlusion, sun);
    let fogged = fog(lit, distance, -to_eye, to_light, frame.look.fog_density);
    *out_color = fogged.extend(1.0);
}

/// The sun's shadow map, grass at its fewest segments: the tessellation level
/// `lod.fewest` everywhere.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_control(output_vertices = 1))]
pub fn grass_shadow_tcs(
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    in_v0: [Vec4; 1],
    in_v1: [Vec4; 1],
    in_v2: [Vec4; 1],
    in_up: [Vec4; 1],
    in_tint: [Vec4; 1],
    out_v0: &mut [Vec4; 1],
    out_v1: &mut [Vec4; 1],
    out_v2: &mut [Vec4; 1],
    out_up: &mut [Vec4; 1],
    #[spirv(tess_level_outer)] outer: &mut [f32; 4],
    #[spirv(tess_level_inner)] inner: &mut [f32; 2],
) {
    out_v0[0] = in_v0[0];
    out_v1[0] = in_v1[0];
    out_v2[0] = in_v2[0];
    out_up[0] = in_up[0];
    let (o, i) = tess_levels(frame.lod.fewest);
    // A blade that covers no sample on screen (a thin one left out) casts no shadow
    // either, nor one outside the map: an outer level of 0 drops the patch.
    let (mask, _) = unpack_coverage(in_tint[0].w);
    let blade = blade_of(in_v0[0], in_v1[0], in_v2[0], in_up[0]);
    let inside = shared::look::in_shadow_map(frame.look.shadow_view_proj, &blade);
    let drop = if mask == 0 || !inside { 0.0 } else { 1.0 };
    *outer = [o[0] * drop, o[1] * drop, o[2] * drop, o[3] * drop];
    *inner = i;
}

/// The blade surface seen from the sun (depth only).
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn grass_shadow_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    in_v0: [Vec4; 1],
    in_v1: [Vec4; 1],
    in_v2: [Vec4; 1],
    in_up: [Vec4; 1],
    #[spirv(position)] out_position: &mut Vec4,
) {
    let blade = blade_of(in_v0[0], in_v1[0], in_v2[0], in_up[0]);
    let grass = &frame.grass;
    let p = surface_point(&blade, coord.x, coord.y, grass.shape, grass.tip_start);
    *out_position = frame.look.shadow_view_proj * p.position.extend(1.0);
}

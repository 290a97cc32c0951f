//! The grass pipelines: one visible blade is one patch of one control point.
//!
//! The draws have no vertex buffer: vertex k stands for the k-th slot of the compacted
//! visible list, and only an index and the level travel between stages (the
//! tessellator's per-patch data is what the NVIDIA H100 pays for). The paper look's
//! stages read the stored blade through its index; the natural look's read the blade
//! as it draws it, which the compute pass wrote to the same slot of the dressed
//! buffer (`shared::draw::look::clump::dress`). rust-gpu has no `patch` decoration for user
//! outputs, so they go from the control to the evaluation stage as per-vertex arrays
//! of length 1. The tessellation levels get their `Patch` decoration from the runner's
//! build script.

use crate::{ShadowMap, sun_shadow};
use shared::Blade;
use shared::cull::lod::{blade_level, dealt_slot, tess_levels, tess_levels_if};
use shared::draw::look::clump::{Clump, DressedBlade, caster_blade, species_albedo};
use shared::draw::look::coverage::{coverage_species, unpack_coverage};
use shared::draw::look::leaf::{ambient_occlusion, rounded_normal, shade_leaf};
use shared::draw::look::sky::fog;
use shared::draw::look::visibility;
use shared::draw::shade::{blade_colour, facing_normal, lod_shade, shade_tagged};
use shared::draw::shape::{SurfacePoint, row_point, surface_point};
use shared::draw::temporal::{BladeMotion, blade_point_motion};
use shared::gpu::counters::COUNTER_VISIBLE;
use shared::gpu::layout::{FrameUniforms, IDS_WORDS};
use shared::species::row_v;
use spirv_std::glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use spirv_std::{Sampler, spirv};

/// The index of the visible blade this vertex stands for: the visible list dealt out
/// (`shared::cull::lod::dealt_slot`).
#[spirv(vertex)]
pub fn grass_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    out_blade: &mut u32,
) {
    *out_blade = visible[dealt_slot(vertex, counters[COUNTER_VISIBLE]) as usize];
}

/// Level of detail: a continuous tessellation level along the blade from its height
/// on screen, passed on for the LOD view.
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
    let level = blade_level(
        &blades[in_blade[0] as usize],
        &frame.lod,
        &frame.camera,
        frame.grass.shape,
    );
    out_level[0] = level;
    let (o, i) = tess_levels(level);
    *outer = o;
    *inner = i;
}

/// Blade shape: the surface point at (u, v) of the tessellated quad, in clip space,
/// with the fragment stage's two varyings: the normal with v in w, and the level (the
/// same over the blade, flat). Nothing else: on the NVIDIA H100, which rasterises on
/// few SMs, every varying a tiny triangle carries costs (performance notes, attempt
/// 12); the fragment stage tells the faces apart by their winding.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn grass_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    in_blade: [u32; 1],
    in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_normal_v: &mut Vec4,
    #[spirv(flat)] out_level: &mut f32,
) {
    let blade = &blades[in_blade[0] as usize];
    (*out_position, *out_normal_v, _, _) = paper_vertex(frame, blade, coord);
    *out_level = in_level[0];
}

/// [`grass_tes`] with temporal anti-aliasing: also the vertex's motion, from the
/// blade's previous control points in the motion buffer (at the blade's index, as the
/// paper look's compute pass writes them).
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn grass_taa_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 24)] motion: &[BladeMotion],
    in_blade: [u32; 1],
    in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_normal_v: &mut Vec4,
    #[spirv(flat)] out_level: &mut f32,
    out_motion: &mut Vec4,
) {
    let slot = in_blade[0] as usize;
    let blade = &blades[slot];
    let point;
    let v;
    (*out_position, *out_normal_v, point, v) = paper_vertex(frame, blade, coord);
    *out_level = in_level[0];
    let moved = point_motion(frame, motion, slot, point, v, blade);
    *out_motion = moved.extend(0.0).extend(0.0);
}

/// Lambert plus ambient with the base-to-tip gradient, both faces lit (the normal
/// turned to the face the triangle's winding shows); also the wireframe view's.
/// The views are entry points of their own, not a branch on `grass.view`: that branch
/// alone took 2.2 of the 5.1 ms of the paper look's mesh-path grass at the edge
/// camera with 1 M blades on the NVIDIA H100 (performance notes, attempt 12).
#[spirv(fragment)]
pub fn grass_fs(
    normal_v: Vec4,
    #[spirv(front_facing)] front: bool,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    let facing = facing_normal(normal_v.xyz().normalize_or_zero(), front);
    *out_color = shade_tagged(facing, frame.light, normal_v.w).extend(1.0);
}

/// [`grass_fs`] with temporal anti-aliasing: also the blade's own motion into the
/// motion target.
#[spirv(fragment)]
pub fn grass_taa_fs(
    normal_v: Vec4,
    #[spirv(flat)] _level: f32,
    motion: Vec4,
    #[spirv(front_facing)] front: bool,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
    out_motion: &mut Vec4,
) {
    grass_fs(normal_v, front, frame, out_color);
    *out_motion = motion;
}

/// The LOD view: each blade in the colour of its tessellation level.
#[spirv(fragment)]
pub fn grass_lod_fs(
    normal_v: Vec4,
    #[spirv(flat)] level: f32,
    #[spirv(front_facing)] front: bool,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    let facing = facing_normal(normal_v.xyz().normalize_or_zero(), front);
    *out_color = lod_shade(facing, frame.light, normal_v.w, level).extend(1.0);
}

/// The natural look: the slot of the visible list this vertex stands for (the
/// dressed buffer's slot), the list dealt out (`shared::cull::lod::dealt_slot`).
#[spirv(vertex)]
pub fn natural_vs(
    #[spirv(vertex_index)] vertex: u32,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &[u32],
    out_slot: &mut u32,
) {
    *out_slot = dealt_slot(vertex, counters[COUNTER_VISIBLE]);
}

/// The natural look's level of detail, from the blade as drawn; thin blades their
/// coverage leaves out are dropped.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_control(output_vertices = 1))]
pub fn natural_tcs(
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    in_slot: [u32; 1],
    out_slot: &mut [u32; 1],
    out_level: &mut [f32; 1],
    #[spirv(tess_level_outer)] outer: &mut [f32; 4],
    #[spirv(tess_level_inner)] inner: &mut [f32; 2],
) {
    out_slot[0] = in_slot[0];
    let drawn = &dressed[in_slot[0] as usize];
    let level = blade_level(&drawn.blade, &frame.lod, &frame.camera, frame.grass.shape);
    out_level[0] = level;
    // A thin blade its coverage left out (`shared::draw::look::clump::dress`) is dropped.
    let (mask, _) = unpack_coverage(drawn.tint.w);
    let (o, i) = tess_levels_if(level, mask != 0);
    *outer = o;
    *inner = i;
}

/// The natural look's blade surface, with its tint, coverage and width direction for
/// the fragment stage: the same at every vertex of a blade, so flat (no
/// interpolation to set up per triangle). Drawn this way with multisampling; at one
/// sample the natural look is shaded after the draw ([`natural_vis_tes`]).
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn natural_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    in_slot: [u32; 1],
    in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_normal: &mut Vec3,
    out_world: &mut Vec3,
    out_uv_level: &mut Vec3,
    #[spirv(flat)] out_tint: &mut Vec4,
    #[spirv(flat)] out_width_dir: &mut Vec3,
) {
    let drawn = &dressed[in_slot[0] as usize];
    let (p, v) = natural_point(frame, drawn, coord);
    *out_position = frame.camera.view_proj * p.position.extend(1.0);
    *out_normal = p.normal;
    *out_world = p.position;
    *out_uv_level = Vec3::new(coord.x, v, in_level[0]);
    *out_tint = drawn.tint;
    *out_width_dir = p.width_dir;
}

/// The natural look drawn for shading after the draw (one sample per pixel,
/// `shared::draw::look::visibility`): each vertex's surface coordinates and, flat,
/// the blade's slot; nothing to shade with.
#[allow(clippy::too_many_arguments)]
#[spirv(tessellation_evaluation(quads, spacing_fraction_odd, vertex_order_ccw))]
pub fn natural_vis_tes(
    #[spirv(tess_coord)] coord: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    in_slot: [u32; 1],
    _in_level: [f32; 1],
    #[spirv(position)] out_position: &mut Vec4,
    out_uv: &mut Vec4,
    #[spirv(flat)] out_slot: &mut f32,
) {
    let slot = in_slot[0];
    let (p, v) = natural_point(frame, &dressed[slot as usize], coord);
    *out_position = frame.camera.view_proj * p.position.extend(1.0);
    *out_uv = Vec4::new(coord.x, v, coord.z, 0.0);
    *out_slot = slot as f32;
}

/// The natural look's fragment at one sample: which blade and where on it, packed
/// into the colour (`visibility::pack`) for `compute::shade::shade_natural`.
#[spirv(fragment)]
pub fn natural_vis_fs(uv: Vec4, #[spirv(flat)] slot: f32, out_color: &mut Vec4) {
    *out_color = visibility::pack(slot as u32, uv.xy());
}

/// The paper look's vertex of a strip or a tessellated patch at (u, t, _): clip
/// position, and the normal with its row's v (`shape::row_point`) tagged with the
/// blade's species (the varyings of both paths), the world position and that v.
pub(crate) fn paper_vertex(
    frame: &FrameUniforms,
    blade: &Blade,
    uvl: Vec3,
) -> (Vec4, Vec4, Vec3, f32) {
    let grass = &frame.grass;
    let kind = (shared::species::of(blade), grass.mixed != 0);
    let (p, v, species) = row_point(blade, kind, (uvl.x, uvl.y), grass.shape, grass.tip_start);
    let clip = frame.camera.view_proj * p.position.extend(1.0);
    let tagged = shared::species::tag_v(v, species);
    (clip, p.normal.extend(tagged), p.position, v)
}

/// The natural look's surface point of a strip or a tessellated patch at (u, t, _) on
/// the `drawn` blade, and its row's v (`species::row_v` of its species, from its
/// coverage). The paper look's stages draw grass alone in the field's shape
/// ([`paper_vertex`], `shape::row_point`); the natural look's measured no faster so.
pub(crate) fn natural_point(
    frame: &FrameUniforms,
    drawn: &DressedBlade,
    uvl: Vec3,
) -> (SurfacePoint, f32) {
    let grass = &frame.grass;
    let v = row_v(coverage_species(drawn.tint.w), uvl.y);
    let p = surface_point(&drawn.blade, uvl.x, v, grass.shape, grass.tip_start);
    (p, v)
}

/// The own motion of a blade's `point` at height `v`, from the previous control
/// points at `slot` of the motion buffer
/// (`shared::draw::temporal::blade_point_motion`); nil while temporal anti-aliasing is
/// off (the buffer is not read).
pub(crate) fn point_motion(
    frame: &FrameUniforms,
    motion: &[BladeMotion],
    slot: usize,
    point: Vec3,
    v: f32,
    blade: &Blade,
) -> Vec2 {
    if frame.temporal.on == 0 {
        return Vec2::ZERO;
    }
    blade_point_motion(&frame.temporal, point, v, blade, &motion[slot])
}

/// The natural look: the blade's tint and drier tip, its leaf rounded across the
/// width, sky light with ambient occlusion, the sun (direct, through the leaf,
/// specular) with its shadow, fog. The LOD and wireframe views are
/// [`natural_view_fs`].
#[allow(clippy::too_many_arguments)]
#[spirv(fragment)]
pub fn natural_fs(
    normal: Vec3,
    world: Vec3,
    uv_level: Vec3,
    #[spirv(flat)] tint: Vec4,
    #[spirv(flat)] width_dir: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &ShadowMap,
    #[spirv(descriptor_set = 0, binding = 10)] shadow_sampler: &Sampler,
    out_color: &mut Vec4,
) {
    let leaf = Leaf {
        normal,
        world,
        uv: uv_level.truncate(),
        tint,
        width_dir,
    };
    *out_color = natural_colour(frame, shadow_map, shadow_sampler, &leaf).extend(1.0);
}

/// The natural look's LOD and wireframe views, as in the paper look.
#[spirv(fragment)]
pub fn natural_view_fs(
    normal: Vec3,
    world: Vec3,
    uv_level: Vec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    out_color: &mut Vec4,
) {
    let n = normal.normalize_or_zero();
    let facing = facing_normal(n, n.dot(frame.camera.position - world) >= 0.0);
    let (view, light) = (frame.grass.view, frame.light);
    *out_color = blade_colour(view, facing, light, uv_level.y, uv_level.z).extend(1.0);
}

/// A point of a blade as the natural look shades it.
pub(crate) struct Leaf {
    /// Surface normal (either face, not unit).
    pub normal: Vec3,
    /// World position.
    pub world: Vec3,
    /// (u across, v along) the blade.
    pub uv: Vec2,
    /// The dressed blade's tint and coverage (`shared::draw::look::clump::dress`).
    pub tint: Vec4,
    /// The blade's width direction.
    pub width_dir: Vec3,
}

/// The natural look's colour of `leaf`: the blade's tint and drier tip, its leaf rounded
/// across the width, sky light with ambient occlusion, the sun (direct, through the
/// leaf, specular) with its shadow, fog. The fragment stage's and the compute
/// rasterizer's resolve's.
pub(crate) fn natural_colour(
    frame: &FrameUniforms,
    shadow_map: &ShadowMap,
    shadow_sampler: &Sampler,
    leaf: &Leaf,
) -> Vec3 {
    let n = leaf.normal.normalize_or_zero();
    let (_, density) = unpack_coverage(leaf.tint.w);
    let to_camera = frame.camera.position - leaf.world;
    let distance = to_camera.length();
    let to_eye = to_camera / distance.max(1e-6);
    let facing = facing_normal(n, n.dot(to_eye) >= 0.0);
    let rounded = rounded_normal(facing, leaf.width_dir, leaf.uv.x);
    let albedo = species_albedo(leaf.tint.xyz(), leaf.uv.y, coverage_species(leaf.tint.w));
    let occlusion = ambient_occlusion(leaf.uv.y, density);
    let sun = sun_shadow(frame, shadow_map, shadow_sampler, leaf.world);
    let to_light = frame.light.direction;
    let lit = shade_leaf(albedo, rounded, to_light, to_eye, occlusion, sun);
    fog(lit, distance, -to_eye, to_light, frame.look.fog_density)
}

/// Blade `index` as it casts its shadow (`clump::caster_blade`): read from the blade
/// and clump buffers, named by its id in a tiled field.
pub(crate) fn caster(
    frame: &FrameUniforms,
    blades: &[Blade],
    clumps: &[Vec4],
    ids: &[u32],
    index: u32,
) -> Blade {
    let i = index as usize;
    let id = if frame.grass.tiled != 0 {
        ids[IDS_WORDS * i]
    } else {
        index
    };
    caster_blade(&blades[i], &Clump::unpack(clumps[i]), id, frame.look.seed)
}

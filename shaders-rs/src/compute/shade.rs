//! The natural look shaded after the draw (`shared::draw::look::visibility`): one
//! thread per pixel finds the blade the draw packed there and shades it.

use crate::ShadowMap;
use crate::grass::{Leaf, natural_colour, point_motion};
use shared::draw::look::clump::DressedBlade;
use shared::draw::look::visibility;
use shared::draw::shape::surface_point;
use shared::draw::temporal::BladeMotion;
use shared::gpu::layout::FrameUniforms;
use spirv_std::glam::{UVec3, Vec4};
use spirv_std::{Image, Sampler, spirv};

/// One thread per pixel: where the HDR image holds a blade's packed visibility, the
/// blade's surface at that (u, v) (`shape::surface_point`, the geometry stages'
/// function) shaded as the natural look's fragment stage would
/// (`grass::natural_colour`), in place; with temporal anti-aliasing every pixel's
/// own motion into `motion` (the blade's, `temporal::blade_point_motion`; nil
/// elsewhere). Workgroups of `layout::TEMPORAL_WORKGROUP` squared.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn shade_natural(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &ShadowMap,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(descriptor_set = 0, binding = 10)] shadow_sampler: &Sampler,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 24)] blade_motion: &[BladeMotion],
    #[spirv(descriptor_set = 1, binding = 0)] hdr: &Image!(2D, format = rgba16f, sampled = false),
    #[spirv(descriptor_set = 1, binding = 1)] motion: &Image!(
        2D,
        format = rgba16f,
        sampled = false
    ),
) {
    let texel = id.truncate();
    if texel.x >= frame.raster.width || texel.y >= frame.raster.height {
        return;
    }
    let drawn: Vec4 = hdr.read(texel);
    let mut own = Vec4::ZERO;
    if visibility::is_packed(drawn) {
        let (slot, uv) = visibility::unpack(drawn);
        let blade = &dressed[slot as usize];
        let grass = &frame.grass;
        let p = surface_point(&blade.blade, uv.x, uv.y, grass.shape, grass.tip_start);
        let leaf = Leaf {
            normal: p.normal,
            world: p.position,
            uv,
            tint: blade.tint,
            width_dir: p.width_dir,
        };
        let colour = natural_colour(frame, shadow_map, shadow_sampler, &leaf);
        unsafe { hdr.write(texel, colour.extend(1.0)) };
        let moved = point_motion(
            frame,
            blade_motion,
            slot as usize,
            p.position,
            uv.y,
            &blade.blade,
        );
        own = moved.extend(0.0).extend(0.0);
    }
    if frame.temporal.on != 0 {
        unsafe { motion.write(texel, own) };
    }
}

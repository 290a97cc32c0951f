//! The natural look shaded after the draw (`shared::draw::look::visibility`): one
//! thread per pixel finds the blade the draw packed there, or the far blade the
//! compute rasterizer left in front of it, and shades it.

use crate::ShadowMap;
use crate::grass::{Leaf, natural_colour, point_motion};
use shared::draw::look::clump::DressedBlade;
use shared::draw::look::visibility;
use shared::draw::raster::{pixel_index, unpack_words};
use shared::draw::shade::VIEW_SHADED;
use shared::draw::shape::surface_point;
use shared::draw::temporal::{BladeMotion, motion_over, pixel_centre};
use shared::gpu::counters::far_slot;
use shared::gpu::layout::{FrameUniforms, RASTER_DRAW};
use spirv_std::glam::{UVec2, UVec3, Vec2, Vec3, Vec4};
use spirv_std::{Image, Sampler, spirv};

/// One thread per pixel: where the HDR image holds a blade's packed visibility, the
/// blade's surface at that (u, v) (`shape::surface_point`, the geometry stages'
/// function) shaded as the natural look's fragment stage would
/// (`grass::natural_colour`), in place; with temporal anti-aliasing every pixel's
/// own motion into `motion` (the blade's, `temporal::blade_point_motion`; nil
/// elsewhere). Where the compute rasterizer left a far blade (`shared::draw::raster`:
/// only in front of the hardware's depth), that blade at the centre of its width
/// instead, as its resolve would have drawn it, so the natural look's far blades
/// need no rendering scope of their own; its motion is the camera's of its own
/// depth, which the depth buffer lacks (`temporal::motion_over`). Workgroups of
/// `layout::TEMPORAL_WORKGROUP` squared.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn shade_natural(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &ShadowMap,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(descriptor_set = 0, binding = 10)] shadow_sampler: &Sampler,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] far: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 16)] raster_args: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &[f32],
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
    let shade = |blade: &DressedBlade, uv: Vec2| {
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
        p.position
    };
    let pixel = pixel_index(texel.x, texel.y, frame.raster.width);
    // The far blades are this pass's where the draw left them to it (`passes::draw`):
    // the shaded view, with the rasterizer on and blades for it this frame.
    let far_here = frame.grass.view == VIEW_SHADED
        && frame.raster.below > 0.0
        && raster_args[RASTER_DRAW] != 0;
    let far_blade = if far_here {
        unpack_words(far[2 * pixel], far[2 * pixel + 1])
    } else {
        None
    };
    let mut own = Vec4::ZERO;
    if let Some((depth, k, v)) = far_blade {
        let slot = far_slot(k, frame.grass.blades) as usize;
        shade(&dressed[slot], Vec2::new(0.5, v));
        if frame.temporal.on != 0 {
            let size = UVec2::new(frame.raster.width, frame.raster.height);
            let (_, ndc) = pixel_centre(texel, size);
            let moved = motion_over(ndc, depth, hardware[pixel], &frame.temporal);
            own = moved.extend(0.0).extend(0.0);
        }
    } else if visibility::is_packed(drawn) {
        let (slot, uv) = visibility::unpack(drawn);
        let blade = &dressed[slot as usize];
        let position: Vec3 = shade(blade, uv);
        let moved = point_motion(
            frame,
            blade_motion,
            slot as usize,
            position,
            uv.y,
            &blade.blade,
        );
        own = moved.extend(0.0).extend(0.0);
    }
    if frame.temporal.on != 0 {
        unsafe { motion.write(texel, own) };
    }
}

//! The compute rasterizer's resolve (`shared::raster`): a full-screen triangle in a
//! second rendering scope on the frame's images, after the hardware-drawn grass and
//! ground and the rasterizer. Each pixel a far blade won in the visibility buffer is
//! shaded with the fragment stages' functions at the blade's point and written with
//! its depth, so the depth test composites it with what the hardware drew, sample by
//! sample; the other pixels are discarded.

use crate::ShadowMap;
use crate::grass::{Leaf, natural_colour};
use shared::Blade;
use shared::draw::look::clump::DressedBlade;
use shared::draw::raster::{EMPTY, pixel_index, unpack};
use shared::draw::shade::{facing_normal, shade_species};
use shared::draw::shape::{SurfacePoint, surface_point};
use shared::gpu::counters::far_slot;
use shared::gpu::layout::FrameUniforms;
use spirv_std::arch::kill;
use spirv_std::glam::{Vec2, Vec3, Vec4};
use spirv_std::{Sampler, spirv};

/// The LOD view's colour of the blades the compute rasterizer drew (the hardware's are
/// coloured by their level, blue to red): white.
pub const COMPUTE_DRAWN: Vec3 = Vec3::new(1.0, 1.0, 1.0);

/// A triangle covering the screen.
#[spirv(vertex)]
pub fn resolve_vs(#[spirv(vertex_index)] vertex: u32, #[spirv(position)] out_position: &mut Vec4) {
    let x = if vertex == 1 { 3.0 } else { -1.0 };
    let y = if vertex == 2 { 3.0 } else { -1.0 };
    *out_position = Vec4::new(x, y, 0.0, 1.0);
}

/// This pixel's far blade in the visibility buffer: (depth, far slot, v); the
/// invocation is discarded where none won.
fn winner(coord: Vec4, frame: &FrameUniforms, visibility: &[u64]) -> (f32, u32, f32) {
    let value = visibility[pixel_index(coord.x as u32, coord.y as u32, frame.raster.width)];
    if value == EMPTY {
        kill();
    }
    let (depth, k, v) = unpack(value);
    (depth, far_slot(k, frame.grass.blades), v)
}

/// The point of `blade` at `v` on its centre line, turned towards the camera.
fn centre(blade: &Blade, v: f32, frame: &FrameUniforms) -> (SurfacePoint, Vec3) {
    let grass = &frame.grass;
    let p = surface_point(blade, 0.5, v, grass.shape, grass.tip_start);
    let front = p.normal.dot(frame.camera.position - p.position) >= 0.0;
    (p, facing_normal(p.normal, front))
}

/// The paper look: the far blade's pixel lit as the grass fragment stage lights it.
#[spirv(fragment(depth_replacing))]
pub fn resolve_paper_fs(
    #[spirv(frag_coord)] coord: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &[u64],
    #[spirv(frag_depth)] out_depth: &mut f32,
    out_color: &mut Vec4,
) {
    let (depth, slot, v) = winner(coord, frame, visibility);
    let blade = &blades[visible[slot as usize] as usize];
    let (_, facing) = centre(blade, v, frame);
    *out_depth = depth;
    let species = shared::species::of(blade);
    *out_color = shade_species(facing, frame.light, v, species).extend(1.0);
}

/// The LOD view: what the compute rasterizer drew, in [`COMPUTE_DRAWN`].
#[spirv(fragment(depth_replacing))]
pub fn resolve_lod_fs(
    #[spirv(frag_coord)] coord: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &[u64],
    #[spirv(frag_depth)] out_depth: &mut f32,
    out_color: &mut Vec4,
) {
    let (depth, _, _) = winner(coord, frame, visibility);
    *out_depth = depth;
    *out_color = COMPUTE_DRAWN.extend(1.0);
}

/// The natural look: the far blade's pixel shaded as the natural fragment stage shades
/// its dressed blade at the centre of its width.
#[allow(clippy::too_many_arguments)]
#[spirv(fragment(depth_replacing))]
pub fn resolve_natural_fs(
    #[spirv(frag_coord)] coord: Vec4,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &[u64],
    #[spirv(descriptor_set = 0, binding = 8)] shadow_map: &ShadowMap,
    #[spirv(descriptor_set = 0, binding = 10)] shadow_sampler: &Sampler,
    #[spirv(frag_depth)] out_depth: &mut f32,
    out_color: &mut Vec4,
) {
    let (depth, slot, v) = winner(coord, frame, visibility);
    let drawn = &dressed[slot as usize];
    let (p, _) = centre(&drawn.blade, v, frame);
    let leaf = Leaf {
        normal: p.normal,
        world: p.position,
        uv: Vec2::new(0.5, v),
        tint: drawn.tint,
        width_dir: p.width_dir,
    };
    *out_depth = depth;
    *out_color = natural_colour(frame, shadow_map, shadow_sampler, &leaf).extend(1.0);
}

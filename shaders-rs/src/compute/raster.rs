//! The compute rasterizer of far blades: preparation, the blades into the visibility
//! buffer, and the tally of their pixels.

use crate::{DepthImage, DepthImageMs};
use shared::Blade;
use shared::draw::look::clump::DressedBlade;
use shared::draw::look::coverage::unpack_coverage;
use shared::draw::raster::{Coverage, EMPTY, in_front, packed_depth, pixel_index, raster_blade};
use shared::gpu::counters::{
    COUNTER_FAR, COUNTER_RASTER_COVERED, COUNTER_RASTER_WRITTEN, far_slot,
};
use shared::gpu::layout::IDS_WORDS;
use shared::gpu::layout::{FrameUniforms, PreparePush, SIMULATE_WORKGROUP, flat_index};
use spirv_std::arch::{
    atomic_i_add, atomic_load, atomic_u_min, workgroup_memory_barrier_with_group_sync,
};
use spirv_std::glam::{UVec2, UVec3, Vec4};
use spirv_std::image::ImageWithMethods;
use spirv_std::image::sample_with::sample_index;
use spirv_std::memory::{Scope, Semantics};
use spirv_std::spirv;

/// The compute rasterizer (`shared::raster`), paper look: one thread per far blade,
/// its line or, where it is wide, its surface (`raster_blade`), into the visibility
/// buffer ([`RasterTarget::plot`]).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn raster_far(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] blades: &[Blade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; 2],
) {
    let k = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let mut target = RasterTarget {
        frame,
        visibility,
        hardware,
    };
    let mut pixels = (0, 0);
    if k < counters[COUNTER_FAR] {
        let index = visible[far_slot(k, frame.grass.blades) as usize];
        let blade = &blades[index as usize];
        let camera = &frame.camera;
        let shape = (frame.grass.shape, frame.grass.tip_start);
        let name = blade_name(index, frame, ids);
        let coverage = Coverage::of(blade, name, shape, camera.position, camera.focal_pixels);
        pixels = target.draw(blade, k, &coverage);
    }
    count_pixels(local, pixels, counters, tally);
}

/// [`raster_far`] for the natural look: the dressed blade, drawn if its coverage keeps
/// it (`shared::draw::look::clump::dress`).
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64)))]
pub fn raster_far_natural(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(local_invocation_index)] local: u32,
    #[spirv(num_workgroups)] workgroups: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] visible: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] counters: &mut [u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] dressed: &[DressedBlade],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 21)] ids: &[u32],
    #[spirv(workgroup)] tally: &mut [u32; 2],
) {
    let k = flat_index(id, workgroups, SIMULATE_WORKGROUP);
    let mut target = RasterTarget {
        frame,
        visibility,
        hardware,
    };
    let mut pixels = (0, 0);
    if k < counters[COUNTER_FAR] {
        let slot = far_slot(k, frame.grass.blades);
        let drawn = &dressed[slot as usize];
        let (mask, _) = unpack_coverage(drawn.tint.w);
        if mask != 0 {
            let (camera, shape) = (&frame.camera, (frame.grass.shape, frame.grass.tip_start));
            let focal = camera.focal_pixels;
            // The coverage hash of the blade's own name, as in the paper look: its
            // slot changes from frame to frame with the compaction's order.
            let name = blade_name(visible[slot as usize], frame, ids);
            let coverage = Coverage::of(&drawn.blade, name, shape, camera.position, focal);
            pixels = target.draw(&drawn.blade, k, &coverage);
        }
    }
    count_pixels(local, pixels, counters, tally);
}

/// Blade `index`'s name for the per-blade hashes: its index in a stored field, its
/// id (`tiles::blade_id`) in a tiled one.
fn blade_name(index: u32, frame: &FrameUniforms, ids: &[u32]) -> u32 {
    if frame.grass.tiled != 0 {
        ids[IDS_WORDS * index as usize]
    } else {
        index
    }
}

/// What the rasterizer draws into: the frame, the visibility buffer and the
/// hardware's depth.
struct RasterTarget<'a> {
    frame: &'a FrameUniforms,
    visibility: &'a mut [u64],
    hardware: &'a [f32],
}

impl RasterTarget<'_> {
    /// Far blade `k` into the visibility buffer (`raster_blade`). Returns (pixels
    /// covered, pixels written).
    fn draw(&mut self, blade: &Blade, k: u32, coverage: &Coverage) -> (u32, u32) {
        let (view_proj, params) = (self.frame.camera.view_proj, self.frame.raster);
        let mut written = 0;
        let covered = raster_blade(blade, k, coverage, view_proj, &params, |x, y, packed| {
            if self.plot(x, y, packed) {
                written += 1;
            }
        });
        (covered, written)
    }

    /// A far blade's sample into the visibility buffer, nearest first by atomic
    /// minimum: only where it is in front of the hardware's depth and of the value the
    /// pixel holds (`shared::draw::raster::in_front`), so a hidden pixel costs a load
    /// instead of an atomic. Returns whether it took the atomic.
    fn plot(&mut self, x: u32, y: u32, packed: u64) -> bool {
        let i = pixel_index(x, y, self.frame.raster.width);
        let held = unsafe {
            atomic_load::<u64, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                &self.visibility[i],
            )
        };
        let front = in_front(packed_depth(packed), self.hardware[i]) && packed < held;
        if front {
            unsafe {
                atomic_u_min::<u64, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut self.visibility[i],
                    packed,
                );
            }
        }
        front
    }
}

/// The compute rasterizer's preparation, one thread per pixel (an indirect dispatch,
/// none without far blades): the visibility buffer's pixel cleared, and the
/// hardware's depth copied from the depth target into the rasterizer's buffer
/// (`shared::gpu::layout::BINDING_DEPTH_IMAGE`).
#[spirv(compute(threads(8, 8)))]
pub fn raster_prepare(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &mut [f32],
    #[spirv(descriptor_set = 0, binding = 18)] depth: &DepthImage,
) {
    let params = &frame.raster;
    if id.x < params.width && id.y < params.height {
        let i = pixel_index(id.x, id.y, params.width);
        let texel: Vec4 = depth.fetch(UVec2::new(id.x, id.y));
        visibility[i] = EMPTY;
        hardware[i] = texel.x;
    }
}

/// [`raster_prepare`] under MSAA: the farthest of the pixel's samples of the
/// multisampled depth target (`shared::gpu::layout::BINDING_DEPTH_IMAGE_MS`), so a far
/// blade is hidden early only where every sample hides it.
#[spirv(compute(threads(8, 8)))]
pub fn raster_prepare_ms(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(push_constant)] push: &PreparePush,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] frame: &FrameUniforms,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 15)] visibility: &mut [u64],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 17)] hardware: &mut [f32],
    #[spirv(descriptor_set = 0, binding = 19)] depth: &DepthImageMs,
) {
    let params = &frame.raster;
    if id.x < params.width && id.y < params.height {
        let i = pixel_index(id.x, id.y, params.width);
        let mut farthest = 0.0f32;
        let mut s = 0;
        while s < push.samples {
            let texel: Vec4 = depth.fetch_with(UVec2::new(id.x, id.y), sample_index(s));
            farthest = farthest.max(texel.x);
            s += 1;
        }
        visibility[i] = EMPTY;
        hardware[i] = farthest;
    }
}

/// Adds this thread's (covered, written) pixels to the rasterizer's counters: summed
/// in workgroup memory, then one device atomic per workgroup and counter.
fn count_pixels(
    local: u32,
    (covered, written): (u32, u32),
    counters: &mut [u32],
    tally: &mut [u32; 2],
) {
    if local < 2 {
        tally[local as usize] = 0;
    }
    workgroup_memory_barrier_with_group_sync();
    if covered > 0 {
        unsafe {
            atomic_i_add::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[0],
                covered,
            );
        }
    }
    if written > 0 {
        unsafe {
            atomic_i_add::<u32, { Scope::Workgroup as u32 }, { Semantics::NONE.bits() }>(
                &mut tally[1],
                written,
            );
        }
    }
    workgroup_memory_barrier_with_group_sync();
    if local < 2 {
        let n = tally[local as usize];
        if n > 0 {
            let counter = if local == 0 {
                COUNTER_RASTER_COVERED
            } else {
                COUNTER_RASTER_WRITTEN
            };
            unsafe {
                atomic_i_add::<u32, { Scope::Device as u32 }, { Semantics::NONE.bits() }>(
                    &mut counters[counter],
                    n,
                );
            }
        }
    }
}

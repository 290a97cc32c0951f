//! What a field asks of a device, checked before any blade is generated: the largest
//! buffer's range, device memory, indirect draws.

use super::Field;
use crate::vulkan::Context;
use anyhow::{Result, bail};
use shared::Blade;
use shared::cull::lod::blades_per_chunk;
use shared::draw::look::clump::DressedBlade;
use shared::draw::meshlet::StripBlade;
use shared::draw::temporal::BladeMotion;

/// Device memory per blade: the blade, its collision strength, its index in the
/// visible and the casters' two lists, its slot in the dressed buffer, its clump, the
/// mesh path's level and binned slot, and its previous control points.
pub const DEVICE_BYTES_PER_BLADE: u64 = size_of::<Blade>() as u64
    + 4
    + 4
    + 8
    + size_of::<DressedBlade>() as u64
    + 16
    + 4
    + size_of::<StripBlade>() as u64
    + size_of::<BladeMotion>() as u64;

impl Field {
    /// Fails with a message naming the limit when `count` blades cannot fit this
    /// device's buffers; checked before any blade is generated.
    pub fn check_limits(ctx: &Context, count: u64) -> Result<()> {
        // The largest buffer: the dressed blades, one per blade at most.
        let per_blade = size_of::<DressedBlade>() as u64;
        let bytes = count * per_blade;
        let limits = &ctx.properties.limits;
        if count == 0 {
            bail!("the field needs at least one blade");
        }
        if bytes > u64::from(limits.max_storage_buffer_range) {
            bail!(
                "{count} blades need {bytes} bytes, more than this device's \
                 maxStorageBufferRange ({} bytes, {} blades); ask for fewer with --blades or --density",
                limits.max_storage_buffer_range,
                limits.max_storage_buffer_range / per_blade as u32
            );
        }
        // The blades, their strengths and their indices on the device; the host keeps
        // a copy of the blades while uploading them.
        let device_bytes = count * DEVICE_BYTES_PER_BLADE;
        let heap = ctx.largest_device_heap();
        if device_bytes > heap / 2 {
            bail!(
                "{count} blades need {} MiB of device memory, more than half of this device's \
                 largest device-local heap ({} MiB); ask for fewer with --blades or --density",
                device_bytes >> 20,
                heap >> 20
            );
        }
        let chunk_count = count.div_ceil(u64::from(blades_per_chunk()));
        if chunk_count > u64::from(limits.max_draw_indirect_count) {
            bail!(
                "{count} blades need {chunk_count} draws, more than this device's \
                 maxDrawIndirectCount ({}); ask for fewer with --blades or --density",
                limits.max_draw_indirect_count
            );
        }
        Ok(())
    }
}

//! The field's buffers made again while it lives: its blades replaced, its depth
//! pyramid resized for a new target.

use super::Field;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::{Buffer, Context};
use anyhow::{Result, bail};
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::Blade;
use shared::gpu::layout;
use shared::sim::grid::REACH_MARGIN;
use std::sync::Arc;

impl Field {
    /// Replaces the blades by `blades` (as many as before) at rest, with no collision
    /// strength left. No frame may be in flight.
    pub fn replace_blades(
        &mut self,
        ctx: &Arc<Context>,
        pool: &CommandPool,
        blades: &[Blade],
    ) -> Result<()> {
        if blades.len() as u32 != self.blade_count {
            bail!(
                "{} blades cannot replace a field of {}",
                blades.len(),
                self.blade_count
            );
        }
        use vk::BufferUsageFlags as U;
        let usage = U::STORAGE_BUFFER | U::TRANSFER_SRC;
        self.blades = Buffer::upload(ctx, pool, "blades", blades, usage)?;
        (self.reach, self.mixed) = stored_growth(blades);
        self.roots = root_range(blades);
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        self.descriptors
            .write_buffer(layout::BINDING_BLADES, storage, self.blades.buffer);
        // New blades: no trail, no cut.
        pool.one_shot(|rec| {
            rec.fill_buffer(self.strengths.buffer, 0);
            rec.fill_buffer(self.cuts.buffer, shared::sim::cut::NO_CELL);
        })
    }

    /// A tiled field grown as the species `mix` under the maps `paint` from now on:
    /// its reach and whether it may hold a species other than grass
    /// (`shared::world::paint::tallest` and `paint::mixed`).
    pub fn set_tiled_species(&mut self, paint: &[u32], mix: shared::species::Mix) {
        (self.reach, self.mixed) = tiled_growth(paint, mix);
    }

    pub(super) fn pyramid_buffer(ctx: &Arc<Context>, floats: u32) -> Result<Buffer> {
        use vk::BufferUsageFlags as U;
        Buffer::new(
            ctx,
            "depth pyramid",
            u64::from(floats.max(1)) * 4,
            U::STORAGE_BUFFER | U::TRANSFER_DST | U::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )
    }

    /// Replaces the depth pyramid with one of `floats` values. No frame may be in
    /// flight.
    pub fn resize_pyramid(&mut self, ctx: &Arc<Context>, floats: u32) -> Result<()> {
        self.pyramid = Self::pyramid_buffer(ctx, floats)?;
        self.descriptors.write_buffer(
            layout::BINDING_PYRAMID,
            vk::DescriptorType::STORAGE_BUFFER,
            self.pyramid.buffer,
        );
        Ok(())
    }
}

/// The lowest and highest height of `blades`' roots (`None` for no blade).
pub(super) fn root_range(blades: &[Blade]) -> Option<(f32, f32)> {
    let heights = blades.iter().map(|b| b.root().y);
    let low = heights.clone().fold(f32::INFINITY, f32::min);
    let high = heights.fold(f32::NEG_INFINITY, f32::max);
    (low <= high).then_some((low, high))
}

/// How far a stored field of `blades` reaches ([`Field::reach`]: its tallest, at
/// least a hundredth, times `REACH_MARGIN`) and whether one of them is of a species
/// other than grass ([`Field::mixed`]).
pub(super) fn stored_growth(blades: &[Blade]) -> (f32, bool) {
    let tallest = blades.iter().map(Blade::height).fold(0.01, f32::max);
    let mixed = blades
        .iter()
        .any(|b| shared::species::of(b) != shared::species::GRASS);
    (REACH_MARGIN * tallest, mixed)
}

/// [`stored_growth`] for a tiled field under the maps `paint` growing the species
/// `mix` (`shared::world::paint::tallest`, `paint::mixed`).
pub(super) fn tiled_growth(paint: &[u32], mix: shared::species::Mix) -> (f32, bool) {
    use shared::world::paint;
    (
        REACH_MARGIN * paint::tallest(paint, mix),
        paint::mixed(paint, mix),
    )
}

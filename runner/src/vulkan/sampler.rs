//! Samplers.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;
use std::sync::Arc;

/// A sampler, destroyed on drop.
pub struct Sampler {
    ctx: Arc<Context>,
    /// The sampler.
    pub sampler: vk::Sampler,
}

impl Sampler {
    /// Linear filtering, coordinates clamped to the edge.
    pub fn linear_clamped(ctx: &Arc<Context>) -> Result<Self> {
        Self::clamped(ctx, vk::Filter::LINEAR)
    }

    /// Nearest texel, coordinates clamped to the edge (depth maps, whose formats need
    /// not filter).
    pub fn nearest_clamped(ctx: &Arc<Context>) -> Result<Self> {
        Self::clamped(ctx, vk::Filter::NEAREST)
    }

    fn clamped(ctx: &Arc<Context>, filter: vk::Filter) -> Result<Self> {
        let clamp = vk::SamplerAddressMode::CLAMP_TO_EDGE;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(clamp)
            .address_mode_v(clamp)
            .address_mode_w(clamp)
            .max_lod(0.0);
        let sampler =
            unsafe { ctx.device.create_sampler(&info, None) }.context("create sampler")?;
        Ok(Self {
            ctx: ctx.clone(),
            sampler,
        })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_sampler(self.sampler, None) };
    }
}

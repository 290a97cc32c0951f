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
        Self::clamped(ctx, vk::Filter::LINEAR, None)
    }

    /// Nearest texel, coordinates clamped to the edge: an image read pixel for pixel.
    pub fn nearest_clamped(ctx: &Arc<Context>) -> Result<Self> {
        Self::clamped(ctx, vk::Filter::NEAREST, None)
    }

    /// A depth-comparison sampler for shadow maps of `format`: LESS_OR_EQUAL against
    /// the reference, coordinates clamped, bilinear over the four nearest results
    /// where the format can be filtered (else the nearest texel's).
    pub fn shadow_compare(ctx: &Arc<Context>, format: vk::Format) -> Result<Self> {
        let features = unsafe {
            ctx.instance
                .get_physical_device_format_properties(ctx.physical, format)
        }
        .optimal_tiling_features;
        let filter = if features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR) {
            vk::Filter::LINEAR
        } else {
            vk::Filter::NEAREST
        };
        Self::clamped(ctx, filter, Some(vk::CompareOp::LESS_OR_EQUAL))
    }

    /// A sampler of `filter`, coordinates clamped to the edge, one mip level, comparing
    /// against a reference with `compare` if given.
    fn clamped(
        ctx: &Arc<Context>,
        filter: vk::Filter,
        compare: Option<vk::CompareOp>,
    ) -> Result<Self> {
        let clamp = vk::SamplerAddressMode::CLAMP_TO_EDGE;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(clamp)
            .address_mode_v(clamp)
            .address_mode_w(clamp)
            .compare_enable(compare.is_some())
            .compare_op(compare.unwrap_or(vk::CompareOp::NEVER))
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

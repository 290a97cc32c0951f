//! The images the ground and grass draw into, beside the frame's target: the depth
//! image (also the occlusion pre-pass's), and for the natural look or MSAA a linear
//! HDR image and multisampled colour and depth.
//!
//! | look, samples | colour drawn into | resolved into | then |
//! |---|---|---|---|
//! | paper, 1 | the target | | |
//! | paper, N | multisampled, target format | the target | |
//! | natural, 1 | HDR | | tone map → target |
//! | natural, N | multisampled HDR | HDR | tone map → target |

use super::{Renderer, SKY, Target};
use crate::passes::DEPTH_FORMAT;
use crate::passes::draw::DrawImages;
use crate::vulkan::{Context, Image};
use anyhow::{Context as _, Result};
use ash::vk;
use std::sync::Arc;

/// Format of the natural look's linear HDR image.
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// What the targets are made for.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TargetSpec {
    /// Size in pixels.
    pub extent: vk::Extent2D,
    /// Drawn in linear HDR and tone-mapped (the natural look).
    pub hdr: bool,
    /// Samples per pixel.
    pub samples: u32,
}

/// The draw's images for one [`TargetSpec`].
pub struct DrawTargets {
    /// What they were made for.
    pub spec: TargetSpec,
    /// Single-sample depth: the occlusion pre-pass's, and the draw's without MSAA
    /// (read by the compute rasterizer's preparation).
    pub depth: Image,
    /// The resolved HDR image the tone map reads (natural look).
    pub hdr: Option<Image>,
    /// Multisampled colour (MSAA).
    pub color_ms: Option<Image>,
    /// Multisampled depth (MSAA).
    pub depth_ms: Option<Image>,
}

impl DrawTargets {
    /// The images of `spec`; `target_format` is the frame target's.
    pub fn new(ctx: &Arc<Context>, spec: TargetSpec, target_format: vk::Format) -> Result<Self> {
        use vk::ImageUsageFlags as U;
        let (extent, color, depth) = (
            spec.extent,
            vk::ImageAspectFlags::COLOR,
            vk::ImageAspectFlags::DEPTH,
        );
        let depth_image = Image::new(
            ctx,
            "depth",
            extent,
            DEPTH_FORMAT,
            // Copied into the pyramid, read for the compute rasterizer.
            U::DEPTH_STENCIL_ATTACHMENT | U::TRANSFER_SRC | U::SAMPLED,
            depth,
        )?;
        let hdr = spec
            .hdr
            .then(|| {
                let usage = U::COLOR_ATTACHMENT | U::SAMPLED;
                Image::new(ctx, "hdr", extent, HDR_FORMAT, usage, color)
            })
            .transpose()?;
        let samples = vk::SampleCountFlags::from_raw(spec.samples);
        let (color_ms, depth_ms) = if spec.samples > 1 {
            let format = if spec.hdr { HDR_FORMAT } else { target_format };
            let transient = U::TRANSIENT_ATTACHMENT;
            let c = Image::multisampled(
                ctx,
                "colour (MSAA)",
                extent,
                format,
                U::COLOR_ATTACHMENT | transient,
                color,
                samples,
            )?;
            // Read by the compute rasterizer's preparation (its farthest sample).
            let d = Image::multisampled(
                ctx,
                "depth (MSAA)",
                extent,
                DEPTH_FORMAT,
                U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED,
                depth,
                samples,
            )?;
            (Some(c), Some(d))
        } else {
            (None, None)
        };
        Ok(Self {
            spec,
            depth: depth_image,
            hdr,
            color_ms,
            depth_ms,
        })
    }

    /// Format of the colour the draw writes.
    pub fn draw_format(spec_hdr: bool, target_format: vk::Format) -> vk::Format {
        if spec_hdr { HDR_FORMAT } else { target_format }
    }
}

impl Renderer {
    /// The draw's images and the depth pyramid for `extent`, the look and `samples`
    /// (lowered to what the device has), and the pipelines that draw into them.
    pub(super) fn ensure_targets(
        &mut self,
        extent: vk::Extent2D,
        hdr: bool,
        samples: u32,
    ) -> Result<()> {
        let spec = TargetSpec {
            extent,
            hdr,
            samples: self.ctx.supported_samples(samples),
        };
        let old = self.targets.as_ref().map(|t| t.spec);
        if old == Some(spec) {
            return Ok(());
        }
        // The old images may still be in use by a frame in flight.
        self.ctx.wait_idle()?;
        self.targets = None;
        if old.is_none_or(|o| o.extent != extent) {
            self.occlusion.resize(&self.ctx, &mut self.field, extent)?;
            self.draw.raster.resize(&self.field, extent)?;
        }
        let targets = DrawTargets::new(&self.ctx, spec, self.color_format)?;
        let set = &self.field.descriptors;
        set.write_sampled_image(shared::gpu::layout::BINDING_DEPTH_IMAGE, targets.depth.view);
        if let Some(ms) = &targets.depth_ms {
            set.write_sampled_image(shared::gpu::layout::BINDING_DEPTH_IMAGE_MS, ms.view);
        }
        if let Some(hdr) = &targets.hdr {
            self.tonemap.set_source(hdr.view);
        }
        let drawn_into = (
            DrawTargets::draw_format(hdr, self.color_format),
            spec.samples,
        );
        self.draw
            .retarget(&self.ctx, &self.module, &self.field, drawn_into)?;
        if spec.samples != samples {
            log::warn!(
                "{samples} samples per pixel asked, the device has {} at most: using that",
                spec.samples
            );
        }
        self.targets = Some(targets);
        Ok(())
    }

    /// The single-sample depth image (image, view) for a target of `extent`, the
    /// frames' other draw images kept as they are.
    pub(crate) fn single_depth(
        &mut self,
        extent: vk::Extent2D,
    ) -> Result<(vk::Image, vk::ImageView)> {
        let spec = self.targets.as_ref().map(|t| (t.spec.hdr, t.spec.samples));
        let (hdr, samples) = spec.unwrap_or((false, 1));
        self.ensure_targets(extent, hdr, samples)?;
        let depth = &self.targets.as_ref().context("draw targets")?.depth;
        Ok((depth.image, depth.view))
    }
}

/// The images the draw writes for `target` (this module's table).
pub(super) fn draw_images<'t>(targets: &'t DrawTargets, target: &Target) -> DrawImages<'t> {
    let single = targets
        .hdr
        .as_ref()
        .map_or((target.image, target.view), |h| (h.image, h.view));
    let (color, resolve) = match &targets.color_ms {
        Some(ms) => ((ms.image, ms.view), Some(single)),
        None => (single, None),
    };
    DrawImages {
        color,
        resolve,
        depth: targets.depth_ms.as_ref().unwrap_or(&targets.depth),
        samples: targets.spec.samples,
        // The natural look's sky is drawn by the tone map where alpha leaves room.
        clear: if targets.hdr.is_some() { [0.0; 4] } else { SKY },
        extent: target.extent,
    }
}

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

use crate::passes::DEPTH_FORMAT;
use crate::vulkan::{Context, Image};
use anyhow::Result;
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

//! The images the ground and grass draw into, beside the frame's target: the depth
//! image (also the occlusion pre-pass's), for the natural look or MSAA a linear HDR
//! image and multisampled colour and depth, and for temporal anti-aliasing (TAA) the
//! motion target and two histories that take turns (one read, one written).
//!
//! | look, anti-aliasing | colour drawn into | resolved into | then |
//! |---|---|---|---|
//! | paper, none | the target | | |
//! | paper, MSAA | multisampled, target format | the target | |
//! | natural, none | HDR | | tone map → target |
//! | natural, MSAA | multisampled HDR | HDR | tone map → target |
//! | either, TAA | HDR and motion | a history (the resolve) | tone map → target |
//!
//! At one sample the natural look draws its blades' visibility into the HDR image
//! and shades it after the draw (`passes::shade`, which writes the motion with TAA):
//! the HDR image is also a storage image, the motion image one the shading writes
//! (four half floats) rather than a colour target.

use super::{Renderer, SKY, Target};
use crate::passes::by_target::{DrawTarget, MOTION_FORMAT};
use crate::passes::draw::DrawImages;
use crate::passes::temporal::TemporalImages;
use crate::passes::tonemap::{ToneMapPass, ToneMapSource};
use crate::passes::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vulkan::{Context, Image, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use shared::gpu::layout::FrameUniforms;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// What the targets are made for.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TargetSpec {
    /// Size in pixels.
    pub extent: vk::Extent2D,
    /// Drawn in linear HDR and tone-mapped (the natural look; either look with TAA).
    pub hdr: bool,
    /// Samples per pixel.
    pub samples: u32,
    /// Temporal anti-aliasing: a motion target and the histories.
    pub taa: bool,
    /// The natural look shaded after the draw (`passes::shade`), asked; kept only
    /// at one sample per pixel.
    pub deferred: bool,
    /// The caller's depth is reversed (1 near, 0 far; [`DrawTarget::reverse_z`]).
    pub reverse_z: bool,
    /// Drawn smaller than the frame's target, which takes blits: the tone map writes
    /// [`DrawTargets::shown`] at the drawn size, blitted up to the target, instead of
    /// running over every pixel of the target.
    pub shown: bool,
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
    /// Each pixel's motion (TAA; `passes::by_target::MOTION_FORMAT`).
    pub motion: Option<Image>,
    /// The resolved frames, HDR: one read as the history while the other is written
    /// (TAA).
    pub history: Option<[Image; 2]>,
    /// The frame tone-mapped at the drawn size, in the target's format, blitted up to
    /// the target ([`TargetSpec::shown`]).
    pub shown: Option<Image>,
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
                let shaded = if spec.deferred {
                    U::STORAGE
                } else {
                    U::empty()
                };
                let usage = U::COLOR_ATTACHMENT | U::SAMPLED | shaded;
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
        let motion = if spec.deferred {
            // Written by the shading (a storage format every device has), then left
            // in the colour attachment's layout as the draw leaves its targets.
            let usage = U::STORAGE | U::SAMPLED | U::COLOR_ATTACHMENT;
            Some(Image::new(ctx, "motion", extent, HDR_FORMAT, usage, color)?)
        } else if spec.taa {
            let usage = U::COLOR_ATTACHMENT | U::SAMPLED;
            Some(Image::new(
                ctx,
                "motion",
                extent,
                MOTION_FORMAT,
                usage,
                color,
            )?)
        } else {
            None
        };
        let history = if spec.taa {
            let usage = U::STORAGE | U::SAMPLED;
            let history = [
                Image::new(ctx, "history 0", extent, HDR_FORMAT, usage, color)?,
                Image::new(ctx, "history 1", extent, HDR_FORMAT, usage, color)?,
            ];
            Some(history)
        } else {
            None
        };
        let shown = spec
            .shown
            .then(|| {
                let usage = U::COLOR_ATTACHMENT | U::TRANSFER_SRC;
                Image::new(ctx, "shown", extent, target_format, usage, color)
            })
            .transpose()?;
        Ok(Self {
            spec,
            depth: depth_image,
            hdr,
            color_ms,
            depth_ms,
            motion,
            history,
            shown,
        })
    }

    /// The images the temporal resolve reads and writes, with TAA.
    pub fn temporal(&self) -> Option<TemporalImages<'_>> {
        Some(TemporalImages {
            hdr: self.hdr.as_ref()?,
            motion: self.motion.as_ref()?,
            depth: &self.depth,
            history: self.history.as_ref()?,
        })
    }

    /// The HDR and motion images the natural look's shading after the draw writes,
    /// where it is shaded so.
    pub fn shaded(&self) -> Option<(&Image, &Image)> {
        match self.spec.deferred {
            true => Some((self.hdr.as_ref()?, self.motion.as_ref()?)),
            false => None,
        }
    }

    /// Format of the colour the draw writes.
    pub fn draw_format(spec_hdr: bool, target_format: vk::Format) -> vk::Format {
        if spec_hdr { HDR_FORMAT } else { target_format }
    }
}

impl Renderer {
    /// The draw's images and the depth pyramid for `spec` (its samples lowered to
    /// what the device has), and the pipelines that draw into them.
    pub(super) fn ensure_targets(&mut self, spec: TargetSpec) -> Result<()> {
        let (extent, hdr, samples) = (spec.extent, spec.hdr, spec.samples);
        let lowered = self.ctx.supported_samples(samples);
        let spec = TargetSpec {
            samples: lowered,
            deferred: spec.deferred && lowered == 1,
            ..spec
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
        self.tonemap
            .set_sources(targets.hdr.as_ref(), targets.temporal());
        if let Some(images) = targets.temporal() {
            self.temporal_pass.set_images(images, &self.field);
        }
        if let Some((hdr, motion)) = targets.shaded() {
            self.shade.set_images(hdr, motion);
        }
        let drawn_into = DrawTarget {
            format: DrawTargets::draw_format(hdr, self.color_format),
            samples: vk::SampleCountFlags::from_raw(spec.samples),
            motion: spec.taa && !spec.deferred,
            deferred: spec.deferred,
            reverse_z: spec.reverse_z,
        };
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
    // Used by the program (`app`).
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    pub(crate) fn single_depth(
        &mut self,
        extent: vk::Extent2D,
    ) -> Result<(vk::Image, vk::ImageView)> {
        let spec = match self.targets.as_ref() {
            Some(t) => TargetSpec { extent, ..t.spec },
            None => TargetSpec {
                extent,
                hdr: false,
                samples: 1,
                taa: false,
                deferred: false,
                reverse_z: false,
                shown: false,
            },
        };
        self.ensure_targets(spec)?;
        let depth = &self.targets.as_ref().context("draw targets")?.depth;
        Ok((depth.image, depth.view))
    }
}

/// The images the draw writes for `target` (this module's table), in the `natural`
/// look or not.
pub(super) fn draw_images<'t>(
    targets: &'t DrawTargets,
    target: &Target,
    drawn: vk::Extent2D,
    natural: bool,
) -> DrawImages<'t> {
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
        // Shaded after the draw, the motion is no colour target.
        motion: match targets.spec.deferred {
            true => None,
            false => targets.motion.as_ref().map(|m| (m.image, m.view)),
        },
        samples: targets.spec.samples,
        // The natural look's sky is drawn by the tone map where alpha leaves room.
        clear: if natural { [0.0; 4] } else { SKY },
        extent: drawn,
    }
}

/// Leaves the frame's target in its final layout, its pixels first copied to
/// `capture` if given.
pub(super) fn finish_frame(rec: &Recorder, target: &Target, capture: Option<vk::Buffer>) {
    let copy_layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    match capture {
        Some(buffer) => {
            // Copied from the transfer layout, then left in the target's own (a
            // swapchain image's screenshot goes back to presentable).
            let copied = Target {
                final_layout: copy_layout,
                ..*target
            };
            finish_target(rec, &copied);
            let color = vk::ImageAspectFlags::COLOR;
            rec.copy_image_to_buffer(target.image, color, target.extent, buffer);
            rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
            if target.final_layout != copy_layout {
                rec.image_barrier(
                    target.image,
                    color,
                    (copy_layout, target.final_layout),
                    (S::COPY, A::TRANSFER_READ),
                    (S::NONE, A::NONE),
                );
            }
        }
        None => finish_target(rec, target),
    }
}

/// Tone-maps `source` (drawn at `drawn` pixels) into the frame's `target` (except
/// over `hidden`), or, where the targets have a [`DrawTargets::shown`] image, into
/// that at the drawn size, blitted up to the target.
pub(super) fn tone_map(
    rec: &Recorder,
    pass: &ToneMapPass,
    targets: &DrawTargets,
    (source, drawn): (ToneMapSource, vk::Extent2D),
    (target, uniforms, hidden): (&Target, &FrameUniforms, Option<vk::Rect2D>),
) {
    match targets.shown.as_ref() {
        Some(shown) => {
            let at_drawn = (shown.image, shown.view, drawn);
            pass.record(rec, (source, drawn), at_drawn, uniforms, None);
            blit_up(rec, shown, target);
        }
        None => {
            let out = (target.image, target.view, target.extent);
            pass.record(rec, (source, drawn), out, uniforms, hidden);
        }
    }
}

/// Blits `shown` (the frame tone-mapped at its drawn size, just rendered) up to the
/// whole `target`, each pixel the nearest of `shown`'s, as the tone map's own fetch
/// scales; the target is left as the tone map leaves it, a colour attachment written.
fn blit_up(rec: &Recorder, shown: &Image, target: &Target) {
    let color = vk::ImageAspectFlags::COLOR;
    let written = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    let blit_read = (S::BLIT, A::TRANSFER_READ);
    let blit_write = (S::BLIT, A::TRANSFER_WRITE);
    let (src, dst) = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    let attachment = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    rec.image_barrier(shown.image, color, (attachment, src), written, blit_read);
    let before = (S::COLOR_ATTACHMENT_OUTPUT, A::NONE);
    let undefined = vk::ImageLayout::UNDEFINED;
    rec.image_barrier(target.image, color, (undefined, dst), before, blit_write);
    rec.blit_nearest((shown.image, shown.extent), (target.image, target.extent));
    rec.image_barrier(target.image, color, (dst, attachment), blit_write, written);
    // Written again as an attachment by the next frame's tone map.
    rec.image_barrier(shown.image, color, (src, attachment), blit_read, written);
}

/// Leaves the target in its final layout.
fn finish_target(rec: &Recorder, target: &Target) {
    let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    let (dst, dst_access) = match target.final_layout {
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL => (S::COPY, A::TRANSFER_READ),
        // A host-linear image, read by the host once the frame is done.
        vk::ImageLayout::GENERAL => (S::HOST, A::HOST_READ),
        _ => (S::NONE, A::NONE),
    };
    rec.image_barrier(
        target.image,
        vk::ImageAspectFlags::COLOR,
        (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            target.final_layout,
        ),
        color_out,
        (dst, dst_access),
    );
}

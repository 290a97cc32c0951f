//! The last pass before the overlay: a grid of cells over the screen that puts the
//! sky (or the meadow beyond the field) behind the scene in the HDR image, where its
//! alpha leaves room, and tone-maps it into the sRGB target
//! (`shared::draw::look::sky::tone_map`, Narkowicz's ACES fit). The sky is evaluated at
//! the grid's corners and interpolated; the sun disc and the tone map run per pixel.
//! With temporal anti-aliasing it reads the history the resolve wrote
//! ([`super::temporal`]), in either look: the paper look's is then shown as drawn (no
//! sky, no tone map).

use super::area::around;
use super::temporal::TemporalImages;
use super::to_sampled;
use crate::shaders;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::{Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use shared::gpu::layout::{FrameUniforms, ToneMapPush};
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The tone map's own set: the HDR image.
pub const BINDINGS: [BindingSpec; 1] = [BindingSpec {
    binding: 0,
    ty: vk::DescriptorType::SAMPLED_IMAGE,
    stages: vk::ShaderStageFlags::FRAGMENT,
}];

/// Push-constant range of the tone map's layout.
pub const PUSH_CONSTANTS: (vk::ShaderStageFlags, u32) = (
    vk::ShaderStageFlags::from_raw(
        vk::ShaderStageFlags::VERTEX.as_raw() | vk::ShaderStageFlags::FRAGMENT.as_raw(),
    ),
    size_of::<ToneMapPush>() as u32,
);

/// The tone-map pipeline and the sets naming its sources: the HDR image, and with
/// temporal anti-aliasing each history.
pub struct ToneMapPass {
    set: DescriptorSet,
    history_sets: [DescriptorSet; 2],
    layout: PipelineLayout,
    pipeline: Pipeline,
}

/// What the tone map reads: the HDR image as drawn, or history k (temporal
/// anti-aliasing).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ToneMapSource {
    /// The HDR image as drawn (from the draw's attachment to sampled here).
    Drawn {
        /// The image.
        image: vk::Image,
        /// Shown as drawn (the paper look drawn smaller than the target).
        as_drawn: bool,
    },
    /// A history, left sampled by the resolve.
    History {
        /// Which.
        k: usize,
        /// The frame shown as drawn (the paper look).
        as_drawn: bool,
    },
}

impl ToneMapPass {
    /// The pipeline for a target of `format`.
    pub fn new(ctx: &Arc<Context>, module: &ShaderModules, format: vk::Format) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let set = DescriptorSet::new(ctx, &BINDINGS)?;
        let layout = PipelineLayout::new(ctx, set.layout, PUSH_CONSTANTS)?;
        let stages = [
            (St::VERTEX, shaders::TONEMAP_VS),
            (St::FRAGMENT, shaders::TONEMAP_FS),
        ];
        let mut desc =
            GraphicsDesc::patches(module, &stages, &layout, format, vk::Format::UNDEFINED);
        desc.patch_control_points = 0;
        let pipeline = Pipeline::graphics(ctx, &desc)?;
        let history_sets = [
            DescriptorSet::new(ctx, &BINDINGS)?,
            DescriptorSet::new(ctx, &BINDINGS)?,
        ];
        Ok(Self {
            set,
            history_sets,
            layout,
            pipeline,
        })
    }

    /// Reads `hdr` (and with temporal anti-aliasing the `temporal` histories) from now
    /// on, each in SHADER_READ_ONLY_OPTIMAL. No frame may be in flight.
    pub fn set_sources(&self, hdr: Option<&Image>, temporal: Option<TemporalImages>) {
        if let Some(hdr) = hdr {
            self.set.write_sampled_image(0, hdr.view);
        }
        if let Some(t) = temporal {
            for (set, history) in self.history_sets.iter().zip(t.history) {
                set.write_sampled_image(0, history.view);
            }
        }
    }

    /// Puts the sky behind `source` (drawn at `drawn` pixels) and tone-maps it into
    /// `target` (image, view, extent; larger where the frame was drawn smaller: each
    /// pixel takes the nearest), for the frame of `uniforms`, except over `hidden`
    /// (what the overlay will cover); the target from undefined to attachment.
    pub fn record(
        &self,
        rec: &Recorder,
        (source, drawn): (ToneMapSource, vk::Extent2D),
        target: (vk::Image, vk::ImageView, vk::Extent2D),
        uniforms: &FrameUniforms,
        hidden: Option<vk::Rect2D>,
    ) {
        let (set, as_drawn) = match source {
            ToneMapSource::Drawn { image, as_drawn } => {
                to_sampled(rec, image, (S::FRAGMENT_SHADER, A::SHADER_READ));
                (&self.set, as_drawn)
            }
            ToneMapSource::History { k, as_drawn } => (&self.history_sets[k], as_drawn),
        };
        rec.image_barrier(
            target.0,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::NONE),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
        );
        rec.begin_rendering(Some((target.1, None)), None, target.2);
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        let layout = self.layout.layout;
        rec.bind_pipeline(graphics, self.pipeline.pipeline, layout, set.set);
        let scale = |d: u32, t: u32| d as f32 / t.max(1) as f32;
        let source = (
            scale(drawn.width, target.2.width),
            scale(drawn.height, target.2.height),
        );
        let push = push(uniforms, as_drawn, source);
        rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        let whole = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: target.2,
        };
        match hidden {
            // The grid once per rectangle around what is hidden, each scissored.
            Some(hidden) => {
                for area in around(whole, hidden) {
                    rec.set_scissor(area);
                    rec.draw(0, shared::gpu::layout::TONEMAP_VERTICES);
                }
            }
            None => rec.draw(0, shared::gpu::layout::TONEMAP_VERTICES),
        }
        rec.end_rendering();
    }
}

/// The tone map's constants for the frame of `uniforms`; `as_drawn`: the frame shown
/// as drawn (no sky, no tone map); `source`: the source's pixels per target pixel.
fn push(uniforms: &FrameUniforms, as_drawn: bool, source: (f32, f32)) -> ToneMapPush {
    let camera = &uniforms.camera;
    ToneMapPush {
        clip_to_world: camera.view_proj.inverse(),
        camera: camera.position.extend(uniforms.look.exposure),
        sun: uniforms
            .light
            .direction
            .extend(f32::from(u8::from(as_drawn))),
        ground: shared::draw::look::ground::horizon_ground(&uniforms.look),
        source: glam::Vec4::new(source.0, source.1, 0.0, 0.0),
    }
}

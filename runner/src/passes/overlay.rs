//! The overlay: egui's tessellated output drawn over the frame, with rust-gpu shaders
//! like every other pass. Textures (the font atlas) are uploaded as egui changes
//! them; vertices and indices go through a host-visible buffer per frame slot.

use crate::shaders;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::sampler::Sampler;
use crate::vulkan::{Buffer, Context, Image, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use egui::epaint::{ImageDelta, Primitive, Vertex};
use egui::{ClippedPrimitive, TextureId, TexturesDelta};
use gpu_allocator::MemoryLocation;
use shared::gpu::layout::OverlayPush;
use std::collections::HashMap;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The overlay's one binding: the texture of a mesh (fragment stage).
pub const BINDINGS: [BindingSpec; 1] = [BindingSpec {
    binding: 0,
    ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
    stages: vk::ShaderStageFlags::FRAGMENT,
}];

/// Texture format: egui's colours are sRGB with premultiplied alpha.
const TEXTURE_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// What egui produced for one frame.
pub struct OverlayFrame<'a> {
    /// Meshes, each with its clip rectangle (in points).
    pub primitives: &'a [ClippedPrimitive],
    /// Textures to create, update or free.
    pub textures: &'a TexturesDelta,
    /// Pixels per egui point.
    pub pixels_per_point: f32,
}

struct Texture {
    image: Image,
    set: DescriptorSet,
}

/// Per-slot vertex and index buffers, grown as needed.
#[derive(Default)]
struct Geometry {
    vertices: Option<Buffer>,
    indices: Option<Buffer>,
}

/// The overlay pipeline and egui's textures.
pub struct OverlayPass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    layout: PipelineLayout,
    // Only its layout is used: every texture's set has an identical one.
    _layout_set: DescriptorSet,
    sampler: Sampler,
    textures: HashMap<TextureId, Texture>,
    geometry: Vec<Geometry>,
}

impl OverlayPass {
    /// The pipeline for a colour target of `color_format`, with `slots` frames in flight.
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        color_format: vk::Format,
        slots: usize,
    ) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let layout_set = DescriptorSet::new(ctx, &BINDINGS)?;
        let push = (St::VERTEX, size_of::<OverlayPush>() as u32);
        let layout = PipelineLayout::new(ctx, layout_set.layout, push)?;
        // egui's Vertex: position, uv (two f32 each), colour (four u8, sRGB).
        let attribute = |location, format, offset| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format,
            offset,
        };
        let input = (
            [vk::VertexInputBindingDescription {
                binding: 0,
                stride: size_of::<Vertex>() as u32,
                input_rate: vk::VertexInputRate::VERTEX,
            }],
            vec![
                attribute(0, vk::Format::R32G32_SFLOAT, 0),
                attribute(1, vk::Format::R32G32_SFLOAT, 8),
                attribute(2, vk::Format::R8G8B8A8_UNORM, 16),
            ],
        );
        let stages = [
            (St::VERTEX, shaders::OVERLAY_VS),
            (St::FRAGMENT, shaders::OVERLAY_FS),
        ];
        let mut desc = GraphicsDesc::opaque(
            module,
            &stages,
            &layout,
            &input,
            color_format,
            vk::Format::UNDEFINED,
        );
        desc.premultiplied_blend = true;
        let pipeline = Pipeline::graphics(ctx, &desc)?;
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
            layout,
            _layout_set: layout_set,
            sampler: Sampler::linear_clamped(ctx)?,
            textures: HashMap::new(),
            geometry: (0..slots).map(|_| Geometry::default()).collect(),
        })
    }

    /// Creates and updates the textures egui asks for (waits for the GPU first: egui
    /// changes its textures rarely, mostly in the first frame).
    pub fn update_textures(&mut self, pool: &CommandPool, delta: &TexturesDelta) -> Result<()> {
        if delta.set.is_empty() {
            return Ok(());
        }
        self.ctx.wait_idle()?;
        for (id, images) in &delta.set {
            for image in images {
                self.set_texture(pool, *id, image)
                    .with_context(|| format!("overlay texture {id:?}"))?;
            }
        }
        Ok(())
    }

    /// Frees the textures egui no longer needs, once the frame using them is done.
    pub fn free_textures(&mut self, delta: &TexturesDelta) -> Result<()> {
        if !delta.free.is_empty() {
            self.ctx.wait_idle()?;
            for id in &delta.free {
                self.textures.remove(id);
            }
        }
        Ok(())
    }

    fn set_texture(&mut self, pool: &CommandPool, id: TextureId, delta: &ImageDelta) -> Result<()> {
        let egui::ImageData::Color(image) = &delta.image;
        let extent = vk::Extent2D {
            width: image.size[0] as u32,
            height: image.size[1] as u32,
        };
        let whole = delta.pos.is_none();
        if whole || !self.textures.contains_key(&id) {
            let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
            let image = Image::new(
                &self.ctx,
                "overlay texture",
                extent,
                TEXTURE_FORMAT,
                usage,
                vk::ImageAspectFlags::COLOR,
            )?;
            let set = DescriptorSet::new(&self.ctx, &BINDINGS)?;
            set.write_image(0, image.view, self.sampler.sampler);
            self.textures.insert(id, Texture { image, set });
        }
        let texture = &self.textures[&id];
        let pixels: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
        let mut staging = Buffer::new(
            &self.ctx,
            "overlay texture upload",
            pixels.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(&pixels)?;
        let [x, y] = delta.pos.unwrap_or([0, 0]);
        let offset = vk::Offset2D {
            x: x as i32,
            y: y as i32,
        };
        // A partial update keeps the rest of the image.
        let old_layout = if whole {
            vk::ImageLayout::UNDEFINED
        } else {
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
        };
        let target = texture.image.image;
        pool.one_shot(|rec| {
            let color = vk::ImageAspectFlags::COLOR;
            rec.image_barrier(
                target,
                color,
                (old_layout, vk::ImageLayout::TRANSFER_DST_OPTIMAL),
                (S::FRAGMENT_SHADER, A::NONE),
                (S::COPY, A::TRANSFER_WRITE),
            );
            rec.copy_buffer_to_image(staging.buffer, target, offset, extent);
            rec.image_barrier(
                target,
                color,
                (
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                ),
                (S::COPY, A::TRANSFER_WRITE),
                (S::FRAGMENT_SHADER, A::SHADER_READ),
            );
        })
    }

    /// Writes the frame's meshes into the slot's buffers and records their draws over
    /// `view` (loaded, not cleared) of size `extent`.
    pub fn record(
        &mut self,
        rec: &Recorder,
        slot: usize,
        view: vk::ImageView,
        extent: vk::Extent2D,
        frame: &OverlayFrame,
    ) -> Result<()> {
        let meshes: Vec<_> = frame
            .primitives
            .iter()
            .filter_map(|p| match &p.primitive {
                Primitive::Mesh(mesh) if !mesh.indices.is_empty() => Some((p.clip_rect, mesh)),
                _ => None,
            })
            .collect();
        if meshes.is_empty() {
            return Ok(());
        }
        let geometry = &mut self.geometry[slot];
        let vertices: Vec<Vertex> = meshes
            .iter()
            .flat_map(|(_, m)| m.vertices.iter().copied())
            .collect();
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let vertex_buffer = upload(
            &self.ctx,
            &mut geometry.vertices,
            "overlay vertices",
            &vertices,
            usage,
        )?;
        let indices: Vec<u32> = meshes
            .iter()
            .flat_map(|(_, m)| m.indices.iter().copied())
            .collect();
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        let index_buffer = upload(
            &self.ctx,
            &mut geometry.indices,
            "overlay indices",
            &indices,
            usage,
        )?;

        let ppp = frame.pixels_per_point;
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        rec.begin_rendering(Some((view, None)), None, extent);
        rec.bind_vertex_buffer(vertex_buffer);
        rec.bind_index_buffer(index_buffer);
        let push = OverlayPush {
            screen: glam::Vec2::new(extent.width as f32, extent.height as f32) / ppp,
        };
        let (mut first_index, mut vertex_offset) = (0u32, 0i32);
        let mut bound = None;
        for (clip, mesh) in meshes {
            let (count, vertices) = (mesh.indices.len() as u32, mesh.vertices.len() as i32);
            let scissor = scissor(clip, ppp, extent);
            if let (Some(texture), Some(rect)) = (self.textures.get(&mesh.texture_id), scissor) {
                if bound.is_none() {
                    let layout = self.layout.layout;
                    rec.bind_pipeline(graphics, self.pipeline.pipeline, layout, texture.set.set);
                    rec.push_constants(
                        layout,
                        vk::ShaderStageFlags::VERTEX,
                        bytemuck::bytes_of(&push),
                    );
                } else if bound != Some(mesh.texture_id) {
                    rec.bind_set(graphics, self.layout.layout, texture.set.set);
                }
                bound = Some(mesh.texture_id);
                rec.set_scissor(rect);
                rec.draw_indexed(first_index, count, vertex_offset);
            }
            first_index += count;
            vertex_offset += vertices;
        }
        rec.end_rendering();
        Ok(())
    }
}

/// Writes `data` into the slot's host-visible buffer, first replaced by a larger one
/// (with room to grow) when it does not fit; returns the buffer.
fn upload<T: bytemuck::Pod>(
    ctx: &Arc<Context>,
    buffer: &mut Option<Buffer>,
    name: &str,
    data: &[T],
    usage: vk::BufferUsageFlags,
) -> Result<vk::Buffer> {
    let bytes = size_of_val(data) as u64;
    if buffer.as_ref().is_none_or(|b| b.size < bytes) {
        let size = bytes.next_power_of_two().max(64 * 1024);
        *buffer = Some(Buffer::new(
            ctx,
            name,
            size,
            usage,
            MemoryLocation::CpuToGpu,
        )?);
    }
    let buffer = buffer.as_mut().context("overlay buffer")?;
    buffer.write(data)?;
    Ok(buffer.buffer)
}

/// A clip rectangle in points as a scissor in pixels inside `extent`; `None` when
/// nothing of it is on screen.
fn scissor(clip: egui::Rect, ppp: f32, extent: vk::Extent2D) -> Option<vk::Rect2D> {
    let (w, h) = (extent.width as f32, extent.height as f32);
    let x0 = (clip.min.x * ppp).round().clamp(0.0, w);
    let y0 = (clip.min.y * ppp).round().clamp(0.0, h);
    let x1 = (clip.max.x * ppp).round().clamp(0.0, w);
    let y1 = (clip.max.y * ppp).round().clamp(0.0, h);
    (x1 > x0 && y1 > y0).then_some(vk::Rect2D {
        offset: vk::Offset2D {
            x: x0 as i32,
            y: y0 as i32,
        },
        extent: vk::Extent2D {
            width: (x1 - x0) as u32,
            height: (y1 - y0) as u32,
        },
    })
}

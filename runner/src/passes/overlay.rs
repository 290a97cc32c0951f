//! The overlay: egui's tessellated output drawn over the frame, with rust-gpu shaders
//! like every other pass. egui's meshes are drawn into a layer of the target's size
//! when they change, and the layer is laid over every frame: its opaque part (the
//! window's fill) copied, the rest of the pixels it covers blended as quads. On a
//! software device drawing the interface's text every frame cost about a third of a
//! 1080p frame, and blending the layer over the window's pixels a sixth. Textures
//! (the font atlas) are uploaded as egui changes them; vertices and indices go
//! through a host-visible buffer per frame slot.

use super::area::{around, bottom, rect, right};
use crate::shaders;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::descriptors::{BindingSpec, DescriptorSet};
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, PipelineLayout, ShaderModules};
use crate::vulkan::sampler::Sampler;
use crate::vulkan::{Attachments, Buffer, Context, Image, Recorder};
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
    /// The meshes replace the layer; false: the layer is kept and laid over again.
    pub changed: bool,
    /// Meshes, each with its clip rectangle (in points).
    pub primitives: &'a [ClippedPrimitive],
    /// Textures to create, update or free.
    pub textures: &'a TexturesDelta,
    /// Pixels per egui point.
    pub pixels_per_point: f32,
    /// Where the meshes are opaque (in points): copied, not blended.
    pub opaque: Option<egui::Rect>,
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

/// The overlay's last picture: egui's meshes over transparent black, premultiplied,
/// in the target's format, the pixels they cover, and of those the pixels they
/// cover opaquely.
struct Layer {
    image: Image,
    set: DescriptorSet,
    covered: Option<vk::Rect2D>,
    opaque: Option<vk::Rect2D>,
}

/// The overlay pipeline, egui's textures and the layer.
pub struct OverlayPass {
    ctx: Arc<Context>,
    pipeline: Pipeline,
    layout: PipelineLayout,
    // Only its layout is used: every texture's set has an identical one.
    _layout_set: DescriptorSet,
    sampler: Sampler,
    /// The layer is read pixel for pixel.
    nearest: Sampler,
    textures: HashMap<TextureId, Texture>,
    geometry: Vec<Geometry>,
    /// Per slot: the quad that lays the layer over the frame.
    quads: Vec<Option<Buffer>>,
    color_format: vk::Format,
    layer: Option<Layer>,
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
            nearest: Sampler::nearest_clamped(ctx)?,
            textures: HashMap::new(),
            geometry: (0..slots).map(|_| Geometry::default()).collect(),
            quads: (0..slots).map(|_| None).collect(),
            color_format,
            layer: None,
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

    /// Makes the layer ready for a target of `extent`: when the frame's meshes are
    /// new (or the size changed), draws them into it through the slot's buffers.
    /// Recorded before the frame's passes: it touches only the layer.
    pub fn prepare(
        &mut self,
        rec: &Recorder,
        slot: usize,
        extent: vk::Extent2D,
        frame: &OverlayFrame,
    ) -> Result<()> {
        let resized = self.layer.as_ref().is_none_or(|l| l.image.extent != extent);
        if resized {
            self.layer = Some(self.new_layer(extent)?);
        }
        if frame.changed || resized {
            self.draw_layer(rec, slot, extent, frame)?;
        }
        Ok(())
    }

    /// The pixels [`Self::lay_over`] will copy into a target that takes transfer
    /// writes: what is drawn there before is hidden.
    pub fn opaque(&self) -> Option<vk::Rect2D> {
        self.layer.as_ref()?.opaque
    }

    fn new_layer(&self, extent: vk::Extent2D) -> Result<Layer> {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = vk::ImageAspectFlags::COLOR;
        let image = Image::new(
            &self.ctx,
            "overlay layer",
            extent,
            self.color_format,
            usage,
            color,
        )?;
        let set = DescriptorSet::new(&self.ctx, &BINDINGS)?;
        set.write_image(0, image.view, self.nearest.sampler);
        Ok(Layer {
            image,
            set,
            covered: None,
            opaque: None,
        })
    }

    /// egui's meshes into the layer, cleared first where they fall (the last frame
    /// that read or copied the layer is earlier on the queue: the barrier waits for
    /// it).
    fn draw_layer(
        &mut self,
        rec: &Recorder,
        slot: usize,
        extent: vk::Extent2D,
        frame: &OverlayFrame,
    ) -> Result<()> {
        let ppp = frame.pixels_per_point;
        // Each mesh with its scissor; those with no texture or nothing on screen go.
        let mut meshes = Vec::new();
        let (mut first_index, mut vertex_offset) = (0u32, 0i32);
        for p in frame.primitives {
            let Primitive::Mesh(mesh) = &p.primitive else {
                continue;
            };
            let drawn = scissor(p.clip_rect, ppp, extent)
                .filter(|_| self.textures.contains_key(&mesh.texture_id))
                .and_then(|rect| Some((rect, bounds(&mesh.vertices, ppp, rect)?)));
            if let Some((rect, covers)) = drawn.filter(|_| !mesh.indices.is_empty()) {
                meshes.push((mesh, rect, covers, first_index, vertex_offset));
            }
            first_index += mesh.indices.len() as u32;
            vertex_offset += mesh.vertices.len() as i32;
        }
        let covered = meshes.iter().map(|m| m.2).reduce(union);
        let layer = self.layer.as_mut().context("overlay layer")?;
        layer.covered = covered;
        layer.opaque = covered.and_then(|c| inner_pixels(frame.opaque?, ppp, c));
        let Some(area) = covered else {
            return Ok(());
        };
        let geometry = &mut self.geometry[slot];
        let primitives = || {
            frame.primitives.iter().filter_map(|p| match &p.primitive {
                Primitive::Mesh(mesh) => Some(mesh),
                Primitive::Callback(_) => None,
            })
        };
        let vertices: Vec<Vertex> = primitives().flat_map(|m| m.vertices.clone()).collect();
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let vertex_buffer = upload(
            &self.ctx,
            &mut geometry.vertices,
            "overlay vertices",
            &vertices,
            usage,
        )?;
        let indices: Vec<u32> = primitives().flat_map(|m| m.indices.clone()).collect();
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        let index_buffer = upload(
            &self.ctx,
            &mut geometry.indices,
            "overlay indices",
            &indices,
            usage,
        )?;

        let color = vk::ImageAspectFlags::COLOR;
        rec.image_barrier(
            layer.image.image,
            color,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            (
                S::FRAGMENT_SHADER | S::COPY,
                A::SHADER_READ | A::TRANSFER_READ,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
        );
        let target = Attachments {
            color: Some((layer.image.view, Some([0.0; 4]))),
            area: Some(area),
            ..Default::default()
        };
        rec.begin_rendering_with(&target, extent);
        rec.bind_vertex_buffer(vertex_buffer);
        rec.bind_index_buffer(index_buffer);
        let push = OverlayPush {
            screen: glam::Vec2::new(extent.width as f32, extent.height as f32) / ppp,
        };
        let (graphics, layout) = (vk::PipelineBindPoint::GRAPHICS, self.layout.layout);
        let mut bound = None;
        for (mesh, rect, _, first_index, vertex_offset) in meshes {
            let set = self.textures[&mesh.texture_id].set.set;
            if bound.is_none() {
                rec.bind_pipeline(graphics, self.pipeline.pipeline, layout, set);
                let stage = vk::ShaderStageFlags::VERTEX;
                rec.push_constants(layout, stage, bytemuck::bytes_of(&push));
            } else if bound != Some(mesh.texture_id) {
                rec.bind_set(graphics, layout, set);
            }
            bound = Some(mesh.texture_id);
            rec.set_scissor(rect);
            rec.draw_indexed(first_index, mesh.indices.len() as u32, vertex_offset);
        }
        rec.end_rendering();
        rec.image_barrier(
            layer.image.image,
            color,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            (S::FRAGMENT_SHADER, A::SHADER_READ),
        );
        Ok(())
    }

    /// The layer over `target` (image, view, size; in COLOR_ATTACHMENT_OPTIMAL,
    /// loaded): the pixels of `copied` (its [`Self::opaque`] part, where the image
    /// takes transfer writes) copied, the rest of the pixels egui covered as quads
    /// (two triangles each, positions in pixels, white), blended as egui's meshes are.
    pub fn lay_over(
        &mut self,
        rec: &Recorder,
        slot: usize,
        (image, view, extent): (vk::Image, vk::ImageView, vk::Extent2D),
        copied: Option<vk::Rect2D>,
    ) -> Result<()> {
        let Some(layer) = self.layer.as_ref() else {
            return Ok(());
        };
        let Some(rect) = layer.covered else {
            return Ok(());
        };
        let blended = match copied {
            Some(opaque) => {
                copy_opaque(rec, layer.image.image, image, opaque);
                around(rect, opaque)
            }
            None => vec![rect],
        };
        if blended.is_empty() {
            return Ok(());
        }
        let (w, h) = (extent.width as f32, extent.height as f32);
        let corner = |x: i32, y: i32| Vertex {
            pos: egui::pos2(x as f32, y as f32),
            uv: egui::pos2(x as f32 / w, y as f32 / h),
            color: egui::Color32::WHITE,
        };
        let quads: Vec<Vertex> = blended
            .iter()
            .flat_map(|r| {
                let (x0, y0, x1, y1) = (r.offset.x, r.offset.y, right(*r), bottom(*r));
                let (a, b, c, d) = (
                    corner(x0, y0),
                    corner(x1, y0),
                    corner(x1, y1),
                    corner(x0, y1),
                );
                [a, b, c, a, c, d]
            })
            .collect();
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let buffer = upload(
            &self.ctx,
            &mut self.quads[slot],
            "overlay quads",
            &quads,
            usage,
        )?;
        let layout = self.layout.layout;
        let target = Attachments {
            color: Some((view, None)),
            area: Some(rect),
            ..Default::default()
        };
        rec.begin_rendering_with(&target, extent);
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        rec.bind_pipeline(graphics, self.pipeline.pipeline, layout, layer.set.set);
        let push = OverlayPush {
            screen: glam::Vec2::new(w, h),
        };
        rec.push_constants(
            layout,
            vk::ShaderStageFlags::VERTEX,
            bytemuck::bytes_of(&push),
        );
        rec.bind_vertex_buffer(buffer);
        rec.draw(0, quads.len() as u32);
        rec.end_rendering();
        Ok(())
    }
}

/// Copies the `area` of the layer (SHADER_READ_ONLY_OPTIMAL) into the target
/// (COLOR_ATTACHMENT_OPTIMAL, written by the passes before), leaving both as found.
fn copy_opaque(rec: &Recorder, layer: vk::Image, target: vk::Image, area: vk::Rect2D) {
    use vk::ImageLayout as L;
    let color = vk::ImageAspectFlags::COLOR;
    let attachment = (
        S::COLOR_ATTACHMENT_OUTPUT,
        A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
    );
    rec.image_barrier(
        target,
        color,
        (L::COLOR_ATTACHMENT_OPTIMAL, L::TRANSFER_DST_OPTIMAL),
        attachment,
        (S::COPY, A::TRANSFER_WRITE),
    );
    rec.image_barrier(
        layer,
        color,
        (L::SHADER_READ_ONLY_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
        (S::FRAGMENT_SHADER, A::NONE),
        (S::COPY, A::TRANSFER_READ),
    );
    rec.copy_image(layer, target, area);
    rec.image_barrier(
        target,
        color,
        (L::TRANSFER_DST_OPTIMAL, L::COLOR_ATTACHMENT_OPTIMAL),
        (S::COPY, A::TRANSFER_WRITE),
        attachment,
    );
    rec.image_barrier(
        layer,
        color,
        (L::TRANSFER_SRC_OPTIMAL, L::SHADER_READ_ONLY_OPTIMAL),
        (S::COPY, A::NONE),
        (S::FRAGMENT_SHADER, A::SHADER_READ),
    );
}

/// The whole pixels inside `opaque` (in points, times `ppp`: rounded in), within
/// `covered`; `None` when empty.
fn inner_pixels(opaque: egui::Rect, ppp: f32, covered: vk::Rect2D) -> Option<vk::Rect2D> {
    let x0 = ((opaque.min.x * ppp).ceil() as i32).max(covered.offset.x);
    let y0 = ((opaque.min.y * ppp).ceil() as i32).max(covered.offset.y);
    let x1 = ((opaque.max.x * ppp).floor() as i32).min(right(covered));
    let y1 = ((opaque.max.y * ppp).floor() as i32).min(bottom(covered));
    rect(x0, y0, x1, y1)
}

/// The pixels a mesh can touch: its vertices' bounds (in points, times `ppp`),
/// rounded out to whole pixels, inside its scissor `clip`; `None` when empty.
fn bounds(vertices: &[Vertex], ppp: f32, clip: vk::Rect2D) -> Option<vk::Rect2D> {
    let (mut min, mut max) = (
        egui::pos2(f32::MAX, f32::MAX),
        egui::pos2(f32::MIN, f32::MIN),
    );
    for v in vertices {
        min = min.min(v.pos);
        max = max.max(v.pos);
    }
    let x0 = ((min.x * ppp).floor() as i32).max(clip.offset.x);
    let y0 = ((min.y * ppp).floor() as i32).max(clip.offset.y);
    let x1 = ((max.x * ppp).ceil() as i32).min(right(clip));
    let y1 = ((max.y * ppp).ceil() as i32).min(bottom(clip));
    rect(x0, y0, x1, y1)
}

/// The smallest rectangle holding `a` and `b`.
fn union(a: vk::Rect2D, b: vk::Rect2D) -> vk::Rect2D {
    let x0 = a.offset.x.min(b.offset.x);
    let y0 = a.offset.y.min(b.offset.y);
    let (x1, y1) = (right(a).max(right(b)), bottom(a).max(bottom(b)));
    rect(x0, y0, x1, y1).unwrap_or(a)
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
    rect(x0 as i32, y0 as i32, x1 as i32, y1 as i32)
}

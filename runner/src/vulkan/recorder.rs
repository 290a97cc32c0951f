//! Command recording: the frame's passes record through this, so the `unsafe` ash
//! calls stay in the Vulkan layer.

use super::image::subresource_range;
use ash::vk;
use std::cell::Cell;

/// The attachments of one rendering scope ([`Recorder::begin_rendering_with`]).
#[derive(Copy, Clone, Debug, Default)]
pub struct Attachments {
    /// The colour view, cleared to the value given or (`None`) loaded.
    pub color: Option<(vk::ImageView, Option<[f32; 4]>)>,
    /// Where the multisampled colour is averaged when rendering ends
    /// (COLOR_ATTACHMENT_OPTIMAL).
    pub color_resolve: Option<vk::ImageView>,
    /// A second colour view after it (single-sample, not resolved: the draw's motion
    /// target, the temporal history), cleared to zero (`true`) or loaded.
    pub second: Option<(vk::ImageView, bool)>,
    /// The depth view, cleared to 1 (`true`) or loaded.
    pub depth: Option<(vk::ImageView, bool)>,
    /// The pixels rendered, cleared and stored, inside the extent (`None`: all).
    pub area: Option<vk::Rect2D>,
}

/// A command buffer being recorded on a device.
#[derive(Clone)]
pub struct Recorder<'a> {
    device: &'a ash::Device,
    /// The command buffer.
    pub cmd: vk::CommandBuffer,
    /// The (layout, set) bound for graphics and for compute, so that passes sharing
    /// them bind them once per command buffer.
    bound: Cell<[Option<(vk::PipelineLayout, vk::DescriptorSet)>; 2]>,
}

/// (stages, accesses) of one side of a dependency.
pub type Scope = (vk::PipelineStageFlags2, vk::AccessFlags2);

impl<'a> Recorder<'a> {
    /// Records into `cmd`, which must be in the recording state.
    pub fn new(device: &'a ash::Device, cmd: vk::CommandBuffer) -> Self {
        Self {
            device,
            cmd,
            bound: Cell::new([None; 2]),
        }
    }

    /// A global memory dependency: `src` before `dst`.
    pub fn memory_barrier(&self, src: Scope, dst: Scope) {
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(src.0)
            .src_access_mask(src.1)
            .dst_stage_mask(dst.0)
            .dst_access_mask(dst.1)];
        let info = vk::DependencyInfo::default().memory_barriers(&barrier);
        unsafe { self.device.cmd_pipeline_barrier2(self.cmd, &info) };
    }

    /// A layout transition of a whole single-level image, with its dependency.
    pub fn image_barrier(
        &self,
        image: vk::Image,
        aspect: vk::ImageAspectFlags,
        layouts: (vk::ImageLayout, vk::ImageLayout),
        src: Scope,
        dst: Scope,
    ) {
        let barrier = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(src.0)
            .src_access_mask(src.1)
            .dst_stage_mask(dst.0)
            .dst_access_mask(dst.1)
            .old_layout(layouts.0)
            .new_layout(layouts.1)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image)
            .subresource_range(subresource_range(aspect))];
        let info = vk::DependencyInfo::default().image_memory_barriers(&barrier);
        unsafe { self.device.cmd_pipeline_barrier2(self.cmd, &info) };
    }

    /// Writes `data` (a multiple of 4 bytes) at the start of `buffer`, in updates of
    /// 64 KiB at most (`vkCmdUpdateBuffer`'s limit).
    pub fn update_buffer(&self, buffer: vk::Buffer, data: &[u8]) {
        const MOST: usize = 65536;
        for (k, part) in data.chunks(MOST).enumerate() {
            let offset = (k * MOST) as u64;
            unsafe {
                self.device
                    .cmd_update_buffer(self.cmd, buffer, offset, part)
            };
        }
    }

    /// Fills the whole of `buffer` with `value`.
    pub fn fill_buffer(&self, buffer: vk::Buffer, value: u32) {
        self.fill_buffer_start(buffer, vk::WHOLE_SIZE, value);
    }

    /// Fills the first `bytes` of `buffer` (a multiple of 4, or `vk::WHOLE_SIZE`) with
    /// `value`.
    pub fn fill_buffer_start(&self, buffer: vk::Buffer, bytes: u64, value: u32) {
        unsafe {
            self.device
                .cmd_fill_buffer(self.cmd, buffer, 0, bytes, value)
        };
    }

    /// Clears the whole depth `image` (in `TRANSFER_DST_OPTIMAL`) to `depth`.
    pub fn clear_depth_image(&self, image: vk::Image, depth: f32) {
        let range = subresource_range(vk::ImageAspectFlags::DEPTH);
        let value = vk::ClearDepthStencilValue { depth, stencil: 0 };
        unsafe {
            self.device.cmd_clear_depth_stencil_image(
                self.cmd,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &value,
                &[range],
            )
        };
    }

    /// Copies `size` bytes from the start of `src` to the start of `dst`.
    pub fn copy_buffer(&self, src: vk::Buffer, dst: vk::Buffer, size: u64) {
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size,
        };
        unsafe { self.device.cmd_copy_buffer(self.cmd, src, dst, &[region]) };
    }

    /// Copies the `aspect` of an image (in TRANSFER_SRC_OPTIMAL) into a tightly packed
    /// buffer.
    pub fn copy_image_to_buffer(
        &self,
        image: vk::Image,
        aspect: vk::ImageAspectFlags,
        extent: vk::Extent2D,
        dst: vk::Buffer,
    ) {
        let region = image_region(aspect, vk::Offset2D::default(), extent);
        unsafe {
            self.device.cmd_copy_image_to_buffer(
                self.cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                &[region],
            )
        };
    }

    /// Copies the pixels of `area` of a colour image (in TRANSFER_SRC_OPTIMAL) to the
    /// same place of another of the same format (in TRANSFER_DST_OPTIMAL).
    pub fn copy_image(&self, src: vk::Image, dst: vk::Image, area: vk::Rect2D) {
        // The same subresource, place and size on both sides.
        let at = image_region(vk::ImageAspectFlags::COLOR, area.offset, area.extent);
        let region = vk::ImageCopy::default()
            .src_subresource(at.image_subresource)
            .src_offset(at.image_offset)
            .dst_subresource(at.image_subresource)
            .dst_offset(at.image_offset)
            .extent(at.image_extent);
        unsafe {
            self.device.cmd_copy_image(
                self.cmd,
                src,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
    }

    /// Copies a tightly packed buffer into the `extent` of a colour image (in
    /// TRANSFER_DST_OPTIMAL) at `offset`.
    pub fn copy_buffer_to_image(
        &self,
        src: vk::Buffer,
        image: vk::Image,
        offset: vk::Offset2D,
        extent: vk::Extent2D,
    ) {
        let region = image_region(vk::ImageAspectFlags::COLOR, offset, extent);
        self.copy_regions_to_image(src, image, region);
    }

    /// Copies a tightly packed buffer of `f32` depths (each 0 to 1) into the whole
    /// `extent` of a `D32_SFLOAT` image's depth (in TRANSFER_DST_OPTIMAL).
    pub fn copy_buffer_to_depth(&self, src: vk::Buffer, image: vk::Image, extent: vk::Extent2D) {
        let aspect = vk::ImageAspectFlags::DEPTH;
        let region = image_region(aspect, vk::Offset2D::default(), extent);
        self.copy_regions_to_image(src, image, region);
    }

    /// Copies `src` into `image` (in TRANSFER_DST_OPTIMAL) as `region` says.
    fn copy_regions_to_image(
        &self,
        src: vk::Buffer,
        image: vk::Image,
        region: vk::BufferImageCopy,
    ) {
        unsafe {
            self.device.cmd_copy_buffer_to_image(
                self.cmd,
                src,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
    }

    /// Blits the whole of `src` (TRANSFER_SRC_OPTIMAL) onto the whole of `dst`
    /// (TRANSFER_DST_OPTIMAL), scaled, each pixel the nearest of `src`'s.
    pub fn blit_nearest(
        &self,
        (src, src_extent): (vk::Image, vk::Extent2D),
        (dst, dst_extent): (vk::Image, vk::Extent2D),
    ) {
        let layers = image_region(
            vk::ImageAspectFlags::COLOR,
            vk::Offset2D::default(),
            src_extent,
        )
        .image_subresource;
        let corner = |e: vk::Extent2D| vk::Offset3D {
            x: e.width as i32,
            y: e.height as i32,
            z: 1,
        };
        let region = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner(src_extent)])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner(dst_extent)]);
        unsafe {
            self.device.cmd_blit_image(
                self.cmd,
                src,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::NEAREST,
            )
        };
    }

    /// Binds `pipeline` and `set` (set 0) at `bind_point`.
    pub fn bind_pipeline(
        &self,
        bind_point: vk::PipelineBindPoint,
        pipeline: vk::Pipeline,
        layout: vk::PipelineLayout,
        set: vk::DescriptorSet,
    ) {
        unsafe {
            self.device
                .cmd_bind_pipeline(self.cmd, bind_point, pipeline);
        }
        // Binding the same set again is redundant (and costs lavapipe host memory
        // while the frame block was a uniform buffer: docs/reliability.md, "Validation, core and synchronization").
        let point = usize::from(bind_point == vk::PipelineBindPoint::COMPUTE);
        let mut bound = self.bound.get();
        if bound[point] != Some((layout, set)) {
            unsafe {
                self.device
                    .cmd_bind_descriptor_sets(self.cmd, bind_point, layout, 0, &[set], &[]);
            }
            bound[point] = Some((layout, set));
            self.bound.set(bound);
        }
    }

    /// Binds `pipeline` and `sets` from set 0 on, through `layout`.
    pub fn bind_pipeline_sets(
        &self,
        bind_point: vk::PipelineBindPoint,
        pipeline: vk::Pipeline,
        layout: vk::PipelineLayout,
        sets: &[vk::DescriptorSet],
    ) {
        unsafe {
            self.device
                .cmd_bind_pipeline(self.cmd, bind_point, pipeline);
            self.device
                .cmd_bind_descriptor_sets(self.cmd, bind_point, layout, 0, sets, &[]);
        }
        let point = usize::from(bind_point == vk::PipelineBindPoint::COMPUTE);
        let mut bound = self.bound.get();
        bound[point] = sets.first().map(|&set| (layout, set));
        self.bound.set(bound);
    }

    /// Sets push constants from offset 0; `stages` must be every stage of the
    /// layout's range.
    pub fn push_constants(
        &self,
        layout: vk::PipelineLayout,
        stages: vk::ShaderStageFlags,
        data: &[u8],
    ) {
        unsafe {
            self.device
                .cmd_push_constants(self.cmd, layout, stages, 0, data)
        };
    }

    /// Dispatches (x, y, 1) workgroups.
    pub fn dispatch(&self, groups: (u32, u32)) {
        unsafe { self.device.cmd_dispatch(self.cmd, groups.0, groups.1, 1) };
    }

    /// Starts rendering to `color` (cleared to the colour given, else loaded) and
    /// `depth` (cleared to 1 and stored), either optional, with viewport and scissor
    /// covering `extent`.
    pub fn begin_rendering(
        &self,
        color: Option<(vk::ImageView, Option<[f32; 4]>)>,
        depth: Option<vk::ImageView>,
        extent: vk::Extent2D,
    ) {
        let attachments = Attachments {
            color,
            depth: depth.map(|view| (view, true)),
            ..Default::default()
        };
        self.begin_rendering_with(&attachments, extent);
    }

    /// Begins dynamic rendering into `attachments` over `extent` (or its `area`),
    /// with the viewport covering the extent and the scissor the area.
    pub fn begin_rendering_with(&self, attachments: &Attachments, extent: vk::Extent2D) {
        let load = |clear: bool| {
            if clear {
                vk::AttachmentLoadOp::CLEAR
            } else {
                vk::AttachmentLoadOp::LOAD
            }
        };
        let mut color_attachment: Vec<_> = attachments
            .color
            .iter()
            .map(|&(view, clear)| {
                let info = vk::RenderingAttachmentInfo::default();
                let info = match attachments.color_resolve {
                    Some(target) => info
                        .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                        .resolve_image_view(target)
                        .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
                    None => info,
                };
                info.image_view(view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(load(clear.is_some()))
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue {
                            float32: clear.unwrap_or_default(),
                        },
                    })
            })
            .collect();
        if let Some((view, clear)) = attachments.second {
            color_attachment.push(
                vk::RenderingAttachmentInfo::default()
                    .image_view(view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(load(clear))
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue { float32: [0.0; 4] },
                    }),
            );
        }
        let depth_attachment = attachments.depth.map(|(view, clear)| {
            vk::RenderingAttachmentInfo::default()
                .image_view(view)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(load(clear))
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: 1.0,
                        stencil: 0,
                    },
                })
        });
        let area = attachments.area.unwrap_or(vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        });
        let mut info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachment);
        if let Some(depth) = depth_attachment.as_ref() {
            info = info.depth_attachment(depth);
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        unsafe {
            self.device.cmd_begin_rendering(self.cmd, &info);
            self.device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            self.device.cmd_set_scissor(self.cmd, 0, &[area]);
        }
    }

    /// Sets the scissor rectangle.
    pub fn set_scissor(&self, rect: vk::Rect2D) {
        unsafe { self.device.cmd_set_scissor(self.cmd, 0, &[rect]) };
    }

    /// Draws into `rect` alone: the viewport (depth 0..1) and the scissor over it.
    pub fn set_viewport(&self, rect: vk::Rect2D) {
        let viewport = vk::Viewport {
            x: rect.offset.x as f32,
            y: rect.offset.y as f32,
            width: rect.extent.width as f32,
            height: rect.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        unsafe { self.device.cmd_set_viewport(self.cmd, 0, &[viewport]) };
        self.set_scissor(rect);
    }

    /// Binds descriptor set 0 of `layout` alone (the pipeline stays).
    pub fn bind_set(
        &self,
        bind_point: vk::PipelineBindPoint,
        layout: vk::PipelineLayout,
        set: vk::DescriptorSet,
    ) {
        unsafe {
            self.device
                .cmd_bind_descriptor_sets(self.cmd, bind_point, layout, 0, &[set], &[])
        };
    }

    /// Resets queries `first .. first + count` of `pool`.
    pub fn reset_queries(&self, pool: vk::QueryPool, first: u32, count: u32) {
        unsafe {
            self.device
                .cmd_reset_query_pool(self.cmd, pool, first, count)
        };
    }

    /// Writes a timestamp into `query` of `pool` once the stages `stage` are done.
    pub fn write_timestamp(&self, pool: vk::QueryPool, query: u32, stage: vk::PipelineStageFlags2) {
        unsafe {
            self.device
                .cmd_write_timestamp2(self.cmd, stage, pool, query)
        };
    }

    /// Starts counting into query 0 of `pool`.
    pub fn begin_query(&self, pool: vk::QueryPool) {
        unsafe {
            self.device
                .cmd_begin_query(self.cmd, pool, 0, vk::QueryControlFlags::empty())
        };
    }

    /// Stops counting into query 0 of `pool`.
    pub fn end_query(&self, pool: vk::QueryPool) {
        unsafe { self.device.cmd_end_query(self.cmd, pool, 0) };
    }

    /// Ends the rendering scope.
    pub fn end_rendering(&self) {
        unsafe { self.device.cmd_end_rendering(self.cmd) };
    }

    /// Binds `buffer` as vertex buffer 0.
    pub fn bind_vertex_buffer(&self, buffer: vk::Buffer) {
        unsafe {
            self.device
                .cmd_bind_vertex_buffers(self.cmd, 0, &[buffer], &[0])
        };
    }

    /// Binds `buffer` as the 32-bit index buffer.
    pub fn bind_index_buffer(&self, buffer: vk::Buffer) {
        unsafe {
            self.device
                .cmd_bind_index_buffer(self.cmd, buffer, 0, vk::IndexType::UINT32)
        };
    }

    /// Draws `count` indices from `first`, offset by `vertex_offset`, one instance.
    pub fn draw_indexed(&self, first: u32, count: u32, vertex_offset: i32) {
        unsafe {
            self.device
                .cmd_draw_indexed(self.cmd, count, 1, first, vertex_offset, 0)
        };
    }

    /// Draws `count` vertices from `first`, one instance.
    pub fn draw(&self, first: u32, count: u32) {
        unsafe { self.device.cmd_draw(self.cmd, count, 1, first, 0) };
    }

    /// `count` indirect draws read from `buffer`.
    pub fn draw_indirect(&self, buffer: vk::Buffer, count: u32) {
        let stride = size_of::<vk::DrawIndirectCommand>() as u32;
        unsafe {
            self.device
                .cmd_draw_indirect(self.cmd, buffer, 0, count, stride)
        };
    }

    /// A compute dispatch whose workgroup counts are the `VkDispatchIndirectCommand` at
    /// `offset` bytes in `buffer`.
    pub fn dispatch_indirect(&self, buffer: vk::Buffer, offset: u64) {
        unsafe { self.device.cmd_dispatch_indirect(self.cmd, buffer, offset) };
    }

    /// One draw whose counts are the `VkDrawIndirectCommand` at `offset` bytes in
    /// `buffer`.
    pub fn draw_indirect_at(&self, buffer: vk::Buffer, offset: u64) {
        let stride = size_of::<vk::DrawIndirectCommand>() as u32;
        unsafe {
            self.device
                .cmd_draw_indirect(self.cmd, buffer, offset, 1, stride)
        };
    }

    /// Launches a grid of `groups` mesh workgroups.
    pub fn draw_mesh_tasks(&self, mesh: &ash::ext::mesh_shader::Device, groups: [u32; 3]) {
        let [x, y, z] = groups;
        unsafe { mesh.cmd_draw_mesh_tasks(self.cmd, x, y, z) };
    }

    /// Launches the mesh workgroups of the `count` `VkDrawMeshTasksIndirectCommandEXT`
    /// at the start of `buffer` (the mesh stage tells them apart by `DrawIndex`).
    pub fn draw_mesh_tasks_indirect(
        &self,
        mesh: &ash::ext::mesh_shader::Device,
        buffer: vk::Buffer,
        count: u32,
    ) {
        self.draw_mesh_tasks_indirect_at(mesh, buffer, (0, count));
    }

    /// `count` mesh-task draws, their grids from `offset` of `buffer` on.
    pub fn draw_mesh_tasks_indirect_at(
        &self,
        mesh: &ash::ext::mesh_shader::Device,
        buffer: vk::Buffer,
        (offset, count): (u64, u32),
    ) {
        let stride = size_of::<vk::DrawMeshTasksIndirectCommandEXT>() as u32;
        unsafe { mesh.cmd_draw_mesh_tasks_indirect(self.cmd, buffer, offset, count, stride) };
    }
}

/// The `extent` at `offset` of mip level 0, layer 0 of an image's `aspect`, to or from
/// a tightly packed buffer.
fn image_region(
    aspect: vk::ImageAspectFlags,
    offset: vk::Offset2D,
    extent: vk::Extent2D,
) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: aspect,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_offset(vk::Offset3D {
            x: offset.x,
            y: offset.y,
            z: 0,
        })
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}

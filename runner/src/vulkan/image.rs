//! 2D images with one view: depth buffers and offscreen colour targets.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::Allocation;
use std::sync::Arc;

/// An image, its memory and a view of the whole of it; freed on drop.
pub struct Image {
    ctx: Arc<Context>,
    /// The Vulkan image.
    pub image: vk::Image,
    /// A view of its one mip level and layer.
    pub view: vk::ImageView,
    /// Pixel format.
    pub format: vk::Format,
    /// Size in pixels.
    pub extent: vk::Extent2D,
    allocation: Option<Allocation>,
    /// Where a linear image's rows lie in its memory (`None` for an optimal one).
    rows: Option<vk::SubresourceLayout>,
}

impl Image {
    /// A device-local 2D image with a view over `aspect`.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let one = vk::SampleCountFlags::TYPE_1;
        Self::multisampled(ctx, name, extent, format, usage, aspect, one)
    }

    /// A device-local 2D image of `samples` samples per pixel with a view over
    /// `aspect`.
    pub fn multisampled(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let kind = (format, usage, aspect, samples);
        Self::made(
            ctx,
            name,
            extent,
            kind,
            (vk::ImageTiling::OPTIMAL, MemoryLocation::GpuOnly),
        )
    }

    /// A colour image in host-visible memory with its rows one after another
    /// (linear tiling), whose pixels the host reads ([`Image::host_rows`]) once the
    /// frame that wrote them is done: a software device's frames for the window's
    /// shared memory (`app::shm`).
    pub fn host_linear(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        let one = vk::SampleCountFlags::TYPE_1;
        let kind = (format, usage, vk::ImageAspectFlags::COLOR, one);
        Self::made(
            ctx,
            name,
            extent,
            kind,
            (vk::ImageTiling::LINEAR, MemoryLocation::GpuToCpu),
        )
    }

    /// A host-linear image's bytes ([`Image::host_linear`]) and the bytes from one row
    /// to the next.
    pub fn host_rows(&self) -> Result<(&[u8], usize)> {
        let layout = self.rows.context("image is not linear")?;
        let bytes = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .context("image is not host visible")?;
        let start = layout.offset as usize;
        let end = start + layout.size as usize;
        let rows = bytes
            .get(start..end)
            .context("image layout past its memory")?;
        Ok((rows, layout.row_pitch as usize))
    }

    /// An image of `kind` (format, usage, aspect of its view, samples) with `memory`
    /// (tiling, and where its memory lies).
    fn made(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        kind: (
            vk::Format,
            vk::ImageUsageFlags,
            vk::ImageAspectFlags,
            vk::SampleCountFlags,
        ),
        memory: (vk::ImageTiling, MemoryLocation),
    ) -> Result<Self> {
        let (format, usage, aspect, samples) = kind;
        let (tiling, location) = memory;
        let device = &ctx.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(tiling)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let image = unsafe { device.create_image(&info, None) }
            .with_context(|| format!("create image {name}"))?;
        let requirements = unsafe { device.get_image_memory_requirements(image) };
        let linear = tiling == vk::ImageTiling::LINEAR;
        let allocation = match ctx.allocate(name, requirements, location, linear) {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.destroy_image(image, None) };
                return Err(e);
            }
        };
        unsafe { device.bind_image_memory(image, allocation.memory(), allocation.offset()) }
            .with_context(|| format!("bind memory of image {name}"))?;
        let rows = linear.then(|| {
            let color = vk::ImageSubresource::default().aspect_mask(aspect);
            unsafe { device.get_image_subresource_layout(image, color) }
        });
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        let view = unsafe { device.create_image_view(&view_info, None) }
            .with_context(|| format!("create view of image {name}"))?;
        Ok(Self {
            ctx: ctx.clone(),
            image,
            view,
            format,
            extent,
            allocation: Some(allocation),
            rows,
        })
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        unsafe {
            self.ctx.device.destroy_image_view(self.view, None);
            self.ctx.device.destroy_image(self.image, None);
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = self.ctx.allocator.lock().map(|mut a| a.free(allocation));
        }
    }
}

/// The one mip level and layer of an image, for `aspect`.
pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}

//! The window's swapchain, its image views and one "render finished" semaphore per
//! image; recreated on resize.

use super::Context;
use super::commands::Semaphore;
use anyhow::{Context as _, Result};
use ash::{khr, vk};
use std::sync::Arc;

/// A swapchain and what belongs to each of its images.
pub struct Swapchain {
    ctx: Arc<Context>,
    fns: khr::swapchain::Device,
    /// The swapchain.
    pub swapchain: vk::SwapchainKHR,
    /// Its images.
    pub images: Vec<vk::Image>,
    /// A view of each image.
    pub views: Vec<vk::ImageView>,
    /// Signalled when rendering to image i is done; waited on by its present.
    pub render_finished: Vec<Semaphore>,
    /// Pixel format of the images.
    pub format: vk::Format,
    /// Size of the images.
    pub extent: vk::Extent2D,
    /// The images take transfer writes (where the surface allows it).
    pub transfer_dst: bool,
}

impl Swapchain {
    /// The surface's format: an sRGB one, so the shaders write linear colour.
    pub fn surface_format(ctx: &Context) -> Result<vk::SurfaceFormatKHR> {
        let surface = ctx.surface.context("swapchain without a surface")?;
        let formats = unsafe {
            ctx.surface_fn
                .get_physical_device_surface_formats(ctx.physical, surface)
        }
        .context("query surface formats")?;
        formats
            .iter()
            .find(|f| {
                matches!(
                    f.format,
                    vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
                ) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
            })
            .or(formats.first())
            .copied()
            .context("surface has no format")
    }

    /// A swapchain of about `size` pixels, replacing `old` if given; `None` while the
    /// surface is 0x0 (a minimised window), when no swapchain can be made.
    pub fn new(
        ctx: &Arc<Context>,
        size: (u32, u32),
        old: Option<&Swapchain>,
    ) -> Result<Option<Self>> {
        let surface = ctx.surface.context("swapchain without a surface")?;
        let sfn = &ctx.surface_fn;
        let caps = unsafe { sfn.get_physical_device_surface_capabilities(ctx.physical, surface) }
            .context("query surface capabilities")?;
        let format = Self::surface_format(ctx)?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .0
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .1
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        // FIFO is always there and never tears; frame pacing is the driver's.
        // Screenshots copy from the images; the overlay copies into them.
        let transfer_dst = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST);
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        if transfer_dst {
            usage |= vk::ImageUsageFlags::TRANSFER_DST;
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.swapchain));
        let fns = khr::swapchain::Device::new(&ctx.instance, &ctx.device);
        let swapchain = unsafe { fns.create_swapchain(&info, None) }.context("create swapchain")?;
        let images = unsafe { fns.get_swapchain_images(swapchain) }.context("swapchain images")?;
        let views = images
            .iter()
            .map(|&image| {
                let info = vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(format.format)
                    .subresource_range(super::image::subresource_range(
                        vk::ImageAspectFlags::COLOR,
                    ));
                unsafe { ctx.device.create_image_view(&info, None) }
                    .context("create swapchain image view")
            })
            .collect::<Result<Vec<_>>>()?;
        let render_finished = images
            .iter()
            .map(|_| Semaphore::new(ctx))
            .collect::<Result<Vec<_>>>()?;
        log::info!(
            "swapchain {}x{} {:?}, {} images",
            extent.width,
            extent.height,
            format.format,
            images.len()
        );
        Ok(Some(Self {
            ctx: ctx.clone(),
            fns,
            swapchain,
            images,
            views,
            render_finished,
            format: format.format,
            extent,
            transfer_dst,
        }))
    }

    /// Acquires the next image, signalling `signal` when it is ready. `Ok(None)` means
    /// the swapchain is out of date and must be recreated.
    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Option<(u32, bool)>> {
        match unsafe {
            self.fns
                .acquire_next_image(self.swapchain, u64::MAX, signal, vk::Fence::null())
        } {
            Ok((index, suboptimal)) => Ok(Some((index, suboptimal))),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(e) => Err(e).context("acquire swapchain image"),
        }
    }

    /// Presents image `index` once `render_finished[index]` is signalled. Returns
    /// false when the swapchain is out of date or suboptimal.
    pub fn present(&self, index: u32) -> Result<bool> {
        let waits = [self.render_finished[index as usize].semaphore];
        let swapchains = [self.swapchain];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match unsafe { self.fns.queue_present(self.ctx.queue, &info) } {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(e) => Err(e).context("present"),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        unsafe {
            for &view in &self.views {
                self.ctx.device.destroy_image_view(view, None);
            }
            self.fns.destroy_swapchain(self.swapchain, None);
        }
    }
}

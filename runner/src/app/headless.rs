//! The headless side of the frame driver: an offscreen colour image each frame renders
//! into, and the host-visible buffer a captured frame's pixels are copied to.

use super::driver::{Acquired, FrameTarget};
use crate::renderer::Target;
use crate::vulkan::{Buffer, Context, Image};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// Colour format of the offscreen image (written to PNG as is).
pub const FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// An offscreen colour target and the host-visible buffer its pixels are copied to.
pub struct Offscreen {
    /// The colour image.
    pub color: Image,
    /// Receives the pixels of a frame that asks for them.
    pub capture: Buffer,
    /// The overlay may copy into the image (made to take transfer writes); false
    /// has it blend all it covers.
    pub transfer_dst: bool,
}

impl Offscreen {
    /// A `width` × `height` target in [`FORMAT`].
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32) -> Result<Self> {
        let extent = vk::Extent2D { width, height };
        let color = Image::new(
            ctx,
            "offscreen colour",
            extent,
            FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
            vk::ImageAspectFlags::COLOR,
        )?;
        let capture = Buffer::new(
            ctx,
            "capture",
            u64::from(width) * u64::from(height) * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            color,
            capture,
            transfer_dst: true,
        })
    }

    /// The frame target (left ready for the capture copy).
    pub fn target(&self) -> Target {
        Target {
            image: self.color.image,
            view: self.color.view,
            extent: self.color.extent,
            final_layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            transfer_dst: self.transfer_dst,
        }
    }

    /// Its size, (width, height) in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.color.extent.width, self.color.extent.height)
    }

    /// RGBA8 pixels of the last frame that asked for a capture (wait for it first).
    pub fn pixels(&self) -> Result<Vec<u8>> {
        let e = self.color.extent;
        self.capture.read::<u8>((e.width * e.height * 4) as usize)
    }
}

impl FrameTarget for Offscreen {
    /// The same image every frame: frames in flight are ordered by the renderer's
    /// barriers, and nothing waits for the image.
    fn acquire(&mut self, _available: vk::Semaphore, _slot: usize) -> Result<Option<Acquired>> {
        Ok(Some(Acquired {
            target: self.target(),
            wait: None,
            signal: None,
            capture: Some(self.capture.buffer),
            image: 0,
            suboptimal: false,
        }))
    }

    fn present(&mut self, _frame: &Acquired, _done: vk::Fence) -> Result<()> {
        Ok(())
    }
}

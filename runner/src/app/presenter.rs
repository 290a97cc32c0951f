//! The window side of the frame driver: the swapchain, made again when the window's
//! size changes or the surface says it is out of date, and never for a 0x0 surface.

use super::driver::{Acquired, FrameTarget};
use crate::renderer::Target;
use crate::vulkan::Context;
use crate::vulkan::swapchain::Swapchain;
use anyhow::{Result, bail};
use ash::vk;
use std::sync::Arc;

/// Acquires and presents swapchain images.
pub struct Presenter {
    swapchain: Option<Swapchain>,
    /// The swapchains' pixel format, which the renderer's pipelines are built for.
    format: vk::Format,
    /// Make the swapchain again before the next frame.
    pub recreate: bool,
    /// Swapchains made so far.
    pub swapchains: u64,
    ctx: Arc<Context>,
}

impl Presenter {
    /// A presenter for the context's window surface; no swapchain yet.
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        Ok(Self {
            swapchain: None,
            format: Swapchain::surface_format(ctx)?.format,
            recreate: false,
            swapchains: 0,
            ctx: ctx.clone(),
        })
    }

    /// The surface's colour format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// Makes the swapchain for a window of `size` when it is missing or out of date;
    /// false while there is nothing to draw to (a 0x0 surface).
    pub fn prepare(&mut self, size: (u32, u32)) -> Result<bool> {
        if size.0 == 0 || size.1 == 0 {
            return Ok(false);
        }
        if self.recreate || self.swapchain.is_none() {
            self.ctx.wait_idle()?;
            let old = self.swapchain.take();
            let Some(new) = Swapchain::new(&self.ctx, size, old.as_ref())? else {
                // The surface is 0x0 for now: try again next frame.
                return Ok(false);
            };
            if new.format != self.format {
                bail!(
                    "the window's surface format changed from {:?} to {:?}",
                    self.format,
                    new.format
                );
            }
            self.swapchain = Some(new);
            self.swapchains += 1;
            self.recreate = false;
        }
        Ok(true)
    }
}

impl FrameTarget for Presenter {
    fn acquire(&mut self, available: vk::Semaphore) -> Result<Option<Acquired>> {
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(None);
        };
        let Some((index, suboptimal)) = swapchain.acquire(available)? else {
            self.recreate = true;
            return Ok(None);
        };
        let i = index as usize;
        Ok(Some(Acquired {
            target: Target {
                image: swapchain.images[i],
                view: swapchain.views[i],
                extent: swapchain.extent,
                final_layout: vk::ImageLayout::PRESENT_SRC_KHR,
            },
            wait: Some(available),
            signal: Some(swapchain.render_finished[i].semaphore),
            capture: None,
            image: index,
            suboptimal,
        }))
    }

    fn present(&mut self, frame: &Acquired) -> Result<()> {
        if let Some(swapchain) = self.swapchain.as_ref()
            && (!swapchain.present(frame.image)? || frame.suboptimal)
        {
            self.recreate = true;
        }
        Ok(())
    }
}

//! The window side of the frame driver: the swapchain, made again when the window's
//! size changes or the surface says it is out of date, and never for a 0x0 surface;
//! or, for a software device, the window's shared memory ([`ShmPresenter`]).

use super::driver::{Acquired, FrameTarget};
use super::shm::ShmPresenter;
use crate::cli::PresentPath;
use crate::renderer::Target;
use crate::vulkan::Buffer;
use crate::vulkan::Context;
use crate::vulkan::swapchain::Swapchain;
use anyhow::{Context as _, Result, bail};
use ash::vk;
use gpu_allocator::MemoryLocation::GpuToCpu;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use winit::window::Window;

/// Acquires and presents swapchain images, or copies frames to the window's shared
/// memory.
pub struct Presenter {
    swapchain: Option<Swapchain>,
    /// The shared-memory path, where it is taken instead of the swapchain.
    shm: Option<ShmPresenter>,
    /// The swapchains' pixel format, which the renderer's pipelines are built for.
    format: vk::Format,
    /// Make the swapchain again before the next frame.
    pub recreate: bool,
    /// Swapchains (or shared-memory frame sets) made so far.
    pub swapchains: u64,
    /// Copy the next frame to [`Presenter::screenshot`]'s buffer.
    pub screenshot: bool,
    /// Where a screenshot's pixels go, and the size it was made for.
    capture: Option<(Buffer, vk::Extent2D)>,
    ctx: Arc<Context>,
}

impl Presenter {
    /// A presenter for the context's window surface; no swapchain yet.
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        Ok(Self {
            swapchain: None,
            shm: None,
            format: Swapchain::surface_format(ctx)?.format,
            recreate: false,
            swapchains: 0,
            screenshot: false,
            capture: None,
            ctx: ctx.clone(),
        })
    }

    /// A presenter for `window` on the way `path` asks: `Auto` takes the window's
    /// shared memory on a software device under X11 ([`PresentPath::resolve`]).
    pub fn for_window(ctx: &Arc<Context>, window: &Arc<Window>, path: PresentPath) -> Result<Self> {
        use winit::raw_window_handle::{HasDisplayHandle, RawDisplayHandle};
        let display = window.display_handle().context("display handle")?.as_raw();
        let x11 = matches!(
            display,
            RawDisplayHandle::Xlib(_) | RawDisplayHandle::Xcb(_)
        );
        let mut presenter = Self::new(ctx)?;
        if path.resolve(ctx.is_software(), x11) == PresentPath::SharedMemory {
            match ShmPresenter::new(ctx, window) {
                Ok(shm) => {
                    presenter.shm = Some(shm);
                    presenter.format = super::shm::FORMAT;
                }
                // Asked for, it is an error; chosen by itself, the swapchain stands in.
                Err(e) if path == PresentPath::SharedMemory => return Err(e),
                Err(e) => log::warn!("{e:#}: frames go to the window by its swapchain"),
            }
        }
        Ok(presenter)
    }

    /// The way frames reach the window.
    pub fn path(&self) -> PresentPath {
        if self.shm.is_some() {
            PresentPath::SharedMemory
        } else {
            PresentPath::Swapchain
        }
    }

    /// The surface's colour format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// Makes the swapchain for a window of `size` when it is missing or out of date;
    /// false while there is nothing to draw to (a 0x0 surface).
    pub fn prepare(&mut self, size: (u32, u32)) -> Result<bool> {
        if let Some(shm) = self.shm.as_mut() {
            let Some(remade) = shm.prepare(size, self.recreate)? else {
                return Ok(false);
            };
            self.swapchains += u64::from(remade);
            self.recreate = false;
            return Ok(true);
        }
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

impl Presenter {
    /// Writes the frame copied for a screenshot (wait for it first) as a new PNG in
    /// `folder`, named by the time (`grass-<seconds since 1970>.png`, `-2`, `-3`, ...
    /// added when that is taken), and returns its path; the request is then done.
    pub fn save_screenshot(&mut self, folder: &Path) -> Result<PathBuf> {
        self.screenshot = false;
        let (mut pixels, extent) = match self.shm.as_ref() {
            Some(shm) => shm.last_frame()?.context("no screenshot was taken")?,
            None => {
                let (buffer, extent) = self.capture.as_ref().context("no screenshot was taken")?;
                let bytes = (extent.width * extent.height * 4) as usize;
                (buffer.read::<u8>(bytes)?, *extent)
            }
        };
        // The swapchain's BGRA as the PNG's RGBA.
        if matches!(
            self.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        ) {
            pixels
                .as_chunks_mut::<4>()
                .0
                .iter_mut()
                .for_each(|p| p.swap(0, 2));
        }
        // Opaque, whatever the surface's alpha holds.
        pixels
            .as_chunks_mut::<4>()
            .0
            .iter_mut()
            .for_each(|p| p[3] = 255);
        let seconds = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        crate::files::save_png_new(
            folder,
            &format!("grass-{seconds}"),
            &pixels,
            (extent.width, extent.height),
            image::ColorType::Rgba8,
        )
    }
}

impl FrameTarget for Presenter {
    fn acquire(&mut self, available: vk::Semaphore, slot: usize) -> Result<Option<Acquired>> {
        if let Some(shm) = self.shm.as_mut() {
            return shm.acquire(available, slot);
        }
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(None);
        };
        let Some((index, suboptimal)) = swapchain.acquire(available)? else {
            self.recreate = true;
            return Ok(None);
        };
        let i = index as usize;
        let extent = swapchain.extent;
        let capture = if self.screenshot {
            if self.capture.as_ref().is_none_or(|(_, e)| *e != extent) {
                let bytes = u64::from(extent.width) * u64::from(extent.height) * 4;
                let usage = vk::BufferUsageFlags::TRANSFER_DST;
                let buffer = Buffer::new(&self.ctx, "screenshot", bytes, usage, GpuToCpu)?;
                self.capture = Some((buffer, extent));
            }
            self.capture.as_ref().map(|(b, _)| b.buffer)
        } else {
            None
        };
        Ok(Some(Acquired {
            target: Target {
                image: swapchain.images[i],
                view: swapchain.views[i],
                extent: swapchain.extent,
                final_layout: vk::ImageLayout::PRESENT_SRC_KHR,
                transfer_dst: swapchain.transfer_dst,
            },
            wait: Some(available),
            signal: Some(swapchain.render_finished[i].semaphore),
            capture,
            image: index,
            suboptimal,
        }))
    }

    fn present(&mut self, frame: &Acquired, done: vk::Fence) -> Result<()> {
        if let Some(shm) = self.shm.as_mut() {
            return shm.present(frame, done);
        }
        if let Some(swapchain) = self.swapchain.as_ref()
            && (!swapchain.present(frame.image)? || frame.suboptimal)
        {
            self.recreate = true;
        }
        Ok(())
    }
}

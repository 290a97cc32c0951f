//! Presenting a software device's frames through the window system's shared memory
//! instead of a Vulkan swapchain.
//!
//! Mesa's X11 swapchain shares memory with the X server only where the server has
//! DRI3 (`wsi_common_x11.c`); an X server without it (Xvfb, a VNC server) gets every
//! frame of a software device through its socket (`PutImage`): at 1920x1080 about 8 MB
//! copied into the socket, out of it and into the screen, on the cores that also
//! rasterise. Here each frame is drawn into an image in host memory with its rows one
//! after another ([`Image::host_linear`]), and its pixels are copied from there into
//! the window's buffer, which `softbuffer` puts into the window with MIT-SHM where the
//! server has it (the server copies it once from the shared segment) and with a plain
//! `PutImage` where it has not.
//!
//! A frame is shown when the next one has been submitted: its fence is waited for
//! then (the driver keeps [`FRAMES_IN_FLIGHT`] frames in flight), so the host's copy
//! of one frame overlaps the device's work on the next.

use super::driver::{Acquired, FRAMES_IN_FLIGHT, FrameTarget};
use crate::renderer::Target;
use crate::vulkan::{Context, Image};
use anyhow::{Context as _, Result, anyhow};
use ash::vk;
use std::num::NonZeroU32;
use std::sync::Arc;
use winit::window::Window;

/// Colour format of the frames: B, G, R, A bytes, which read as the window system's
/// `0x00RRGGBB` words on a little-endian host (a 24-bit window does not show the top
/// byte, alpha).
pub const FORMAT: vk::Format = vk::Format::B8G8R8A8_SRGB;

/// The window side of a software device's frames: host-linear images and the
/// window's shared-memory buffer.
pub struct ShmPresenter {
    surface: softbuffer::Surface<Arc<Window>, Arc<Window>>,
    /// One image per frame slot of the driver (which waits for a slot's fence before
    /// the slot's next frame), made on its first use.
    frames: [Option<Image>; FRAMES_IN_FLIGHT],
    /// The window size the images are made for.
    size: (u32, u32),
    /// The frame submitted last and not yet shown: its image, and the fence its
    /// submission signals.
    pending: Option<(usize, vk::Fence)>,
    /// The frame shown last: its image.
    shown: Option<usize>,
    ctx: Arc<Context>,
}

impl ShmPresenter {
    /// A presenter for `window`; no images until [`ShmPresenter::prepare`]. An error
    /// where the device cannot draw into host-linear [`FORMAT`] images or the window
    /// system has no buffer for the window.
    pub fn new(ctx: &Arc<Context>, window: &Arc<Window>) -> Result<Self> {
        let features = unsafe {
            ctx.instance
                .get_physical_device_format_properties(ctx.physical, FORMAT)
        }
        .linear_tiling_features;
        let needed =
            vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::TRANSFER_DST;
        anyhow::ensure!(
            features.contains(needed),
            "the device does not draw into host-linear {FORMAT:?} images"
        );
        let context = softbuffer::Context::new(window.clone())
            .map_err(|e| anyhow!("{e}"))
            .context("shared-memory presentation: the display")?;
        let surface = softbuffer::Surface::new(&context, window.clone())
            .map_err(|e| anyhow!("{e}"))
            .context("shared-memory presentation: the window")?;
        Ok(Self {
            surface,
            frames: Default::default(),
            size: (0, 0),
            pending: None,
            shown: None,
            ctx: ctx.clone(),
        })
    }

    /// Sizes the window's buffer for a window of `size` (width, height), the images
    /// made again on their first use, when the size changed or `remake` asks: whether
    /// it did; `None` while there is nothing to draw to (0x0).
    pub fn prepare(&mut self, size: (u32, u32), remake: bool) -> Result<Option<bool>> {
        let (Some(width), Some(height)) = (NonZeroU32::new(size.0), NonZeroU32::new(size.1)) else {
            return Ok(None);
        };
        let remade = remake || size != self.size;
        if remade {
            self.ctx.wait_idle()?;
            // A frame of the old size is not shown.
            self.pending = None;
            self.shown = None;
            self.frames = Default::default();
            self.surface
                .resize(width, height)
                .map_err(|e| anyhow!("{e}"))
                .context("shared-memory presentation: resize")?;
            self.size = size;
            log::info!("shared-memory frames {}x{}", size.0, size.1);
        }
        Ok(Some(remade))
    }

    /// The last submitted frame's pixels, rows of `FORMAT` one after another, and
    /// its size (wait for the frame first); `None` before the first.
    pub fn last_frame(&self) -> Result<Option<(Vec<u8>, vk::Extent2D)>> {
        let Some(at) = self.pending.map(|(i, _)| i).or(self.shown) else {
            return Ok(None);
        };
        let image = self.frames[at]
            .as_ref()
            .context("no image of the last frame")?;
        let extent = image.extent;
        let mut pixels = vec![0; extent.width as usize * extent.height as usize * 4];
        copy_rows(image, &mut pixels)?;
        Ok(Some((pixels, extent)))
    }

    /// The image of frame slot `slot`, made on its first use at the window's size.
    fn image_of(&mut self, slot: usize) -> Result<&Image> {
        let (width, height) = self.size;
        let extent = vk::Extent2D { width, height };
        // The overlay copies its opaque part in (transfer writes).
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST;
        let frame = self
            .frames
            .get_mut(slot)
            .context("a frame slot past those in flight")?;
        if frame.is_none() {
            *frame = Some(Image::host_linear(
                &self.ctx,
                "window frame",
                extent,
                FORMAT,
                usage,
            )?);
        }
        frame.as_ref().context("the frame's image")
    }

    /// Waits for the pending frame and hands its pixels to the window.
    fn show_pending(&mut self) -> Result<()> {
        let Some((at, fence)) = self.pending.take() else {
            return Ok(());
        };
        crate::vulkan::commands::wait_for(&self.ctx, fence)?;
        let mut buffer = self
            .surface
            .buffer_mut()
            .map_err(|e| anyhow!("{e}"))
            .context("shared-memory presentation: the window's buffer")?;
        let words: &mut [u32] = &mut buffer;
        let image = self.frames[at]
            .as_ref()
            .context("no image of the pending frame")?;
        copy_rows(image, bytemuck::cast_slice_mut(words))?;
        buffer
            .present()
            .map_err(|e| anyhow!("{e}"))
            .context("shared-memory presentation: present")?;
        self.shown = Some(at);
        Ok(())
    }
}

impl FrameTarget for ShmPresenter {
    fn acquire(&mut self, _available: vk::Semaphore, slot: usize) -> Result<Option<Acquired>> {
        if self.size.0 == 0 || self.size.1 == 0 {
            return Ok(None);
        }
        let image = self.image_of(slot)?;
        Ok(Some(Acquired {
            target: Target {
                image: image.image,
                view: image.view,
                extent: image.extent,
                // Left for the host to read.
                final_layout: vk::ImageLayout::GENERAL,
                transfer_dst: true,
            },
            wait: None,
            signal: None,
            capture: None,
            image: slot as u32,
            suboptimal: false,
        }))
    }

    fn present(&mut self, frame: &Acquired, done: vk::Fence) -> Result<()> {
        self.show_pending()?;
        self.pending = Some((frame.image as usize, done));
        Ok(())
    }
}

/// Copies a host-linear frame's rows into `out`, one after another (as many as fit).
fn copy_rows(image: &Image, out: &mut [u8]) -> Result<()> {
    let (rows, pitch) = image.host_rows()?;
    let width = image.extent.width as usize * 4;
    if pitch == width {
        let n = out.len().min(rows.len());
        out[..n].copy_from_slice(&rows[..n]);
        return Ok(());
    }
    for (row, line) in out.chunks_exact_mut(width).zip(rows.chunks(pitch)) {
        row.copy_from_slice(line.get(..width).context("a row past the image")?);
    }
    Ok(())
}

//! The window: a swapchain, the same frame into each of its images.

use anyhow::{Context as _, Result, bail};
use ash::vk;
use runner::embed::{self, GrassField, Ground};
use std::sync::Arc;
use std::sync::atomic::Ordering;

use super::args::*;
use super::cube::*;
use super::frame::*;
use super::gpu::*;
use super::stage::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

use ash::khr;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

/// Opens the window and draws until it is closed.
pub fn run(args: &Args) -> Result<()> {
    let (validation, frames, tiled) = (args.validation, args.frames, args.tiled);
    let event_loop = EventLoop::new().context("event loop (is there a display?)")?;
    let mut app = App {
        validation,
        tiled,
        resizes: args.resize_through.iter().rev().copied().collect(),
        frames,
        drawn: 0,
        state: None,
        error: None,
    };
    event_loop.run_app(&mut app)?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    let drawn = app.drawn;
    // Everything destroyed (and checked by the layer) before the count.
    drop(app);
    let errors = VALIDATION_ERRORS.load(Ordering::SeqCst);
    println!("drew {drawn} frames, {errors} validation errors");
    match errors {
        0 => Ok(()),
        _ => bail!("validation reported {errors} errors"),
    }
}

struct App {
    pub(crate) validation: bool,
    pub(crate) tiled: bool,
    /// Window sizes still to ask for, the next last.
    pub(crate) resizes: Vec<(u32, u32)>,
    /// Close after this many frames.
    pub(crate) frames: Option<u32>,
    pub(crate) drawn: u32,
    pub(crate) state: Option<State>,
    pub(crate) error: Option<anyhow::Error>,
}

/// Everything on the GPU, in the order it is dropped.
struct State {
    pub(crate) swapchain: Swapchain,
    pub(crate) field: GrassField,
    pub(crate) cube: Cube,
    pub(crate) stage: Stage,
    pub(crate) pool: vk::CommandPool,
    pub(crate) cmd: vk::CommandBuffer,
    pub(crate) fence: vk::Fence,
    pub(crate) acquired: vk::Semaphore,
    pub(crate) surface: vk::SurfaceKHR,
    pub(crate) surface_fn: khr::surface::Instance,
    pub(crate) gpu: Gpu,
    pub(crate) window: Arc<Window>,
}

/// The swapchain, its images, their depth and the semaphores their presentation
/// waits for.
struct Swapchain {
    pub(crate) loader: khr::swapchain::Device,
    pub(crate) swapchain: vk::SwapchainKHR,
    pub(crate) images: Vec<(vk::Image, vk::ImageView, vk::Semaphore)>,
    pub(crate) depth: Option<OwnedImage>,
    pub(crate) extent: vk::Extent2D,
    pub(crate) format: vk::Format,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_none() {
            match State::new(event_loop, self.validation, self.tiled) {
                Ok(state) => self.state = Some(state),
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        let result = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(_) => state.resize(),
            WindowEvent::RedrawRequested => {
                let drawn = state.draw();
                self.drawn += 1;
                if self.frames.is_some_and(|n| self.drawn >= n) {
                    event_loop.exit();
                }
                if self.drawn.is_multiple_of(10)
                    && let Some((w, h)) = self.resizes.pop()
                {
                    let size = winit::dpi::PhysicalSize::new(w, h);
                    let _ = state.window.request_inner_size(size);
                }
                state.window.request_redraw();
                drawn
            }
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.error = Some(e);
            event_loop.exit();
        }
    }
}

impl State {
    pub(crate) fn new(event_loop: &ActiveEventLoop, validation: bool, tiled: bool) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title("grass in your own renderer (runner::embed)")
            .with_inner_size(winit::dpi::LogicalSize::new(960, 540));
        let window = Arc::new(event_loop.create_window(attributes)?);
        let display = window.display_handle()?.as_raw();
        let extensions = ash_window::enumerate_required_extensions(display)?;
        let (entry, instance) = Gpu::instance(extensions, validation)?;
        let handle = window.window_handle()?.as_raw();
        let surface =
            unsafe { ash_window::create_surface(&entry, &instance, display, handle, None)? };
        let surface_fn = khr::surface::Instance::new(&entry, &instance);
        let format_for = |physical, family| {
            let presents = unsafe {
                surface_fn.get_physical_device_surface_support(physical, family, surface)
            };
            if !presents.unwrap_or(false) {
                return None;
            }
            let formats =
                unsafe { surface_fn.get_physical_device_surface_formats(physical, surface) }
                    .ok()?;
            let srgb = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];
            formats
                .iter()
                .map(|f| f.format)
                .find(|f| srgb.contains(f))
                .or(formats.first().map(|f| f.format))
        };
        let swapchain_ext = [khr::swapchain::NAME];
        let (gpu, format) = Gpu::new((entry, instance), validation, format_for, &swapchain_ext)?;
        let cube = Cube::new(&gpu.device, format)?;
        let field = gpu.grass(Ground::Hills, BLADES, tiled, format)?;
        let stage = Stage::new(&field);
        let (pool, cmd) = gpu.commands()?;
        let device = &gpu.device;
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        let fence = unsafe { device.create_fence(&signalled, None)? };
        let acquired =
            unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)? };
        let loader = khr::swapchain::Device::new(&gpu.instance, device);
        let mut swapchain = Swapchain {
            loader,
            swapchain: vk::SwapchainKHR::null(),
            images: Vec::new(),
            depth: None,
            extent: vk::Extent2D::default(),
            format,
        };
        swapchain.make(&gpu, &surface_fn, surface, format, &window)?;
        window.request_redraw();
        Ok(Self {
            swapchain,
            field,
            cube,
            stage,
            pool,
            cmd,
            fence,
            acquired,
            surface,
            surface_fn,
            gpu,
            window,
        })
    }

    pub(crate) fn resize(&mut self) -> Result<()> {
        let format = self.swapchain.format;
        unsafe { self.gpu.device.device_wait_idle()? };
        self.swapchain.make(
            &self.gpu,
            &self.surface_fn,
            self.surface,
            format,
            &self.window,
        )
    }

    /// One frame: wait for the last, acquire, record the cube and the grass,
    /// submit, present.
    pub(crate) fn draw(&mut self) -> Result<()> {
        let device = &self.gpu.device;
        let sc = &self.swapchain;
        if sc.extent.width == 0 || sc.extent.height == 0 {
            return Ok(());
        }
        unsafe { device.wait_for_fences(&[self.fence], true, u64::MAX)? };
        let acquire = unsafe {
            sc.loader
                .acquire_next_image(sc.swapchain, u64::MAX, self.acquired, vk::Fence::null())
        };
        let index = match acquire {
            Ok((index, _)) => index as usize,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return self.resize(),
            Err(e) => return Err(e.into()),
        };
        unsafe {
            device.reset_fences(&[self.fence])?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(self.cmd, &begin)?;
        }
        let (image, view, rendered) = sc.images[index];
        let depth = sc.depth.as_ref().context("depth image")?;
        let (gpu, cube, stage) = (&self.gpu, &self.cube, &self.stage);
        let cmd = self.cmd;
        record_frame(
            gpu,
            cube,
            &mut self.field,
            stage,
            cmd,
            (image, view),
            depth,
            sc.extent,
        )?;
        transition(
            device,
            cmd,
            (image, vk::ImageAspectFlags::COLOR),
            (L::COLOR_ATTACHMENT_OPTIMAL, L::PRESENT_SRC_KHR),
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            (S::NONE, A::NONE),
        );
        unsafe {
            device.end_command_buffer(cmd)?;
            let waits = [self.acquired];
            let stages = [vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT];
            let cmds = [cmd];
            let signals = [rendered];
            let submit = vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&cmds)
                .signal_semaphores(&signals);
            device.queue_submit(gpu.queue, &[submit], self.fence)?;
            let swapchains = [sc.swapchain];
            let indices = [index as u32];
            let present = vk::PresentInfoKHR::default()
                .wait_semaphores(&signals)
                .swapchains(&swapchains)
                .image_indices(&indices);
            match sc.loader.queue_present(gpu.queue, &present) {
                Ok(_) => Ok(()),
                Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.resize(),
                Err(e) => Err(e.into()),
            }
        }
    }
}

impl Swapchain {
    /// (Re)makes the swapchain for the window's size, with its views, semaphores
    /// and depth image.
    pub(crate) fn make(
        &mut self,
        gpu: &Gpu,
        surface_fn: &khr::surface::Instance,
        surface: vk::SurfaceKHR,
        format: vk::Format,
        window: &Window,
    ) -> Result<()> {
        let caps =
            unsafe { surface_fn.get_physical_device_surface_capabilities(gpu.physical, surface)? };
        let size = window.inner_size();
        let extent = match caps.current_extent.width {
            u32::MAX => vk::Extent2D {
                width: size.width,
                height: size.height,
            },
            _ => caps.current_extent,
        };
        self.release(gpu);
        self.extent = extent;
        println!("swapchain {}x{}", extent.width, extent.height);
        if extent.width == 0 || extent.height == 0 {
            return Ok(());
        }
        let count = (caps.min_image_count + 1).min(match caps.max_image_count {
            0 => u32::MAX,
            n => n,
        });
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format)
            .image_color_space(vk::ColorSpaceKHR::SRGB_NONLINEAR)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(self.swapchain);
        let made = unsafe { self.loader.create_swapchain(&info, None)? };
        unsafe { self.loader.destroy_swapchain(self.swapchain, None) };
        self.swapchain = made;
        self.format = format;
        for image in unsafe { self.loader.get_swapchain_images(made)? } {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format)
                .subresource_range(range(vk::ImageAspectFlags::COLOR));
            let view = unsafe { gpu.device.create_image_view(&view_info, None)? };
            let info = vk::SemaphoreCreateInfo::default();
            let rendered = unsafe { gpu.device.create_semaphore(&info, None)? };
            self.images.push((image, view, rendered));
        }
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        self.depth = Some(gpu.image(extent, embed::DEPTH_FORMAT, usage)?);
        Ok(())
    }

    /// Destroys the views, semaphores and depth image (not the swapchain: the
    /// next one is made from it).
    pub(crate) fn release(&mut self, gpu: &Gpu) {
        for (_, view, rendered) in self.images.drain(..) {
            unsafe {
                gpu.device.destroy_image_view(view, None);
                gpu.device.destroy_semaphore(rendered, None);
            }
        }
        if let Some(depth) = self.depth.take() {
            gpu.destroy_image(depth);
        }
    }
}

impl Drop for State {
    fn drop(&mut self) {
        let gpu = &self.gpu;
        unsafe {
            let _ = gpu.device.device_wait_idle();
            self.swapchain.release(gpu);
            self.swapchain
                .loader
                .destroy_swapchain(self.swapchain.swapchain, None);
            gpu.device.destroy_semaphore(self.acquired, None);
            gpu.device.destroy_fence(self.fence, None);
            gpu.device.destroy_command_pool(self.pool, None);
            self.surface_fn.destroy_surface(self.surface, None);
        }
        // The field and the cube go next (field order), then the device.
    }
}

//! What the viewer holds on the GPU, made again when the device is lost.

use crate::app::driver::{FRAMES_IN_FLIGHT, FrameDriver};
use crate::app::presenter::Presenter;
use crate::cli::{Common, PresentPath};
use crate::renderer::Renderer;
use crate::scene::Scene;
use crate::vulkan::{Context, ContextOptions};
use anyhow::{Context as _, Result};
use shared::species::Mix;
use std::sync::Arc;
use winit::raw_window_handle::HasDisplayHandle;
use winit::window::Window;

/// Everything on the GPU: made once at start, and again after a lost device.
pub(super) struct Gpu {
    /// Runs the frames.
    pub(super) driver: FrameDriver,
    /// The swapchain side.
    pub(super) presenter: Presenter,
}

impl Gpu {
    /// A context for `window`'s surface, validated as `common` asks.
    pub(super) fn context(window: &Window, common: &Common) -> Result<Arc<Context>> {
        let display = window.display_handle().context("display handle")?.as_raw();
        let extensions = ash_window::enumerate_required_extensions(display)
            .context("Vulkan surface extensions for this window system")?;
        Context::new(ContextOptions {
            validation: common.validation_requested(),
            checks: common.checks(),
            surface_extensions: extensions,
            window: Some(window),
        })
    }

    /// The presenter for `window` (`present` asks how), the renderer of `scene` (its
    /// blades as the seed made them) with the overlay, and the frame driver, on `ctx`.
    pub(super) fn new(
        ctx: &Arc<Context>,
        scene: &Scene,
        window: &Arc<Window>,
        present: PresentPath,
    ) -> Result<Self> {
        let presenter = Presenter::for_window(ctx, window, present)?;
        log::info!("frames reach the window by {:?}", presenter.path());
        let mut renderer = Renderer::new(ctx, &scene.meshes(), presenter.format())?;
        renderer.enable_overlay(FRAMES_IN_FLIGHT)?;
        let driver = FrameDriver::new(ctx, renderer)?;
        Ok(Self { driver, presenter })
    }
}

impl Gpu {
    /// The device's name and how frames reach the window, as the overlay shows them.
    pub(super) fn shown_device(&self, ctx: &Context) -> String {
        format!("{}, {}", ctx.device_name(), self.presenter.path().name())
    }

    /// The field of `scene` grown as the species `mix` from the next frame on
    /// (`Scene::set_species`): a stored field's blades replaced, a tiled field's pool
    /// made anew; the collisions reach the tallest of them.
    pub(super) fn set_species(&mut self, scene: &mut Scene, mix: Mix) -> Result<()> {
        if !scene.set_species(mix) {
            return Ok(());
        }
        let renderer = &mut self.driver.renderer;
        match renderer.tiles.as_mut() {
            Some(tiles) => {
                tiles.set_species(mix);
                renderer.field.set_tiled_species(&scene.paint, mix);
            }
            None => renderer.replace_blades(&scene.blades)?,
        }
        log::info!("the field grows {mix}");
        Ok(())
    }
}

/// True when `error` came from a lost device.
pub(super) fn device_lost(error: &anyhow::Error) -> bool {
    error
        .chain()
        .any(|c| c.downcast_ref::<ash::vk::Result>() == Some(&ash::vk::Result::ERROR_DEVICE_LOST))
}

/// Lost devices the viewer makes again before it gives up.
pub(super) const MAX_RECOVERIES: u32 = 3;

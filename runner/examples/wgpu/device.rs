//! The program's wgpu device: wgpu's Vulkan instance and first adapter, and a device
//! on it that can also draw the grass (`runner::embed::wgpu::GrassDevice`), with the
//! validation layer's errors counted where asked.

use anyhow::{Context as _, Result};
use ash::vk;
use runner::embed::wgpu::GrassDevice;

pub use super::validation::VALIDATION_ERRORS;
use super::validation::debug_messenger;

/// What wgpu needs of its device here: the cube's SPIR-V from `shaders-rs` passed
/// through as it is (no WGSL, no translation), and its push constants (wgpu's
/// immediates).
pub const WGPU_FEATURES: wgpu::Features =
    wgpu::Features::PASSTHROUGH_SHADERS.union(wgpu::Features::IMMEDIATES);

/// The device, and the validation layer's messenger while it lives.
pub struct Devices {
    /// wgpu's device and queue, and the same device as the grass takes it.
    pub gpu: GrassDevice,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
}

impl Devices {
    /// On the first Vulkan adapter wgpu finds, for colour textures of `color`; the
    /// validation layer on with `validation`.
    pub fn new(color: wgpu::TextureFormat, validation: bool) -> Result<Self> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        if validation {
            desc.flags |= wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG;
        }
        let instance = wgpu::Instance::new(desc);
        let options = wgpu::RequestAdapterOptions::default();
        let adapter =
            pollster::block_on(instance.request_adapter(&options)).context("no Vulkan adapter")?;
        let desc = wgpu::DeviceDescriptor {
            label: Some("wgpu and grass"),
            required_features: WGPU_FEATURES,
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let gpu = GrassDevice::new(instance, adapter, color, &desc)?;
        let debug = if validation {
            let grass = gpu.grass();
            Some(debug_messenger(&grass.entry, &grass.instance)?)
        } else {
            None
        };
        Ok(Self { gpu, debug })
    }
}

impl Drop for Devices {
    fn drop(&mut self) {
        if let Some((utils, messenger)) = self.debug.take() {
            unsafe { utils.destroy_debug_utils_messenger(messenger, None) };
        }
    }
}

//! The program's own Vulkan: instance, device, queue, allocator, images and the
//! validation messages, as an engine has them before it adds grass.

use anyhow::{Context as _, Result, bail};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use runner::embed::{self, FieldDesc, GrassField, Ground};

pub use super::validation::{VALIDATION_ERRORS, debug_messenger};
use std::ffi::{CStr, c_char};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

/// The program's own Vulkan objects: what any ash renderer has before it adds grass.
pub struct Gpu {
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    pub(crate) queue_family: u32,
    pub(crate) queue: vk::Queue,
    /// Shared with the field; dropped before the device.
    pub(crate) allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    /// What the field asked to enable (and this device has).
    pub(crate) features: embed::DeviceFeatures,
    pub(crate) debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
}

impl Gpu {
    /// The instance, with `extensions` (a window system's) and, if asked, validation.
    pub fn instance(
        extensions: &[*const c_char],
        validation: bool,
    ) -> Result<(ash::Entry, ash::Instance)> {
        let entry = unsafe { ash::Entry::load() }.context("load Vulkan")?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"embed example")
            .api_version(vk::API_VERSION_1_3);
        let mut extensions = extensions.to_vec();
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let layers: &[_] = if validation { &layers } else { &[] };
        if validation {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        // Synchronization validation too: hazards between the program's commands and
        // the field's.
        let checks = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&checks);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(layers)
            .enabled_extension_names(&extensions);
        if validation {
            info = info.push_next(&mut features);
        }
        let instance = unsafe { entry.create_instance(&info, None) }.context("create instance")?;
        Ok((entry, instance))
    }

    /// On the first device with a graphics + compute queue family that `format_for`
    /// gives a colour format for (the one its images will have) and that has what the
    /// grass needs for that format (`embed::requirements`, asked before anything is
    /// made): a device with those features and `extensions`, and its allocator.
    pub fn new(
        (entry, instance): (ash::Entry, ash::Instance),
        validation: bool,
        format_for: impl Fn(vk::PhysicalDevice, u32) -> Option<vk::Format>,
        extensions: &[&CStr],
    ) -> Result<(Self, vk::Format)> {
        let debug = match validation {
            true => Some(debug_messenger(&entry, &instance)?),
            false => None,
        };
        let mut reasons = Vec::new();
        let mut chosen = None;
        for physical in unsafe { instance.enumerate_physical_devices()? } {
            let families =
                unsafe { instance.get_physical_device_queue_family_properties(physical) };
            let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
            let found = (0..families.len() as u32)
                .filter(|&f| families[f as usize].queue_flags.contains(wanted))
                .find_map(|f| Some((f, format_for(physical, f)?)));
            let Some((family, format)) = found else {
                reasons.push("no graphics queue for these images".to_string());
                continue;
            };
            match embed::requirements(&instance, physical, format) {
                Ok(features) => {
                    chosen = Some((physical, family, format, features));
                    break;
                }
                Err(missing) => reasons.push(missing.to_string()),
            }
        }
        let Some((physical, queue_family, format, mut features)) = chosen else {
            bail!("no device can draw the grass: {}", reasons.join("; "));
        };
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let names: Vec<_> = features
            .extensions()
            .into_iter()
            .chain(extensions.iter().copied())
            .map(CStr::as_ptr)
            .collect();
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&names);
        let info = features.enable(info);
        let device =
            unsafe { instance.create_device(physical, &info, None) }.context("create device")?;
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let gpu = Gpu {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue,
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            features,
            debug,
        };
        Ok((gpu, format))
    }

    /// The grass: `blades` on `ground` (or a tiled field), drawing into `format`
    /// images.
    pub fn grass(
        &self,
        ground: Ground,
        blades: u32,
        tiled: bool,
        format: vk::Format,
    ) -> Result<GrassField> {
        let device = embed::Device {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            physical: self.physical,
            device: self.device.clone(),
            queue_family: self.queue_family,
            queue: self.queue,
            allocator: Arc::clone(&self.allocator),
        };
        let desc = FieldDesc {
            ground,
            blades,
            seed: 1,
            species: shared::species::Mix::GRASS,
            color_format: format,
            draw_ground: true,
            tiled,
            reverse_z: false,
        };
        GrassField::new(device, &self.features, desc)
    }

    /// A single-sampled image of `format` with its memory and a view.
    pub(crate) fn image(
        &self,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<OwnedImage> {
        let aspect = if format == embed::DEPTH_FORMAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(extent.into())
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let image = unsafe { self.device.create_image(&info, None)? };
        let requirements = unsafe { self.device.get_image_memory_requirements(image) };
        let memory = self.lock()?.allocate(&AllocationCreateDesc {
            name: "example image",
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        unsafe {
            self.device
                .bind_image_memory(image, memory.memory(), memory.offset())?
        };
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        let view = unsafe { self.device.create_image_view(&view_info, None)? };
        Ok(OwnedImage {
            image,
            view,
            memory: Some(memory),
            aspect,
        })
    }

    /// Destroys an image of [`Self::image`] (no longer in use).
    pub(crate) fn destroy_image(&self, mut image: OwnedImage) {
        unsafe {
            self.device.destroy_image_view(image.view, None);
            self.device.destroy_image(image.image, None);
        }
        if let (Some(memory), Ok(mut allocator)) = (image.memory.take(), self.lock()) {
            let _ = allocator.free(memory);
        }
    }

    pub(crate) fn lock(&self) -> Result<std::sync::MutexGuard<'_, Allocator>> {
        self.allocator
            .lock()
            .map_err(|_| anyhow::anyhow!("allocator lock poisoned"))
    }

    /// A command pool on the queue's family, and one command buffer from it.
    pub(crate) fn commands(&self) -> Result<(vk::CommandPool, vk::CommandBuffer)> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { self.device.create_command_pool(&info, None)? };
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd = unsafe { self.device.allocate_command_buffers(&info)? }[0];
        Ok((pool, cmd))
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            // The field (holding the other clone) is gone by now.
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.debug.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// An image this program made.
pub struct OwnedImage {
    pub(crate) image: vk::Image,
    pub(crate) view: vk::ImageView,
    pub(crate) memory: Option<Allocation>,
    pub(crate) aspect: vk::ImageAspectFlags,
}

/// The whole of a single-level image.
pub(crate) fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}

/// A layout change of the whole `image`, after `src` and before `dst`.
pub(crate) fn transition(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (image, aspect): (vk::Image, vk::ImageAspectFlags),
    layouts: (vk::ImageLayout, vk::ImageLayout),
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(range(aspect))
        .old_layout(layouts.0)
        .new_layout(layouts.1)
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    let info = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &info) };
}

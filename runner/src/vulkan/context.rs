//! Entry, instance, validation messenger, physical device, device, queue, allocator.

use super::features::{DeviceFeatures, name_of};
use anyhow::{Context as _, Result, bail};
use ash::{ext, khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::ffi::{CStr, c_void};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

/// Why no device could be used: the caller (and the user) must know which.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// The Vulkan loader could not be loaded at all.
    #[error(
        "no Vulkan loader found ({0}); install a Vulkan driver, e.g. \
         `sudo apt-get install mesa-vulkan-drivers` for the software device lavapipe"
    )]
    NoVulkan(String),
    /// The loader works but finds no driver (no installable client driver).
    #[error(
        "no Vulkan driver found; install one, e.g. `sudo apt-get install mesa-vulkan-drivers` \
         for the software device lavapipe"
    )]
    NoDriver,
    /// The loader works but reports no physical device.
    #[error(
        "no Vulkan device found; install a driver, e.g. `sudo apt-get install mesa-vulkan-drivers`"
    )]
    NoDevice,
    /// Devices exist, but none has what the renderer needs.
    #[error("no usable Vulkan device: {0}")]
    Unsuitable(String),
}

/// What the context is created for.
#[derive(Default)]
pub struct ContextOptions<'a> {
    /// Enable `VK_LAYER_KHRONOS_validation` and count its errors.
    pub validation: bool,
    /// Which of the layer's checks run beside its core ones.
    pub checks: ValidationChecks,
    /// Instance extensions the window system needs (empty when headless).
    pub surface_extensions: &'a [*const std::ffi::c_char],
    /// Create a surface for this window and pick a device that can present to it.
    #[cfg(feature = "app")]
    pub window: Option<&'a winit::window::Window>,
}

/// The validation layer's checks beside its core ones.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum ValidationChecks {
    /// Synchronization validation: hazards between commands.
    #[default]
    Synchronization,
    /// GPU-assisted validation: shaders instrumented to check their own accesses
    /// (instead of synchronization validation, which the layer does not run with it).
    GpuAssisted,
    /// Synchronization validation and the best-practices checks (warnings about
    /// correct but costly use).
    BestPractices,
}

impl ValidationChecks {
    /// The layer's features this enables.
    fn features(self) -> &'static [vk::ValidationFeatureEnableEXT] {
        use vk::ValidationFeatureEnableEXT as F;
        match self {
            Self::Synchronization => &[F::SYNCHRONIZATION_VALIDATION],
            Self::GpuAssisted => &[F::GPU_ASSISTED, F::GPU_ASSISTED_RESERVE_BINDING_SLOT],
            Self::BestPractices => &[F::SYNCHRONIZATION_VALIDATION, F::BEST_PRACTICES],
        }
    }
}

/// The device and everything created once per run; shared by `Arc`.
pub struct Context {
    /// Loaded Vulkan entry points.
    pub entry: ash::Entry,
    /// The instance.
    pub instance: ash::Instance,
    /// The chosen physical device.
    pub physical: vk::PhysicalDevice,
    /// Its properties (name, limits, type).
    pub properties: vk::PhysicalDeviceProperties,
    /// The logical device.
    pub device: ash::Device,
    /// The one graphics + compute queue.
    pub queue: vk::Queue,
    /// Its family index.
    pub queue_family: u32,
    /// Valid bits of the queue's timestamps; 0 when it has none.
    pub timestamp_bits: u32,
    /// Pipeline statistics queries are enabled (the device has them).
    pub pipeline_statistics: bool,
    /// `VK_EXT_mesh_shader`'s commands, when the device has mesh stages
    /// within the limits the mesh path needs (and they are enabled); else why not.
    pub mesh_shader: Result<ext::mesh_shader::Device, String>,
    /// `Ok` when the device has 64-bit integers and 64-bit atomics on storage buffers
    /// (enabled): what the compute rasterizer's visibility buffer needs; else what is
    /// missing.
    pub int64_atomics: Result<(), String>,
    /// `VK_KHR_pipeline_executable_properties`' commands, where the compute pipelines'
    /// statistics are asked for (`features::STATS_VARIABLE`) and enabled.
    pub executables: Option<khr::pipeline_executable_properties::Device>,
    /// Surface of the window, when there is one.
    pub surface: Option<vk::SurfaceKHR>,
    /// Surface functions.
    pub surface_fn: khr::surface::Instance,
    /// Memory allocator; dropped before the device.
    pub allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    debug: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    validation: Box<ValidationCounts>,
    /// The device and instance are this context's to destroy (not a caller's).
    owned: bool,
}

/// A made device and what the renderer needs of it, by value: ash's instance and
/// device are tables of function pointers, cloned freely.
pub struct DeviceParts {
    /// Loaded Vulkan entry points.
    pub entry: ash::Entry,
    /// The instance.
    pub instance: ash::Instance,
    /// The physical device.
    pub physical: vk::PhysicalDevice,
    /// The logical device.
    pub device: ash::Device,
    /// A queue family with graphics and compute.
    pub queue_family: u32,
    /// A queue of that family: where the renderer submits its uploads (and, in its own
    /// program, its frames).
    pub queue: vk::Queue,
    /// The memory allocator on this device.
    pub allocator: Arc<Mutex<Allocator>>,
}

/// What the validation layer has said: errors, and every message (warnings too).
#[derive(Default)]
struct ValidationCounts {
    errors: AtomicU32,
    messages: AtomicU32,
}

pub(super) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

impl Context {
    /// Loads Vulkan, creates the instance (with validation if asked) and the device
    /// that has every feature the renderer needs.
    pub fn new(options: ContextOptions) -> Result<Arc<Self>> {
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| DeviceError::NoVulkan(e.to_string()))?;
        let validation = Box::new(ValidationCounts::default());

        let mut layers = Vec::new();
        let mut extensions = options.surface_extensions.to_vec();
        if options.validation {
            let available = unsafe { entry.enumerate_instance_layer_properties()? };
            if !available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
            {
                bail!(
                    "validation requested but {} is not installed \
                     (Debian/Ubuntu: `sudo apt-get install vulkan-validationlayers`)",
                    VALIDATION_LAYER.to_string_lossy()
                );
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ext::debug_utils::NAME.as_ptr());
            extensions.push(ext::validation_features::NAME.as_ptr());
        }
        // Validation means synchronization validation too (hazards between commands
        // that core validation does not look for). Its queue-submit check stays off:
        // it crashes inside Debian's layer (1.3.239).
        let mut features = vk::ValidationFeaturesEXT::default()
            .enabled_validation_features(options.checks.features());

        let app = vk::ApplicationInfo::default()
            .application_name(c"grass")
            .api_version(vk::API_VERSION_1_3);
        let mut instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if options.validation {
            instance_info = instance_info.push_next(&mut features);
        }
        let instance = match unsafe { entry.create_instance(&instance_info, None) } {
            Ok(instance) => instance,
            Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => return Err(DeviceError::NoDriver.into()),
            Err(e) => return Err(e).context("create Vulkan instance"),
        };

        let debug = if options.validation {
            let utils = ext::debug_utils::Instance::new(&entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                        | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                        | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(debug_callback))
                .user_data(&*validation as *const ValidationCounts as *mut c_void);
            let messenger = unsafe { utils.create_debug_utils_messenger(&info, None)? };
            Some((utils, messenger))
        } else {
            None
        };

        let surface_fn = khr::surface::Instance::new(&entry, &instance);
        #[cfg(feature = "app")]
        let surface = match options.window {
            Some(window) => Some(create_surface(&entry, &instance, window)?),
            None => None,
        };
        // Without the program's window system only headless contexts are made.
        #[cfg(not(feature = "app"))]
        let surface = None;

        let (physical, queue_family) = pick_device(&instance, &surface_fn, surface)?;
        let mut features = DeviceFeatures::query(&instance, physical)?;
        let device = create_device(
            &instance,
            physical,
            queue_family,
            surface.is_some(),
            &mut features,
        )?;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .context("create memory allocator")?;
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let device = DeviceParts {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue,
            allocator: Arc::new(Mutex::new(allocator)),
        };
        let mut ctx = Self::assemble(device, &features, true);
        ctx.surface = surface;
        ctx.debug = debug;
        ctx.validation = validation;
        Ok(Arc::new(ctx))
    }

    /// A context on a device someone else made and keeps (the embedding API): it
    /// destroys nothing of theirs, and allocates through their allocator. `features`
    /// are what the device was made with ([`DeviceFeatures::enable`]).
    pub fn from_external(device: DeviceParts, features: &DeviceFeatures) -> Arc<Self> {
        Arc::new(Self::assemble(device, features, false))
    }

    /// The context of a made device: its queue, properties and optional paths.
    fn assemble(parts: DeviceParts, features: &DeviceFeatures, owned: bool) -> Self {
        let DeviceParts {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue,
            allocator,
        } = parts;
        let properties = unsafe { instance.get_physical_device_properties(physical) };
        let timestamp_bits = unsafe {
            instance.get_physical_device_queue_family_properties(physical)[queue_family as usize]
                .timestamp_valid_bits
        };
        let mesh_shader = features
            .mesh_shader
            .clone()
            .map(|()| ext::mesh_shader::Device::new(&instance, &device));
        let surface_fn = khr::surface::Instance::new(&entry, &instance);
        let executables = (owned && features.pipeline_executables())
            .then(|| khr::pipeline_executable_properties::Device::new(&instance, &device));
        if std::env::var_os(super::features::STATS_VARIABLE).is_some() && executables.is_none() {
            log::warn!(
                "{} is set, but no pipeline statistics: {}",
                super::features::STATS_VARIABLE,
                if owned {
                    "the device has no VK_KHR_pipeline_executable_properties"
                } else {
                    "the device is the host program's"
                }
            );
        }
        let ctx = Self {
            entry,
            instance,
            physical,
            properties,
            device,
            queue,
            queue_family,
            timestamp_bits,
            pipeline_statistics: features.pipeline_statistics(),
            mesh_shader,
            int64_atomics: features.int64_atomics.clone(),
            executables,
            surface: None,
            surface_fn,
            allocator: ManuallyDrop::new(allocator),
            debug: None,
            validation: Box::default(),
            owned,
        };
        log::info!(
            "device: {} ({:?}), Vulkan {}.{}.{}",
            ctx.device_name(),
            ctx.properties.device_type,
            vk::api_version_major(ctx.properties.api_version),
            vk::api_version_minor(ctx.properties.api_version),
            vk::api_version_patch(ctx.properties.api_version),
        );
        ctx
    }

    /// The device's name as the driver reports it.
    pub fn device_name(&self) -> String {
        name_of(&self.properties)
    }

    /// What the renderer's choices depend on in this device.
    pub fn capabilities(&self) -> Capabilities {
        Capabilities {
            name: self.device_name(),
            software: self.is_software(),
            mesh_shader: self.mesh_shader.as_ref().map(|_| ()).map_err(Clone::clone),
            int64_atomics: self.int64_atomics.clone(),
        }
    }

    /// True for a software rasteriser such as lavapipe.
    pub fn is_software(&self) -> bool {
        self.properties.device_type == vk::PhysicalDeviceType::CPU
    }

    /// Validation errors reported so far (0 when validation is off).
    pub fn validation_errors(&self) -> u32 {
        self.validation.errors.load(Ordering::SeqCst)
    }

    /// Validation messages of any severity (errors and warnings) so far.
    pub fn validation_messages(&self) -> u32 {
        self.validation.messages.load(Ordering::SeqCst)
    }

    /// Device memory this run holds through the allocator: (bytes in live
    /// allocations, bytes of the memory blocks they live in).
    pub fn device_memory(&self) -> (u64, u64) {
        self.allocator.lock().map_or((0, 0), |a| {
            let report = a.generate_report();
            (report.total_allocated_bytes, report.total_capacity_bytes)
        })
    }

    /// Memory for a resource with `requirements` in `location` (`linear` for buffers).
    pub fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: gpu_allocator::MemoryLocation,
        linear: bool,
    ) -> Result<gpu_allocator::vulkan::Allocation> {
        let desc = gpu_allocator::vulkan::AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: gpu_allocator::vulkan::AllocationScheme::GpuAllocatorManaged,
        };
        let mut allocator = self
            .allocator
            .lock()
            .map_err(|_| anyhow::anyhow!("allocator lock poisoned"))?;
        allocator
            .allocate(&desc)
            .with_context(|| format!("allocate {} bytes for {name}", requirements.size))
    }

    /// Size of the largest device-local memory heap, bytes.
    pub fn largest_device_heap(&self) -> u64 {
        let memory = unsafe {
            self.instance
                .get_physical_device_memory_properties(self.physical)
        };
        memory.memory_heaps[..memory.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0)
    }

    /// Workgroups for `items` threads of `size`: x up to the device's limit, then y
    /// (a dispatch's grid).
    pub fn workgroups(&self, items: u32, size: u32) -> (u32, u32) {
        let groups = items.div_ceil(size).max(1);
        let x = groups.min(self.properties.limits.max_compute_work_group_count[0]);
        (x, groups.div_ceil(x))
    }

    /// The most samples per pixel, at most `wanted` (1, 2, 4 or 8), that colour
    /// targets of the renderer's formats and depth targets both have.
    pub fn supported_samples(&self, wanted: u32) -> u32 {
        let limits = &self.properties.limits;
        let both = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
        [8u32, 4, 2]
            .into_iter()
            .find(|&n| n <= wanted && both.contains(vk::SampleCountFlags::from_raw(n)))
            .unwrap_or(1)
    }

    /// Waits until the device is idle (before destroying what it may still use).
    pub fn wait_idle(&self) -> Result<()> {
        unsafe { self.device.device_wait_idle() }.context("wait for device idle")
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            if !self.owned {
                return;
            }
            self.device.destroy_device(None);
            if let Some(surface) = self.surface {
                self.surface_fn.destroy_surface(surface, None);
            }
            if let Some((utils, messenger)) = self.debug.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

#[cfg(feature = "app")]
fn create_surface(
    entry: &ash::Entry,
    instance: &ash::Instance,
    window: &winit::window::Window,
) -> Result<vk::SurfaceKHR> {
    use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
    let display = window.display_handle().context("window display handle")?;
    let handle = window.window_handle().context("window handle")?;
    unsafe { ash_window::create_surface(entry, instance, display.as_raw(), handle.as_raw(), None) }
        .context("create window surface")
}

/// The first discrete GPU, else the first other device, that has Vulkan 1.3, every
/// feature and a graphics + compute queue (able to present, with a surface).
pub(super) fn pick_device(
    instance: &ash::Instance,
    surface_fn: &khr::surface::Instance,
    surface: Option<vk::SurfaceKHR>,
) -> Result<(vk::PhysicalDevice, u32)> {
    let devices = unsafe { instance.enumerate_physical_devices() }.unwrap_or_default();
    if devices.is_empty() {
        return Err(DeviceError::NoDevice.into());
    }
    let mut reasons = Vec::new();
    let mut candidates = Vec::new();
    for physical in devices {
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let name = name_of(&props);
        if let Err(missing) = DeviceFeatures::query(instance, physical) {
            reasons.push(format!("{name}: missing {}", missing.missing.join(", ")));
            continue;
        }
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let family = families.iter().enumerate().position(|(i, f)| {
            let flags = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
            let presents = surface.is_none_or(|s| unsafe {
                surface_fn
                    .get_physical_device_surface_support(physical, i as u32, s)
                    .unwrap_or(false)
            });
            f.queue_flags.contains(flags) && presents
        });
        match family {
            Some(family) => candidates.push((props.device_type, physical, family as u32)),
            None => reasons.push(format!("{name}: no graphics queue that can present")),
        }
    }
    let rank = |t: vk::PhysicalDeviceType| match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    };
    candidates.sort_by_key(|(t, _, _)| rank(*t));
    match candidates.first() {
        Some(&(_, physical, family)) => Ok((physical, family)),
        None => Err(DeviceError::Unsuitable(reasons.join("; ")).into()),
    }
}

fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    queue_family: u32,
    present: bool,
    features: &mut DeviceFeatures,
) -> Result<ash::Device> {
    let priorities = [1.0];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let mut extensions: Vec<_> = features.extensions().iter().map(|e| e.as_ptr()).collect();
    if present {
        extensions.push(khr::swapchain::NAME.as_ptr());
    }
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions);
    let info = features.enable(info);
    unsafe { instance.create_device(physical, &info, None) }.context("create Vulkan device")
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let message = unsafe { data.as_ref() }
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    let counts = unsafe { (user as *const ValidationCounts).as_ref() };
    if let Some(counts) = counts {
        counts.messages.fetch_add(1, Ordering::SeqCst);
    }
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        if let Some(counts) = counts {
            counts.errors.fetch_add(1, Ordering::SeqCst);
        }
        log::error!("validation: {message}");
    } else {
        log::warn!("validation: {message}");
    }
    vk::FALSE
}

/// What the renderer's choices depend on in a device: the one it would use here (the
/// probe's, `super::probe`), or the one a context holds ([`Context::capabilities`]).
#[derive(Clone, Debug)]
pub struct Capabilities {
    /// Its name, as its driver reports it.
    pub name: String,
    /// A software rasteriser such as lavapipe.
    pub software: bool,
    /// `Ok` when the mesh path is available; else why not.
    pub mesh_shader: Result<(), String>,
    /// `Ok` when the compute rasterizer is available; else why not.
    pub int64_atomics: Result<(), String>,
}

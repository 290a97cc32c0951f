//! The grass on a wgpu device, through wgpu-hal's Vulkan interop (the `wgpu`
//! feature; wgpu 29, whose ash and gpu-allocator are this crate's).
//!
//! - [`GrassDevice::new`] makes the `VkDevice` with ash, with the wgpu features asked
//!   and what the grass needs ([`super::requirements`], enabled beside wgpu's own
//!   feature structs by [`DeviceFeatures::enable_beside`]), and hands it to wgpu
//!   (`device_from_raw`, `create_device_from_hal`). wgpu's own hook for adding to its
//!   device, `open_with_callback`, cannot: it overwrites the core features, where
//!   `tessellationShader` lives.
//! - [`record`] records a field's frame into wgpu's colour and depth textures: wgpu
//!   may not mix its commands with raw ones in one encoder, so the grass gets an
//!   encoder of its own, to submit after wgpu's (in the same `Queue::submit`).
//!
//! wgpu opens queue 0 of family 0; the field takes the same queue, and
//! [`super::GrassField::new`] submits its uploads there: make it on the thread that
//! submits wgpu's work. wgpu owns the `VkDevice` and destroys it with its last
//! handle: drop the field first.

use super::{DeviceFeatures, Frame, GrassField, Targets};
use anyhow::{Context as _, Result, bail};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::sync::{Arc, Mutex};
use wgpu::hal::api::Vulkan;

use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// wgpu's instance, adapter, device and queue on a `VkDevice` that can also draw the
/// grass, and that device as the grass takes it.
pub struct GrassDevice {
    // First to go: the allocator frees its memory before wgpu's last handle destroys
    // the device.
    grass: super::Device,
    /// wgpu's device (it owns the `VkDevice`).
    pub device: wgpu::Device,
    /// wgpu's queue: the `VkQueue` the field submits its uploads to.
    pub queue: wgpu::Queue,
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The instance.
    pub instance: wgpu::Instance,
    /// What the device was made with for the grass.
    pub features: DeviceFeatures,
}

impl GrassDevice {
    /// A device on `adapter` (of `instance`, Vulkan) as `desc` asks wgpu for one (its
    /// features, limits, experimental features and memory hints), with what the grass
    /// needs to draw into colour textures of `color`; or why not (the adapter is not
    /// Vulkan, the device lacks what the grass needs, naming each thing, or its queue
    /// family 0 has no graphics and compute).
    pub fn new(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        color: wgpu::TextureFormat,
        desc: &wgpu::DeviceDescriptor,
    ) -> Result<Self> {
        let (features, limits) = (desc.required_features, &desc.required_limits);
        let hal = unsafe { adapter.as_hal::<Vulkan>() }.context("not a Vulkan adapter")?;
        let shared = hal.shared_instance();
        let (entry, raw_instance) = (shared.entry().clone(), shared.raw_instance().clone());
        let physical = hal.raw_physical_device();
        let color_format = hal.texture_format_as_raw(color);
        let mut grass_features = super::requirements(&raw_instance, physical, color_format)?;
        let families =
            unsafe { raw_instance.get_physical_device_queue_family_properties(physical) };
        let both = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        if !families
            .first()
            .is_some_and(|f| f.queue_flags.contains(both))
        {
            bail!("queue family 0 (wgpu's) has no graphics and compute");
        }
        let mut extensions = hal.required_device_extensions(features);
        for name in grass_features.extensions() {
            if !extensions.contains(&name) {
                extensions.push(name);
            }
        }
        let mut theirs = hal.physical_device_features(&extensions, features);
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(0)
            .queue_priorities(&priorities)];
        let names: Vec<_> = extensions.iter().map(|e| e.as_ptr()).collect();
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&names);
        let info = grass_features.enable_beside(theirs.add_to_device_create(info));
        let raw = unsafe { raw_instance.create_device(physical, &info, None) }
            .context("create the device")?;
        let hints = &desc.memory_hints;
        // No drop callback: wgpu destroys the device when its last handle goes.
        let open = unsafe {
            hal.device_from_raw(
                raw.clone(),
                None,
                &extensions,
                features,
                limits,
                hints,
                0,
                0,
            )
        }
        .context("wgpu on the device")?;
        drop(hal);
        let (device, queue) = unsafe { adapter.create_device_from_hal::<Vulkan>(open, desc) }
            .context("wgpu device")?;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: raw_instance.clone(),
            device: raw.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .context("allocator")?;
        let grass = super::Device {
            entry,
            instance: raw_instance,
            physical,
            queue: unsafe { raw.get_device_queue(0, 0) },
            device: raw,
            queue_family: 0,
            allocator: Arc::new(Mutex::new(allocator)),
        };
        Ok(Self {
            device,
            queue,
            adapter,
            instance,
            features: grass_features,
            grass,
        })
    }

    /// The device as [`GrassField::new`] takes it (handles shared with wgpu).
    pub fn grass(&self) -> super::Device {
        let g = &self.grass;
        super::Device {
            entry: g.entry.clone(),
            instance: g.instance.clone(),
            physical: g.physical,
            device: g.device.clone(),
            queue_family: g.queue_family,
            queue: g.queue,
            allocator: Arc::clone(&g.allocator),
        }
    }

    /// The `VkDevice`'s functions.
    pub fn raw(&self) -> &ash::Device {
        &self.grass.device
    }
}

/// A colour or depth texture with the view the field draws through.
#[derive(Copy, Clone)]
pub struct TextureTarget<'a> {
    /// The texture (single-sampled; its usage has `RENDER_ATTACHMENT`).
    pub texture: &'a wgpu::Texture,
    /// A view of its one level and layer.
    pub view: &'a wgpu::TextureView,
}

/// Records `field`'s frame (`camera`, `seconds` and `colliders` as in [`Frame`])
/// into wgpu's `color` and `depth` textures (depth `Depth32Float`, in the convention
/// the field was made for), after what `scene` recorded: `scene` gets the
/// transitions that leave the textures as attachments, and the grass is recorded
/// into a command buffer of its own, returned, to submit right after `scene`'s (in
/// the same `Queue::submit`). The textures stay where wgpu believes them (colour and
/// depth attachments), and the grass's writes are made visible to whatever wgpu does
/// next.
pub fn record(
    device: &GrassDevice,
    scene: &mut wgpu::CommandEncoder,
    (color, depth): (TextureTarget, TextureTarget),
    field: &mut GrassField,
    (camera, seconds): (super::Viewpoint, f64),
    colliders: &[shared::sim::collide::Collider],
) -> Result<wgpu::CommandBuffer> {
    let raw = device.raw();
    scene.transition_resources(
        std::iter::empty(),
        [
            wgpu::TextureTransition {
                texture: color.texture,
                selector: None,
                state: wgpu::TextureUses::COLOR_TARGET,
            },
            wgpu::TextureTransition {
                texture: depth.texture,
                selector: None,
                state: wgpu::TextureUses::DEPTH_STENCIL_WRITE,
            },
        ]
        .into_iter(),
    );
    let size = color.texture.size();
    let targets = Targets {
        color: unsafe { color.view.as_hal::<Vulkan>() }
            .map(|v| unsafe { v.raw_handle() })
            .context("colour view")?,
        depth: unsafe { depth.view.as_hal::<Vulkan>() }
            .map(|v| unsafe { v.raw_handle() })
            .context("depth view")?,
        extent: vk::Extent2D {
            width: size.width,
            height: size.height,
        },
    };
    let depth_image = unsafe { depth.texture.as_hal::<Vulkan>() }
        .map(|t| unsafe { t.raw_handle() })
        .context("depth texture")?;
    let frame = Frame {
        targets,
        camera,
        seconds,
        colliders,
    };
    let mut grass = device
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("grass"),
        });
    let recorded = unsafe {
        grass.as_hal_mut::<Vulkan, _, _>(|encoder| -> Result<()> {
            let cmd = encoder.context("not a Vulkan encoder")?.raw_handle();
            let tests = (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            );
            // wgpu keeps depth in DEPTH_STENCIL_ATTACHMENT_OPTIMAL, the field draws
            // into DEPTH_ATTACHMENT_OPTIMAL.
            let layouts = (
                L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                L::DEPTH_ATTACHMENT_OPTIMAL,
            );
            depth_barrier(raw, cmd, depth_image, layouts, tests);
            field.record(cmd, &frame)?;
            depth_barrier(raw, cmd, depth_image, (layouts.1, layouts.0), tests);
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(S::COLOR_ATTACHMENT_OUTPUT)
                .src_access_mask(A::COLOR_ATTACHMENT_WRITE)
                .dst_stage_mask(S::ALL_COMMANDS)
                .dst_access_mask(A::MEMORY_READ | A::MEMORY_WRITE)];
            let info = vk::DependencyInfo::default().memory_barriers(&barrier);
            raw.cmd_pipeline_barrier2(cmd, &info);
            Ok(())
        })
    };
    recorded.context("record the grass")?;
    Ok(grass.finish())
}

/// `image`'s depth from `layouts.0` to `layouts.1`, between depth tests.
fn depth_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layouts: (vk::ImageLayout, vk::ImageLayout),
    (stages, access): (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let range = vk::ImageSubresourceRange::default()
        .aspect_mask(vk::ImageAspectFlags::DEPTH)
        .level_count(1)
        .layer_count(1);
    let barrier = [vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(range)
        .old_layout(layouts.0)
        .new_layout(layouts.1)
        .src_stage_mask(stages)
        .src_access_mask(access)
        .dst_stage_mask(stages)
        .dst_access_mask(access)];
    let info = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &info) };
}

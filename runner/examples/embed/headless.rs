//! Headless: the frames simulated and the last one read back, tone-mapped on the host
//! for the natural look.

use anyhow::{Context as _, Result};
use ash::vk;
use glam::{Vec2, Vec3};
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{AllocationCreateDesc, AllocationScheme};
use runner::embed::{self, Ground};
use shared::settings::Look;

use super::args::*;
use super::cube::*;
use super::frame::*;
use super::gpu::*;
use super::stage::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// Format of the headless colour image (written to PNG as is).
pub const HEADLESS_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// Format of the headless HDR image of the natural look (tone-mapped on the host).
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// One headless run's picture.
pub struct Shot {
    /// RGBA8 (sRGB) pixels, row by row.
    pub rgba: Vec<u8>,
    /// (width, height).
    pub size: (u32, u32),
    /// Blades the last frame drew.
    pub drawn: u32,
    /// The cube's corners in pixels, in the last frame.
    pub cube_corners: Vec<Vec2>,
    /// GPU time of the field's passes in the last frame, where the device has
    /// timestamps.
    pub times: Option<embed::PassTimes>,
    /// The device is a software rasterizer (lavapipe): its timestamps do not time
    /// passes (its drawing is deferred).
    pub software: bool,
}

/// `args.frames` frames of `args.size` in `args.look` into an offscreen image, the
/// last one read back (the natural look's HDR image tone-mapped on the host).
pub fn render_headless(args: &Args) -> Result<Shot> {
    let (size, frames, look, validation) = (
        args.size,
        args.frames.unwrap_or(90),
        args.look,
        args.validation,
    );
    let format = match look {
        Look::Paper => HEADLESS_FORMAT,
        Look::Natural => HDR_FORMAT,
    };
    let (gpu, format) = Gpu::new(
        Gpu::instance(&[], validation)?,
        validation,
        |_, _| Some(format),
        &[],
    )?;
    let extent = vk::Extent2D {
        width: size.0,
        height: size.1,
    };
    use vk::ImageUsageFlags as U;
    let color = gpu.image(extent, format, U::COLOR_ATTACHMENT | U::TRANSFER_SRC)?;
    let depth = gpu.image(extent, embed::DEPTH_FORMAT, U::DEPTH_STENCIL_ATTACHMENT)?;
    let texel = if format == HDR_FORMAT { 8 } else { 4 };
    let bytes = u64::from(size.0) * u64::from(size.1) * texel;
    let info = vk::BufferCreateInfo::default()
        .size(bytes)
        .usage(vk::BufferUsageFlags::TRANSFER_DST);
    let buffer = unsafe { gpu.device.create_buffer(&info, None)? };
    let requirements = unsafe { gpu.device.get_buffer_memory_requirements(buffer) };
    let memory = gpu.lock()?.allocate(&AllocationCreateDesc {
        name: "readback",
        requirements,
        location: MemoryLocation::GpuToCpu,
        linear: true,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    })?;
    unsafe {
        gpu.device
            .bind_buffer_memory(buffer, memory.memory(), memory.offset())?
    };
    let cube = Cube::new(&gpu.device, format)?;
    let mut field = gpu.grass(Ground::Hills, args.blades, args.tiled, format)?;
    field.settings.look.style = look;
    let stage = Stage::new(&field);
    let (pool, cmd) = gpu.commands()?;
    let fence = unsafe {
        gpu.device
            .create_fence(&vk::FenceCreateInfo::default(), None)?
    };
    let device = &gpu.device;
    // One frame into `color` and `depth` of `extent`, copied to the buffer if `copy`.
    let mut frame_into = |color: &OwnedImage, depth: &OwnedImage, extent, copy| -> Result<()> {
        unsafe {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(cmd, &begin)?;
        }
        let target = (color.image, color.view);
        record_frame(&gpu, &cube, &mut field, &stage, cmd, target, depth, extent)?;
        if copy {
            transition(
                device,
                cmd,
                (color.image, color.aspect),
                (L::COLOR_ATTACHMENT_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (S::COPY, A::TRANSFER_READ),
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(color.aspect)
                        .layer_count(1),
                )
                .image_extent(extent.into());
            unsafe {
                device.cmd_copy_image_to_buffer(
                    cmd,
                    color.image,
                    L::TRANSFER_SRC_OPTIMAL,
                    buffer,
                    &[region],
                );
            }
        }
        unsafe {
            device.end_command_buffer(cmd)?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            device.queue_submit(gpu.queue, &[submit], fence)?;
            device.wait_for_fences(&[fence], true, u64::MAX)?;
            device.reset_fences(&[fence])?;
        }
        Ok(())
    };
    // A window's resizes: a frame at each size first, into images of that size.
    for &(width, height) in &args.resize_through {
        let extent = vk::Extent2D { width, height };
        let color = gpu.image(extent, format, U::COLOR_ATTACHMENT | U::TRANSFER_SRC)?;
        let depth = gpu.image(extent, embed::DEPTH_FORMAT, U::DEPTH_STENCIL_ATTACHMENT)?;
        frame_into(&color, &depth, extent, false)?;
        gpu.destroy_image(color);
        gpu.destroy_image(depth);
    }
    for frame in 0..frames {
        frame_into(&color, &depth, extent, frame + 1 == frames)?;
    }
    let mapped = memory.mapped_slice().context("readback not mapped")?;
    let exposure = field.settings.look.exposure;
    let rgba = match look {
        Look::Paper => mapped[..bytes as usize].to_vec(),
        Look::Natural => tone_map_on_host(&mapped[..bytes as usize], exposure),
    };
    let shot = Shot {
        rgba,
        size,
        drawn: field.counts()?.drawn,
        times: field.times()?,
        software: unsafe { gpu.instance.get_physical_device_properties(gpu.physical) }.device_type
            == vk::PhysicalDeviceType::CPU,
        cube_corners: stage.cube_corners_px(field.time(), size),
    };
    drop(field);
    drop(cube);
    unsafe {
        gpu.device.destroy_fence(fence, None);
        gpu.device.destroy_command_pool(pool, None);
        gpu.device.destroy_buffer(buffer, None);
    }
    let _ = gpu.lock()?.free(memory);
    gpu.destroy_image(color);
    gpu.destroy_image(depth);
    Ok(shot)
}

/// RGBA16F linear radiance to RGBA8 sRGB: `shared::draw::look::sky::tone_map` (ACES, with the
/// field's exposure), as the program's own tone-map pass does it.
pub(crate) fn tone_map_on_host(hdr: &[u8], exposure: f32) -> Vec<u8> {
    hdr.as_chunks::<8>()
        .0
        .iter()
        .flat_map(|texel| {
            let channel = |i: usize| half::f16::from_le_bytes([texel[2 * i], texel[2 * i + 1]]);
            let radiance = Vec3::new(channel(0).into(), channel(1).into(), channel(2).into());
            let display = shared::draw::look::sky::tone_map(radiance, exposure);
            let byte = |c: f32| (shared::draw::shade::linear_to_srgb(c) * 255.0).round() as u8;
            [byte(display.x), byte(display.y), byte(display.z), 255]
        })
        .collect()
}

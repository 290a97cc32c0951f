//! Buffers with their memory, from the allocator.

use super::Context;
use super::commands::CommandPool;
use anyhow::{Context as _, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::Allocation;
use std::sync::Arc;

/// A buffer and its memory; freed on drop.
pub struct Buffer {
    ctx: Arc<Context>,
    /// The Vulkan buffer.
    pub buffer: vk::Buffer,
    /// Size in bytes.
    pub size: u64,
    allocation: Option<Allocation>,
}

impl Buffer {
    /// A buffer of `size` bytes (at least 4) in `location`.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let size = size.max(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &ctx.device;
        let buffer = unsafe { device.create_buffer(&info, None) }
            .with_context(|| format!("create buffer {name} ({size} bytes)"))?;
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocation = match ctx.allocate(name, requirements, location, true) {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.destroy_buffer(buffer, None) };
                return Err(e);
            }
        };
        unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) }
            .with_context(|| format!("bind memory of buffer {name}"))?;
        Ok(Self {
            ctx: ctx.clone(),
            buffer,
            size,
            allocation: Some(allocation),
        })
    }

    /// A device-local buffer holding `data`, uploaded through a staging buffer;
    /// `usage` gets TRANSFER_DST added.
    pub fn upload<T: bytemuck::Pod>(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self> {
        let bytes = std::mem::size_of_val(data) as u64;
        let usage = usage | vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = Self::new(ctx, name, bytes, usage, MemoryLocation::GpuOnly)?;
        let mut staging = Self::new(
            ctx,
            &format!("{name} upload"),
            bytes,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(data)?;
        pool.one_shot(|rec| rec.copy_buffer(staging.buffer, buffer.buffer, bytes))
            .with_context(|| format!("upload {name}"))?;
        Ok(buffer)
    }

    fn mapped(&self) -> Result<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .context("buffer is not host visible")
    }

    /// Writes `data` at the start of a host-visible buffer.
    pub fn write<T: bytemuck::Pod>(&mut self, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mapped = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .context("buffer is not host visible")?;
        mapped
            .get_mut(..bytes.len())
            .context("data larger than the buffer")?
            .copy_from_slice(bytes);
        Ok(())
    }

    /// Reads `count` values of `T` from the start of a host-visible buffer.
    pub fn read<T: bytemuck::Pod>(&self, count: usize) -> Result<Vec<T>> {
        let bytes = self
            .mapped()?
            .get(..count * size_of::<T>())
            .context("read past the end of the buffer")?;
        Ok(bytemuck::pod_collect_to_vec(bytes))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_buffer(self.buffer, None) };
        if let Some(allocation) = self.allocation.take() {
            let _ = self.ctx.allocator.lock().map(|mut a| a.free(allocation));
        }
    }
}

//! Command pool, per-frame command buffers, fences and semaphores, and one-shot
//! submissions for uploads.

use super::{Context, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use std::sync::Arc;

/// A command pool: one per frame slot (reset whole before the slot records again),
/// and one for one-shot uploads.
pub struct CommandPool {
    ctx: Arc<Context>,
    /// The pool.
    pub pool: vk::CommandPool,
}

impl CommandPool {
    /// A pool on the context's queue family. Its buffers are reset with the whole
    /// pool, not one by one (what the layer's best practices ask).
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(ctx.queue_family);
        let pool = unsafe { ctx.device.create_command_pool(&info, None) }
            .context("create command pool")?;
        Ok(Self {
            ctx: ctx.clone(),
            pool,
        })
    }

    /// `count` primary command buffers.
    pub fn allocate(&self, count: u32) -> Result<Vec<vk::CommandBuffer>> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count);
        unsafe { self.ctx.device.allocate_command_buffers(&info) }
            .context("allocate command buffers")
    }

    /// Resets the whole pool, then begins recording `cmd` (its one buffer) for one
    /// submission.
    pub fn begin(&self, cmd: vk::CommandBuffer) -> Result<Recorder<'_>> {
        let device = &self.ctx.device;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        unsafe {
            device.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty())?;
            device.begin_command_buffer(cmd, &begin)?;
        }
        Ok(Recorder::new(device, cmd))
    }

    /// Ends `cmd` and submits it: it waits for `wait` before writing colour, then
    /// signals `signal` and `fence` (which is reset first).
    pub fn submit(
        &self,
        cmd: vk::CommandBuffer,
        wait: Option<vk::Semaphore>,
        signal: Option<vk::Semaphore>,
        fence: &Fence,
    ) -> Result<()> {
        let device = &self.ctx.device;
        unsafe { device.end_command_buffer(cmd) }.context("record frame")?;
        let waits: Vec<_> = wait.into_iter().collect();
        let stages = [vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT];
        let signals: Vec<_> = signal.into_iter().collect();
        let cmds = [cmd];
        let mut submit = vk::SubmitInfo::default().command_buffers(&cmds);
        // Semaphore arrays only where there are semaphores (an empty array's pointer
        // with a count of 0 draws a best-practices warning).
        if !waits.is_empty() {
            submit = submit
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages[..waits.len()]);
        }
        if !signals.is_empty() {
            submit = submit.signal_semaphores(&signals);
        }
        fence.reset()?;
        unsafe { device.queue_submit(self.ctx.queue, &[submit], fence.fence) }
            .context("submit frame")
    }

    /// Records `record` into a fresh command buffer, submits it and waits for it.
    pub fn one_shot(&self, record: impl FnOnce(&Recorder)) -> Result<()> {
        let device = &self.ctx.device;
        let cmd = self.allocate(1)?[0];
        let fence = Fence::new(&self.ctx, false)?;
        unsafe {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(cmd, &begin)?;
            record(&Recorder::new(device, cmd));
            device.end_command_buffer(cmd)?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            device
                .queue_submit(self.ctx.queue, &[submit], fence.fence)
                .context("submit one-shot commands")?;
            fence.wait()?;
            device.free_command_buffers(self.pool, &cmds);
        }
        Ok(())
    }
}

impl Drop for CommandPool {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_command_pool(self.pool, None) };
    }
}

/// A fence, destroyed on drop.
pub struct Fence {
    ctx: Arc<Context>,
    /// The fence.
    pub fence: vk::Fence,
}

/// Longest wait for the GPU before giving up with an error instead of hanging.
const GPU_TIMEOUT_NS: u64 = 60_000_000_000;

/// The same on a software device, whose first frames also compile every pipeline
/// they use (lavapipe compiles a compute pipeline at its first dispatch, 8 to 24 s
/// for the simulate pass; one warm-up frame of the valley soak took 59 s with an
/// empty shader cache).
const SOFTWARE_TIMEOUT_NS: u64 = 600_000_000_000;

impl Fence {
    /// A fence, signalled already if `signaled`.
    pub fn new(ctx: &Arc<Context>, signaled: bool) -> Result<Self> {
        let flags = if signaled {
            vk::FenceCreateFlags::SIGNALED
        } else {
            vk::FenceCreateFlags::empty()
        };
        let fence = unsafe {
            ctx.device
                .create_fence(&vk::FenceCreateInfo::default().flags(flags), None)
        }
        .context("create fence")?;
        Ok(Self {
            ctx: ctx.clone(),
            fence,
        })
    }

    /// Waits for the fence (a minute at most, ten on a software device: a longer
    /// wait is a lost device).
    pub fn wait(&self) -> Result<()> {
        wait_for(&self.ctx, self.fence)
    }

    /// Back to unsignalled.
    pub fn reset(&self) -> Result<()> {
        unsafe { self.ctx.device.reset_fences(&[self.fence]) }.context("reset fence")
    }
}

/// Waits for `fence` as [`Fence::wait`] does.
pub fn wait_for(ctx: &Context, fence: vk::Fence) -> Result<()> {
    let timeout = if ctx.is_software() {
        SOFTWARE_TIMEOUT_NS
    } else {
        GPU_TIMEOUT_NS
    };
    unsafe { ctx.device.wait_for_fences(&[fence], true, timeout) }.context("wait for the GPU")
}

impl Drop for Fence {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_fence(self.fence, None) };
    }
}

/// A binary semaphore, destroyed on drop.
pub struct Semaphore {
    ctx: Arc<Context>,
    /// The semaphore.
    pub semaphore: vk::Semaphore,
}

impl Semaphore {
    /// A new binary semaphore.
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        let semaphore = unsafe {
            ctx.device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .context("create semaphore")?;
        Ok(Self {
            ctx: ctx.clone(),
            semaphore,
        })
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_semaphore(self.semaphore, None) };
    }
}

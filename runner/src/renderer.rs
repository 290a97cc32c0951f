//! One frame, start to end: update the uniforms and reset the counter (transfer),
//! simulate and cull (compute), draw ground and grass (graphics), and read the visible
//! count back without stalling (each frame slot reads its own, one frame later).

use crate::field::Field;
use crate::passes::DEPTH_FORMAT;
use crate::passes::grass::GrassPass;
use crate::passes::ground::GroundPass;
use crate::passes::simulate::SimulatePass;
use crate::scene::{Scene, builtin};
use crate::shaders;
use crate::vulkan::commands::{CommandPool, Fence, Semaphore};
use crate::vulkan::pipeline::ShaderModule;
use crate::vulkan::{Buffer, Context, Image, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use shared::layout::{COUNTER_COUNT, COUNTER_VISIBLE, FrameUniforms, SimulatePush};
use shared::shade::{MATERIAL_ROCK, MATERIAL_SOIL};
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// Frames the CPU may record ahead of the GPU.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Sky colour behind the field (linear).
const SKY: [f32; 4] = [0.42, 0.62, 0.86, 1.0];

/// What a frame renders into.
#[derive(Copy, Clone)]
pub struct Target {
    /// The colour image.
    pub image: vk::Image,
    /// Its view.
    pub view: vk::ImageView,
    /// Its size.
    pub extent: vk::Extent2D,
    /// Layout it must be left in (present, or transfer source for a capture).
    pub final_layout: vk::ImageLayout,
}

/// Per-slot objects of a frame in flight.
pub struct FrameSlot {
    cmd: vk::CommandBuffer,
    fence: Fence,
    /// Signalled when the swapchain image of this frame is ready.
    image_available: Semaphore,
    counters: Buffer,
    submitted: bool,
}

/// The renderer: the field, the passes and the frame slots.
pub struct Renderer {
    ctx: Arc<Context>,
    /// The field's buffers.
    pub field: Field,
    simulate: SimulatePass,
    ground: GroundPass,
    grass: GrassPass,
    slots: Vec<FrameSlot>,
    next: usize,
    depth: Option<Image>,
    /// Visible blades in the newest frame whose counters were read back.
    pub visible: Option<u32>,
    pool: CommandPool,
    _module: ShaderModule,
}

impl Renderer {
    /// Uploads the scene's blades and surfaces and builds every pipeline for a colour
    /// target of `color_format`.
    pub fn new(ctx: &Arc<Context>, scene: &Scene, color_format: vk::Format) -> Result<Self> {
        let pool = CommandPool::new(ctx)?;
        let field = Field::new(ctx, &pool, &scene.blades)?;
        let module = ShaderModule::new(ctx, shaders::SPIRV)?;
        let simulate = SimulatePass::new(ctx, &module, &field)?;
        let surfaces = [
            (&scene.surface, MATERIAL_SOIL),
            (&scene.bare, MATERIAL_ROCK),
        ];
        let ball = builtin::sphere(Vec3::ZERO, 1.0, 3);
        let ground = GroundPass::new(ctx, &pool, &module, &field, color_format, &surfaces, &ball)?;
        let grass = GrassPass::new(ctx, &module, &field, color_format)?;
        let cmds = pool.allocate(FRAMES_IN_FLIGHT as u32)?;
        let slots = cmds
            .into_iter()
            .map(|cmd| {
                Ok(FrameSlot {
                    cmd,
                    fence: Fence::new(ctx, true)?,
                    image_available: Semaphore::new(ctx)?,
                    counters: Buffer::new(
                        ctx,
                        "counter readback",
                        (COUNTER_COUNT * 4) as u64,
                        vk::BufferUsageFlags::TRANSFER_DST,
                        MemoryLocation::GpuToCpu,
                    )?,
                    submitted: false,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            ctx: ctx.clone(),
            field,
            simulate,
            ground,
            grass,
            slots,
            next: 0,
            depth: None,
            visible: None,
            pool,
            _module: module,
        })
    }

    /// Waits until the next frame slot is free, reads the counters its last frame left,
    /// and returns it.
    pub fn begin_frame(&mut self) -> Result<usize> {
        let index = self.next;
        let slot = &mut self.slots[index];
        slot.fence.wait()?;
        if slot.submitted {
            self.visible = Some(slot.counters.read::<u32>(COUNTER_COUNT)?[COUNTER_VISIBLE]);
        }
        Ok(index)
    }

    /// The slot's semaphore to signal when acquiring a swapchain image.
    pub fn image_available(&self, slot: usize) -> vk::Semaphore {
        self.slots[slot].image_available.semaphore
    }

    fn ensure_depth(&mut self, extent: vk::Extent2D) -> Result<vk::ImageView> {
        if self.depth.as_ref().is_none_or(|d| d.extent != extent) {
            // The old depth image may still be in use by a frame in flight.
            self.ctx.wait_idle()?;
            self.depth = Some(Image::new(
                &self.ctx,
                "depth",
                extent,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
            )?);
        }
        Ok(self.depth.as_ref().map(|d| d.view).unwrap_or_default())
    }

    /// Records and submits the frame of `slot`. With a swapchain, `wait` is the
    /// slot's image-available semaphore and `signal` the image's render-finished one;
    /// `capture` receives the rendered pixels (target left in TRANSFER_SRC_OPTIMAL).
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        slot: usize,
        target: &Target,
        uniforms: &FrameUniforms,
        push: SimulatePush,
        wait: Option<vk::Semaphore>,
        signal: Option<vk::Semaphore>,
        capture: Option<&Buffer>,
    ) -> Result<()> {
        let depth = self.ensure_depth(target.extent)?;
        let cmd = self.begin_commands(slot)?;
        let rec = Recorder::new(&self.ctx.device, cmd);
        self.record_compute(&rec, slot, uniforms, push);
        self.record_draw(&rec, target, depth, uniforms);
        if let Some(buffer) = capture {
            rec.copy_image_to_buffer(target.image, target.extent, buffer.buffer);
            rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
        }
        self.submit(slot, wait, signal)
    }

    /// Records and submits only the compute part of a frame (simulate, cull, chunk
    /// draws), then waits for it: what the GPU-against-host tests run.
    pub fn compute_frame(&mut self, uniforms: &FrameUniforms, push: SimulatePush) -> Result<()> {
        let slot = self.begin_frame()?;
        let cmd = self.begin_commands(slot)?;
        self.record_compute(&Recorder::new(&self.ctx.device, cmd), slot, uniforms, push);
        self.submit(slot, None, None)?;
        self.finish()
    }

    /// Waits for every frame in flight and reads the newest frame's counters.
    pub fn finish(&mut self) -> Result<()> {
        self.ctx.wait_idle()?;
        let newest = (self.next + self.slots.len() - 1) % self.slots.len();
        if self.slots[newest].submitted {
            let counters = self.slots[newest].counters.read::<u32>(COUNTER_COUNT)?;
            self.visible = Some(counters[COUNTER_VISIBLE]);
        }
        Ok(())
    }

    fn begin_commands(&self, slot: usize) -> Result<vk::CommandBuffer> {
        let cmd = self.slots[slot].cmd;
        let device = &self.ctx.device;
        unsafe {
            device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
            device.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )?;
        }
        Ok(cmd)
    }

    fn record_compute(
        &self,
        rec: &Recorder,
        slot: usize,
        uniforms: &FrameUniforms,
        push: SimulatePush,
    ) {
        let field = &self.field;
        // Everything the previous frame read or wrote is done before this one
        // overwrites the uniforms, the counters and the blades.
        rec.memory_barrier(
            (S::ALL_COMMANDS, A::MEMORY_WRITE),
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
        );
        rec.update_buffer(field.uniforms.buffer, bytemuck::bytes_of(uniforms));
        rec.fill_buffer(field.counters.buffer, 0);
        rec.memory_barrier(
            (S::CLEAR | S::COPY, A::TRANSFER_WRITE),
            (
                S::COMPUTE_SHADER | S::ALL_GRAPHICS,
                A::SHADER_READ | A::SHADER_WRITE | A::UNIFORM_READ,
            ),
        );
        self.simulate.record(rec, field, push);
        rec.copy_buffer(
            field.counters.buffer,
            self.slots[slot].counters.buffer,
            field.counters.size,
        );
        rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
    }

    fn record_draw(
        &self,
        rec: &Recorder,
        target: &Target,
        depth: vk::ImageView,
        uniforms: &FrameUniforms,
    ) {
        let depth_image = self.depth.as_ref().map(|d| d.image).unwrap_or_default();
        let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        let depth_tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        rec.image_barrier(
            target.image,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            (S::COLOR_ATTACHMENT_OUTPUT, A::NONE),
            color_out,
        );
        rec.image_barrier(
            depth_image,
            vk::ImageAspectFlags::DEPTH,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            (depth_tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (depth_tests, depth_rw),
        );
        rec.begin_rendering(target.view, depth, target.extent, SKY);
        let used = (uniforms.flags.w as usize).min(uniforms.colliders.len());
        let balls = &uniforms.colliders[..used];
        self.ground.record(rec, &self.field, balls);
        self.grass.record(rec, &self.field);
        rec.end_rendering();
        let (dst, dst_access) = if target.final_layout == vk::ImageLayout::TRANSFER_SRC_OPTIMAL {
            (S::COPY, A::TRANSFER_READ)
        } else {
            (S::NONE, A::NONE)
        };
        rec.image_barrier(
            target.image,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                target.final_layout,
            ),
            color_out,
            (dst, dst_access),
        );
    }

    fn submit(
        &mut self,
        slot: usize,
        wait: Option<vk::Semaphore>,
        signal: Option<vk::Semaphore>,
    ) -> Result<()> {
        let device = &self.ctx.device;
        let frame = &mut self.slots[slot];
        unsafe { device.end_command_buffer(frame.cmd) }.context("record frame")?;
        let waits: Vec<_> = wait.into_iter().collect();
        let stages = [vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT];
        let signals: Vec<_> = signal.into_iter().collect();
        let cmds = [frame.cmd];
        let submit = vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages[..waits.len()])
            .command_buffers(&cmds)
            .signal_semaphores(&signals);
        frame.fence.reset()?;
        unsafe { device.queue_submit(self.ctx.queue, &[submit], frame.fence.fence) }
            .context("submit frame")?;
        frame.submitted = true;
        self.next = (slot + 1) % self.slots.len();
        Ok(())
    }

    /// Copies a device buffer into host memory and returns `count` values of `T`.
    pub fn download<T: bytemuck::Pod>(&self, buffer: &Buffer, count: usize) -> Result<Vec<T>> {
        let bytes = (count * size_of::<T>()) as u64;
        let staging = Buffer::new(
            &self.ctx,
            "download",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.ctx.wait_idle()?;
        self.pool
            .one_shot(|rec| rec.copy_buffer(buffer.buffer, staging.buffer, bytes))?;
        staging.read(count)
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        let _ = self.ctx.wait_idle();
    }
}

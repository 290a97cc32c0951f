//! One frame, start to end: update the uniforms and reset the counters (transfer);
//! draw the occluders' depth and reduce it to a pyramid (graphics, compute); simulate,
//! cull and count (compute); draw ground and grass, then the overlay (graphics). The
//! counters and timestamps are read back without stalling: each frame slot reads its
//! own when it comes round again, one frame later.

use crate::field::Field;
use crate::passes::DEPTH_FORMAT;
use crate::passes::grass::GrassPass;
use crate::passes::ground::GroundPass;
use crate::passes::occlusion::OcclusionPass;
use crate::passes::overlay::{OverlayFrame, OverlayPass};
use crate::passes::simulate::SimulatePass;
use crate::passes::throughput::ThroughputPass;
use crate::scene::{Scene, builtin};
use crate::shaders;
use crate::vulkan::commands::{CommandPool, Fence, Semaphore};
use crate::vulkan::pipeline::ShaderModule;
use crate::vulkan::query::{TimestampPool, TrianglePool};
use crate::vulkan::{Buffer, Context, Image, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use shared::cull::OCCLUSION;
use shared::layout::{self, COUNTER_COUNT, FrameUniforms, SimulatePush};
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

/// What one frame asks of the renderer.
pub struct FrameInput<'a> {
    /// Where it renders.
    pub target: Target,
    /// The frame's uniform block (the renderer fills in the depth pyramid's layout).
    pub uniforms: FrameUniforms,
    /// The simulation steps to run.
    pub push: SimulatePush,
    /// With a swapchain: the slot's image-available semaphore.
    pub wait: Option<vk::Semaphore>,
    /// With a swapchain: the image's render-finished semaphore.
    pub signal: Option<vk::Semaphore>,
    /// Receives the rendered pixels (target left in TRANSFER_SRC_OPTIMAL).
    pub capture: Option<&'a Buffer>,
    /// The overlay to draw over the frame, if any.
    pub overlay: Option<OverlayFrame<'a>>,
}

impl FrameInput<'_> {
    /// A headless frame: no semaphores, no capture, no overlay.
    pub fn headless(target: Target, uniforms: FrameUniforms, push: SimulatePush) -> Self {
        Self {
            target,
            uniforms,
            push,
            wait: None,
            signal: None,
            capture: None,
            overlay: None,
        }
    }
}

/// How the compute pass sorted the blades of one frame: drawn, or removed by the
/// first test that failed. Every blade lands in exactly one count.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct CullCounts {
    /// Drawn.
    pub drawn: u32,
    /// Removed by the orientation test.
    pub orientation: u32,
    /// Removed by the frustum test.
    pub frustum: u32,
    /// Removed by the distance test.
    pub distance: u32,
    /// Removed by the occlusion test.
    pub occlusion: u32,
    /// Blades the pass looked at, counted on the GPU (the field's size).
    pub examined: u32,
}

impl CullCounts {
    fn from_counters(c: &[u32]) -> Self {
        Self {
            drawn: c[layout::COUNTER_VISIBLE],
            orientation: c[layout::COUNTER_ORIENTATION],
            frustum: c[layout::COUNTER_FRUSTUM],
            distance: c[layout::COUNTER_DISTANCE],
            occlusion: c[layout::COUNTER_OCCLUSION],
            examined: c[layout::COUNTER_EXAMINED],
        }
    }
    /// Blades removed by any test.
    pub fn removed(&self) -> u32 {
        self.orientation + self.frustum + self.distance + self.occlusion
    }
    /// (test name, blades it removed), in the order the tests run.
    pub fn by_test(&self) -> [(&'static str, u32); 4] {
        let removed = [
            self.orientation,
            self.frustum,
            self.distance,
            self.occlusion,
        ];
        std::array::from_fn(|i| (shared::cull::TEST_NAMES[i], removed[i]))
    }
}

/// GPU time of each pass of one frame, in milliseconds, from timestamp queries.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// Uniform update and counter reset, then the occluder depth pre-pass and the
    /// pyramid reduction (when they run).
    pub depth_pyramid: f64,
    /// Simulate, cull, compact and write the draws.
    pub simulate_cull: f64,
    /// Ground and ball.
    pub ground: f64,
    /// Grass.
    pub grass: f64,
    /// Overlay.
    pub overlay: f64,
    /// The whole frame on the GPU.
    pub total: f64,
}

/// Timestamps per frame: start, then after each pass of [`PassTimes`].
const TIMESTAMPS: u32 = 6;

impl PassTimes {
    /// From the milliseconds since the first timestamp at the end of each pass.
    fn from_marks(m: &[f64]) -> Self {
        Self {
            depth_pyramid: m[0],
            simulate_cull: m[1] - m[0],
            ground: m[2] - m[1],
            grass: m[3] - m[2],
            overlay: m[4] - m[3],
            total: m[4],
        }
    }
}

/// Per-slot objects of a frame in flight.
pub struct FrameSlot {
    cmd: vk::CommandBuffer,
    fence: Fence,
    /// Signalled when the swapchain image of this frame is ready.
    image_available: Semaphore,
    counters: Buffer,
    timestamps: Option<TimestampPool>,
    triangles: Option<TrianglePool>,
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
    occlusion: OcclusionPass,
    /// The scene has surfaces that can hide grass (else the pre-pass is skipped).
    pub has_occluders: bool,
    overlay: Option<OverlayPass>,
    color_format: vk::Format,
    slots: Vec<FrameSlot>,
    next: usize,
    /// Frames begun so far.
    frames_begun: u64,
    depth: Option<Image>,
    /// The counts of the newest frame whose counters were read back.
    pub counts: Option<CullCounts>,
    /// The pass times of the newest frame whose timestamps were read back.
    pub times: Option<PassTimes>,
    /// The triangles the grass draw generated in the newest frame read back (pipeline
    /// statistics, where the device has them).
    pub triangles: Option<u64>,
    pool: CommandPool,
    module: ShaderModule,
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
        let occlusion = OcclusionPass::new(ctx, &module, &field)?;
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
                    timestamps: TimestampPool::new(ctx, TIMESTAMPS)?,
                    triangles: TrianglePool::new(ctx)?,
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
            occlusion,
            has_occluders: scene.has_occluders(),
            overlay: None,
            color_format,
            slots,
            next: 0,
            frames_begun: 0,
            depth: None,
            counts: None,
            times: None,
            triangles: None,
            pool,
            module,
        })
    }

    /// Builds the overlay pipeline: frames may then carry an [`OverlayFrame`].
    pub fn enable_overlay(&mut self) -> Result<()> {
        if self.overlay.is_none() {
            let pass =
                OverlayPass::new(&self.ctx, &self.module, self.color_format, FRAMES_IN_FLIGHT)?;
            self.overlay = Some(pass);
        }
        Ok(())
    }

    /// The depth pyramid's layout for the current target (empty before the first
    /// frame).
    pub fn hiz(&self) -> shared::hiz::HiZLayout {
        self.occlusion.hiz
    }

    /// Bandwidth reference: GB/s of the copy shader moving every blade (64 bytes read,
    /// 64 written) into a scratch buffer made for it, the best of `repeats` timed
    /// dispatches; `None` without timestamps.
    pub fn copy_bandwidth(&mut self, repeats: u32) -> Result<Option<f64>> {
        let bytes = u64::from(self.field.blade_count) * size_of::<shared::Blade>() as u64;
        let scratch = Buffer::new(
            &self.ctx,
            "copy reference",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let descriptors = &self.field.descriptors;
        self.ctx.wait_idle()?;
        descriptors.write_buffer(layout::BINDING_SCRATCH, storage, scratch.buffer);
        let best = self.best_time(repeats, |rec| self.simulate.record_copy(rec, &self.field));
        // Back to the placeholder before the scratch buffer goes.
        self.ctx.wait_idle()?;
        descriptors.write_buffer(layout::BINDING_SCRATCH, storage, self.field.visible.buffer);
        Ok(best?.map(|ms| 2.0 * bytes as f64 / (ms * 1e-3) / 1e9))
    }

    /// Triangle-throughput reference: milliseconds to draw `patches` trivially shaded
    /// one-vertex patches at tessellation `level` into `target` (depth tested, on a
    /// grid of small cells), the best of `repeats`, and the triangles generated
    /// (pipeline statistics, where the device has them); `None` without timestamps.
    /// The patches are drawn in chunks of the grass draw's size.
    pub fn triangle_throughput(
        &mut self,
        target: &Target,
        patches: u32,
        level: f32,
        repeats: u32,
    ) -> Result<Option<(f64, Option<u64>)>> {
        self.ensure_depth(target.extent)?;
        let pass = ThroughputPass::new(&self.ctx, &self.module, &self.field, self.color_format)?;
        let depth = self.depth.as_ref().context("depth image")?;
        let push = shared::reference::push(level, target.extent.width, target.extent.height);
        let attachments = (
            S::COLOR_ATTACHMENT_OUTPUT | S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            A::COLOR_ATTACHMENT_WRITE | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
        );
        let layouts = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        let depth_layouts = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        );
        let triangles = TrianglePool::new(&self.ctx)?;
        let best = self.best_time(repeats, |rec| {
            let color = vk::ImageAspectFlags::COLOR;
            rec.image_barrier(target.image, color, layouts, attachments, attachments);
            let aspect = vk::ImageAspectFlags::DEPTH;
            rec.image_barrier(depth.image, aspect, depth_layouts, attachments, attachments);
            if let Some(t) = &triangles {
                rec.reset_queries(t.pool, 0, 1);
            }
            rec.begin_rendering(
                Some((target.view, Some(SKY))),
                Some(depth.view),
                target.extent,
            );
            if let Some(t) = &triangles {
                rec.begin_query(t.pool);
            }
            pass.record(rec, &self.field, push, patches, self.field.chunk_size);
            if let Some(t) = &triangles {
                rec.end_query(t.pool);
            }
            rec.end_rendering();
        })?;
        Ok(best.map(|ms| (ms, triangles.as_ref().and_then(TrianglePool::read))))
    }

    /// The shortest of `repeats` timed runs of `record`, in milliseconds, each after
    /// the previous one's writes; `None` without timestamps.
    fn best_time(&self, repeats: u32, record: impl Fn(&Recorder)) -> Result<Option<f64>> {
        self.ctx.wait_idle()?;
        let Some(stamps) = TimestampPool::new(&self.ctx, 2 * repeats.max(1))? else {
            return Ok(None);
        };
        self.pool.one_shot(|rec| {
            rec.reset_queries(stamps.pool, 0, stamps.count);
            for r in 0..stamps.count / 2 {
                rec.write_timestamp(stamps.pool, 2 * r, S::ALL_COMMANDS);
                record(rec);
                rec.write_timestamp(stamps.pool, 2 * r + 1, S::ALL_COMMANDS);
                rec.memory_barrier(
                    (S::ALL_COMMANDS, A::MEMORY_WRITE),
                    (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
                );
            }
        })?;
        let ms = stamps.read_all_ms().context("reference timestamps")?;
        let best = ms
            .chunks(2)
            .map(|pair| pair[1] - pair[0])
            .fold(f64::MAX, f64::min);
        Ok(Some(best))
    }

    /// Visible blades in the newest frame read back.
    pub fn visible(&self) -> Option<u32> {
        self.counts.map(|c| c.drawn)
    }

    /// Waits until the next frame slot is free, reads the counters and timestamps its
    /// last frame left, and returns it.
    pub fn begin_frame(&mut self) -> Result<usize> {
        let index = self.next;
        crate::vulkan::fault::check_frame(self.frames_begun)
            .with_context(|| format!("wait for frame {}", self.frames_begun))?;
        self.frames_begun += 1;
        self.slots[index].fence.wait()?;
        self.read_back(index)?;
        Ok(index)
    }

    fn read_back(&mut self, index: usize) -> Result<()> {
        let slot = &self.slots[index];
        if slot.submitted {
            let counters = slot.counters.read::<u32>(COUNTER_COUNT)?;
            self.counts = Some(CullCounts::from_counters(&counters));
            if let Some(marks) = slot.timestamps.as_ref().and_then(TimestampPool::read_ms) {
                self.times = Some(PassTimes::from_marks(&marks));
            }
            self.triangles = slot.triangles.as_ref().and_then(TrianglePool::read);
        }
        Ok(())
    }

    /// The slot's semaphore to signal when acquiring a swapchain image.
    pub fn image_available(&self, slot: usize) -> vk::Semaphore {
        self.slots[slot].image_available.semaphore
    }

    /// The depth image and the depth pyramid sized for `extent`.
    fn ensure_depth(&mut self, extent: vk::Extent2D) -> Result<()> {
        if self.depth.as_ref().is_none_or(|d| d.extent != extent) {
            // The old depth image may still be in use by a frame in flight.
            self.ctx.wait_idle()?;
            self.depth = Some(Image::new(
                &self.ctx,
                "depth",
                extent,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::DEPTH,
            )?);
            self.occlusion.resize(&self.ctx, &mut self.field, extent)?;
        }
        Ok(())
    }

    /// Records and submits the frame of `slot`.
    pub fn render(&mut self, slot: usize, input: FrameInput) -> Result<()> {
        let target = input.target;
        self.ensure_depth(target.extent)?;
        if let (Some(pass), Some(frame)) = (self.overlay.as_mut(), input.overlay.as_ref()) {
            pass.update_textures(&self.pool, frame.textures)?;
        }
        let mut uniforms = input.uniforms;
        // Without the occlusion test, or anything to hide grass, the pyramid is
        // neither built nor read.
        let occlusion = uniforms.flags.x & OCCLUSION != 0 && self.has_occluders;
        uniforms.hiz = if occlusion {
            self.occlusion.hiz
        } else {
            Default::default()
        };
        let cmd = self.begin_commands(slot)?;
        let rec = Recorder::new(&self.ctx.device, cmd);
        let stamps = self.slots[slot].timestamps.as_ref().map(|t| t.pool);
        let stamp = |query: u32| {
            if let Some(pool) = stamps {
                rec.write_timestamp(pool, query, S::ALL_COMMANDS);
            }
        };
        if let Some(pool) = stamps {
            rec.reset_queries(pool, 0, TIMESTAMPS);
        }
        let triangles = self.slots[slot].triangles.as_ref().map(|t| t.pool);
        if let Some(pool) = triangles {
            rec.reset_queries(pool, 0, 1);
        }
        stamp(0);
        self.begin_compute(&rec, &uniforms);
        if occlusion {
            let depth = self.depth.as_ref().context("depth image")?;
            self.occlusion
                .record(&rec, &self.field, &self.ground, depth);
        }
        stamp(1);
        self.record_compute(&rec, slot, input.push);
        stamp(2);
        self.record_draw(&rec, &target, &uniforms, &stamp, triangles);
        stamp(4);
        if let (Some(pass), Some(frame)) = (self.overlay.as_mut(), input.overlay.as_ref()) {
            rec.memory_barrier(
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (
                    S::COLOR_ATTACHMENT_OUTPUT,
                    A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
                ),
            );
            pass.record(&rec, slot, target.view, target.extent, frame)?;
        }
        stamp(5);
        self.finish_target(&rec, &target);
        if let Some(buffer) = input.capture {
            let color = vk::ImageAspectFlags::COLOR;
            rec.copy_image_to_buffer(target.image, color, target.extent, buffer.buffer);
            rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
        }
        self.submit(slot, input.wait, input.signal)?;
        if let (Some(pass), Some(frame)) = (self.overlay.as_mut(), input.overlay.as_ref()) {
            pass.free_textures(frame.textures)?;
        }
        Ok(())
    }

    /// Records and submits only the compute part of a frame (simulate, cull, chunk
    /// draws), then waits for it: what the GPU-against-host tests run.
    pub fn compute_frame(&mut self, uniforms: &FrameUniforms, push: SimulatePush) -> Result<()> {
        let slot = self.begin_frame()?;
        let cmd = self.begin_commands(slot)?;
        let rec = Recorder::new(&self.ctx.device, cmd);
        // No target, so no pyramid: the occlusion test keeps every blade.
        let uniforms = FrameUniforms {
            hiz: Default::default(),
            ..*uniforms
        };
        self.begin_compute(&rec, &uniforms);
        self.record_compute(&rec, slot, push);
        self.submit(slot, None, None)?;
        self.finish()
    }

    /// Waits for every frame in flight and reads the newest frame's counters.
    pub fn finish(&mut self) -> Result<()> {
        self.ctx.wait_idle()?;
        let newest = (self.next + self.slots.len() - 1) % self.slots.len();
        self.read_back(newest)
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

    /// Orders the frame after the previous one, then updates the uniforms and clears
    /// the counters.
    fn begin_compute(&self, rec: &Recorder, uniforms: &FrameUniforms) {
        let field = &self.field;
        // Everything the previous frame read or wrote is done before this one
        // overwrites the uniforms, the counters, the pyramid and the blades.
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
    }

    /// Simulate, cull and compact, then copy the counters for the read-back.
    fn record_compute(&self, rec: &Recorder, slot: usize, push: SimulatePush) {
        let field = &self.field;
        self.simulate.record(rec, field, push);
        rec.copy_buffer(
            field.counters.buffer,
            self.slots[slot].counters.buffer,
            field.counters.size,
        );
        rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
    }

    /// Ground, then grass, into the target; `stamp(3)` between them, the grass's
    /// triangles counted into `triangles`.
    fn record_draw(
        &self,
        rec: &Recorder,
        target: &Target,
        uniforms: &FrameUniforms,
        stamp: &dyn Fn(u32),
        triangles: Option<vk::QueryPool>,
    ) {
        let depth = self
            .depth
            .as_ref()
            .map(|d| (d.image, d.view))
            .unwrap_or_default();
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
        // After the pre-pass's copy (or the last frame's tests) is done with it.
        rec.image_barrier(
            depth.0,
            vk::ImageAspectFlags::DEPTH,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            (depth_tests | S::COPY, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (depth_tests, depth_rw),
        );
        rec.begin_rendering(Some((target.view, Some(SKY))), Some(depth.1), target.extent);
        let used = (uniforms.flags.w as usize).min(uniforms.colliders.len());
        let balls = &uniforms.colliders[..used];
        self.ground.record(rec, &self.field, balls);
        stamp(3);
        if let Some(pool) = triangles {
            rec.begin_query(pool);
        }
        self.grass.record(rec, &self.field, uniforms.modes.y);
        if let Some(pool) = triangles {
            rec.end_query(pool);
        }
        rec.end_rendering();
    }

    /// Leaves the target in its final layout.
    fn finish_target(&self, rec: &Recorder, target: &Target) {
        let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
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

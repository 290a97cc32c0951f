//! The frame driver: the one place that runs frames. It owns the frame slots (command
//! buffer, fence, image-available semaphore and read-back objects of each frame in
//! flight), the simulation's fixed-step clock and the newest read-back, and drives a
//! [`FrameTarget`]: a [`Presenter`](super::presenter::Presenter) acquires and presents
//! swapchain images (or, for a software device, copies each frame to the window's
//! shared memory: [`ShmPresenter`](super::shm::ShmPresenter)), an
//! [`Offscreen`](super::headless::Offscreen) image is captured.
//!
//! A client (the viewer, `render`, `soak`, `bench`, the GPU tests) says what each
//! frame shows: [`FrameDriver::begin`] waits for the next slot, reads back what its
//! last frame left and acquires the target's image; the client asks for the frame
//! (`shared::plan::FrameRequest`) from [`Frame`] and [`FrameDriver::readback`];
//! [`FrameDriver::submit`] records, submits and presents.

use crate::passes::overlay::OverlayFrame;
use crate::renderer::{FrameInput, FrameQueries, Readback, Renderer, Target};
use crate::vulkan::Context;
use crate::vulkan::commands::{CommandPool, Fence, Semaphore};
use anyhow::{Context as _, Result};
use ash::vk;
use shared::gpu::layout::SimulatePush;
use shared::plan::FrameRequest;
use shared::sim::simulate::SimClock;
use std::sync::Arc;

/// Frames the CPU may record ahead of the GPU.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// An image a frame renders into, and how it is handed over.
pub struct Acquired {
    /// The colour image, its view, size and final layout.
    pub target: Target,
    /// Waited for before colour is written (a swapchain image's availability).
    pub wait: Option<vk::Semaphore>,
    /// Signalled when the frame is done (for presentation).
    pub signal: Option<vk::Semaphore>,
    /// Host-visible buffer the frame's pixels can be copied to.
    pub capture: Option<vk::Buffer>,
    /// The swapchain image's index.
    pub image: u32,
    /// The swapchain no longer matches the surface exactly.
    pub suboptimal: bool,
}

/// Where frames go: a window's swapchain or an offscreen image.
pub trait FrameTarget {
    /// The image of the next frame, recorded in frame slot `slot` (whose previous
    /// frame is done); `available` is signalled when it may be written. `None` skips
    /// the frame (an out-of-date swapchain, to be made again).
    fn acquire(&mut self, available: vk::Semaphore, slot: usize) -> Result<Option<Acquired>>;
    /// Hands the submitted frame over (presents it), if there is anything to do;
    /// `done` is the fence its submission signals.
    fn present(&mut self, frame: &Acquired, done: vk::Fence) -> Result<()>;
}

/// One frame in flight, between [`FrameDriver::begin`] and [`FrameDriver::submit`].
pub struct Frame {
    /// The slot it records into.
    pub slot: usize,
    /// Its image.
    pub acquired: Acquired,
    /// The simulation steps it runs.
    pub push: SimulatePush,
    /// Simulated time after its steps, seconds.
    pub time: f32,
}

impl Frame {
    /// Simulated seconds its steps take.
    pub fn seconds(&self) -> f32 {
        self.push.steps as f32 * shared::sim::simulate::STEP_SECONDS
    }

    /// The image's size, (width, height) in pixels.
    pub fn extent(&self) -> (u32, u32) {
        let e = self.acquired.target.extent;
        (e.width, e.height)
    }
}

/// What a client asks of one frame.
pub struct FrameSpec<'a> {
    /// What the frame shows.
    pub request: FrameRequest,
    /// The overlay drawn over it.
    pub overlay: Option<OverlayFrame<'a>>,
    /// Copy its pixels to the target's capture buffer.
    pub capture: bool,
}

impl FrameSpec<'_> {
    /// A frame of `request` (`Settings::request`), no overlay, no capture.
    pub fn plain(request: FrameRequest) -> Self {
        Self {
            request,
            overlay: None,
            capture: false,
        }
    }
}

/// Per-slot objects of a frame in flight.
struct FrameSlot {
    /// The slot's own pool, reset whole when the slot records again.
    pool: CommandPool,
    cmd: vk::CommandBuffer,
    fence: Fence,
    /// Signalled when the swapchain image of this frame is ready.
    image_available: Semaphore,
    queries: FrameQueries,
    submitted: bool,
}

/// Runs frames of a [`Renderer`] on a [`FrameTarget`].
pub struct FrameDriver {
    /// What records each frame.
    pub renderer: Renderer,
    /// The simulation's fixed steps: frame times in, steps out.
    pub clock: SimClock,
    /// What the newest frame read back left.
    pub readback: Readback,
    slots: Vec<FrameSlot>,
    next: usize,
    /// Frames begun so far.
    frames_begun: u64,
    ctx: Arc<Context>,
}

impl FrameDriver {
    /// [`FRAMES_IN_FLIGHT`] slots for `renderer`.
    pub fn new(ctx: &Arc<Context>, renderer: Renderer) -> Result<Self> {
        let slots = (0..FRAMES_IN_FLIGHT)
            .map(|_| {
                let pool = CommandPool::new(ctx)?;
                let cmd = pool.allocate(1)?[0];
                Ok(FrameSlot {
                    pool,
                    cmd,
                    fence: Fence::new(ctx, true)?,
                    image_available: Semaphore::new(ctx)?,
                    queries: FrameQueries::new(ctx)?,
                    submitted: false,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            renderer,
            clock: SimClock::default(),
            readback: Readback::default(),
            slots,
            next: 0,
            frames_begun: 0,
            ctx: ctx.clone(),
        })
    }

    /// Waits until the next slot is free and reads back what its last frame left.
    fn next_slot(&mut self) -> Result<usize> {
        let index = self.next;
        crate::vulkan::fault::check_frame(self.frames_begun)
            .with_context(|| format!("wait for frame {}", self.frames_begun))?;
        crate::vulkan::fault::leak_device(&self.ctx)?;
        self.frames_begun += 1;
        self.slots[index].fence.wait()?;
        self.read_back(index)?;
        Ok(index)
    }

    fn read_back(&mut self, index: usize) -> Result<()> {
        let slot = &self.slots[index];
        if slot.submitted {
            let new = slot.queries.read()?;
            self.readback = Readback {
                // Timestamps not yet available keep the last ones shown.
                times: new.times.or(self.readback.times),
                ..new
            };
        }
        Ok(())
    }

    /// Starts a frame of `seconds` on `target`: waits for the next slot, reads back its
    /// last frame, acquires the image, advances the clock. `None` when the target has
    /// no image this time (nothing is simulated then).
    pub fn begin(&mut self, target: &mut dyn FrameTarget, seconds: f64) -> Result<Option<Frame>> {
        let slot = self.next_slot()?;
        let available = self.slots[slot].image_available.semaphore;
        let Some(acquired) = target.acquire(available, slot)? else {
            return Ok(None);
        };
        let (first_step, steps) = self.clock.advance(seconds);
        Ok(Some(Frame {
            slot,
            acquired,
            push: SimulatePush {
                first_step,
                steps,
                ..Default::default()
            },
            time: self.clock.time(),
        }))
    }

    /// Records `frame` as `spec` asks, submits it and hands it to `target`.
    pub fn submit(
        &mut self,
        frame: Frame,
        target: &mut dyn FrameTarget,
        spec: FrameSpec,
    ) -> Result<()> {
        let acquired = &frame.acquired;
        let input = FrameInput {
            target: acquired.target,
            request: spec.request,
            push: frame.push,
            capture: acquired.capture.filter(|_| spec.capture),
            overlay: spec.overlay,
        };
        let slot = &mut self.slots[frame.slot];
        let rec = slot.pool.begin(slot.cmd)?;
        self.renderer
            .record(&rec, &slot.queries, frame.slot, &input)?;
        slot.pool
            .submit(slot.cmd, acquired.wait, acquired.signal, &slot.fence)?;
        slot.submitted = true;
        let done = slot.fence.fence;
        self.next = (frame.slot + 1) % self.slots.len();
        self.renderer.submitted(&input)?;
        target.present(acquired, done)
    }

    /// One frame of `seconds` showing what `request` asks (`Settings::request`),
    /// captured if `capture`; nothing when the target has no image this time.
    pub fn run(
        &mut self,
        target: &mut dyn FrameTarget,
        seconds: f64,
        request: impl FnOnce(&Frame) -> FrameRequest,
        capture: bool,
    ) -> Result<()> {
        let Some(frame) = self.begin(target, seconds)? else {
            return Ok(());
        };
        let spec = FrameSpec {
            capture,
            ..FrameSpec::plain(request(&frame))
        };
        self.submit(frame, target, spec)
    }

    /// Only the compute part of a frame (simulate, cull, chunk draws), then waits for
    /// it and reads its counters: what the GPU-against-host tests run.
    #[cfg(feature = "test-hooks")]
    pub fn compute_frame(&mut self, request: &FrameRequest, push: SimulatePush) -> Result<()> {
        let index = self.next_slot()?;
        let slot = &mut self.slots[index];
        let rec = slot.pool.begin(slot.cmd)?;
        self.renderer
            .record_compute_only(&rec, &slot.queries, request, push)?;
        slot.pool.submit(slot.cmd, None, None, &slot.fence)?;
        slot.submitted = true;
        self.next = (index + 1) % self.slots.len();
        self.finish()
    }

    /// Waits for every frame in flight and reads the newest frame's counters.
    pub fn finish(&mut self) -> Result<()> {
        self.ctx.wait_idle()?;
        let newest = (self.next + self.slots.len() - 1) % self.slots.len();
        self.read_back(newest)
    }
}

impl Drop for FrameDriver {
    fn drop(&mut self) {
        // The slots' command buffers, fences and semaphores may still be in use.
        let _ = self.ctx.wait_idle();
    }
}

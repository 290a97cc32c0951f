//! The compute rasterizer of far blades (`shared::raster`). Once the
//! hardware has drawn the near grass and the ground, a compute pass copies their depth
//! into a buffer (the farthest sample under MSAA), and another draws each far blade
//! into the visibility buffer: a pixel behind that depth costs a load, one in front a
//! 64-bit atomic minimum. A second rendering scope then resolves it: a
//! full-screen draw shades each pixel a far blade won and writes its depth, so the
//! depth test composites the two paths.

use super::by_target::{ByTarget, DrawTarget};
use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Buffer, Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::gpu::layout;
use shared::gpu::layout::PreparePush;
use shared::settings::{Look, View};
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The resolve's pipelines for one draw format.
struct Resolve {
    paper: Pipeline,
    lod: Pipeline,
    natural: Pipeline,
}

/// The compute rasterizer's pipelines and visibility buffer; `None` inside on a device
/// without 64-bit atomics (every blade then takes the hardware path).
pub struct RasterPass {
    ctx: Arc<Context>,
    far: Option<(Pipeline, Pipeline)>,
    /// The preparation, single-sample and multisampled.
    prepare: Option<(Pipeline, Pipeline)>,
    /// The resolve's, for each draw target.
    resolve: Option<ByTarget<Resolve>>,
    visibility: Option<Buffer>,
    hardware_depth: Option<Buffer>,
}

impl RasterPass {
    /// The pipelines, where the device has 64-bit atomics, the resolve's for
    /// `target` (see [`Self::retarget`]); the visibility buffer comes with
    /// [`Self::resize`].
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<Self> {
        let far = match &ctx.int64_atomics {
            Ok(()) => {
                let layout = &field.layout;
                let paper = Pipeline::compute(ctx, layout, module, shaders::RASTER_FAR)?;
                let natural = Pipeline::compute(ctx, layout, module, shaders::RASTER_FAR_NATURAL)?;
                Some((paper, natural))
            }
            Err(_) => None,
        };
        let prepare = match &far {
            Some(_) => {
                let layout = &field.layout;
                let single = Pipeline::compute(ctx, layout, module, shaders::RASTER_PREPARE)?;
                let ms = Pipeline::compute(ctx, layout, module, shaders::RASTER_PREPARE_MS)?;
                Some((single, ms))
            }
            None => None,
        };
        let mut pass = Self {
            ctx: ctx.clone(),
            far,
            prepare,
            resolve: None,
            visibility: None,
            hardware_depth: None,
        };
        pass.retarget(module, field, target)?;
        Ok(pass)
    }

    /// Whether the device runs the compute rasterizer.
    pub fn supported(&self) -> bool {
        self.far.is_some()
    }

    /// Uses the resolve's pipelines for `target`, made the first time they are asked
    /// for; a motion target is kept as it is (far blades move with the camera, which
    /// the temporal resolve finds from their depth).
    pub fn retarget(
        &mut self,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<()> {
        if self.far.is_none() {
            return Ok(());
        }
        use vk::ShaderStageFlags as St;
        let make = |fragment| {
            let stages = [(St::VERTEX, shaders::RESOLVE_VS), (St::FRAGMENT, fragment)];
            let desc = GraphicsDesc {
                patch_control_points: 0,
                samples: target.samples,
                second_color: target.second_color(false),
                depth_compare: target.depth_compare(),
                ..GraphicsDesc::patches(
                    module,
                    &stages,
                    &field.layout,
                    target.format,
                    super::DEPTH_FORMAT,
                )
            };
            Pipeline::graphics(&self.ctx, &desc)
        };
        let make_all = || -> Result<Resolve> {
            Ok(Resolve {
                paper: make(shaders::RESOLVE_PAPER_FS)?,
                lod: make(shaders::RESOLVE_LOD_FS)?,
                natural: make(shaders::RESOLVE_NATURAL_FS)?,
            })
        };
        match &mut self.resolve {
            Some(kept) => kept.select(target, make_all)?,
            None => self.resolve = Some(ByTarget::new(target, make_all()?)),
        }
        Ok(())
    }

    /// A visibility buffer and a buffer for the hardware's depth, for a target of
    /// `extent`, bound for the passes.
    pub fn resize(&mut self, field: &Field, extent: vk::Extent2D) -> Result<()> {
        if self.far.is_none() {
            return Ok(());
        }
        self.ctx.wait_idle()?;
        let pixels = (u64::from(extent.width) * u64::from(extent.height)).max(1);
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let gpu = MemoryLocation::GpuOnly;
        let visibility = Buffer::new(&self.ctx, "visibility", pixels * 8, usage, gpu)?;
        let depth = Buffer::new(&self.ctx, "hardware depth", pixels * 4, usage, gpu)?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let set = &field.descriptors;
        set.write_buffer(layout::BINDING_VISIBILITY, storage, visibility.buffer);
        set.write_buffer(layout::BINDING_HARDWARE_DEPTH, storage, depth.buffer);
        self.visibility = Some(visibility);
        self.hardware_depth = Some(depth);
        Ok(())
    }

    /// The visibility buffer, once sized.
    pub fn visibility(&self) -> Option<&Buffer> {
        self.visibility.as_ref()
    }

    /// The hardware's depth as the rasterizer read it, once sized.
    pub fn hardware_depth(&self) -> Option<&Buffer> {
        self.hardware_depth.as_ref()
    }

    /// Records the compute rasterizer between the hardware's rendering scope and the
    /// resolve's. Its preparation (an indirect dispatch, none without far blades)
    /// clears the visibility buffer and copies the hardware's depth for the
    /// rasterizer from `depth`, the scope's depth image with `samples` per pixel (the
    /// farthest of them), in DEPTH_ATTACHMENT_OPTIMAL and left so; then one thread per
    /// far blade (an indirect dispatch), ready for the resolve's fragment stage or
    /// the shading after the draw.
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        natural: bool,
        depth: &Image,
        samples: u32,
    ) {
        let (Some((paper, natural_far)), Some((single, multi)), Some(_)) =
            (&self.far, &self.prepare, &self.visibility)
        else {
            return;
        };
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        let compute = vk::PipelineBindPoint::COMPUTE;
        let aspect = vk::ImageAspectFlags::DEPTH;
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        let (attachment, sampled) = (
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        );
        let written = (S::LATE_FRAGMENT_TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE);
        let read = (S::COMPUTE_SHADER, A::SHADER_READ);
        rec.image_barrier(depth.image, aspect, (attachment, sampled), written, read);
        if samples > 1 {
            rec.bind_pipeline(compute, multi.pipeline, layout, set);
            let push = PreparePush { samples };
            rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
        } else {
            rec.bind_pipeline(compute, single.pipeline, layout, set);
        }
        rec.dispatch_indirect(
            field.raster_args.buffer,
            (layout::RASTER_PREPARE * 4) as u64,
        );
        rec.image_barrier(
            depth.image,
            aspect,
            (sampled, attachment),
            (S::COMPUTE_SHADER, A::NONE),
            (tests, depth_rw),
        );
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
        );
        let pipeline = if natural { natural_far } else { paper };
        rec.bind_pipeline(compute, pipeline.pipeline, layout, set);
        // As many threads as far blades (the compute pass wrote the counts).
        let at = (layout::RASTER_DISPATCH * 4) as u64;
        rec.dispatch_indirect(field.raster_args.buffer, at);
        // Read by the resolve's fragment stage, a capture's copy, or the natural look's
        // shading after the draw.
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (
                S::FRAGMENT_SHADER | S::COMPUTE_SHADER | S::COPY,
                A::SHADER_STORAGE_READ | A::TRANSFER_READ,
            ),
        );
    }

    /// Records the resolve inside its rendering scope, in `view` and the look
    /// `style`.
    pub fn record_resolve(&self, rec: &Recorder, field: &Field, view: View, look: Look) {
        let Some(resolve) = self.resolve.as_ref().map(ByTarget::current) else {
            return;
        };
        let pipeline = match (view == View::Lod, look == Look::Natural) {
            (true, _) => &resolve.lod,
            (false, true) => &resolve.natural,
            (false, false) => &resolve.paper,
        };
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        rec.bind_pipeline(
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.pipeline,
            layout,
            set,
        );
        // Three vertices with far blades, none without.
        let at = (layout::RASTER_DRAW * 4) as u64;
        rec.draw_indirect_at(field.raster_args.buffer, at);
    }
}

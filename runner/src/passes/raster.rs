//! The compute rasterizer of far blades (`shared::raster`, issue 18): a compute pass
//! draws each far blade's curve into the visibility buffer, one 64-bit atomic minimum
//! per pixel; inside the frame's rendering scope, after the hardware-drawn grass and
//! ground, a full-screen resolve shades each pixel a far blade won and writes its
//! depth, so the depth test composites the two.

use crate::field::Field;
use crate::shaders;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules};
use crate::vulkan::{Buffer, Context, Recorder};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::layout;
use shared::look::LOOK_NATURAL;
use shared::shade::VIEW_LOD;
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
    resolve: Option<Resolve>,
    visibility: Option<Buffer>,
}

impl RasterPass {
    /// The pipelines, where the device has 64-bit atomics, the resolve's for colour
    /// targets of `color_format` with `samples` (see [`Self::retarget`]); the
    /// visibility buffer comes with [`Self::resize`].
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
        samples: vk::SampleCountFlags,
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
        let mut pass = Self {
            ctx: ctx.clone(),
            far,
            resolve: None,
            visibility: None,
        };
        pass.retarget(module, field, color_format, samples)?;
        Ok(pass)
    }

    /// Whether the device runs the compute rasterizer.
    pub fn supported(&self) -> bool {
        self.far.is_some()
    }

    /// The resolve's pipelines for colour targets of `color_format` with `samples`.
    pub fn retarget(
        &mut self,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
        samples: vk::SampleCountFlags,
    ) -> Result<()> {
        if self.far.is_none() {
            return Ok(());
        }
        use vk::ShaderStageFlags as St;
        let make = |fragment| {
            let stages = [(St::VERTEX, shaders::RESOLVE_VS), (St::FRAGMENT, fragment)];
            let desc = GraphicsDesc {
                patch_control_points: 0,
                samples,
                ..GraphicsDesc::patches(
                    module,
                    &stages,
                    &field.layout,
                    color_format,
                    super::DEPTH_FORMAT,
                )
            };
            Pipeline::graphics(&self.ctx, &desc)
        };
        self.resolve = Some(Resolve {
            paper: make(shaders::RESOLVE_PAPER_FS)?,
            lod: make(shaders::RESOLVE_LOD_FS)?,
            natural: make(shaders::RESOLVE_NATURAL_FS)?,
        });
        Ok(())
    }

    /// A visibility buffer for a target of `extent`, bound for the passes.
    pub fn resize(&mut self, field: &Field, extent: vk::Extent2D) -> Result<()> {
        if self.far.is_none() {
            return Ok(());
        }
        self.ctx.wait_idle()?;
        let pixels = u64::from(extent.width) * u64::from(extent.height);
        let buffer = Buffer::new(
            &self.ctx,
            "visibility",
            pixels.max(1) * 8,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        field
            .descriptors
            .write_buffer(layout::BINDING_VISIBILITY, storage, buffer.buffer);
        self.visibility = Some(buffer);
        Ok(())
    }

    /// The visibility buffer, once sized.
    pub fn visibility(&self) -> Option<&Buffer> {
        self.visibility.as_ref()
    }

    /// Records the compute rasterizer after the compute pass: the visibility buffer
    /// cleared, then one thread per far blade (an indirect dispatch), ready for the
    /// resolve's fragment stage.
    pub fn record(&self, rec: &Recorder, field: &Field, natural: bool) {
        let (Some((paper, natural_far)), Some(visibility)) = (&self.far, &self.visibility) else {
            return;
        };
        rec.fill_buffer(visibility.buffer, u32::MAX);
        rec.memory_barrier(
            (
                S::CLEAR | S::COPY | S::COMPUTE_SHADER,
                A::TRANSFER_WRITE | A::SHADER_WRITE,
            ),
            (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
        );
        let pipeline = if natural { natural_far } else { paper };
        let (layout, set) = (field.layout.layout, field.descriptors.set);
        rec.bind_pipeline(
            vk::PipelineBindPoint::COMPUTE,
            pipeline.pipeline,
            layout,
            set,
        );
        // As many threads as far blades (the compute pass wrote the counts).
        let at = (layout::RASTER_DISPATCH * 4) as u64;
        rec.dispatch_indirect(field.raster_args.buffer, at);
        rec.memory_barrier(
            (S::COMPUTE_SHADER, A::SHADER_WRITE),
            (S::FRAGMENT_SHADER, A::SHADER_STORAGE_READ),
        );
    }

    /// Records the resolve inside the frame's rendering scope, in `view` and the look
    /// `style`.
    pub fn record_resolve(&self, rec: &Recorder, field: &Field, view: u32, style: u32) {
        let Some(resolve) = &self.resolve else {
            return;
        };
        let pipeline = match (view == VIEW_LOD, style == LOOK_NATURAL) {
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

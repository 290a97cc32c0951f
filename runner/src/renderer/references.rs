//! The benchmark's references, measured with the renderer's own field and pipelines:
//! how fast this device copies the blade buffer, and how fast it draws patches
//! tessellated like a blade (`grass bench`, docs/performance.md).

use super::{FRAME_STAGES, Renderer, SKY, Target};
use crate::passes::throughput::ThroughputPass;
use crate::vulkan::query::{TimestampPool, TrianglePool};
use crate::vulkan::{Buffer, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::gpu::layout;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

impl Renderer {
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
    /// grid of small cells), or with `mesh` as many of the mesh path's strips of that
    /// level, the best of `repeats`, and the triangles generated (pipeline statistics,
    /// where the device has them); `None` without timestamps, or without mesh stages
    /// for `mesh`. The patches are drawn in chunks of the grass draw's size.
    pub fn triangle_throughput(
        &mut self,
        target: &Target,
        patches: u32,
        level: f32,
        repeats: u32,
        mesh: bool,
    ) -> Result<Option<(f64, Option<u64>)>> {
        // Keeps the draw targets the frames use; the reference needs single-sample depth.
        let spec = self.targets.as_ref().map(|t| (t.spec.hdr, t.spec.samples));
        let (hdr, samples) = spec.unwrap_or((false, 1));
        self.ensure_targets(target.extent, hdr, samples)?;
        let pass = ThroughputPass::new(&self.ctx, &self.module, &self.field, self.color_format)?;
        if mesh && !pass.has_mesh() {
            return Ok(None);
        }
        let depth = &self.targets.as_ref().context("draw targets")?.depth;
        let push = shared::draw::reference::push(level, target.extent.width, target.extent.height);
        // Each image's barrier names its own kind of access only.
        let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        let depth_tests = (
            S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            A::DEPTH_STENCIL_ATTACHMENT_WRITE,
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
            rec.image_barrier(target.image, color, layouts, color_out, color_out);
            let aspect = vk::ImageAspectFlags::DEPTH;
            rec.image_barrier(depth.image, aspect, depth_layouts, depth_tests, depth_tests);
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
            if mesh {
                pass.record_mesh(rec, &self.field, push, patches);
            } else {
                pass.record(rec, &self.field, push, patches, self.field.chunk_size);
            }
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
                rec.write_timestamp(stamps.pool, 2 * r, S::BOTTOM_OF_PIPE);
                record(rec);
                rec.write_timestamp(stamps.pool, 2 * r + 1, S::BOTTOM_OF_PIPE);
                rec.memory_barrier(
                    (FRAME_STAGES, A::MEMORY_WRITE),
                    (FRAME_STAGES, A::MEMORY_READ | A::MEMORY_WRITE),
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
}

//! What the GPU-against-host tests need of the renderer besides whole frames: the
//! compute part of a frame alone, the mesh path's vertices, a tile generated alone.

use super::{FrameQueries, Renderer};
use crate::field::PUSH_CONSTANTS;
use crate::shaders;
use crate::vulkan::pipeline::Pipeline;
use crate::vulkan::{Buffer, Recorder};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::Blade;
use shared::glam::IVec2;
use shared::gpu::layout::SimulatePush;
use shared::plan::FrameRequest;

impl Renderer {
    /// Records only the compute part of `request`'s frame (simulate, cull, chunk
    /// draws), with its counters copied to `queries`. Without a target there is no
    /// pyramid: no occlusion test.
    pub fn record_compute_only(
        &mut self,
        rec: &Recorder,
        queries: &FrameQueries,
        request: &FrameRequest,
        push: SimulatePush,
    ) -> Result<()> {
        let plan = request.plan().within(false, self.draw.raster.supported());
        // No target: no size, and the plan reads no pyramid.
        let facts = self.facts(vk::Extent2D::default(), push);
        let uniforms = self.make_block(request, &plan, &facts);
        let colliders = &request.colliders()[..uniforms.forces.colliders as usize];
        let questions = request.questions();
        self.begin_compute(rec, &uniforms, (colliders, questions));
        // The simulation, the answers and the counters alone: nothing is drawn, so
        // nothing dressed.
        let asks = super::Asked::of(request);
        self.record_compute(rec, self.simulate_push(push), (false, asks))?;
        self.copy_counters(rec, queries);
        Ok(())
    }

    /// With `Some(buffer)`, the mesh path's later frames draw the paper look through
    /// `mesh::paper_mesh_capture`, which writes each vertex's clip position into
    /// `buffer` (`meshlet::MAX_STRIP_VERTICES` `vec4` per binned blade); `None` goes
    /// back to the frame's own pipelines.
    pub fn capture_mesh_vertices(&mut self, buffer: Option<&Buffer>) -> Result<()> {
        self.ctx.wait_idle()?;
        let target = buffer.map_or(self.field.visible.buffer, |b| b.buffer);
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let descriptors = &self.field.descriptors;
        descriptors.write_buffer(shared::gpu::layout::BINDING_SCRATCH, storage, target);
        self.draw.grass.current_mut().capturing = buffer.is_some();
        Ok(())
    }

    /// The compute rasterizer's visibility buffer (`u64` per pixel of the target), once
    /// a frame sized it on a device that has it.
    pub fn visibility(&self) -> Option<&Buffer> {
        self.draw.raster.visibility()
    }

    /// The blades of one tile as the GPU generates them (`compute::generate_tile`,
    /// `shared::tiles`): `per_side`² blades, width 0 where a blade's rank has left it.
    pub fn generate_tile(&self, push: &shared::gpu::layout::TilePush) -> Result<Vec<Blade>> {
        let count = (push.params.per_side * push.params.per_side) as usize;
        self.run_into_scratch(
            shaders::GENERATE_TILE,
            bytemuck::bytes_of(push),
            count,
            count,
        )
    }

    /// The tiles in view as the GPU selects them (`compute::select_tiles`), in the
    /// order its threads appended them.
    pub fn select_tiles(&self, push: &shared::gpu::layout::SelectPush) -> Result<Vec<IVec2>> {
        let candidates = (push.count.x * push.count.y) as usize;
        let words: Vec<u32> = self.run_into_scratch(
            shaders::SELECT_TILES,
            bytemuck::bytes_of(push),
            candidates,
            1 + 2 * candidates,
        )?;
        let selected = (words[0] as usize).min(candidates);
        Ok((0..selected)
            .map(|i| IVec2::new(words[1 + 2 * i] as i32, words[2 + 2 * i] as i32))
            .collect())
    }

    /// Runs compute entry point `entry` once, `threads` threads in workgroups of
    /// `SIMULATE_WORKGROUP`, with `push` as its push constants and the scratch
    /// binding pointed at a zeroed host-visible buffer of `count` values of `T`, and
    /// returns them (the scratch binding goes back to the frame's own after).
    fn run_into_scratch<T: bytemuck::Pod>(
        &self,
        entry: &str,
        push: &[u8],
        threads: usize,
        count: usize,
    ) -> Result<Vec<T>> {
        let out = Buffer::new(
            &self.ctx,
            "scratch read-back",
            (count.max(1) * size_of::<T>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let pipeline = Pipeline::compute(&self.ctx, &self.field.layout, &self.module, entry)?;
        self.ctx.wait_idle()?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let descriptors = &self.field.descriptors;
        descriptors.write_buffer(shared::gpu::layout::BINDING_SCRATCH, storage, out.buffer);
        let (layout, set) = (self.field.layout.layout, descriptors.set);
        let groups = (threads as u32).div_ceil(shared::gpu::layout::SIMULATE_WORKGROUP);
        use vk::AccessFlags2 as A;
        use vk::PipelineStageFlags2 as S;
        let result = self.pool.one_shot(|rec| {
            rec.fill_buffer(out.buffer, 0);
            rec.memory_barrier(
                (S::CLEAR | S::COPY, A::TRANSFER_WRITE),
                (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE),
            );
            rec.bind_pipeline(
                vk::PipelineBindPoint::COMPUTE,
                pipeline.pipeline,
                layout,
                set,
            );
            rec.push_constants(layout, PUSH_CONSTANTS.0, push);
            rec.dispatch((groups, 1));
            rec.memory_barrier(
                (S::COMPUTE_SHADER, A::SHADER_WRITE),
                (S::HOST, A::HOST_READ),
            );
        });
        // Back to the frame's own binding (the bandwidth reference binds its own).
        let frame_own = self.field.visible.buffer;
        descriptors.write_buffer(shared::gpu::layout::BINDING_SCRATCH, storage, frame_own);
        result?;
        out.read(count)
    }

    /// The sun's shadow map as the newest frame left it: depth per texel, row by row.
    pub fn shadow_map(&self) -> Result<Vec<f32>> {
        use vk::AccessFlags2 as A;
        use vk::PipelineStageFlags2 as S;
        let map = self.shadow.image();
        let texels = (map.extent.width * map.extent.height) as usize;
        let out = Buffer::new(
            &self.ctx,
            "shadow map read-back",
            (texels * 4) as u64,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.ctx.wait_idle()?;
        self.pool.one_shot(|rec| {
            let depth = vk::ImageAspectFlags::DEPTH;
            let sampled = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
            let copied = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            let read = (S::FRAGMENT_SHADER, A::SHADER_READ);
            let copy = (S::COPY, A::TRANSFER_READ);
            rec.image_barrier(map.image, depth, (sampled, copied), read, copy);
            rec.copy_image_to_buffer(map.image, depth, map.extent, out.buffer);
            rec.image_barrier(map.image, depth, (copied, sampled), copy, read);
            rec.memory_barrier((S::COPY, A::TRANSFER_WRITE), (S::HOST, A::HOST_READ));
        })?;
        out.read(texels)
    }

    /// The hardware's depth as the compute rasterizer read it (`f32` per pixel of the
    /// target), once a frame sized it on a device that has the rasterizer.
    pub fn hardware_depth(&self) -> Option<&Buffer> {
        self.draw.raster.hardware_depth()
    }
}

//! What the GPU-against-host tests need of the renderer besides whole frames: the
//! compute part of a frame alone, and a device buffer copied back to the host.

use super::{FrameQueries, Renderer};
use crate::field::PUSH_CONSTANTS;
use crate::shaders;
use crate::vulkan::pipeline::Pipeline;
use crate::vulkan::{Buffer, Recorder};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::Blade;
use shared::layout::{FrameUniforms, SimulatePush};

impl Renderer {
    /// Records only the compute part of a frame (simulate, cull, chunk draws), with
    /// its counters copied to `queries`. Without a target there is no pyramid: the
    /// occlusion test keeps every blade.
    pub fn record_compute_only(
        &self,
        rec: &Recorder,
        queries: &FrameQueries,
        uniforms: &FrameUniforms,
        push: SimulatePush,
    ) {
        let uniforms = FrameUniforms {
            hiz: Default::default(),
            ..*uniforms
        };
        self.begin_compute(rec, &uniforms);
        // The simulation and the counters alone: nothing is drawn, so nothing dressed.
        let mesh = uniforms.grass.pipeline == shared::layout::PIPELINE_MESH;
        self.record_compute(rec, push, false, mesh);
        self.copy_counters(rec, queries);
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

    /// With `Some(buffer)`, the mesh path's later frames draw the paper look through
    /// `mesh::paper_mesh_capture`, which writes each vertex's clip position into
    /// `buffer` (`meshlet::MAX_STRIP_VERTICES` `vec4` per binned blade); `None` goes
    /// back to the frame's own pipelines.
    pub fn capture_mesh_vertices(&mut self, buffer: Option<&Buffer>) -> Result<()> {
        self.ctx.wait_idle()?;
        let target = buffer.map_or(self.field.visible.buffer, |b| b.buffer);
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let descriptors = &self.field.descriptors;
        descriptors.write_buffer(shared::layout::BINDING_SCRATCH, storage, target);
        self.grass.capturing = buffer.is_some();
        Ok(())
    }

    /// The compute rasterizer's visibility buffer (`u64` per pixel of the target), once
    /// a frame sized it on a device that has it.
    pub fn visibility(&self) -> Option<&Buffer> {
        self.raster.visibility()
    }

    /// The blades of one tile as the GPU generates them (`compute::generate_tile`,
    /// `shared::tiles`): `per_side`² blades, width 0 where a blade's rank has left it.
    pub fn generate_tile(&self, push: &shared::tiles::TilePush) -> Result<Vec<Blade>> {
        let count = (push.params.per_side * push.params.per_side) as usize;
        let out = Buffer::new(
            &self.ctx,
            "tile blades",
            (count.max(1) * size_of::<Blade>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let pipeline = Pipeline::compute(
            &self.ctx,
            &self.field.layout,
            &self.module,
            shaders::GENERATE_TILE,
        )?;
        self.ctx.wait_idle()?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let descriptors = &self.field.descriptors;
        descriptors.write_buffer(shared::layout::BINDING_SCRATCH, storage, out.buffer);
        let (layout, set) = (self.field.layout.layout, descriptors.set);
        let groups = (count as u32).div_ceil(shared::layout::SIMULATE_WORKGROUP);
        let result = self.pool.one_shot(|rec| {
            rec.bind_pipeline(
                vk::PipelineBindPoint::COMPUTE,
                pipeline.pipeline,
                layout,
                set,
            );
            rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(push));
            rec.dispatch((groups, 1));
            rec.memory_barrier(
                (
                    vk::PipelineStageFlags2::COMPUTE_SHADER,
                    vk::AccessFlags2::SHADER_WRITE,
                ),
                (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
            );
        });
        // Back to the frame's own binding (the bandwidth reference binds its own).
        descriptors.write_buffer(
            shared::layout::BINDING_SCRATCH,
            storage,
            self.field.visible.buffer,
        );
        result?;
        out.read(count)
    }

    /// The hardware's depth as the compute rasterizer read it (`f32` per pixel of the
    /// target), once a frame sized it on a device that has the rasterizer.
    pub fn hardware_depth(&self) -> Option<&Buffer> {
        self.raster.hardware_depth()
    }
}

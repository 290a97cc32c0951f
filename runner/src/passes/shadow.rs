//! The sun's shadow map (natural look): the scene's surfaces, the collider balls and
//! the grass's shadow casters at one segment, depth only, from the sun
//! (`shared::draw::look::shadow::sun_view_proj`). Ground and grass fragments read it through
//! binding 8 of the field's set.
//!
//! Two cascades side by side in one depth image (Dimitrov 2007): the near one on the
//! left over a sphere of `shadow::NEAR_REACH` around the camera, the far one on the
//! right over the whole shadowed region, each `side` texels a side; each drawn with
//! its own pipelines into its half. The fragment stages read the cascade that holds
//! the point (`shadow::cascade_coord`) with one fetch through a comparison sampler.
//!
//! Grass is drawn from the compute pass's list of casters: every blade inside the map
//! and within `look.caster_distance` of the camera, whatever the camera's culling
//! tests decide (a blade outside the view or turned edge-on still casts its shadow),
//! dressed as the natural look draws it without the camera's fades
//! (`shared::draw::look::clump::caster_blade`), at a fixed level of detail
//! (`shadow::CASTER_LEVEL`: one segment, two triangles). The casters are drawn by
//! compute threads, a caster a thread, into a buffer of depth words
//! (`shared::draw::look::shadow_raster`), which is copied into the map; the surfaces
//! and balls are then drawn over it by the hardware. The map depends on where the
//! camera is, not on where it looks.

use crate::field::Field;
use crate::passes::DEPTH_FORMAT;
use crate::passes::ground::GroundPass;
use crate::shaders;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules, vec4_vertex_input};
use crate::vulkan::sampler::Sampler;
use crate::vulkan::{Attachments, Buffer, Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::draw::look::shadow_raster::EMPTY_DEPTH;
use shared::gpu::layout::SurfaceVertex;
use shared::settings::SHADOW_SIZES;
use shared::sim::collide::Collider;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

use shared::gpu::layout::{BINDING_SHADOW_DEPTH, BINDING_SHADOW_MAP, BINDING_SHADOW_SAMPLER};

/// The shadow map and its pipelines.
pub struct ShadowPass {
    map: Image,
    /// The casters' depth words, a `u32` a texel of the map, copied into it.
    casters_depth: Buffer,
    /// The comparison sampler the field's set names: kept alive with the map.
    _sampler: Sampler,
    /// The casters' compute threads into each cascade: near, then far.
    casters: [Pipeline; 2],
    /// The surfaces into each cascade.
    surfaces: [Pipeline; 2],
}

impl ShadowPass {
    /// The map, `side` texels a side (cleared to the far plane, so everything reads
    /// lit until the first shadow pass, and left ready to be sampled), and its
    /// pipelines; points the field's bindings 8 and 9 at them.
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        module: &ShaderModules,
        field: &Field,
        side: u32,
    ) -> Result<Self> {
        let (map, casters_depth) = Self::map(ctx, pool, field, side)?;
        let sampler = Sampler::shadow_compare(ctx, DEPTH_FORMAT)?;
        let set = &field.descriptors;
        set.write_sampler(BINDING_SHADOW_SAMPLER, sampler.sampler);
        let none = vk::Format::UNDEFINED;
        // The position alone (location 0): the shadow's vertex stage reads no normal.
        let mut input = vec4_vertex_input::<SurfaceVertex>();
        input.1.truncate(1);
        let surfaces = |entry| {
            let stages = [(vk::ShaderStageFlags::VERTEX, entry)];
            let desc =
                GraphicsDesc::opaque(module, &stages, &field.layout, &input, none, DEPTH_FORMAT);
            Pipeline::graphics(ctx, &desc)
        };
        let casters = |entry| Pipeline::compute(ctx, &field.layout, module, entry);
        Ok(Self {
            map,
            casters_depth,
            _sampler: sampler,
            casters: [
                casters(shaders::RASTER_NEAR_CASTERS)?,
                casters(shaders::RASTER_CASTERS)?,
            ],
            surfaces: [
                surfaces(shaders::SHADOW_SURFACE_NEAR_VS)?,
                surfaces(shaders::SHADOW_SURFACE_VS)?,
            ],
        })
    }

    /// The map (depth, `SHADER_READ_ONLY_OPTIMAL` between frames).
    pub fn image(&self) -> &Image {
        &self.map
    }

    /// Side of each cascade in texels.
    pub fn size(&self) -> u32 {
        self.map.extent.height
    }

    /// Makes the map again `side` texels a side, unless it is already; waits for the
    /// frames in flight, which may read the old one.
    pub fn resize(
        &mut self,
        ctx: &Arc<Context>,
        pool: &CommandPool,
        field: &Field,
        side: u32,
    ) -> Result<()> {
        if side != self.size() {
            ctx.wait_idle()?;
            (self.map, self.casters_depth) = Self::map(ctx, pool, field, side)?;
        }
        Ok(())
    }

    /// A map of two cascades `side` texels a side, cleared to the far plane and ready
    /// to be sampled, bound to the field's binding 8, and the casters' depth words for
    /// it, bound to binding 13.
    fn map(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        field: &Field,
        side: u32,
    ) -> Result<(Image, Buffer)> {
        use vk::ImageUsageFlags as U;
        anyhow::ensure!(
            SHADOW_SIZES.contains(&side),
            "shadow map of {side} texels: the sides are {SHADOW_SIZES:?}"
        );
        let most = ctx.properties.limits.max_image_dimension2_d;
        anyhow::ensure!(
            2 * side <= most,
            "shadow map of {side} texels: its two cascades need an image {} texels wide, \
             this device makes them {most} wide at most; choose a smaller --shadow-size",
            2 * side
        );
        let extent = vk::Extent2D {
            width: 2 * side,
            height: side,
        };
        let words = u64::from(extent.width) * u64::from(extent.height);
        let most = u64::from(ctx.properties.limits.max_storage_buffer_range);
        anyhow::ensure!(
            4 * words <= most,
            "shadow map of {side} texels: its casters' depth needs {} bytes, more than \
             this device's maxStorageBufferRange ({most}); choose a smaller --shadow-size",
            4 * words
        );
        use vk::BufferUsageFlags as B;
        let casters_depth = Buffer::new(
            ctx,
            "shadow casters' depth",
            4 * words,
            B::STORAGE_BUFFER | B::TRANSFER_DST | B::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let map = Image::new(
            ctx,
            "shadow map",
            extent,
            DEPTH_FORMAT,
            // Copied out by the tests (`Renderer::shadow_map`).
            U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED | U::TRANSFER_DST | U::TRANSFER_SRC,
            vk::ImageAspectFlags::DEPTH,
        )?;
        pool.one_shot(|rec| {
            let depth = vk::ImageAspectFlags::DEPTH;
            let cleared = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            rec.image_barrier(
                map.image,
                depth,
                (vk::ImageLayout::UNDEFINED, cleared),
                (S::NONE, A::NONE),
                (S::CLEAR, A::TRANSFER_WRITE),
            );
            rec.clear_depth_image(map.image, 1.0);
            rec.image_barrier(
                map.image,
                depth,
                (cleared, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL),
                (S::CLEAR, A::TRANSFER_WRITE),
                (READERS, A::SHADER_READ),
            )
        })?;
        let set = &field.descriptors;
        set.write_sampled_image(BINDING_SHADOW_MAP, map.view);
        set.write_buffer(
            BINDING_SHADOW_DEPTH,
            vk::DescriptorType::STORAGE_BUFFER,
            casters_depth.buffer,
        );
        Ok((map, casters_depth))
    }

    /// Records the map: the grass's casters by compute threads into the depth words,
    /// copied into the map, then the surfaces and `colliders` drawn over them; the map is
    /// then ready for the fragment stages and the shading pass to sample.
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        (ground, colliders): (&GroundPass, &[Collider]),
    ) {
        let aspect = vk::ImageAspectFlags::DEPTH;
        let words = self.casters_depth.buffer;
        let compute_rw = (
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
        );
        // After the last frame's copy read the words.
        let filled = (S::CLEAR | S::COPY, A::TRANSFER_WRITE);
        rec.memory_barrier((S::COPY, A::TRANSFER_READ), filled);
        rec.fill_buffer(words, EMPTY_DEPTH);
        rec.memory_barrier(filled, compute_rw);
        // Near first: the dispatches are the near cascade's, then all casters'.
        let dispatches = field.caster_dispatches();
        for (pipeline, at) in self.casters.iter().zip(dispatches) {
            rec.bind_pipeline(
                vk::PipelineBindPoint::COMPUTE,
                pipeline.pipeline,
                field.layout.layout,
                field.descriptors.set,
            );
            rec.dispatch_indirect(field.mesh_draw.buffer, at);
        }
        let copied = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        rec.memory_barrier(compute_rw, (S::COPY, A::TRANSFER_READ));
        rec.image_barrier(
            self.map.image,
            aspect,
            (vk::ImageLayout::UNDEFINED, copied),
            (READERS, A::NONE),
            (S::COPY, A::TRANSFER_WRITE),
        );
        rec.copy_buffer_to_depth(words, self.map.image, self.map.extent);
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        rec.image_barrier(
            self.map.image,
            aspect,
            (copied, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL),
            (S::COPY, A::TRANSFER_WRITE),
            (tests, depth_rw),
        );
        let loaded = Attachments {
            color: None,
            color_resolve: None,
            second: None,
            depth: Some((self.map.view, false)),
            area: None,
        };
        rec.begin_rendering_with(&loaded, self.map.extent);
        let side = self.size();
        for (k, surfaces) in self.surfaces.iter().enumerate() {
            rec.set_viewport(vk::Rect2D {
                offset: vk::Offset2D {
                    x: k as i32 * side as i32,
                    y: 0,
                },
                extent: vk::Extent2D {
                    width: side,
                    height: side,
                },
            });
            ground.record_with(surfaces, rec, field, (colliders, &|_| true));
        }
        rec.end_rendering();
        rec.image_barrier(
            self.map.image,
            aspect,
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (S::LATE_FRAGMENT_TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (READERS, A::SHADER_READ),
        );
    }
}

/// The stages that sample the map: the lit fragment stages and the natural look's
/// shading after the draw (`passes::shade`).
const READERS: S = S::from_raw(S::FRAGMENT_SHADER.as_raw() | S::COMPUTE_SHADER.as_raw());

//! The sun's shadow map (natural look): the scene's surfaces, the collider balls and
//! the grass's shadow casters at their fewest segments, depth only, from the sun
//! (`shared::draw::look::shadow::sun_view_proj`). Ground and grass fragments read it through
//! binding 8 of the field's set.
//!
//! The fragment stages read it with one fetch through a comparison sampler.
//!
//! Grass is drawn from the compute pass's list of casters: every blade inside the map
//! and within `look.caster_distance` of the camera, whatever the camera's culling
//! tests decide (a blade outside the view or turned edge-on still casts its shadow),
//! dressed as the natural look draws it without the camera's fades
//! (`shared::draw::look::clump::caster_blade`), at the level of detail `lod.fewest`:
//! one patch of one segment (2 triangles) per caster. The map depends on where the
//! camera is, not on where it looks.

use crate::field::Field;
use crate::passes::DEPTH_FORMAT;
use crate::passes::ground::GroundPass;
use crate::shaders;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules, vec4_vertex_input};
use crate::vulkan::sampler::Sampler;
use crate::vulkan::{Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use glam::Vec4;
use shared::gpu::layout::SurfaceVertex;
use shared::settings::SHADOW_SIZES;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

use shared::gpu::layout::{BINDING_SHADOW_MAP, BINDING_SHADOW_SAMPLER};

/// The shadow map and its pipelines.
pub struct ShadowPass {
    map: Image,
    /// The comparison sampler the field's set names: kept alive with the map.
    _sampler: Sampler,
    surfaces: Pipeline,
    grass: Pipeline,
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
        use vk::ShaderStageFlags as St;
        let map = Self::map(ctx, pool, field, side)?;
        let sampler = Sampler::shadow_compare(ctx, DEPTH_FORMAT)?;
        let set = &field.descriptors;
        set.write_sampler(BINDING_SHADOW_SAMPLER, sampler.sampler);
        let none = vk::Format::UNDEFINED;
        // The position alone (location 0): the shadow's vertex stage reads no normal.
        let mut input = vec4_vertex_input::<SurfaceVertex>();
        input.1.truncate(1);
        let stages = [(St::VERTEX, shaders::SHADOW_SURFACE_VS)];
        let surfaces =
            GraphicsDesc::opaque(module, &stages, &field.layout, &input, none, DEPTH_FORMAT);
        let surfaces = Pipeline::graphics(ctx, &surfaces)?;
        let stages = [
            (St::VERTEX, shaders::SHADOW_VS),
            (St::TESSELLATION_CONTROL, shaders::GRASS_SHADOW_TCS),
            (St::TESSELLATION_EVALUATION, shaders::GRASS_SHADOW_TES),
        ];
        let grass = GraphicsDesc::patches(module, &stages, &field.layout, none, DEPTH_FORMAT);
        let grass = Pipeline::graphics(ctx, &grass)?;
        Ok(Self {
            map,
            _sampler: sampler,
            surfaces,
            grass,
        })
    }

    /// The map (depth, `SHADER_READ_ONLY_OPTIMAL` between frames).
    pub fn image(&self) -> &Image {
        &self.map
    }

    /// Side of the map in texels.
    pub fn size(&self) -> u32 {
        self.map.extent.width
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
            self.map = Self::map(ctx, pool, field, side)?;
        }
        Ok(())
    }

    /// A map `side` texels a side, cleared to the far plane and ready to be sampled,
    /// bound to the field's binding 8.
    fn map(ctx: &Arc<Context>, pool: &CommandPool, field: &Field, side: u32) -> Result<Image> {
        use vk::ImageUsageFlags as U;
        anyhow::ensure!(
            SHADOW_SIZES.contains(&side),
            "shadow map of {side} texels: the sides are {SHADOW_SIZES:?}"
        );
        let extent = vk::Extent2D {
            width: side,
            height: side,
        };
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
                (S::FRAGMENT_SHADER, A::SHADER_READ),
            )
        })?;
        field
            .descriptors
            .write_sampled_image(BINDING_SHADOW_MAP, map.view);
        Ok(map)
    }

    /// Records the map: surfaces, `balls` and the grass's casters; it is then ready
    /// for the fragment stages to sample.
    pub fn record(&self, rec: &Recorder, field: &Field, ground: &GroundPass, balls: &[Vec4]) {
        let aspect = vk::ImageAspectFlags::DEPTH;
        let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        rec.image_barrier(
            self.map.image,
            aspect,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            (S::FRAGMENT_SHADER, A::NONE),
            (tests, depth_rw),
        );
        rec.begin_rendering(None, Some(self.map.view), self.map.extent);
        ground.record_with(&self.surfaces, rec, field, balls);
        rec.bind_pipeline(
            vk::PipelineBindPoint::GRAPHICS,
            self.grass.pipeline,
            field.layout.layout,
            field.descriptors.set,
        );
        rec.draw_indirect_at(field.draws.buffer, field.casters_draw());
        rec.end_rendering();
        rec.image_barrier(
            self.map.image,
            aspect,
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            ),
            (S::LATE_FRAGMENT_TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
            (S::FRAGMENT_SHADER, A::SHADER_READ),
        );
    }
}

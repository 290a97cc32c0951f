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
//! (`shadow::CASTER_LEVEL`): one segment (two triangles) per caster, through the
//! grass's pipeline: a patch, or a lane of a mesh workgroup. The
//! map depends on where the camera is, not on where it looks.

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
    /// Surfaces and casters (tessellated) into each cascade: near, then far.
    cascades: [(Pipeline, Pipeline); 2],
    /// The casters through mesh stages into each cascade, where the device has them.
    mesh: Option<([Pipeline; 2], ash::ext::mesh_shader::Device)>,
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
        let cascade = |surface_vs, (grass_tcs, grass_tes)| -> Result<(Pipeline, Pipeline)> {
            let stages = [(St::VERTEX, surface_vs)];
            let surfaces =
                GraphicsDesc::opaque(module, &stages, &field.layout, &input, none, DEPTH_FORMAT);
            let stages = [
                (St::VERTEX, shaders::SHADOW_VS),
                (St::TESSELLATION_CONTROL, grass_tcs),
                (St::TESSELLATION_EVALUATION, grass_tes),
            ];
            let grass = GraphicsDesc::patches(module, &stages, &field.layout, none, DEPTH_FORMAT);
            Ok((
                Pipeline::graphics(ctx, &surfaces)?,
                Pipeline::graphics(ctx, &grass)?,
            ))
        };
        let mesh = match &ctx.mesh_shader {
            Ok(commands) => {
                let make = |entry| {
                    let stages = [(St::MESH_EXT, entry)];
                    let mut desc =
                        GraphicsDesc::patches(module, &stages, &field.layout, none, DEPTH_FORMAT);
                    desc.patch_control_points = 0;
                    Pipeline::graphics(ctx, &desc)
                };
                let pipelines = [
                    make(shaders::SHADOW_NEAR_MESH)?,
                    make(shaders::SHADOW_MESH)?,
                ];
                Some((pipelines, commands.clone()))
            }
            Err(_) => None,
        };
        Ok(Self {
            map,
            _sampler: sampler,
            mesh,
            cascades: [
                cascade(
                    shaders::SHADOW_SURFACE_NEAR_VS,
                    (shaders::GRASS_SHADOW_TCS, shaders::GRASS_SHADOW_NEAR_TES),
                )?,
                cascade(
                    shaders::SHADOW_SURFACE_VS,
                    (shaders::GRASS_SHADOW_TCS, shaders::GRASS_SHADOW_TES),
                )?,
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
            self.map = Self::map(ctx, pool, field, side)?;
        }
        Ok(())
    }

    /// A map of two cascades `side` texels a side, cleared to the far plane and ready
    /// to be sampled, bound to the field's binding 8.
    fn map(ctx: &Arc<Context>, pool: &CommandPool, field: &Field, side: u32) -> Result<Image> {
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
        field
            .descriptors
            .write_sampled_image(BINDING_SHADOW_MAP, map.view);
        Ok(map)
    }

    /// Records the map: surfaces, `balls` and the grass's casters (through mesh stages
    /// with `mesh`, where the device has them); it is then ready for the fragment
    /// stages to sample.
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        (ground, balls): (&GroundPass, &[Vec4]),
        mesh: bool,
    ) {
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
            (READERS, A::NONE),
            (tests, depth_rw),
        );
        rec.begin_rendering(None, Some(self.map.view), self.map.extent);
        let side = self.size();
        // Near first, with its own casters; then far, with all of them.
        let casters = [field.near_casters_draw(), field.casters_draw()];
        let mesh_casters = field.casters_mesh_draws();
        let mesh = self.mesh.as_ref().filter(|_| mesh);
        for (k, (surfaces, grass)) in self.cascades.iter().enumerate() {
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
            let grass = mesh.map_or(grass, |(pipelines, _)| &pipelines[k]);
            rec.bind_pipeline(
                vk::PipelineBindPoint::GRAPHICS,
                grass.pipeline,
                field.layout.layout,
                field.descriptors.set,
            );
            match mesh {
                Some((_, commands)) => {
                    // Near first: the mesh grids are all casters', then the near ones'.
                    let at = mesh_casters[1 - k];
                    rec.draw_mesh_tasks_indirect_at(commands, field.mesh_draw.buffer, (at, 1));
                }
                None => rec.draw_indirect_at(field.draws.buffer, casters[k]),
            }
            // After the casters: the ground under the grass then fails the early depth
            // test instead of being written and written over.
            ground.record_with(surfaces, rec, field, balls);
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

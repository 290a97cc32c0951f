//! The main draw: the visible blades, then the ground, into the draw's colour and
//! depth, and the far blades of the compute rasterizer resolved into the same images.
//! It owns the three passes that draw there ([`ground`](super::ground),
//! [`grass`](super::grass), [`raster`](super::raster)) and keeps their pipelines made
//! for the images' format and samples.

use super::Mark;
use super::by_target::{ByTarget, DrawTarget};
use super::grass::GrassPass;
use super::ground::GroundPass;
use super::raster::RasterPass;
use crate::field::Field;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::pipeline::ShaderModules;
use crate::vulkan::{Attachments, Context, Image, Recorder};
use anyhow::Result;
use ash::vk;
use shared::plan::FramePlan;
use shared::settings::View;
use shared::sim::collide::Collider;
use shared::world::mesh::SurfaceMesh;
use std::sync::Arc;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// The images one frame's draw writes.
pub struct DrawImages<'a> {
    /// The colour drawn into (image, view): the target, the HDR image or the
    /// multisampled one.
    pub color: (vk::Image, vk::ImageView),
    /// Where a multisampled colour resolves to, when it is.
    pub resolve: Option<(vk::Image, vk::ImageView)>,
    /// The depth drawn into (multisampled with the colour).
    pub depth: &'a Image,
    /// The motion target (image, view), cleared to nothing written, with temporal
    /// anti-aliasing.
    pub motion: Option<(vk::Image, vk::ImageView)>,
    /// Samples per pixel of `color` and `depth`.
    pub samples: u32,
    /// The colour cleared to.
    pub clear: [f32; 4],
    /// Their size.
    pub extent: vk::Extent2D,
}

/// A caller's colour and depth views, drawn over (loaded and stored).
pub struct LoadedImages {
    /// The colour view.
    pub color: vk::ImageView,
    /// The depth view.
    pub depth: vk::ImageView,
    /// Their size.
    pub extent: vk::Extent2D,
}

/// The passes that draw into the frame's colour and depth.
pub struct DrawPass {
    /// The surfaces and the collider ball.
    pub ground: GroundPass,
    /// The visible blades (a pipeline set per colour format and samples).
    pub grass: ByTarget<GrassPass>,
    /// The compute rasterizer's far blades.
    pub raster: RasterPass,
    /// What the pipelines draw into.
    drawn_into: DrawTarget,
}

impl DrawPass {
    /// The passes for single-sample colour of `color_format`, the ground made of
    /// `surfaces` (mesh, material), the collider `ball` and a `valley`'s grid.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
        surfaces: &[(&SurfaceMesh, u32)],
        ball: &SurfaceMesh,
        valley: Option<f32>,
    ) -> Result<Self> {
        let target = DrawTarget::single(color_format);
        let ground = GroundPass::new(
            ctx,
            pool,
            module,
            field,
            color_format,
            surfaces,
            ball,
            valley,
        )?;
        let raster = RasterPass::new(ctx, module, field, target)?;
        let grass = ByTarget::new(target, GrassPass::new(ctx, module, field, target)?);
        Ok(Self {
            ground,
            grass,
            raster,
            drawn_into: target,
        })
    }

    /// The pipelines for `target` (made once per target, kept).
    pub fn retarget(
        &mut self,
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<()> {
        if target == self.drawn_into {
            return Ok(());
        }
        self.ground.retarget(ctx, module, field, target)?;
        self.grass
            .select(target, || GrassPass::new(ctx, module, field, target))?;
        self.raster.retarget(module, field, target)?;
        self.drawn_into = target;
        Ok(())
    }

    /// Grass, then ground, into `images`; [`Mark::Grass`] and [`Mark::Ground`] after
    /// each, the grass's triangles counted into `triangles`. Grass first: the ground
    /// under it then fails the early depth test instead of being shaded and drawn
    /// over (docs/performance.md); the blades that surfaces hide are culled before
    /// (the occlusion test). With `plan`'s far blades, that scope ends, the compute
    /// rasterizer reads its depth ([`Mark::Raster`]), and a second scope on the same
    /// images resolves the far blades; the multisample resolve comes at the end of
    /// the last scope.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        rec: &Recorder,
        field: &Field,
        images: &DrawImages,
        plan: &FramePlan,
        colliders: &[Collider],
        stamp: &dyn Fn(Mark),
        triangles: Option<vk::QueryPool>,
    ) {
        let (color, resolve, depth) = (images.color, images.resolve, images.depth);
        let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        let depth_tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        let colours = [Some(color), resolve, images.motion];
        // After the last frame's tone map read them.
        let last_read = S::COLOR_ATTACHMENT_OUTPUT | S::FRAGMENT_SHADER;
        for image in colours.into_iter().flatten().map(|c| c.0) {
            rec.image_barrier(
                image,
                vk::ImageAspectFlags::COLOR,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                (last_read, A::NONE),
                color_out,
            );
        }
        // After the pre-pass's copy (or the last frame's tests, copy and compute
        // reads) is done with it.
        rec.image_barrier(
            depth.image,
            vk::ImageAspectFlags::DEPTH,
            (
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            (
                depth_tests | S::COPY | S::COMPUTE_SHADER,
                A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            (depth_tests, depth_rw),
        );
        let far = plan.far;
        let hardware = Attachments {
            color: Some((color.1, Some(images.clear))),
            color_resolve: if far { None } else { resolve.map(|r| r.1) },
            second: images.motion.map(|m| (m.1, true)),
            depth: Some((depth.view, true)),
            area: None,
        };
        rec.begin_rendering_with(&hardware, images.extent);
        if let Some(pool) = triangles {
            rec.begin_query(pool);
        }
        self.grass
            .current()
            .record(rec, field, plan.view, plan.look, plan.pipeline);
        if let Some(pool) = triangles {
            rec.end_query(pool);
        }
        stamp(Mark::Grass);
        self.ground.record(rec, field, colliders);
        stamp(Mark::Ground);
        if !far {
            stamp(Mark::Raster);
            rec.end_rendering();
            return;
        }
        rec.end_rendering();
        self.raster
            .record(rec, field, plan.natural(), depth, images.samples);
        stamp(Mark::Raster);
        if self.far_in_shading(plan) {
            return;
        }
        let far_blades = Attachments {
            color: Some((color.1, None)),
            color_resolve: resolve.map(|r| r.1),
            second: images.motion.map(|m| (m.1, false)),
            depth: Some((depth.view, false)),
            area: None,
        };
        rec.begin_rendering_with(&far_blades, images.extent);
        self.raster.record_resolve(rec, field, plan.view, plan.look);
        rec.end_rendering();
    }

    /// Whether the far blades are left to the shading after the draw
    /// (`compute::shade::shade_natural`, which reads the same conditions from the
    /// frame) instead of a rendering scope of their own: the natural look's shaded
    /// view on a target shaded after the draw. A full-screen fragment pass with its
    /// depth written took the NVIDIA H100 0.19 ms at 1920x1080 with nothing to draw.
    fn far_in_shading(&self, plan: &FramePlan) -> bool {
        self.drawn_into.deferred && plan.natural() && plan.view == View::Shaded
    }

    /// The grass (and the ground, with `ground`) drawn over a caller's `images`,
    /// loaded and stored: [`Mark::Grass`] and [`Mark::Ground`] after each.
    pub fn record_over(
        &self,
        rec: &Recorder,
        field: &Field,
        images: &LoadedImages,
        plan: &FramePlan,
        ground: bool,
        stamp: &dyn Fn(Mark),
    ) {
        let loaded = Attachments {
            color: Some((images.color, None)),
            color_resolve: None,
            second: None,
            depth: Some((images.depth, false)),
            area: None,
        };
        rec.begin_rendering_with(&loaded, images.extent);
        self.grass
            .current()
            .record(rec, field, plan.view, plan.look, plan.pipeline);
        stamp(Mark::Grass);
        if ground {
            self.ground.record(rec, field, &[]);
        }
        stamp(Mark::Ground);
        rec.end_rendering();
    }
}

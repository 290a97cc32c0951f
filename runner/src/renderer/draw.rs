//! The draw: grass, then ground, into the draw's colour and depth, and the far blades
//! of the compute rasterizer resolved into the same images.

use super::*;

impl Renderer {
    /// Grass, then ground, into the draw's colour (the target, the HDR image or the
    /// multisampled one, see [`targets`]); [`Mark::Grass`] and [`Mark::Ground`]
    /// after each, the grass's triangles counted into `triangles`. Grass first: the
    /// ground under it then fails the early depth test instead of being shaded and
    /// drawn over (performance notes, attempt 12); the blades that surfaces hide are
    /// culled before (the occlusion test). With the compute rasterizer on, that scope
    /// ends, the rasterizer reads its depth ([`Mark::Raster`]), and a second scope on
    /// the same images resolves the far blades; the multisample resolve comes at the
    /// end of the last scope.
    pub(super) fn record_draw(
        &self,
        rec: &Recorder,
        target: &Target,
        plan: &FramePlan,
        balls: &[glam::Vec4],
        stamp: &dyn Fn(Mark),
        triangles: Option<vk::QueryPool>,
    ) -> Result<()> {
        let targets = self.targets.as_ref().context("draw targets")?;
        let single = targets
            .hdr
            .as_ref()
            .map_or((target.image, target.view), |h| (h.image, h.view));
        let (color, resolve) = match &targets.color_ms {
            Some(ms) => ((ms.image, ms.view), Some(single)),
            None => (single, None),
        };
        let far = plan.far;
        let depth_image = targets.depth_ms.as_ref().unwrap_or(&targets.depth);
        let depth = (depth_image.image, depth_image.view);
        let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        let depth_tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
        for image in std::iter::once(color.0).chain(resolve.map(|r| r.0)) {
            rec.image_barrier(
                image,
                vk::ImageAspectFlags::COLOR,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                (S::COLOR_ATTACHMENT_OUTPUT, A::NONE),
                color_out,
            );
        }
        // After the pre-pass's copy (or the last frame's tests, copy and compute
        // reads) is done with it.
        rec.image_barrier(
            depth.0,
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
        // The natural look's sky is drawn by the tone map where alpha leaves room.
        let clear = if targets.hdr.is_some() { [0.0; 4] } else { SKY };
        let extent = target.extent;
        let hardware = Attachments {
            color: Some((color.1, Some(clear))),
            color_resolve: if far { None } else { resolve.map(|r| r.1) },
            depth: Some((depth.1, true)),
        };
        rec.begin_rendering_with(&hardware, extent);
        if let Some(pool) = triangles {
            rec.begin_query(pool);
        }
        self.grass
            .current()
            .record(rec, &self.field, plan.view, plan.look, plan.pipeline);
        if let Some(pool) = triangles {
            rec.end_query(pool);
        }
        stamp(Mark::Grass);
        self.ground.record(rec, &self.field, balls);
        stamp(Mark::Ground);
        if far {
            rec.end_rendering();
            let samples = targets.spec.samples;
            self.raster
                .record(rec, &self.field, plan.natural(), depth_image, samples);
            stamp(Mark::Raster);
            let far_blades = Attachments {
                color: Some((color.1, None)),
                color_resolve: resolve.map(|r| r.1),
                depth: Some((depth.1, false)),
            };
            rec.begin_rendering_with(&far_blades, extent);
            self.raster
                .record_resolve(rec, &self.field, plan.view, plan.look);
        } else {
            stamp(Mark::Raster);
        }
        rec.end_rendering();
        Ok(())
    }
}

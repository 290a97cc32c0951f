//! The frame planned once: what the renderer does in a frame (the look, the view, the
//! pipeline, the samples, the shadow map, the occlusion test, the far blades, the
//! clumps), decided from the settings and what the renderer has. The renderer
//! branches on the plan, never on numbers of the frame's GPU block, which the same
//! settings make (`Settings::uniforms`).

use crate::gpu::layout::FrameUniforms;
use crate::settings::{GrassPipeline, Look, Settings, View, Viewpoint};
use spirv_std::glam::Vec4;

/// What one frame does.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FramePlan {
    /// Paper or natural.
    pub look: Look,
    /// Shaded, LOD colours or wireframe.
    pub view: View,
    /// Tessellation or mesh stages.
    pub pipeline: GrassPipeline,
    /// Samples per pixel asked (the renderer lowers it to what the device has).
    pub samples: u32,
    /// The sun's shadow map's side, where the natural look casts shadows.
    pub shadows: Option<u32>,
    /// The occluders' depth pyramid is built and the occlusion test reads it.
    pub occlusion: bool,
    /// The compute rasterizer draws the blades short on screen.
    pub far: bool,
    /// The clumps' seed and size (natural look), made again when they change.
    pub clumps: (u32, f32),
}

impl FramePlan {
    /// The frame `settings` ask for.
    pub fn of(settings: &Settings) -> Self {
        let look = &settings.look;
        let natural = look.style == Look::Natural;
        Self {
            look: look.style,
            view: settings.view,
            pipeline: settings.pipeline,
            samples: look.msaa,
            shadows: (natural && look.shadows).then_some(look.shadow_size),
            occlusion: settings.cull.tests.occlusion,
            far: settings.compute_raster_below > 0.0,
            clumps: (look.seed, look.clump_size),
        }
    }

    /// This plan where the renderer has `occluders` (surfaces that can hide grass)
    /// and a `compute_raster`izer or not: without them there is no pyramid to build
    /// and no far blade to draw.
    pub fn within(self, occluders: bool, compute_raster: bool) -> Self {
        Self {
            occlusion: self.occlusion && occluders,
            far: self.far && compute_raster,
            ..self
        }
    }

    /// The natural look (HDR target, tone map, dressed blades).
    pub fn natural(&self) -> bool {
        self.look == Look::Natural
    }

    /// Drawn by mesh stages.
    pub fn mesh(&self) -> bool {
        self.pipeline == GrassPipeline::Mesh
    }
}

impl Settings {
    /// The plan and the GPU block of a frame of a field of `blades` seen from `eye`,
    /// with the sphere colliders `balls` ([`Settings::uniforms`]).
    pub fn planned(
        &self,
        eye: &Viewpoint,
        blades: u32,
        balls: &[Vec4],
    ) -> (FramePlan, FrameUniforms) {
        (FramePlan::of(self), self.uniforms(eye, blades, balls))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_is_the_settings_within_the_renderer_s_means() {
        let mut s = Settings::default();
        s.look.style = Look::Natural;
        s.look.shadows = true;
        s.look.shadow_size = 1024;
        s.compute_raster_below = 16.0;
        let plan = FramePlan::of(&s);
        assert_eq!(plan.shadows, Some(1024));
        assert!(plan.far && plan.natural());
        assert!(!plan.within(true, false).far);
        assert!(!plan.within(false, true).occlusion);
        s.look.style = Look::Paper;
        assert_eq!(FramePlan::of(&s).shadows, None, "the paper look casts none");
    }
}

//! The frame planned once. A caller asks for a frame ([`FrameRequest`]: the settings,
//! the viewpoint, the colliders, the questions); the renderer plans it ([`FramePlan`]: the look, the
//! view, the pipeline, the samples, the shadow map, the occlusion test, the far blades,
//! the clumps) from the settings and what it has, and builds the frame's GPU block in
//! one call from the request, the plan and what it knows of the frame
//! ([`FrameFacts`]: the target, its depth pyramid, the field, the time). The renderer
//! branches on the plan, never on numbers of the block, and nothing changes the block
//! once built.

use crate::camera::CameraParams;
use crate::cull::blade::{CullParams, OCCLUSION};
use crate::cull::hiz::HiZLayout;
use crate::cull::lod::{LodParams, focal_pixels};
use crate::draw::look::LookParams;
use crate::draw::look::shadow::{near_sphere, sun_view_proj};
use crate::draw::raster::RasterParams;
use crate::draw::temporal::{TemporalParams, jitter, jittered};
use crate::gpu::layout::{FrameUniforms, GrassParams};
use crate::query::{MAX_QUESTIONS, Question};
use crate::settings::{
    Antialiasing, GrassPipeline, Look, MIN_RENDER_SCALE, NATURAL_EDGE_ON_SHARE, RASTER_SEGMENTS,
    Settings, View, Viewpoint, shadow_sphere,
};
use crate::sim::collide::{Collider, MAX_COLLIDERS};
use crate::sim::colliders::fitted;
use crate::sim::grid::{ColliderGrid, GRID_SLOTS};
use crate::sim::impulse::Impulses;
use crate::sim::simulate::Environment;
use spirv_std::glam::{Mat4, Vec4};

/// What a caller asks of one frame: the settings, where it is seen from, the
/// colliders (the first [`MAX_COLLIDERS`]), the live wind impulses and the questions
/// asked of the grass (the first [`MAX_QUESTIONS`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRequest {
    /// The settings the frame is drawn with.
    pub settings: Settings,
    /// Where it is seen from.
    pub eye: Viewpoint,
    colliders: Vec<Collider>,
    impulses: Impulses,
    questions: Vec<Question>,
    contacts: bool,
}

impl FrameRequest {
    /// A frame of `settings` seen from `eye` with the sphere colliders `balls`
    /// (centre xyz, radius w).
    pub fn new(settings: &Settings, eye: &Viewpoint, balls: &[Vec4]) -> Self {
        Self {
            settings: *settings,
            eye: *eye,
            colliders: Vec::new(),
            impulses: Impulses::default(),
            questions: Vec::new(),
            contacts: false,
        }
        .with_colliders(
            &balls
                .iter()
                .map(|b| Collider::from_sphere(*b))
                .collect::<Vec<_>>(),
        )
    }

    /// This frame with the colliders `more` after those it has (up to
    /// [`MAX_COLLIDERS`] in all).
    pub fn with_colliders(mut self, more: &[Collider]) -> Self {
        let room = MAX_COLLIDERS - self.colliders.len();
        self.colliders
            .extend_from_slice(&more[..more.len().min(room)]);
        self
    }

    /// This frame with the colliders so far (the balls, before any added with
    /// [`FrameRequest::with_colliders`]) cutting the grass instead of pushing it, where
    /// `cuts` (`sim::cut`).
    pub fn with_balls_cutting(mut self, cuts: bool) -> Self {
        if cuts {
            for c in &mut self.colliders {
                *c = c.cutting();
            }
        }
        self
    }

    /// The colliders.
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }

    /// This frame with the wind impulses `impulses` (those not ended act).
    pub fn with_impulses(self, impulses: &Impulses) -> Self {
        Self {
            impulses: *impulses,
            ..self
        }
    }

    /// The wind impulses.
    pub fn impulses(&self) -> &Impulses {
        &self.impulses
    }

    /// This frame with the questions `asked` after those it has (up to
    /// [`MAX_QUESTIONS`] in all), answered over the blades as this frame leaves them.
    pub fn with_questions(mut self, asked: &[Question]) -> Self {
        let room = MAX_QUESTIONS - self.questions.len();
        self.questions
            .extend_from_slice(&asked[..asked.len().min(room)]);
        self
    }

    /// The questions.
    pub fn questions(&self) -> &[Question] {
        &self.questions
    }

    /// This frame marking the colliders touching blades where `on` (`query::CONTACTS`:
    /// a pass after the collision pass, in frames with colliders).
    pub fn with_contacts(self, on: bool) -> Self {
        Self {
            contacts: on,
            ..self
        }
    }

    /// Whether the frame marks the colliders touching blades.
    pub fn contacts(&self) -> bool {
        self.contacts
    }

    /// The frame the settings ask for, before the renderer's means narrow it.
    pub fn plan(&self) -> FramePlan {
        FramePlan::of(&self.settings)
    }

    /// The whole GPU block of this frame drawn as `plan` says, with `facts`
    /// ([`Settings::uniforms`]).
    pub fn uniforms(&self, plan: &FramePlan, facts: &FrameFacts) -> FrameUniforms {
        let around = (self.colliders(), &self.impulses);
        self.settings.uniforms(plan, &self.eye, around, facts)
    }
}

/// What the renderer knows of a frame that the settings do not.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct FrameFacts {
    /// The target's size in pixels, (width, height).
    pub extent: (u32, u32),
    /// The depth pyramid's layout for that target (read where the plan has the
    /// occlusion test).
    pub hiz: HiZLayout,
    /// The field's blades.
    pub field: FieldPart,
    /// Simulated time after the frame's steps, seconds.
    pub time: f32,
    /// How far the field's tallest blade reaches from its root (the colliders'
    /// grid's reach, `sim::grid::ColliderGrid::reach`).
    pub reach: f32,
    /// The lowest and highest height (y) of the field's roots, where known: the
    /// colliders' grid marks only cubes that meet them
    /// (`sim::grid::ColliderGrid::over_roots`).
    pub roots: Option<(f32, f32)>,
    /// Simulated time of the newest cut before this frame (`f32::NEG_INFINITY`:
    /// none): the blades read the cut table while it may still be growing back
    /// (`Environment::cutting`).
    pub last_cut: f32,
    /// Frames drawn before this one (the jitter's place in its sequence).
    pub frame: u32,
    /// The previous frame's unjittered view-projection, where the temporal history
    /// holds that frame (`None`: nothing to blend, on the first frame, a new size or
    /// look).
    pub previous: Option<Mat4>,
}

/// Which blades a field holds and how many of them are simulated.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct FieldPart {
    /// Blades in the field (a tiled field's: its pool's and its far blades' room).
    pub blades: u32,
    /// Blades below this index are simulated.
    pub simulated: u32,
    /// A tiled field: the blades from `simulated` on are generated each frame.
    pub tiled: bool,
    /// A blade may be of a species other than grass (`GrassParams::mixed`).
    pub mixed: bool,
}

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
    /// Temporal anti-aliasing: a jittered frame blended into a history.
    pub taa: bool,
    /// Share of the output's width and height the scene is drawn at
    /// (`LookSettings::render_scale`, within its range).
    pub scale: f32,
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
            samples: if look.aa == Antialiasing::Msaa {
                look.msaa
            } else {
                1
            },
            taa: look.aa == Antialiasing::Taa,
            scale: look.render_scale.clamp(MIN_RENDER_SCALE, 1.0),
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

    /// Drawn smaller than the output (a render scale under 1).
    pub fn scaled(&self) -> bool {
        self.scale < 1.0
    }

    /// The size the scene is drawn at for an output of `output` pixels (width,
    /// height): each side [`Self::drawn_side`].
    pub fn drawn_size(&self, output: (u32, u32)) -> (u32, u32) {
        (self.drawn_side(output.0), self.drawn_side(output.1))
    }

    /// A side of `n` output pixels as drawn: times the scale, rounded up, at least 1.
    pub fn drawn_side(&self, n: u32) -> u32 {
        ((n as f32 * self.scale).ceil() as u32).clamp(1, n.max(1))
    }
}

impl Settings {
    /// A frame of these settings seen from `eye`, with the sphere colliders `balls`
    /// (centre xyz, radius w).
    pub fn request(&self, eye: &Viewpoint, balls: &[Vec4]) -> FrameRequest {
        FrameRequest::new(self, eye, balls)
    }
}

impl Settings {
    /// The whole frame block, built once: these settings drawn as `plan` says (its
    /// look, view, pipeline, shadow map, occlusion test and far blades), seen from
    /// `eye`, with the `colliders` (the first `MAX_COLLIDERS`, in a grid fitted to
    /// them: `sim::colliders::fitted`) and the wind `impulses` around, and what the renderer
    /// knows of the frame (`facts`).
    pub fn uniforms(
        &self,
        plan: &FramePlan,
        eye: &Viewpoint,
        (colliders, impulses): (&[Collider], &Impulses),
        facts: &FrameFacts,
    ) -> FrameUniforms {
        // Drawn smaller than the output, the camera's pixels are the drawn image's.
        let eye = &Viewpoint {
            height: plan.drawn_side(eye.height),
            ..*eye
        };
        let used = colliders.len().min(MAX_COLLIDERS);
        let collider_grid = if used == 0 {
            ColliderGrid::default()
        } else {
            let grid = fitted(&colliders[..used], facts.reach, GRID_SLOTS);
            facts.roots.map_or(grid, |roots| grid.over_roots(roots))
        };
        let cull = &self.cull;
        let lod = &self.lod;
        let field = &facts.field;
        let (width, height) = facts.extent;
        // Without the pyramid, the occlusion test is off and reads none.
        let unplanned = if plan.occlusion { 0 } else { OCCLUSION };
        let temporal = if plan.taa {
            TemporalParams::new(
                eye.view_proj,
                jitter(facts.frame, facts.extent),
                facts.previous,
            )
        } else {
            TemporalParams::default()
        };
        FrameUniforms {
            camera: CameraParams {
                // Moved by the jitter where the frame is blended into a history.
                view_proj: if plan.taa {
                    jittered(eye.view_proj, temporal.jitter)
                } else {
                    eye.view_proj
                },
                position: eye.position,
                focal_pixels: focal_pixels(eye.fov_y, eye.height as f32),
            },
            light: self.look_light(plan.look),
            forces: Environment {
                time: facts.time,
                impulses: impulses.live(),
                cutting: u32::from(
                    colliders[..used].iter().any(Collider::cuts)
                        || facts.time - facts.last_cut < self.regrow,
                ),
                ..self.environment(used as u32)
            },
            collider_grid,
            impulses: *impulses.slots(),
            hiz: if plan.occlusion {
                facts.hiz
            } else {
                HiZLayout::default()
            },
            lod: LodParams {
                pixels_per_segment: lod.pixels_per_segment,
                most: lod.most,
                fewest: if lod.on { lod.fewest } else { lod.most },
            },
            grass: GrassParams {
                blades: field.blades,
                shape: self.shape as u32,
                tip_start: self.tip_start,
                view: plan.view as u32,
                pipeline: plan.pipeline as u32,
                simulated: field.simulated,
                tiled: u32::from(field.tiled),
                mixed: u32::from(field.mixed),
            },
            cull: CullParams {
                orientation_threshold: cull.orientation_threshold,
                frustum_tolerance: cull.frustum_tolerance,
                max_distance: cull.max_distance,
                buckets: cull.buckets,
                enabled: cull.tests.mask() & !unplanned,
                edge_on_pixels: cull.edge_on_pixels
                    * if plan.natural() {
                        NATURAL_EDGE_ON_SHARE
                    } else {
                        1.0
                    },
                focal_pixels: focal_pixels(eye.fov_y, eye.height as f32),
                padding: [0; 2],
            },
            look: self.look_params(plan, eye),
            raster: RasterParams {
                width,
                height,
                below: if plan.far {
                    self.compute_raster_below
                } else {
                    0.0
                },
                segments: RASTER_SEGMENTS,
            },
            temporal,
        }
    }

    /// The look's block as `plan` draws it: the shadow map around what the camera
    /// sees.
    pub fn look_params(&self, plan: &FramePlan, eye: &Viewpoint) -> LookParams {
        let look = &self.look;
        let (centre, radius) = shadow_sphere(look.scene, eye.position);
        LookParams {
            shadow_view_proj: sun_view_proj(look.sun, centre, radius),
            near_view_proj: {
                let (near, r) = near_sphere((centre, radius), eye.position);
                sun_view_proj(look.sun, near, r)
            },
            style: plan.look as u32,
            shadows: u32::from(plan.shadows.is_some()),
            seed: look.seed,
            shadow_size: plan.shadows.unwrap_or(look.shadow_size),
            fog_density: look.fog_density,
            field_distance: self.cull.max_distance,
            pixel_angle: 2.0 * (0.5 * eye.fov_y).tan() / eye.height.max(1) as f32,
            clump_size: look.clump_size,
            caster_distance: look.caster_distance,
            padding: [0; 4],
            exposure: look.exposure,
            ground_level: look.ground_level.unwrap_or(0.0),
            ground_to_horizon: u32::from(look.ground_level.is_some()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::blade::{FRUSTUM, ORIENTATION};
    use crate::draw::shape::SHAPE_QUADRATIC;
    use spirv_std::glam::{Mat4, Vec3};

    /// The drawn size by hand: each side times the scale, rounded up, at least a
    /// pixel; the scale kept within its range.
    #[test]
    fn the_drawn_size_by_hand() {
        let mut s = Settings::default();
        assert!(!FramePlan::of(&s).scaled());
        assert_eq!(FramePlan::of(&s).drawn_size((1280, 720)), (1280, 720));
        s.look.render_scale = 0.5;
        let plan = FramePlan::of(&s);
        assert!(plan.scaled());
        assert_eq!(plan.drawn_size((1280, 720)), (640, 360));
        assert_eq!(plan.drawn_size((1281, 1)), (641, 1));
        s.look.render_scale = 0.01;
        assert_eq!(FramePlan::of(&s).drawn_size((1280, 720)), (320, 180));
        s.look.render_scale = 3.0;
        assert_eq!(FramePlan::of(&s).drawn_size((1280, 720)), (1280, 720));
    }

    #[test]
    fn the_block_by_hand() {
        let mut s = Settings::default();
        s.lod.on = false;
        s.cull.tests.distance = false;
        s.gravity.centre = Vec3::new(0.0, -30.0, 0.0);
        s.wind.direction = 90.0;
        let eye = Viewpoint {
            view_proj: Mat4::IDENTITY,
            position: Vec3::new(1.0, 2.0, 3.0),
            fov_y: std::f32::consts::FRAC_PI_2,
            height: 200,
            forward: Vec3::Z,
        };
        let balls = [Collider::from_sphere(Vec4::ONE); MAX_COLLIDERS + 3];
        let facts = FrameFacts {
            extent: (320, 200),
            field: FieldPart {
                blades: 1234,
                simulated: 1234,
                tiled: false,
                mixed: false,
            },
            time: 2.5,
            ..Default::default()
        };
        let plan = FramePlan::of(&s);
        let u = s.uniforms(&plan, &eye, (&balls, &Impulses::default()), &facts);
        // tan(45°) = 1: the focal length is half the height.
        assert!((u.camera.focal_pixels - 100.0).abs() < 1e-4);
        assert_eq!(u.camera.position, eye.position);
        // LOD off: the fewest segments are the most.
        assert_eq!((u.lod.most, u.lod.fewest), (7.0, 7.0));
        assert_eq!(u.cull.enabled, ORIENTATION | FRUSTUM | OCCLUSION);
        assert_eq!(u.forces.colliders, MAX_COLLIDERS as u32);
        assert_eq!(u.forces.gravity_centre, Vec4::new(0.0, -30.0, 0.0, 9.8));
        assert!((u.forces.wind - Vec4::new(0.0, 0.0, 1.0, 7.0)).length() < 1e-6);
        assert_eq!(
            (u.grass.blades, u.grass.simulated, u.grass.tiled),
            (1234, 1234, 0)
        );
        assert_eq!(u.grass.shape, SHAPE_QUADRATIC);
        assert_eq!((u.raster.width, u.raster.height), (320, 200));
        assert_eq!(u.forces.time, 2.5);
        assert!(u.hiz.is_empty());
    }

    #[test]
    fn the_plan_decides_what_the_block_turns_on() {
        let mut s = Settings::default();
        s.look.style = Look::Natural;
        s.look.shadows = true;
        s.compute_raster_below = 12.0;
        let eye = Viewpoint {
            view_proj: Mat4::IDENTITY,
            position: Vec3::ZERO,
            fov_y: 1.0,
            height: 100,
            forward: Vec3::Z,
        };
        let facts = FrameFacts {
            extent: (64, 32),
            hiz: crate::cull::hiz::HiZLayout::new(64, 32),
            field: FieldPart {
                blades: 100,
                simulated: 40,
                tiled: true,
                mixed: false,
            },
            time: 0.0,
            reach: 2.5,
            roots: None,
            last_cut: f32::NEG_INFINITY,
            frame: 0,
            previous: None,
        };
        let plan = FramePlan::of(&s);
        let full = s.uniforms(&plan, &eye, (&[], &Impulses::default()), &facts);
        assert_eq!(full.hiz, facts.hiz);
        assert_eq!(full.cull.enabled & OCCLUSION, OCCLUSION);
        assert_eq!(full.raster.below, 12.0);
        assert_eq!(
            (full.look.shadows, full.look.shadow_size),
            (1, s.look.shadow_size)
        );
        assert_eq!((full.grass.simulated, full.grass.tiled), (40, 1));
        // Without occluders or a compute rasterizer: no pyramid, no occlusion test, no
        // far blades, whatever the settings say.
        let narrowed = s.uniforms(
            &plan.within(false, false),
            &eye,
            (&[], &Impulses::default()),
            &facts,
        );
        assert!(narrowed.hiz.is_empty());
        assert_eq!(narrowed.cull.enabled & OCCLUSION, 0);
        assert_eq!(narrowed.raster.below, 0.0);
    }

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

//! Grass in your own Vulkan renderer: a [`GrassField`] made on your ash instance,
//! device and gpu-allocator, recording its passes into your command buffer and
//! drawing into your colour and depth images.
//!
//! 1. Before making the device, ask [`requirements`] what the field needs of the
//!    physical device (Vulkan 1.3, features, extensions, formats). It answers with the
//!    [`DeviceFeatures`] to enable, or [`Missing`], naming everything the device lacks.
//! 2. Make the device with them ([`DeviceFeatures::enable`] on your
//!    `vk::DeviceCreateInfo`, [`DeviceFeatures::extensions`] among its extensions), a
//!    queue family with graphics and compute, and a `gpu_allocator` allocator.
//! 3. [`GrassField::new`] uploads the blades of its ground ([`Ground`]: the built-in
//!    hills or plane, or your triangle mesh, checked like a scene file) and builds its
//!    pipelines for your colour format. Your depth image must be [`DEPTH_FORMAT`],
//!    with depth 0 near and 1 far (the field tests `LESS_OR_EQUAL`), or reversed
//!    (1 near, 0 far: [`FieldDesc::reverse_z`], the field tests `GREATER_OR_EQUAL`).
//! 4. Each frame, after drawing your scene into your colour and depth images (left in
//!    `COLOR_ATTACHMENT_OPTIMAL` and `DEPTH_ATTACHMENT_OPTIMAL`) and outside any
//!    rendering scope, call [`GrassField::record`] with your command buffer, camera
//!    ([`viewpoint`] from view and projection matrices), frame time and colliders
//!    (spheres that push the blades down). It simulates, culls and draws the blades
//!    over your picture, depth-tested against it, and leaves the images in the same
//!    layouts; synchronise your later use of them as after your own drawing.
//!
//! Your device, queue, images and command buffers stay yours; the field destroys only
//! what it made, after waiting for the device to be idle. [`GrassField::new`] submits
//! its uploads to your queue (from the calling thread) and waits for them;
//! [`GrassField::record`] only records. A change of the targets' size between frames
//! waits for the device to be idle and makes the field's own images again. Submit every frame that
//! records the field to the same queue (its buffers are ordered from frame to frame by
//! barriers, not by fences).
//!
//! The field draws the paper's look by default. `settings.look.style =
//! Look::Natural` draws the natural look (clumps and colour, rounded normals,
//! translucency, sun shadows, fog) as linear radiance, before exposure and tone
//! mapping: give it a linear HDR colour target (e.g. `R16G16B16A16_SFLOAT`) and tone
//! map it with the rest of your frame (`shared::draw::look::sky::tone_map` is this program's,
//! with `settings.look.exposure`). The program's own sky and tone-map pass are not
//! drawn: they would cover your picture. Nor are its anti-aliasing and render scale
//! (`settings.look.aa`, `msaa`, `render_scale`): the field draws into your targets at
//! their size.
//!
//! A game can ask questions of the grass ([`GrassField::ask`], `shared::query`): how
//! many blades stand around a point, how tall and how bent; how much of a line of
//! sight they hide. The next recorded frame answers them on the GPU over the blades as
//! it leaves them; read the answers ([`GrassField::answers`]) once that frame is done,
//! a frame later, as with [`GrassField::counts`]. Once [`GrassField::grass_events`]
//! is called, each frame also marks the colliders touching blades, which it turns into
//! a collider entering or leaving the grass (footsteps, rustling).
//!
//! `runner/examples/embed/` is a whole program: its own spinning cube and this grass
//! in one frame, in a window or headless (`--out frame.png`).

#[cfg(feature = "wgpu")]
pub mod wgpu;

use crate::answers::Contacts;
use crate::renderer::external::ExternalFrame;
use crate::renderer::{FrameQueries, Meshes, Renderer};
use crate::scene::{BladeCount, Scene, SceneFile, SceneKind};
use crate::vulkan::features::{device_name, format_has};
use crate::vulkan::{Context, Recorder};
use anyhow::{Context as _, Result, bail};
use ash::vk;
use glam::{Mat4, Vec3};
use shared::query::{MAX_QUESTIONS, Question};
use shared::settings::{GrassPipeline, Look};
use shared::sim::collide::{Collider, MAX_COLLIDERS};
use shared::sim::impulse::{Impulse, Impulses, MAX_IMPULSES};
use shared::sim::simulate::{Environment, SimClock};
use shared::world::mesh::SurfaceMesh;
use shared::world::mesh::bvh::IndexedMesh;
use std::sync::Arc;

pub use crate::answers::{Answers, GrassEvent};
pub use crate::passes::DEPTH_FORMAT;
pub use crate::renderer::external::ExternalTargets as Targets;
pub use crate::renderer::{CullCounts, PassTimes};
pub use crate::vulkan::{DeviceFeatures, DeviceParts as Device, Missing};
pub use shared::settings::{Settings, Viewpoint};

/// What the field needs of `physical` to draw into colour images of `color_format`:
/// the features (and extensions) to enable on the device, or everything it lacks.
/// Makes nothing.
pub fn requirements(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    color_format: vk::Format,
) -> Result<DeviceFeatures, Missing> {
    let features = DeviceFeatures::query(instance, physical);
    use vk::FormatFeatureFlags as F;
    let formats = [
        (
            color_format,
            F::COLOR_ATTACHMENT,
            "as a colour attachment (your colour target)",
        ),
        (
            DEPTH_FORMAT,
            F::DEPTH_STENCIL_ATTACHMENT | F::SAMPLED_IMAGE,
            "as a sampled depth attachment (your depth target, the field's own)",
        ),
    ];
    let formats: Vec<String> = formats
        .into_iter()
        .filter(|&(format, needed, _)| !format_has(instance, physical, format, needed))
        .map(|(format, _, what)| format!("format {format:?} {what}"))
        .collect();
    match features {
        Ok(features) if formats.is_empty() => Ok(features),
        Ok(_) => Err(Missing {
            device: device_name(instance, physical),
            missing: formats,
        }),
        Err(mut missing) => {
            missing.missing.extend(formats);
            Err(missing)
        }
    }
}

/// The ground a field grows on.
pub enum Ground {
    /// Rolling hills around the origin, sized for the blade count (about 4 blades a
    /// square unit).
    Hills,
    /// A flat square around the origin, sized for the blade count.
    Plane,
    /// Your triangle mesh (counter-clockwise seen from its normals' side, normals
    /// optional): checked as a scene file's mesh is, grass everywhere on it.
    Mesh(SurfaceMesh),
}

/// What [`GrassField::new`] makes.
pub struct FieldDesc {
    /// The ground.
    pub ground: Ground,
    /// Blades on it, scattered by area (a stored field; a tiled one has its own
    /// density).
    pub blades: u32,
    /// A tiled field (`runner::tiles`): blades generated tile by tile around the
    /// camera, simulated near it and drawn at rest far out, to the horizon and in
    /// bounded memory, instead of `blades` stored and simulated everywhere.
    pub tiled: bool,
    /// Seed of the blades' places and shapes.
    pub seed: u64,
    /// The species the field grows, mixed by weight (`shared::species::Mix`, e.g.
    /// `Mix::new([12, 0, 2, 3])` for grass, flowers and seed grass;
    /// `Mix::GRASS` for grass alone).
    pub species: shared::species::Mix,
    /// Format of the colour images the field draws into.
    pub color_format: vk::Format,
    /// Draw the ground too (else only the blades: your scene has its ground).
    pub draw_ground: bool,
    /// Your depth is reversed: 1 near, 0 far (Bevy's; the field's depth test keeps
    /// the greater). Else 0 near, 1 far.
    pub reverse_z: bool,
}

/// One frame of the field.
pub struct Frame<'a> {
    /// Your colour and depth images (see the module docs for their layouts).
    pub targets: Targets,
    /// Where it is seen from ([`viewpoint`]).
    pub camera: Viewpoint,
    /// Time since the last frame, seconds: the simulation runs in fixed steps of
    /// `shared::sim::simulate::STEP_SECONDS` to catch up with it.
    pub seconds: f64,
    /// Spheres, capsules and boxes that push the blades aside
    /// (`shared::sim::collide::Collider::sphere`, `capsule`, `cuboid`); at most
    /// [`MAX_COLLIDERS`].
    pub colliders: &'a [Collider],
}

/// A grass field drawn by your renderer.
pub struct GrassField {
    /// The settings each frame is drawn with (wind, gravity, culling, LOD, blade
    /// shape, the light, the look); change them between frames.
    pub settings: Settings,
    renderer: Renderer,
    queries: FrameQueries,
    clock: SimClock,
    impulses: Impulses,
    bounds: (Vec3, f32),
    solid: IndexedMesh,
    blades: u32,
    draw_ground: bool,
    reverse_z: bool,
    /// The questions the next frame asks.
    questions: Vec<Question>,
    /// The contacts as [`GrassField::grass_events`] last read them.
    contacts: Contacts,
    /// Frames mark the contacts: [`GrassField::grass_events`] was called.
    watch_contacts: bool,
    ctx: Arc<Context>,
}

impl GrassField {
    /// Checks `device` against [`requirements`], then uploads the blades of `desc` and
    /// builds the pipelines. `features` are those the device was made with.
    pub fn new(device: Device, features: &DeviceFeatures, desc: FieldDesc) -> Result<Self> {
        requirements(&device.instance, device.physical, desc.color_format)?;
        if desc.blades == 0 {
            bail!("a field of 0 blades");
        }
        let (kind, file) = match desc.ground {
            Ground::Hills => (SceneKind::Hills, None),
            Ground::Plane => (SceneKind::Plane, None),
            Ground::Mesh(mesh) => {
                let name = "your mesh";
                let mesh = crate::scene::load::from_mesh(&mesh, name)?;
                let file = SceneFile {
                    name: name.into(),
                    mesh,
                };
                // A scene of a file's kind: its triangles came in as a file's do.
                (SceneKind::File(name.into()), Some(file))
            }
        };
        let count = BladeCount::Total(desc.blades);
        let mut scene = Scene::build(&kind, file, count, desc.seed, |_| Ok(()))?;
        scene.set_species(desc.species);
        let ctx = Context::from_external(device, features);
        if desc.tiled {
            scene.make_tiled(crate::scene::tiled_spec(&scene, ctx.is_software(), 1.0));
        }
        let meshes = Meshes {
            has_occluders: false,
            ..scene.meshes()
        };
        let renderer = Renderer::new(&ctx, &meshes, desc.color_format)?;
        let mut settings = scene.settings();
        settings.look.style = Look::Paper;
        // As the program's `--pipeline auto`: the mesh path wherever the device has it
        // (the faster one on every device measured, docs/pipelines.md, "Measured").
        if ctx.mesh_shader.is_ok() {
            settings.pipeline = GrassPipeline::Mesh;
        }
        Ok(Self {
            settings,
            renderer,
            queries: FrameQueries::new(&ctx)?,
            clock: SimClock::default(),
            impulses: Impulses::default(),
            bounds: scene.bounds,
            blades: scene.blade_count(),
            solid: scene.solid,
            draw_ground: desc.draw_ground,
            reverse_z: desc.reverse_z,
            questions: Vec::new(),
            contacts: Contacts::default(),
            watch_contacts: false,
            ctx,
        })
    }

    /// Records the field's frame into `cmd` (recording, outside any rendering scope):
    /// simulation steps for `frame.seconds`, culling, then the blades (and the ground,
    /// if asked) drawn into `frame.targets`.
    pub fn record(&mut self, cmd: vk::CommandBuffer, frame: &Frame) -> Result<()> {
        if frame.colliders.len() > MAX_COLLIDERS {
            bail!(
                "{} colliders, the field takes at most {MAX_COLLIDERS}",
                frame.colliders.len()
            );
        }
        let extent = frame.targets.extent;
        if extent.width == 0 || extent.height == 0 {
            bail!("targets of {}x{} pixels", extent.width, extent.height);
        }
        // An impulse that ends during this frame's steps still blows until it does.
        self.impulses.retire(self.clock.time());
        let (first_step, steps) = self.clock.advance(frame.seconds);
        let request = self
            .settings
            .request(&frame.camera, &[])
            .with_colliders(frame.colliders)
            .with_impulses(&self.impulses)
            .with_questions(&std::mem::take(&mut self.questions))
            .with_contacts(self.watch_contacts);
        let push = shared::gpu::layout::SimulatePush {
            first_step,
            steps,
            ..Default::default()
        };
        let external = ExternalFrame {
            targets: frame.targets,
            request,
            push,
            ground: self.draw_ground,
            reverse_z: self.reverse_z,
        };
        let rec = Recorder::new(&self.ctx.device, cmd);
        self.renderer
            .record_external(&rec, &self.queries, &external)
            .context("record the grass")
    }

    /// What the culling tests did in the newest frame that finished (wait for it
    /// first, e.g. on its fence).
    pub fn counts(&self) -> Result<CullCounts> {
        self.queries.read()?.counts.context("no counts")
    }

    /// GPU time of the field's passes in the newest frame that finished, where the
    /// queue has timestamps and no later frame of the field is in flight: simulate and
    /// cull (with the uniform upload before), shadow map, grass, ground, and the
    /// whole (`total`; the passes the field does not run read 0).
    pub fn times(&self) -> Result<Option<PassTimes>> {
        Ok(self.queries.read()?.times)
    }

    /// Asks `questions` (`shared::query::Question::around`, `sight`) of the next
    /// frame [`GrassField::record`] records, after any asked before it; refused past
    /// `MAX_QUESTIONS` a frame.
    pub fn ask(&mut self, questions: &[Question]) -> Result<()> {
        if self.questions.len() + questions.len() > MAX_QUESTIONS {
            bail!(
                "{} questions for one frame, the field answers at most {MAX_QUESTIONS}",
                self.questions.len() + questions.len()
            );
        }
        self.questions.extend_from_slice(questions);
        Ok(())
    }

    /// The answers of the newest frame that finished (wait for it first): each
    /// question it asked with its tally (`shared::query::Tally`: the blades counted,
    /// their mean height and bend, the concealment of a sight), and the colliders it
    /// found touching blades.
    pub fn answers(&self) -> Result<Answers> {
        Ok(self.queries.read()?.answers)
    }

    /// The colliders that entered or left the grass between the newest frame that
    /// finished and the one this was last called after (by their index in
    /// [`Frame::colliders`]). The frames recorded after the first call mark the
    /// colliders touching blades (a pass after the collision pass); the frames before
    /// it do not, and cost nothing for it.
    pub fn grass_events(&mut self) -> Result<Vec<GrassEvent>> {
        self.watch_contacts = true;
        let now = self.answers()?.contacts;
        let events = now.events_since(&self.contacts);
        self.contacts = now;
        Ok(events)
    }

    /// The blades of the field.
    pub fn blade_count(&self) -> u32 {
        self.blades
    }

    /// A sphere (centre, radius) holding the ground and the blades standing on it:
    /// what a camera frames.
    pub fn bounds(&self) -> (Vec3, f32) {
        self.bounds
    }

    /// The highest point of the ground straight under (or over) `x`, `z`, if the
    /// ground reaches there: where to stand things on it.
    pub fn ground_at(&self, x: f32, z: f32) -> Option<Vec3> {
        crate::collider::point_below(&self.solid, glam::Vec2::new(x, z)).map(|hit| hit.position)
    }

    /// Simulated time so far, seconds.
    pub fn time(&self) -> f32 {
        self.clock.time()
    }

    /// The wind the blades feel at `point` now (`shared::sim::simulate::wind_at`, the
    /// same function the compute pass steps with, under `settings.wind` and the wind
    /// impulses blowing): an acceleration along the ground, for your own trees, flags
    /// or particles to move with the grass.
    pub fn wind_at(&self, point: Vec3) -> Vec3 {
        let env = Environment {
            impulses: self.impulses.live(),
            ..self.settings.environment(0)
        };
        shared::sim::simulate::wind_at(&env, self.impulses.slots(), point, self.time())
    }

    /// Adds a wind impulse (`shared::sim::impulse`: an explosion's blast, a rotor's
    /// downwash), its start in the field's simulated time ([`Self::time`] for now); it
    /// blows in the frames that follow until its lifetime ends. Refused where a
    /// number is out of range or `MAX_IMPULSES` are already blowing.
    pub fn add_impulse(&mut self, impulse: Impulse) -> Result<()> {
        if let Some(problem) = impulse.problem() {
            bail!("wind impulse {impulse:?}: {problem}");
        }
        self.impulses.retire(self.time());
        if self.impulses.add(impulse).is_err() {
            bail!("{MAX_IMPULSES} wind impulses are blowing already; add one when one ends");
        }
        Ok(())
    }
}

/// The camera as the field needs it, from your `view` (world to eye, right-handed,
/// looking down -z) and `proj` (eye to Vulkan clip space: y down, depth 0 near to 1
/// far) matrices and your target's `height` in pixels.
pub fn viewpoint(view: Mat4, proj: Mat4, height: u32) -> Viewpoint {
    Viewpoint::from_matrices(view, proj, height)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The viewpoint of the same camera as the viewer's orbit camera builds it.
    #[test]
    fn viewpoint_matches_the_orbit_camera() {
        let camera = crate::camera::OrbitCamera::framing(20.0);
        let (w, h) = (640, 360);
        use glam::camera::rh;
        let view = rh::view::look_at_mat4(camera.eye(), camera.target, Vec3::Y);
        let proj = rh::proj::vulkan::perspective(camera.fov_y, w as f32 / h as f32, 0.1, 200.0);
        let ours = viewpoint(view, proj, h);
        let theirs = camera.viewpoint((w, h));
        assert!(
            (ours.fov_y - theirs.fov_y).abs() < 1e-5,
            "{ours:?} {theirs:?}"
        );
        assert!(ours.position.distance(theirs.position) < 1e-3);
        assert!(ours.forward.distance(theirs.forward) < 1e-5);
        assert!(ours.view_proj.abs_diff_eq(theirs.view_proj, 1e-4));
        assert_eq!(ours.height, h);
    }
}

//! Headless rendering: an offscreen colour image, N frames at 1/60 s, a PNG of the last.

use super::driver::{Frame, FrameDriver};
use super::headless::{FORMAT, Offscreen};
use crate::cli::{Common, ImpulseSpec, RenderArgs};
use crate::collider::Ball;
use crate::renderer::{CullCounts, PassTimes, Renderer};
use crate::walkers::Walkers;
use anyhow::{Context as _, Result, bail};
use shared::sim::impulse::{Impulse, Impulses, MAX_IMPULSES};

/// What a headless render produced.
pub struct RenderReport {
    /// RGBA8 pixels, sRGB, row-major.
    pub pixels: Vec<u8>,
    /// Visible blades in the last frame.
    pub visible: u32,
    /// What the culling tests did in the last frame.
    pub counts: CullCounts,
    /// GPU time per pass of the last frame, where the device has timestamps.
    pub times: Option<PassTimes>,
    /// Blades in the field.
    pub blades: u32,
    /// Validation errors reported (0 without validation).
    pub validation_errors: u32,
    /// World to clip of the camera, for tests that locate things in the image.
    pub view_proj: glam::Mat4,
}

/// Renders as `args` asks and writes the PNG.
pub fn run(common: &Common, args: &RenderArgs) -> Result<RenderReport> {
    crate::files::check_output(&args.out, &["png"])?;
    let report = render(common, args)?;
    crate::files::save_png(
        &args.out,
        &report.pixels,
        (args.width, args.height),
        image::ColorType::Rgba8,
    )?;
    log::info!(
        "wrote {} ({}x{}, {} frames, {} of {} blades visible)",
        args.out.display(),
        args.width,
        args.height,
        args.frames,
        report.visible,
        report.blades
    );
    log::info!("last frame: {}", describe(&report.counts));
    if let Some(t) = report.times {
        log::info!(
            "GPU ms: uploads + depth pyramid {:.3}, simulate+cull {:.3}, shadow map {:.3}, \
             ground {:.3}, grass {:.3}, compute raster {:.3}, resolve {:.3}, shading {:.3}, \
             TAA + sky + tone map {:.3}, total {:.3}",
            t.depth_pyramid,
            t.simulate_cull,
            t.shadow,
            t.ground,
            t.grass,
            t.raster,
            t.resolve,
            t.shade,
            t.tone_map,
            t.total
        );
    }
    if report.validation_errors > 0 {
        bail!(
            "{} validation errors (see the log above)",
            report.validation_errors
        );
    }
    Ok(report)
}

/// "N drawn, M by compute, removed: orientation a, frustum b, ... (total T)".
pub fn describe(c: &CullCounts) -> String {
    let removed: Vec<String> = c
        .by_test()
        .iter()
        .map(|(name, n)| format!("{name} {n}"))
        .collect();
    let casters = if c.casters > 0 {
        format!("; shadow casters {} ({} near)", c.casters, c.near_casters)
    } else {
        String::new()
    };
    format!(
        "{} drawn, {} by compute ({} of their {} pixels written), removed by {} (total {}){casters}",
        c.drawn,
        c.compute,
        c.raster_written,
        c.raster_covered,
        removed.join(", "),
        c.examined
    )
}

/// Where the headless camera is at simulated `time` on `scene` for a target of `size`:
/// the scene's framing changed by `args` (zoom, yaw, pitch), turning around the scene
/// by `args.orbit` degrees a second or flying the valley's path (`args.flight`).
pub fn camera_path(
    scene: &crate::scene::Scene,
    args: &crate::cli::CameraArgs,
    size: (u32, u32),
) -> Result<impl Fn(f32) -> shared::settings::Viewpoint + use<>> {
    if args.flight && scene.kind != crate::scene::SceneKind::Valley {
        anyhow::bail!("--flight flies over the valley: add --scene valley");
    }
    let mut camera = scene.camera();
    camera.distance /= args.zoom;
    camera.yaw = args.yaw.map_or(camera.yaw, f32::to_radians);
    camera.pitch = args.pitch.map_or(camera.pitch, f32::to_radians);
    let (flight, orbit) = (args.flight, args.orbit.to_radians());
    Ok(move |time: f32| {
        if flight {
            let travelled = super::bench::FLIGHT_SPEED * time;
            crate::scene::valley_camera(travelled).viewpoint(size)
        } else {
            let mut turned = camera;
            turned.yaw += orbit * time;
            turned.viewpoint(size)
        }
    })
}

/// The command line's ball, made once: the collider path it rolls along (none with
/// `--no-ball`), its speed and radius.
pub struct BallPath {
    path: crate::collider::ColliderPath,
    speed: f32,
    radius: f32,
}

impl BallPath {
    /// The ball `common` asks for, if any.
    pub fn of(common: &Common) -> Option<Self> {
        let path = common.collider_path.clone().filter(|_| !common.no_ball)?;
        Some(Self {
            path,
            speed: common.collider_speed,
            radius: common.collider_radius,
        })
    }

    /// The ball's sphere at simulated `time`, dropped onto `scene`'s surface.
    pub fn spheres_at(&self, scene: &crate::scene::Scene, time: f32) -> Vec<glam::Vec4> {
        let at = self.path.at(self.speed * time);
        Ball::dropped(&scene.solid, at, self.radius)
            .iter()
            .map(Ball::sphere)
            .collect()
    }
}

/// A headless run made ready: the scene and its settings, the frame driver, the
/// offscreen target and the camera's path (what `render` and `record` start from).
pub struct Headless {
    /// The device.
    pub ctx: std::sync::Arc<crate::vulkan::Context>,
    /// The scene asked for.
    pub scene: crate::scene::Scene,
    /// Its settings, as the command line and the device make them.
    pub settings: shared::settings::Settings,
    /// Declared before the target, so it is dropped first: its drop waits for the GPU,
    /// which may still be drawing into the target when a frame fails.
    pub driver: FrameDriver,
    /// The offscreen colour image and its capture buffer.
    pub offscreen: Offscreen,
    /// The camera at a simulated time.
    pub eye_at: Box<dyn Fn(f32) -> shared::settings::Viewpoint>,
    /// The ball, if the command line has one.
    pub ball: Option<BallPath>,
    /// The command line's wind impulses (`--impulse`), centred on the ground.
    pub impulses: Impulses,
    /// The command line's walkers and mowers (`--walkers`, `--mowers`).
    pub walkers: Walkers,
    /// The ball cuts (`--ball-cuts`).
    pub ball_cuts: bool,
    /// The questions each frame asks of the grass (`shared::query`; none but in
    /// `grass query`), the contacts marked with them.
    pub questions: Vec<shared::query::Question>,
}

impl Headless {
    /// Opens the device, builds the scene and a target of `width` x `height`, and the
    /// camera's path from `camera`.
    pub fn open(
        common: &Common,
        (width, height): (u32, u32),
        camera: &crate::cli::CameraArgs,
        events: &crate::cli::ImpulseArgs,
    ) -> Result<Self> {
        let (file, ctx) = super::open_headless(common, common.validation_requested())?;
        let (scene, settings) = super::prepare(common, &ctx, file)?;
        let offscreen = Offscreen::new(&ctx, width, height)?;
        let driver = FrameDriver::new(&ctx, Renderer::new(&ctx, &scene.meshes(), FORMAT)?)?;
        let eye_at = Box::new(camera_path(&scene, camera, offscreen.size())?);
        let impulses = on_the_ground(&scene, &events.impulses)?;
        let walkers = Walkers::new(&scene, common.walkers).with_mowers(common.mowers);
        let ball_cuts = common.ball_cuts;
        Ok(Self {
            ctx,
            scene,
            settings,
            driver,
            offscreen,
            eye_at,
            ball: BallPath::of(common),
            impulses,
            walkers,
            ball_cuts,
            questions: Vec::new(),
        })
    }

    /// Runs one frame of `seconds`, the camera, the ball and the walkers where they
    /// are at its simulated time, captured if `capture`.
    pub fn frame(&mut self, seconds: f64, capture: bool) -> Result<()> {
        let (scene, settings, eye_at) = (&self.scene, &self.settings, &self.eye_at);
        let (ball, impulses, walkers) = (self.ball.as_ref(), &self.impulses, &self.walkers);
        let (ball_cuts, questions) = (self.ball_cuts, &self.questions);
        let request = |f: &Frame| {
            let balls = ball
                .map(|b| b.spheres_at(scene, f.time))
                .unwrap_or_default();
            settings
                .request(&eye_at(f.time), &balls)
                .with_balls_cutting(ball_cuts)
                .with_colliders(&walkers.colliders(scene, f.time, f.seconds()))
                .with_impulses(impulses)
                .with_questions(questions)
                .with_contacts(!questions.is_empty())
        };
        self.driver
            .run(&mut self.offscreen, seconds, request, capture)
    }
}

/// The wind impulses `specs` asks for, each centred on `scene`'s ground below its
/// point; an error where the ground does not reach, or for more than a frame holds.
pub fn on_the_ground(scene: &crate::scene::Scene, specs: &[ImpulseSpec]) -> Result<Impulses> {
    let mut impulses = Impulses::default();
    for spec in specs {
        let below = crate::collider::point_below(&scene.solid, spec.at);
        let ground = below.with_context(|| {
            format!("--impulse at {},{}: no ground there", spec.at.x, spec.at.y)
        })?;
        let impulse = Impulse {
            centre: ground.position.extend(spec.impulse.start()),
            ..spec.impulse
        };
        if impulses.add(impulse).is_err() {
            bail!("--impulse: at most {MAX_IMPULSES} wind impulses");
        }
    }
    Ok(impulses)
}

/// Renders as `args` asks and returns the pixels of the last frame, writing nothing.
pub fn render(common: &Common, args: &RenderArgs) -> Result<RenderReport> {
    let mut run = Headless::open(
        common,
        (args.width, args.height),
        &args.camera,
        &args.events,
    )?;
    let progress_every = (args.frames / 10).max(1);
    for frame in 0..args.frames {
        run.frame(1.0 / 60.0, frame + 1 == args.frames)?;
        if args.frames >= 100 && (frame + 1) % progress_every == 0 {
            log::info!("frame {}/{}", frame + 1, args.frames);
        }
    }
    run.driver.finish()?;
    let readback = &run.driver.readback;
    Ok(RenderReport {
        pixels: run.offscreen.pixels()?,
        visible: readback.visible().unwrap_or(0),
        counts: readback.counts.unwrap_or_default(),
        times: readback.times,
        blades: run.scene.blade_count(),
        validation_errors: run.ctx.validation_errors(),
        // Where the camera was at the last frame's simulated time.
        view_proj: (run.eye_at)(run.driver.clock.time()).view_proj,
    })
}

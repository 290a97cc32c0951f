//! The window viewer: winit event loop, orbit camera, the collider ball, the live
//! switches (culling tests, LOD, view, wind, blade shape) by key and in the overlay,
//! swapchain recreated on resize, frame rate and blade counts in the title once a
//! second.

mod gpu;
mod keys;

use super::driver::FrameSpec;
use super::overlay::{Overlay, Readings, said};
use super::storm::{Gust, Storm};
use crate::app::overlay::Actors;
use crate::camera::{Fly, OrbitCamera};
use crate::cli::{Common, PresentPath, ViewArgs};
use crate::collider::{Ball, drop_onto};
use crate::passes::overlay::OverlayFrame;
use crate::scene::{Scene, SceneFile};
use crate::walkers::Walkers;
use anyhow::{Context as _, Result};
use glam::{Vec2, Vec3, Vec3Swizzles};
use gpu::{Gpu, MAX_RECOVERIES, device_lost};
use shared::settings::Settings;
use shared::sim::impulse::{IMPULSE_BLAST, IMPULSE_DOWNWASH, Impulse, Impulses, MAX_IMPULSES};
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

/// Opens the window and runs until it is closed (or Esc).
pub fn run(common: &Common, args: &ViewArgs) -> Result<()> {
    crate::files::check_folder(&args.screenshot_dir, "--screenshot-dir")?;
    let file = common.scene_kind().read()?;
    let event_loop = EventLoop::new()
        .context("cannot open a window (no display?); `grass render` works without one")?;
    let mut app = Viewer {
        common: common.clone(),
        args: args.clone(),
        file,
        state: None,
        error: None,
    };
    event_loop.run_app(&mut app).context("event loop")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct Viewer {
    common: Common,
    args: ViewArgs,
    file: Option<SceneFile>,
    state: Option<Running>,
    error: Option<anyhow::Error>,
}

/// Mouse state for the orbit camera.
#[derive(Default)]
struct Mouse {
    rotating: bool,
    panning: bool,
    last: Option<(f64, f64)>,
    modifiers: ModifiersState,
}

/// The controls, printed at start.
pub const CONTROLS: &str = "drag: rotate, right-drag or shift-drag: pan, wheel: zoom, \
arrows: roll the ball (or fly), F: fly the camera with the arrows, + -: flying speed, B: ball on/off, C: the ball cuts, X: blast at the ball, R: rotor downwash at the ball, W: next wind, [ ]: wind weaker/stronger, \
, .: turn the wind, S: next blade shape, 1 2 3 4: orientation, frustum, distance, \
occlusion culling on/off, L: LOD on/off, V: next view (shaded, LOD colours, wireframe), \
N: look (paper, natural), H: shadows on/off, M: anti-aliasing (none, TAA, MSAA 2/4/8), P: pipeline (tessellation, mesh), K: screenshot, O: overlay on/off, Esc: quit";

/// Arrow keys held down.
#[derive(Default)]
struct Arrows {
    left: bool,
    right: bool,
    up: bool,
    down: bool,
}

impl Arrows {
    /// (right, forward) in −1..1.
    fn axis(&self) -> Vec2 {
        let f = |a: bool, b: bool| f32::from(u8::from(a)) - f32::from(u8::from(b));
        Vec2::new(f(self.right, self.left), f(self.up, self.down))
    }
}

/// The viewer's pace: frames drawn, the frame rate over the last whole second, and
/// the wall-clock time of the last frame (simulated time follows it).
struct Pace {
    /// Frames drawn since the start.
    frames: u64,
    /// Frames per second over the last whole second.
    fps: f64,
    /// When the last frame began.
    last_frame: Instant,
    /// Start of the second being counted, and its frames so far.
    second: (Instant, u32),
}

impl Pace {
    fn new() -> Self {
        Self {
            frames: 0,
            fps: 0.0,
            last_frame: Instant::now(),
            second: (Instant::now(), 0),
        }
    }

    /// Seconds since the last frame began; this one begins now.
    fn tick(&mut self) -> f64 {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        dt
    }

    /// Counts a drawn frame; true when a second is complete and `fps` new.
    fn drawn(&mut self) -> bool {
        self.frames += 1;
        self.second.1 += 1;
        let elapsed = self.second.0.elapsed().as_secs_f64();
        if elapsed < 1.0 {
            return false;
        }
        self.fps = f64::from(self.second.1) / elapsed;
        self.second = (Instant::now(), 0);
        true
    }
}

// Fields drop in order: GPU objects first (the last of them ends the context), then
// the window its surface belongs to.
struct Running {
    gpu: Gpu,
    scene: Scene,
    settings: Settings,
    common: Common,
    camera: OrbitCamera,
    ball: Option<Ball>,
    /// The ball on or off, and how many walkers wander (`walkers`' count).
    actors: Actors,
    walkers: Walkers,
    /// The wind impulses blowing.
    impulses: Impulses,
    /// A wind impulse asked for (X, R or the overlay), started at the next frame.
    blow: Option<u32>,
    arrows: Arrows,
    /// The arrows fly the camera.
    fly: Fly,
    /// A tiled field's distance every blade is kept within (the overlay's control).
    full_distance: Option<f32>,
    /// The species the field grows (the overlay's control).
    species: shared::species::Mix,
    mouse: Mouse,
    overlay: Overlay,
    pace: Pace,
    /// The scripted window changes of `--resize-storm`.
    storm: Option<Storm>,
    /// Lost devices made again so far.
    recoveries: u32,
    /// Shown in the overlay and the title after a recovery.
    notice: Option<String>,
    /// Where the K key's screenshots go.
    screenshot_dir: std::path::PathBuf,
    /// What became of the last screenshot or settings file, for the overlay.
    saved: Option<(String, bool)>,
    /// How frames reach the window (`--present`).
    present: PresentPath,
    window: Arc<Window>,
}

impl Running {
    fn new(
        event_loop: &ActiveEventLoop,
        common: &Common,
        args: &ViewArgs,
        file: Option<SceneFile>,
    ) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title("grass")
            .with_inner_size(PhysicalSize::new(args.width, args.height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("create window")?,
        );
        let ctx = Gpu::context(&window, common)?;
        let (scene, settings) = super::prepare(common, &ctx, file)?;
        let gpu = Gpu::new(&ctx, &scene, &window, args.present)?;
        let mut overlay = Overlay::new(&window, gpu.shown_device(&ctx));
        overlay.visible = !args.no_overlay;
        log::info!("{CONTROLS}");
        // The ball starts at the path's start, else in front of the camera's target.
        let start = common
            .collider_path
            .as_ref()
            .map_or(scene.camera().target.xz(), |p| p.at(0.0));
        let ball = Ball::dropped(&scene.solid, start, common.collider_radius);
        Ok(Self {
            gpu,
            settings,
            common: common.clone(),
            camera: scene.camera(),
            ball,
            actors: Actors::of(common),
            walkers: Walkers::new(&scene, common.walkers).with_mowers(common.mowers),
            impulses: Impulses::default(),
            blow: None,
            arrows: Arrows::default(),
            fly: Fly::default(),
            full_distance: scene.tiles.map(|t| t.params.full_distance),
            species: scene.species,
            scene,
            mouse: Mouse::default(),
            overlay,
            pace: Pace::new(),
            storm: args.resize_storm.then(Storm::default),
            screenshot_dir: args.screenshot_dir.clone(),
            saved: None,
            recoveries: 0,
            notice: None,
            present: args.present,
            window,
        })
    }

    /// The window's size; 0x0 while minimised (or while the storm says so).
    fn size(&self) -> PhysicalSize<u32> {
        if self.storm.as_ref().is_some_and(Storm::hidden) {
            PhysicalSize::new(0, 0)
        } else {
            self.window.inner_size()
        }
    }

    /// After a lost device: a new context, presenter, renderer (the field as the seed
    /// made it) and overlay; the camera, the settings and the ball stay. An error when
    /// the device is lost too often, or cannot be made again.
    fn recover(&mut self, error: anyhow::Error) -> Result<()> {
        if self.recoveries >= MAX_RECOVERIES {
            return Err(error.context(format!(
                "the GPU device was lost {} times",
                MAX_RECOVERIES + 1
            )));
        }
        self.recoveries += 1;
        log::warn!(
            "{error:#}: making the device again ({} of {MAX_RECOVERIES})",
            self.recoveries
        );
        let ctx = Gpu::context(&self.window, &self.common)
            .context("make the device again after it was lost")?;
        // The new objects are made before the old ones go: the old device is lost, and
        // its objects only wait to be destroyed.
        self.gpu = Gpu::new(&ctx, &self.scene, &self.window, self.present)
            .context("make the renderer again")?;
        let visible = self.overlay.visible;
        self.overlay = Overlay::new(&self.window, self.gpu.shown_device(&ctx));
        self.overlay.visible = visible;
        let notice = format!(
            "The GPU device was lost and has been made again ({} of {MAX_RECOVERIES}); the \
             field starts anew.",
            self.recoveries
        );
        log::warn!("{notice}");
        self.window.set_title(&format!("grass: {notice}"));
        self.notice = Some(notice);
        Ok(())
    }

    /// Draws one frame; returns without drawing while minimised.
    fn frame(&mut self) -> Result<()> {
        let size = self.size();
        if !self.gpu.presenter.prepare((size.width, size.height))? {
            return Ok(());
        }
        // The look's blade size (loaded scenes are in metres): grow a stored field
        // again.
        self.gpu.set_species(&mut self.scene, self.species)?;
        let scale = self.scene.scale_for(self.settings.look.style);
        if self.scene.rescale(scale) {
            log::info!("blades grown again at {scale} times the course's size");
            self.gpu
                .driver
                .renderer
                .replace_blades(&self.scene.blades)?;
        }
        // Simulated time and the ball follow the wall clock.
        let dt = self.pace.tick();
        let gpu = &mut self.gpu;
        let Some(frame) = gpu.driver.begin(&mut gpu.presenter, dt)? else {
            return Ok(());
        };
        self.move_ball(dt as f32, frame.time);
        self.impulses.retire(frame.time);
        if let Some(kind) = self.blow.take().or_else(|| self.overlay.blow.take()) {
            self.start_impulse(kind, frame.time);
        }
        self.overlay.frame_time((dt * 1000.0) as f32);
        // After the read-back, so the overlay shows the newest counts.
        let readback = &self.gpu.driver.readback;
        let readings = Readings {
            fps: self.pace.fps,
            blades: self.scene.blade_count(),
            counts: readback.counts,
            times: readback.times,
            occluders: self.gpu.driver.renderer.has_occluders,
            pool: self.gpu.driver.renderer.tiles.as_ref().map(|t| t.stats),
            answers: readback.answers.clone(),
            notice: self.notice.clone(),
            saved: self.saved.clone(),
        };
        let painted = self.overlay.run(
            &self.window,
            &readings,
            &mut self.settings,
            (&mut self.actors, &mut self.fly),
            (&mut self.full_distance, &mut self.species),
        );
        let Actors {
            walkers, mowers, ..
        } = self.actors;
        self.walkers = self.walkers.with_count(walkers).with_mowers(mowers);
        if std::mem::take(&mut self.overlay.save_settings) {
            let path = self.screenshot_dir.join("grass-settings.toml");
            let viewer = crate::config::ViewerState {
                full_distance: self.full_distance,
                ball: self.actors.ball,
                walkers: self.walkers.count(),
                mowers: self.walkers.mowers(),
                ball_cuts: self.actors.ball_cuts,
                species: self.species,
            };
            let text = crate::config::current(&self.common, &self.settings, &viewer);
            let written = crate::files::write(&path, text.as_bytes());
            self.saved = Some(said(
                written.map(|()| path),
                "settings saved (--config reads them)",
                "settings not saved",
            ));
        }
        if let (Some(d), Some(tiles)) =
            (self.full_distance, self.gpu.driver.renderer.tiles.as_mut())
        {
            tiles.set_full_distance(d);
        }
        let balls: Vec<_> = self
            .ball
            .iter()
            .filter(|_| self.actors.ball)
            .map(Ball::sphere)
            .collect();
        let eye = self.camera.viewpoint(frame.extent());
        let asked = self.ball.filter(|_| self.actors.ask && self.actors.ball);
        let questions = asked.map_or(vec![], |b| b.questions(eye.position).to_vec());
        let spec = FrameSpec {
            request: self
                .settings
                .request(&eye, &balls)
                .with_balls_cutting(self.actors.ball_cuts)
                .with_colliders(
                    &self
                        .walkers
                        .colliders(&self.scene, frame.time, frame.seconds()),
                )
                .with_impulses(&self.impulses)
                .with_questions(&questions)
                .with_contacts(!questions.is_empty()),
            overlay: painted.as_ref().map(|p| OverlayFrame {
                changed: p.changed,
                primitives: &p.primitives,
                textures: &p.textures,
                pixels_per_point: p.pixels_per_point,
                opaque: p.opaque,
            }),
            capture: self.gpu.presenter.screenshot,
        };
        let gpu = &mut self.gpu;
        let screenshot = gpu.presenter.screenshot;
        gpu.driver.submit(frame, &mut gpu.presenter, spec)?;
        if screenshot {
            gpu.driver.finish()?;
            // A screenshot that cannot be written is said, never the end of the viewer.
            let saved = gpu.presenter.save_screenshot(&self.screenshot_dir);
            self.saved = Some(said(saved, "screenshot", "screenshot not saved"));
        }
        if self.pace.drawn() {
            self.report();
        }
        Ok(())
    }

    /// Once a second: frame rate and visible blades in the title and the log.
    fn report(&mut self) {
        let readback = &self.gpu.driver.readback;
        // The hardware's blades and the compute rasterizer's.
        let visible = readback.counts.map_or(0, |c| c.drawn + c.compute);
        let line = format!(
            "{:.1} fps, {visible} of {} blades visible, {}, wind {:?}, shape {:?}",
            self.pace.fps,
            self.scene.blade_count(),
            self.scene.name,
            self.settings.wind.field,
            self.settings.shape,
        );
        self.window.set_title(&format!("grass: {line}"));
        log::info!("{line}");
        if let Some(counts) = self.gpu.driver.readback.counts {
            log::info!("{}", super::render::describe(&counts));
        }
        log::debug!("pass times {:?}", self.gpu.driver.readback.times);
    }

    /// One turn of the event loop under `--resize-storm`: the next scripted change.
    fn blow(&mut self) {
        let Some(storm) = self.storm.as_mut() else {
            return;
        };
        let gust = storm.tick();
        if storm.restored() {
            self.window.set_minimized(false);
            log::info!("storm: restored");
        }
        let Some(gust) = gust else { return };
        log::info!("storm: {gust:?}");
        match gust {
            Gust::Resize(w, h) => {
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
            Gust::Burst(w, h) => {
                let _ = self.window.request_inner_size(PhysicalSize::new(h, w));
                let _ = self.window.request_inner_size(PhysicalSize::new(w, h));
            }
            Gust::Minimise => self.window.set_minimized(true),
            Gust::Zero => {}
        }
        // Whatever the window system makes of it, the next frame checks the surface.
        self.gpu.presenter.recreate = true;
    }

    /// Moves the ball along its path (to where it is at simulated time `time`), or by
    /// the arrow keys (relative to the camera).
    fn move_ball(&mut self, dt: f32, time: f32) {
        let axis = self.arrows.axis();
        if self.fly.on {
            let solid = &self.scene.solid;
            let ground = |x, z| drop_onto(solid, Vec2::new(x, z)).map(|c| c.position.y);
            self.fly.step(&mut self.camera, axis, dt.min(0.1), ground);
            return;
        }
        let Some(ball) = self.ball.as_mut() else {
            return;
        };
        if axis != Vec2::ZERO {
            // A key takes over from the path.
            self.common.collider_path = None;
            let (sin, cos) = self.camera.yaw.sin_cos();
            let right = Vec3::new(cos, 0.0, -sin);
            let forward = Vec3::new(-sin, 0.0, -cos);
            let speed = self.common.collider_speed.max(0.5) * dt.min(0.1);
            ball.slide(
                &self.scene.solid,
                (right * axis.x + forward * axis.y) * speed,
            );
        } else if let Some(path) = &self.common.collider_path {
            let travelled = self.common.collider_speed * time;
            if let Some(contact) = drop_onto(&self.scene.solid, path.at(travelled)) {
                ball.contact = contact;
            }
        }
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_none() {
            match Running::new(event_loop, &self.common, &self.args, self.file.take()) {
                Ok(state) => self.state = Some(state),
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        // The overlay sees events first; what it uses does not move the camera.
        let used = state.overlay.on_event(&state.window, &event);
        let input = matches!(
            event,
            WindowEvent::KeyboardInput { .. }
                | WindowEvent::MouseInput { .. }
                | WindowEvent::MouseWheel { .. }
                | WindowEvent::CursorMoved { .. }
        );
        if used && input {
            // Keep the camera from sticking in a drag that ended over the overlay.
            if matches!(event, WindowEvent::MouseInput { .. }) {
                state.mouse.rotating = false;
                state.mouse.panning = false;
            }
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed
                    && event.logical_key == Key::Named(NamedKey::Escape) =>
            {
                event_loop.exit()
            }
            WindowEvent::KeyboardInput { event, .. } => match event.state {
                ElementState::Pressed if !event.repeat => state.key(&event.logical_key),
                ElementState::Pressed => {}
                ElementState::Released => state.key_up(&event.logical_key),
            },
            WindowEvent::Focused(false) => state.arrows = Arrows::default(),
            WindowEvent::ModifiersChanged(m) => state.mouse.modifiers = m.state(),
            WindowEvent::Resized(_) => state.gpu.presenter.recreate = true,
            WindowEvent::MouseInput {
                state: pressed,
                button,
                ..
            } => {
                let down = pressed == ElementState::Pressed;
                match button {
                    MouseButton::Left => state.mouse.rotating = down,
                    MouseButton::Right | MouseButton::Middle => state.mouse.panning = down,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => state.mouse_moved(position.x, position.y),
            WindowEvent::CursorLeft { .. } => state.mouse.last = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                state.camera.zoom(steps);
            }
            WindowEvent::RedrawRequested => {
                let result = match state.frame() {
                    Err(e) if device_lost(&e) => state.recover(e),
                    other => other,
                };
                if let Err(e) = result {
                    self.error = Some(e);
                    event_loop.exit();
                } else if self.args.frames.is_some_and(|n| state.pace.frames >= n) {
                    event_loop.exit();
                } else if self.args.screenshot_at.contains(&state.pace.frames) {
                    state.gpu.presenter.screenshot = true;
                }
            }
            _ => {}
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            let gusts = state.storm.as_ref().map_or(0, |s| s.gusts);
            log::info!(
                "{} frames drawn, {} window targets made, {gusts} storm gusts",
                state.pace.frames,
                state.gpu.presenter.swapchains
            );
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        state.blow();
        let size = state.size();
        if size.width == 0 || size.height == 0 {
            // Minimised: sleep until an event instead of spinning on empty frames (the
            // storm has no event to wait for, only its next tick).
            event_loop.set_control_flow(match state.storm {
                Some(_) => ControlFlow::wait_duration(std::time::Duration::from_millis(16)),
                None => ControlFlow::Wait,
            });
        } else {
            event_loop.set_control_flow(ControlFlow::Poll);
            state.window.request_redraw();
        }
    }
}

//! The viewer's overlay (egui): frame rate and a frame-time graph, GPU time per pass,
//! the blade counts of each culling test, and every live setting as a control
//! (`controls`).

use crate::answers::Answers;
use crate::camera::Fly;
use crate::passes::tiles::PoolStats;
use crate::renderer::{CullCounts, PassTimes};
use egui::{ClippedPrimitive, Color32, Stroke, TexturesDelta};
use shared::settings::Settings;
use shared::species::Mix;
use std::collections::VecDeque;
use std::time::{Duration, Instant};
use winit::event::WindowEvent;
use winit::window::Window;

mod controls;
pub use controls::{AA_CHOICES, Actors, aa_name, next_aa};

/// Frames in the frame-time graph.
const HISTORY: usize = 240;

/// How often the readings (frame rate, graph, pass times, counts) refresh while
/// nothing else changes the overlay. Between runs of the interface its last picture
/// is kept and laid over each frame (`passes::overlay`): a software device then
/// draws the interface twice a second, not every frame.
pub const REFRESH: Duration = Duration::from_millis(500);

/// What the overlay shows besides the settings.
pub struct Readings {
    /// Frames per second over the last second.
    pub fps: f64,
    /// Blades in the field.
    pub blades: u32,
    /// The newest counts read back.
    pub counts: Option<CullCounts>,
    /// The newest pass times read back.
    pub times: Option<PassTimes>,
    /// The scene has surfaces that can hide grass.
    pub occluders: bool,
    /// A tiled field's pool, as the last frame left it.
    pub pool: Option<PoolStats>,
    /// The answers of the newest frame read back (the ball's, where asked).
    pub answers: Answers,
    /// Something the user should know, shown above everything (a device made again).
    pub notice: Option<String>,
    /// What became of the last screenshot or settings file: where it went, or why it
    /// was not written (`true`).
    pub saved: Option<(String, bool)>,
}

/// What the overlay says of a file written (`saved`: its path) or not (why), also
/// logged: `(message, failed)`.
pub fn said(saved: anyhow::Result<std::path::PathBuf>, done: &str, failed: &str) -> (String, bool) {
    match saved {
        Ok(path) => {
            let message = format!("{done}: {}", path.display());
            log::info!("{message}");
            (message, false)
        }
        Err(e) => {
            let message = format!("{failed}: {e:#}");
            log::warn!("{message}");
            (message, true)
        }
    }
}

/// egui's output for one frame, ready for the overlay pass.
pub struct Painted {
    /// egui ran this frame: `primitives` replace the overlay's last picture. When
    /// false the picture is kept and `primitives` and `textures` are empty.
    pub changed: bool,
    /// Tessellated meshes.
    pub primitives: Vec<ClippedPrimitive>,
    /// Texture changes.
    pub textures: TexturesDelta,
    /// Pixels per point.
    pub pixels_per_point: f32,
    /// Where the picture is opaque (the window's fill, in points): the pass copies
    /// these pixels instead of blending them (`passes::overlay`).
    pub opaque: Option<egui::Rect>,
}

/// egui state of the viewer's window.
pub struct Overlay {
    ctx: egui::Context,
    state: egui_winit::State,
    /// Shown (toggled with O).
    pub visible: bool,
    frame_ms: VecDeque<f32>,
    /// The device's name, shown with the frame rate.
    device: String,
    /// The "save settings" button was pressed (the viewer writes the file and clears
    /// this).
    pub save_settings: bool,
    /// A wind impulse's button was pressed: its kind (the viewer starts it at the
    /// ball and clears this).
    pub blow: Option<u32>,
    /// egui took an event that asks for a new picture since it last ran.
    input: bool,
    /// When egui last ran and what it showed then besides the readings.
    last: Option<(Instant, Shown)>,
    /// When egui asked to run again (an animation), if it did.
    repaint_at: Option<Instant>,
}

/// What the overlay shows that can change between its refreshes: a change runs the
/// interface at once.
#[derive(Clone, PartialEq)]
struct Shown {
    settings: Settings,
    actors: Actors,
    fly: Fly,
    full_distance: Option<f32>,
    species: Mix,
    notice: Option<String>,
    saved: Option<(String, bool)>,
    size: (u32, u32),
}

impl Overlay {
    /// The overlay of `window` drawn by `device` (its name), shown.
    pub fn new(window: &Window, device: String) -> Self {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        Self {
            ctx,
            state,
            visible: true,
            frame_ms: VecDeque::with_capacity(HISTORY),
            device,
            save_settings: false,
            blow: None,
            input: false,
            last: None,
            repaint_at: None,
        }
    }

    /// Passes a window event to egui; true when egui used it (the pointer is over
    /// the overlay, or a control has the keyboard), so the camera should not.
    pub fn on_event(&mut self, window: &Window, event: &WindowEvent) -> bool {
        if !self.visible {
            return false;
        }
        let response = self.state.on_window_event(window, event);
        // egui asks for a picture on every redraw request: only input counts.
        self.input |= response.repaint && !matches!(event, WindowEvent::RedrawRequested);
        response.consumed
            || self.ctx.egui_wants_pointer_input()
            || self.ctx.egui_wants_keyboard_input()
    }

    /// Adds a frame's duration to the graph.
    pub fn frame_time(&mut self, ms: f32) {
        if self.frame_ms.len() == HISTORY {
            self.frame_ms.pop_front();
        }
        self.frame_ms.push_back(ms);
    }

    /// Runs the interface for one frame when its picture is due (input for it, an
    /// animation, a changed setting or message, the window's size, or [`REFRESH`]
    /// passed): shows `readings`, lets the user edit `settings` and `actors`, and
    /// returns what to paint (nothing when hidden; the last picture kept when not due).
    pub fn run(
        &mut self,
        window: &Window,
        readings: &Readings,
        settings: &mut Settings,
        (actors, fly): (&mut Actors, &mut Fly),
        (full_distance, species): (&mut Option<f32>, &mut Mix),
    ) -> Option<Painted> {
        if !self.visible {
            self.last = None;
            return None;
        }
        let now = Instant::now();
        let size = window.inner_size();
        let shown = |settings: &Settings, actors: Actors, fly: Fly, full_distance, species| Shown {
            settings: *settings,
            actors,
            fly,
            full_distance,
            species,
            notice: readings.notice.clone(),
            saved: readings.saved.clone(),
            size: (size.width, size.height),
        };
        let before = shown(settings, *actors, *fly, *full_distance, *species);
        let due = self.input
            || self.repaint_at.is_some_and(|at| now >= at)
            || self
                .last
                .as_ref()
                .is_none_or(|(at, was)| now.duration_since(*at) >= REFRESH || *was != before);
        if !due {
            return Some(Painted {
                changed: false,
                primitives: Vec::new(),
                textures: TexturesDelta::default(),
                pixels_per_point: 1.0,
                opaque: None,
            });
        }
        self.input = false;
        let input = self.state.take_egui_input(window);
        let frame_ms: &[f32] = self.frame_ms.make_contiguous();
        let mut save = false;
        let mut blow = None;
        let mut window_rect = None;
        let output = self.ctx.run_pass(input, |ctx| {
            let shown = panel().show(ctx, |ui| {
                performance(ui, readings, &self.device, frame_ms);
                counts(ui, readings);
                answers(ui, readings);
                tiles(ui, readings, fly, full_distance, &mut settings.far_sway);
                species_mix(ui, species);
                controls::controls(ui, settings, actors, &mut blow);
                ui.separator();
                save |= ui
                    .button("save settings (grass-settings.toml)")
                    .on_hover_text("read back with --config grass-settings.toml")
                    .clicked();
            });
            window_rect = shown.map(|s| s.response.rect);
        });
        self.save_settings |= save;
        self.blow = blow.or(self.blow);
        self.state
            .handle_platform_output(window, output.platform_output);
        let delay = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        self.repaint_at = now.checked_add(delay);
        self.last = Some((
            now,
            shown(settings, *actors, *fly, *full_distance, *species),
        ));
        let pixels_per_point = output.pixels_per_point;
        let primitives = self.ctx.tessellate(output.shapes, pixels_per_point);
        let opaque = window_rect.and_then(|rect| opaque_part(&self.ctx.global_style(), rect));
        Some(Painted {
            changed: true,
            primitives,
            textures: output.textures_delta,
            pixels_per_point,
            opaque,
        })
    }
}

/// The overlay's window, at the top left. It appears at once, not fading in: its
/// fill is opaque from the first frame ([`opaque_part`]).
pub fn panel() -> egui::Window<'static> {
    egui::Window::new("grass")
        .default_pos([12.0, 12.0])
        .default_width(300.0)
        .fade_in(false)
}

/// The part of a window of `rect` that its fill covers opaquely: inside its rounded
/// corners and its stroke, when the style's fill is opaque. Whatever egui draws there
/// lies on that fill (a popup too), so the picture is opaque there.
pub fn opaque_part(style: &egui::Style, rect: egui::Rect) -> Option<egui::Rect> {
    let v = &style.visuals;
    if v.window_fill.a() < 255 {
        return None;
    }
    let r = v.window_corner_radius;
    let inset = f32::from(r.nw.max(r.ne).max(r.sw).max(r.se)) + v.window_stroke.width + 1.0;
    Some(rect.shrink(inset)).filter(|r| r.is_positive())
}

/// FPS, the frame-time graph and GPU time per pass.
fn performance(ui: &mut egui::Ui, r: &Readings, device: &str, frame_ms: &[f32]) {
    if let Some(notice) = &r.notice {
        ui.colored_label(Color32::from_rgb(255, 170, 60), notice);
    }
    if let Some((said, failed)) = &r.saved {
        let colour = if *failed {
            Color32::from_rgb(255, 90, 80)
        } else {
            Color32::from_rgb(150, 220, 150)
        };
        ui.colored_label(colour, said);
    }
    let last = frame_ms.last().copied().unwrap_or(0.0);
    ui.label(format!("{:.1} fps, {last:.2} ms ({device})", r.fps));
    let top = frame_ms.iter().copied().fold(1000.0 / 30.0, f32::max);
    let (response, painter) =
        ui.allocate_painter(egui::vec2(ui.available_width(), 60.0), egui::Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_black_alpha(120));
    let at = |i: usize, ms: f32| {
        egui::pos2(
            rect.left() + rect.width() * i as f32 / (HISTORY - 1) as f32,
            rect.bottom() - rect.height() * (ms / top).min(1.0),
        )
    };
    // 60 fps line.
    let y = at(0, 1000.0 / 60.0).y;
    painter.line_segment(
        [egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
        Stroke::new(1.0, Color32::from_gray(110)),
    );
    let points: Vec<_> = frame_ms
        .iter()
        .enumerate()
        .map(|(i, &ms)| at(i, ms))
        .collect();
    painter.add(egui::Shape::line(
        points,
        Stroke::new(1.5, Color32::LIGHT_GREEN),
    ));
    ui.label(format!(
        "graph: last {HISTORY} frames, top {top:.0} ms, grey line 60 fps"
    ));
    match r.times {
        Some(t) => {
            egui::Grid::new("passes").num_columns(2).show(ui, |ui| {
                let total = [("GPU total", t.total)];
                let rows = t.named().into_iter().chain(total);
                for (name, ms) in rows {
                    ui.label(name);
                    ui.label(format!("{ms:.3} ms"));
                    ui.end_row();
                }
            });
        }
        None => {
            ui.label("GPU timestamps: not available on this device");
        }
    }
}

/// Blades in the field, drawn, and removed by each test.
fn counts(ui: &mut egui::Ui, r: &Readings) {
    ui.separator();
    let Some(c) = r.counts else {
        ui.label(format!("{} blades", r.blades));
        return;
    };
    let share = |n: u32| 100.0 * f64::from(n) / f64::from(c.examined.max(1));
    egui::Grid::new("counts").num_columns(3).show(ui, |ui| {
        ui.label("blades");
        ui.label(c.examined.to_string());
        ui.label("");
        ui.end_row();
        for (name, n) in c.by_test() {
            ui.label(format!("removed by {name}"));
            ui.label(n.to_string());
            ui.label(format!("{:.1} %", share(n)));
            ui.end_row();
        }
        ui.label("drawn");
        ui.label(c.drawn.to_string());
        ui.label(format!("{:.1} %", share(c.drawn)));
        ui.end_row();
        ui.label("drawn by compute");
        ui.label(c.compute.to_string());
        ui.label(format!("{:.1} %", share(c.compute)));
        ui.end_row();
        if c.compute > 0 {
            ui.label("their pixels written");
            ui.label(c.raster_written.to_string());
            ui.label(format!("of {} covered", c.raster_covered));
            ui.end_row();
        }
    });
    if !r.occluders {
        ui.label("(flat ground, no rock: nothing here can occlude)");
    }
}

/// The answers about the ball (`Ball::questions`), where the frame asked: the grass
/// around it, how hidden it is, whether it touches the grass.
fn answers(ui: &mut egui::Ui, r: &Readings) {
    let [(_, around), (_, sight)] = r.answers.answers.as_slice() else {
        return;
    };
    ui.separator();
    ui.label(format!(
        "around the ball: {} blades, {:.2} tall, bent {:.0} %",
        around.blades,
        around.mean_height(),
        100.0 * around.mean_bend()
    ));
    let touching = if r.answers.contacts.touching(0) {
        "touching the grass, "
    } else {
        ""
    };
    ui.label(format!(
        "the ball: {touching}{:.0} % hidden from the camera",
        100.0 * sight.concealment()
    ));
}

/// A tiled field's far tiles and pool, the distance every blade is kept within,
/// whether the far blades sway, and flying.
fn tiles(
    ui: &mut egui::Ui,
    r: &Readings,
    fly: &mut Fly,
    full_distance: &mut Option<f32>,
    far_sway: &mut bool,
) {
    ui.separator();
    if let Some(d) = full_distance {
        ui.add(
            egui::Slider::new(d, 1.0..=200.0)
                .logarithmic(true)
                .text("every blade kept within (units)"),
        );
        ui.checkbox(far_sway, "far blades sway with the wind");
    }
    if let (Some(pool), Some(c)) = (r.pool, r.counts) {
        egui::Grid::new("tiles").num_columns(2).show(ui, |ui| {
            let rows = [
                ("far tiles in view", c.far_tiles.to_string()),
                ("their blades", c.far_blades.to_string()),
                ("far tiles short of room", c.tiles_short.to_string()),
                ("tiles hidden (occlusion)", c.tiles_hidden.to_string()),
                (
                    "pool tiles held",
                    format!("{} of {}", pool.held, pool.slots),
                ),
                ("placed this frame", pool.placed.to_string()),
                ("evicted, all told", pool.evictions.to_string()),
                ("needed, no slot", pool.dropped.to_string()),
                ("kept by a trail", pool.pinned.to_string()),
            ];
            for (name, value) in rows {
                ui.label(name);
                ui.label(value);
                ui.end_row();
            }
        });
    }
    ui.horizontal(|ui| {
        ui.checkbox(&mut fly.on, "fly with the arrows (F)");
        ui.add(
            egui::Slider::new(&mut fly.speed, Fly::SPEEDS.0..=Fly::SPEEDS.1)
                .logarithmic(true)
                .text("units/s (+ -)"),
        );
    });
}

/// The species the field grows: a weight for each (`shared::species::Mix`); a change
/// grows the field again.
fn species_mix(ui: &mut egui::Ui, mix: &mut Mix) {
    use shared::species::{COUNT, NAMES};
    ui.collapsing("species", |ui| {
        let mut weights = mix.weights.to_le_bytes();
        // Grass only is grass at weight 1.
        if mix.weights == 0 {
            weights[0] = 1;
        }
        for k in 0..COUNT as usize {
            ui.add(egui::Slider::new(&mut weights[k], 0..=255).text(NAMES[k]))
                .on_hover_text("the share of blades of this species, where no type map picks one");
        }
        *mix = Mix::new(weights);
    });
}

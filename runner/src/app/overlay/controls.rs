//! The overlay's controls: the look, the culling tests, LOD and view, the wind and
//! its impulses, the forces, the blade shape, the ball and the walkers.

use shared::settings::{
    Antialiasing, BladeShape, GrassPipeline, Look, MIN_RENDER_SCALE, SHADOW_SIZES, Settings, View,
    WindField,
};
use shared::sim::impulse::{IMPULSE_BLAST, IMPULSE_DOWNWASH};

/// What moves through the grass besides the wind: the ball and the walkers.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Actors {
    /// The ball is on (B).
    pub ball: bool,
    /// Walkers wandering the ground (`--walkers`).
    pub walkers: u32,
    /// Mowers cutting the grass (`--mowers`).
    pub mowers: u32,
    /// The ball cuts the grass (C; `--ball-cuts`).
    pub ball_cuts: bool,
    /// Ask the grass about the ball each frame (`shared::query`): the overlay shows
    /// the answers.
    pub ask: bool,
}

impl Actors {
    /// As the command line asks.
    pub fn of(common: &crate::cli::Common) -> Self {
        Self {
            ball: !common.no_ball,
            walkers: common.walkers,
            mowers: common.mowers,
            ball_cuts: common.ball_cuts,
            ask: false,
        }
    }
}

/// The culling tests, LOD, view, wind, forces, shape, ball and walkers.
pub(super) fn controls(
    ui: &mut egui::Ui,
    s: &mut Settings,
    actors: &mut Actors,
    blow: &mut Option<u32>,
) {
    egui::CollapsingHeader::new("Look (keys N, H, M)")
        .default_open(true)
        .show(ui, |ui| look(ui, s));
    egui::CollapsingHeader::new("Culling (keys 1-4)")
        .default_open(true)
        .show(ui, |ui| culling(ui, s));
    egui::CollapsingHeader::new("Pipeline, level of detail and view")
        .default_open(false)
        .show(ui, |ui| detail(ui, s));
    egui::CollapsingHeader::new("Wind, forces, shape, ball, walkers")
        .default_open(false)
        .show(ui, |ui| forces(ui, s, actors, blow));
    ui.label("O hides this panel");
}

fn look(ui: &mut egui::Ui, s: &mut Settings) {
    let look = &mut s.look;
    ui.horizontal(|ui| {
        ui.label("look (N)");
        for style in Look::ALL {
            ui.radio_value(&mut look.style, style, format!("{style:?}"));
        }
    });
    let natural = look.style == Look::Natural;
    ui.add_enabled(
        natural,
        egui::Checkbox::new(&mut look.shadows, "sun shadows (H)"),
    );
    ui.add_enabled_ui(natural && look.shadows, |ui| {
        ui.horizontal(|ui| {
            ui.label("shadow map");
            for n in SHADOW_SIZES {
                ui.radio_value(&mut look.shadow_size, n, n.to_string());
            }
        })
    });
    // A list, not a row of five buttons: the row widened the panel over the scene.
    let current = aa_name(look.aa, look.msaa);
    egui::ComboBox::from_label("anti-aliasing (M)")
        .selected_text(current.clone())
        .show_ui(ui, |ui| {
            for (aa, samples) in AA_CHOICES {
                let name = aa_name(aa, samples);
                if ui.selectable_label(name == current, name).clicked() {
                    look.aa = aa;
                    if aa == Antialiasing::Msaa {
                        look.msaa = samples;
                    }
                }
            }
        });
    ui.add(
        egui::Slider::new(&mut look.render_scale, MIN_RENDER_SCALE..=1.0)
            .step_by(0.05)
            .text("render scale"),
    )
    .on_hover_text("the scene drawn at this share of the window's width and height");
    ui.add_enabled(
        natural,
        egui::Slider::new(&mut look.exposure, 0.05..=8.0)
            .logarithmic(true)
            .text("exposure"),
    );
    ui.add_enabled(
        natural,
        egui::Slider::new(&mut look.fog_density, 0.0..=0.05).text("fog density"),
    );
    ui.add_enabled(
        natural,
        egui::Slider::new(&mut look.clump_size, 0.2..=20.0)
            .logarithmic(true)
            .text("clump size"),
    );
}

/// The anti-aliasing the overlay and the M key offer: (method, samples of
/// multisampling).
pub const AA_CHOICES: [(Antialiasing, u32); 5] = [
    (Antialiasing::None, 1),
    (Antialiasing::Taa, 1),
    (Antialiasing::Msaa, 2),
    (Antialiasing::Msaa, 4),
    (Antialiasing::Msaa, 8),
];

/// The choice's name: `none`, `TAA`, `MSAA 4x`.
pub fn aa_name(aa: Antialiasing, samples: u32) -> String {
    match aa {
        Antialiasing::None => "none".into(),
        Antialiasing::Taa => "TAA".into(),
        Antialiasing::Msaa => format!("MSAA {samples}x"),
    }
}

/// The choice after the settings' `aa` and `msaa` in [`AA_CHOICES`], round to the
/// first.
pub fn next_aa(aa: Antialiasing, msaa: u32) -> (Antialiasing, u32) {
    let at = AA_CHOICES
        .iter()
        .position(|&(a, n)| a == aa && (a != Antialiasing::Msaa || n == msaa));
    AA_CHOICES[at.map_or(0, |i| (i + 1) % AA_CHOICES.len())]
}

fn culling(ui: &mut egui::Ui, s: &mut Settings) {
    let c = &mut s.cull;
    ui.horizontal_wrapped(|ui| {
        for (name, on) in c.tests.named_mut() {
            ui.checkbox(on, name);
        }
    });
    ui.add(
        egui::Slider::new(&mut c.orientation_threshold, 0.0..=1.0).text("orientation threshold"),
    );
    ui.add(egui::Slider::new(&mut c.edge_on_pixels, 0.0..=16.0).text("edge-on pixels"))
        .on_hover_text("an edge-on blade is removed only where it is narrower than this; 0: every one (the paper)");
    ui.add(egui::Slider::new(&mut c.frustum_tolerance, 0.0..=2.0).text("frustum tolerance"));
    ui.add(
        egui::Slider::new(&mut c.max_distance, 1.0..=1000.0)
            .logarithmic(true)
            .text("max distance"),
    );
    ui.add(egui::Slider::new(&mut c.buckets, 1..=32).text("distance buckets"));
}

fn detail(ui: &mut egui::Ui, s: &mut Settings) {
    ui.horizontal(|ui| {
        ui.label("pipeline (P)");
        ui.radio_value(&mut s.pipeline, GrassPipeline::Tess, "tessellation");
        ui.radio_value(&mut s.pipeline, GrassPipeline::Mesh, "mesh");
    });
    let lod = &mut s.lod;
    ui.checkbox(&mut lod.on, "level of detail (L)");
    ui.add(egui::Slider::new(&mut lod.most, 1.0..=shared::cull::lod::MAX_LEVEL).text("level near"));
    ui.add(
        egui::Slider::new(&mut lod.fewest, 1.0..=shared::cull::lod::MAX_LEVEL).text("level far"),
    );
    ui.add(
        egui::Slider::new(&mut lod.pixels_per_segment, 1.0..=200.0)
            .logarithmic(true)
            .text("pixels per segment"),
    );
    ui.add(
        egui::Slider::new(&mut s.compute_raster_below, 0.0..=64.0)
            .text("compute-raster blades below (pixels; 0 off)"),
    );
    ui.horizontal(|ui| {
        ui.label("view (V)");
        for view in View::ALL {
            ui.radio_value(&mut s.view, view, format!("{view:?}"));
        }
    });
}

fn forces(ui: &mut egui::Ui, s: &mut Settings, actors: &mut Actors, blow: &mut Option<u32>) {
    let wind = &mut s.wind;
    egui::ComboBox::from_label("wind (W)")
        .selected_text(format!("{:?}", wind.field))
        .show_ui(ui, |ui| {
            for w in WindField::ALL {
                ui.selectable_value(&mut wind.field, w, format!("{w:?}"));
            }
        });
    ui.add(egui::Slider::new(&mut wind.strength, 0.0..=30.0).text("wind strength"));
    ui.add(egui::Slider::new(&mut wind.direction, -180.0..=180.0).text("wind direction °"));
    if wind.field == WindField::Turbulent {
        ui.add(egui::Slider::new(&mut wind.gust_speed, 0.0..=30.0).text("gust speed"));
    }
    ui.add(
        egui::Slider::new(&mut s.stiffness, 0.0..=100.0)
            .logarithmic(true)
            .text("stiffness ×"),
    );
    ui.add(egui::Slider::new(&mut s.gravity.acceleration, 0.0..=30.0).text("gravity"));
    ui.horizontal(|ui| {
        ui.label("wind impulse at the ball");
        if ui.button("blast (X)").clicked() {
            *blow = Some(IMPULSE_BLAST);
        }
        if ui.button("downwash (R)").clicked() {
            *blow = Some(IMPULSE_DOWNWASH);
        }
    });

    ui.separator();
    egui::ComboBox::from_label("blade shape (S)")
        .selected_text(format!("{:?}", s.shape))
        .show_ui(ui, |ui| {
            for shape in BladeShape::ALL {
                ui.selectable_value(&mut s.shape, shape, format!("{shape:?}"));
            }
        });
    ui.add(egui::Slider::new(&mut s.tip_start, 0.0..=1.0).text("tip start"));
    ui.checkbox(&mut actors.ball, "ball (B)");
    ui.checkbox(&mut actors.ask, "ask the grass about the ball")
        .on_hover_text(
            "with the ball on (B): the blades around it, how hidden it is from the camera \
             (grass query)",
        );
    let most = crate::walkers::MAX_WALKERS;
    ui.add(egui::Slider::new(&mut actors.walkers, 0..=most).text("walkers"))
        .on_hover_text("capsules the size of people wandering the ground (--walkers)");
    ui.checkbox(&mut actors.ball_cuts, "ball cuts (C)")
        .on_hover_text("the ball cuts the grass it rolls over (--ball-cuts)");
    let mowers = crate::walkers::MAX_MOWERS;
    ui.add(egui::Slider::new(&mut actors.mowers, 0..=mowers).text("mowers"))
        .on_hover_text("boxes driving the walkers' ground, cutting the grass (--mowers)");
    ui.add(
        egui::Slider::new(&mut s.regrow, 0.1..=600.0)
            .logarithmic(true)
            .text("regrow s"),
    )
    .on_hover_text("seconds cut grass takes to grow back (--regrow)");
}

//! The options every command takes (`Common`: the scene, the field, the look and the
//! culling), which of them were given, and their parsers.

use crate::collider::ColliderPath;
use crate::parse::{parse_coordinates, range};
use crate::scene::{BladeCount, SceneKind};
use crate::vulkan::ValidationChecks;
use clap::{Args, ValueEnum};
use glam::Vec3;
use shared::settings::{
    Antialiasing, BladeShape, CullTests, Look, LookSettings, MIN_RENDER_SCALE, View, WindField,
};
use std::path::PathBuf;

/// Where a field's blades come from (`--field`).
#[derive(ValueEnum, Copy, Clone, Debug, PartialEq, Eq)]
pub enum FieldChoice {
    /// Generated once and stored, every blade simulated.
    Stored,
    /// Generated from tiles every frame; a pool of near tiles simulated.
    Tiles,
}

/// Which options were given, by long name: on the command line itself, or by a
/// settings file (`--config`). An option that does not apply where it is given is
/// refused when typed, and noted in the log when it comes from a file (a settings file
/// saved from the viewer serves every command).
#[derive(Clone, Debug, Default)]
pub struct Given {
    /// Given on the command line.
    pub command_line: std::collections::BTreeSet<String>,
    /// Set by the settings file.
    pub file: std::collections::BTreeSet<String>,
}

impl Given {
    /// Each of `options` given here does not apply, for the reason `why` ("soak cycles
    /// it itself"): an error naming the first typed on the command line; those from the
    /// settings file are noted in the log.
    pub fn refuse(&self, options: &[&str], why: &str) -> anyhow::Result<()> {
        if let Some(option) = options.iter().find(|o| self.command_line.contains(**o)) {
            anyhow::bail!("--{option}: {why}");
        }
        for option in options.iter().filter(|o| self.file.contains(**o)) {
            log::warn!("settings file: `{option}` not used: {why}");
        }
        Ok(())
    }
}

/// Adds the long names of the options `matches` of `command` took from the command line.
pub(crate) fn typed(
    matches: &clap::ArgMatches,
    command: &clap::Command,
    out: &mut std::collections::BTreeSet<String>,
) {
    for arg in command.get_arguments() {
        let id = arg.get_id().as_str();
        if matches.value_source(id) == Some(clap::parser::ValueSource::CommandLine) {
            out.extend(arg.get_long().map(str::to_owned));
        }
    }
    if let Some((name, sub)) = matches.subcommand()
        && let Some(command) = command.find_subcommand(name)
    {
        typed(sub, command, out);
    }
}

/// Options every command takes.
#[derive(Args, Debug, Clone)]
pub struct Common {
    /// Which options were given, and where (filled in after parsing).
    #[arg(skip)]
    pub given: Given,
    /// Read settings from this TOML file, keys named like the flags
    /// (`wind-strength = 7.0`; `grass config` prints them all); flags given on the
    /// command line override the file's.
    #[arg(long, global = true)]
    pub config: Option<PathBuf>,
    /// Number of blades, spread over the surface by area [default: 131072 on a GPU,
    /// 2048 on a software device].
    #[arg(long, global = true, value_parser = clap::value_parser!(u32).range(1..=(1 << 26)))]
    pub blades: Option<u32>,
    /// Blades per square unit of surface, instead of a total count.
    #[arg(long, global = true, conflicts_with = "blades", value_parser = parse_density)]
    pub density: Option<f32>,
    /// Surface: plane, hills, planet, meadow (the glTF scene in assets/), walls (stone
    /// walls hiding grass: occlusion culling), valley (2 km, tiled), or a .gltf, .glb
    /// or .obj file.
    #[arg(long, global = true, default_value = "plane")]
    pub scene: String,
    /// Where the blades come from: `stored` (generated once, every blade simulated:
    /// the paper's field) or `tiles` (generated from tiles every frame, the near ones
    /// simulated in a pool: a world of any size in bounded memory; any scene, a mesh's
    /// over its triangles) [default: tiles on the valley, stored elsewhere].
    #[arg(long, global = true, value_enum)]
    pub field: Option<FieldChoice>,
    /// A greyscale PNG laid over the scene's ground seen from above (its top row at
    /// −z), or on a tiled mesh with texture coordinates over those: white where every
    /// blade grows, black where none does.
    #[arg(long, global = true)]
    pub density_map: Option<PathBuf>,
    /// A greyscale PNG over the ground (as --density-map): each blade's height times
    /// twice its grey (mid grey keeps it) [tiled fields].
    #[arg(long, global = true)]
    pub height_map: Option<PathBuf>,
    /// A colour PNG over the ground (as --density-map): the natural look's blade
    /// colours times its colour (white keeps them) [tiled fields].
    #[arg(long, global = true)]
    pub colour_map: Option<PathBuf>,
    /// A greyscale PNG over the ground (as --density-map), what grows there by its
    /// grey: black (0) bare, 64 seed grass, 128 dandelions, 192 flowers, white the
    /// --species mix [tiled fields].
    #[arg(long, global = true)]
    pub type_map: Option<PathBuf>,
    /// Species mixed by weight where no type map picks one, e.g.
    /// "grass=6,flower=1,seed-grass=1" (grass, dandelion, flower, seed-grass; weights 0
    /// to 255) [default: grass only].
    #[arg(long, global = true, value_parser = parse_species)]
    pub species: Option<shared::species::Mix>,
    /// Wind field.
    #[arg(long, global = true, value_enum, default_value_t = WindField::Breeze)]
    pub wind: WindField,
    /// Wind strength (acceleration at full alignment).
    #[arg(long, global = true, default_value_t = 7.0, value_parser = range(0.0, 100.0))]
    pub wind_strength: f32,
    /// Wind direction in degrees around the vertical (0 = +X, 90 = +Z).
    #[arg(long, global = true, default_value_t = 19.3, allow_hyphen_values = true, value_parser = range(-360.0, 360.0))]
    pub wind_direction: f32,
    /// Speed of the turbulent wind's gusts downwind, units a second (`--wind
    /// turbulent`).
    #[arg(long, global = true, default_value_t = shared::sim::simulate::DEFAULT_GUST_SPEED, value_parser = range(0.0, 100.0))]
    pub gust_speed: f32,
    /// Pull gravity towards this point "x,y,z" instead of straight down (the planet
    /// scene does this around its centre).
    #[arg(long, global = true, allow_hyphen_values = true, value_parser = parse_point)]
    pub gravity_centre: Option<Vec3>,
    /// Blade shape.
    #[arg(long, global = true, value_enum, default_value_t = BladeShape::Quadratic)]
    pub shape: BladeShape,
    /// Where the triangle-tip shape starts narrowing, 0 (root) to 1 (tip).
    #[arg(long, global = true, default_value_t = 0.5, value_parser = range(0.0, 1.0))]
    pub tip_start: f32,
    /// A ball pressing through the grass along "x,z x,z ..." (scene units, dropped
    /// onto the surface).
    #[arg(long, global = true, allow_hyphen_values = true, value_parser = ColliderPath::parse)]
    pub collider_path: Option<ColliderPath>,
    /// Radius of the collider ball.
    #[arg(long, global = true, default_value_t = 1.5, value_parser = range(0.05, 100.0))]
    pub collider_radius: f32,
    /// Speed of the ball along its path, units per second.
    #[arg(long, global = true, default_value_t = 3.0, value_parser = range(0.0, 1000.0))]
    pub collider_speed: f32,
    /// Walkers: capsules the size of people (0.3 by 1.8 units) wandering the ground,
    /// each pushing the grass aside like the ball (in the valley, around the first 60
    /// units of its path).
    #[arg(long, global = true, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=i64::from(crate::walkers::MAX_WALKERS)))]
    pub walkers: u32,
    /// Mowers (0 to 64): boxes 1.2 wide driving over the walkers' ground that cut the
    /// grass 0.1 above it; it grows back over --regrow seconds.
    #[arg(long, global = true, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=i64::from(crate::walkers::MAX_MOWERS)))]
    pub mowers: u32,
    /// The ball cuts the grass it rolls over instead of pressing it down.
    #[arg(long, global = true)]
    pub ball_cuts: bool,
    /// Seconds cut grass takes to grow back to its height.
    #[arg(long, global = true, default_value_t = shared::sim::simulate::DEFAULT_REGROW, value_parser = range(0.1, 3600.0))]
    pub regrow: f32,
    /// How fast trampled grass gets its stiffness back: collision strength lost per
    /// second (strength 1 holds a blade down fully).
    #[arg(long, global = true, default_value_t = 0.25, value_parser = range(0.0, 100.0))]
    pub trample_decay: f32,
    /// Seed of the random field: the same seed gives the same blades.
    #[arg(long, global = true, default_value_t = 1)]
    pub seed: u64,
    /// Factor on every blade's stiffness (how fast it stands back up); the recovery is
    /// taken semi-implicitly, so blades settle at any factor.
    #[arg(long, global = true, default_value_t = 1.0, value_parser = range(0.0, 100.0))]
    pub stiffness: f32,
    /// Gravity's acceleration.
    #[arg(long, global = true, default_value_t = 9.8, value_parser = range(0.0, 100.0))]
    pub gravity: f32,
    /// Culling, level of detail and the grass view.
    #[command(flatten)]
    pub cull: CullArgs,
    /// The look: `paper` is the paper's Lambert blades on a flat sky (the reference
    /// images); `natural` adds clumps and colour, rounded leaves lit through, ambient
    /// occlusion, sun shadows, sky and fog, in linear HDR with a tone map.
    #[arg(long, global = true, value_enum, default_value_t = Look::Natural)]
    pub look: Look,
    /// No sun shadows (natural look) [default: shadows on a GPU, none on a software
    /// device].
    #[arg(long, global = true)]
    pub no_shadows: bool,
    /// A tiled field's far blades at rest instead of in the pose the wind settles
    /// them into.
    #[arg(long, global = true)]
    pub far_at_rest: bool,
    /// Sun shadows also on a software device (natural look).
    #[arg(long, global = true, conflicts_with = "no_shadows")]
    pub shadows: bool,
    /// Anti-aliasing: `taa` blends each jittered frame into a history that follows
    /// every pixel's motion, `msaa` takes --msaa samples per pixel (4 unless given),
    /// `none` one sample [default: taa on a GPU, none on a software device; msaa
    /// where --msaa asks for more than one sample].
    #[arg(long, global = true, value_enum)]
    pub aa: Option<Antialiasing>,
    /// Samples per pixel of multisampling, 1, 2, 4 or 8 (lowered to what the device
    /// has); more than one means --aa msaa [default: 4].
    #[arg(long, global = true, value_parser = parse_msaa)]
    pub msaa: Option<u32>,
    /// Draw the scene at this share of the output's width and height, 0.25 to 1: the
    /// tone map scales the frame up [default: 0.5 with --aa taa on a software device,
    /// 1 otherwise].
    #[arg(long, global = true, value_parser = range(MIN_RENDER_SCALE, 1.0))]
    pub render_scale: Option<f32>,
    /// Side of each of the sun's two shadow cascades in texels: 256, 512, 1024, 2048
    /// or 4096 [default: 1024 on a GPU, 512 on a software device].
    #[arg(long, global = true, value_parser = parse_shadow_size)]
    pub shadow_size: Option<u32>,
    /// How the grass is drawn: `tess` through the tessellator (a patch per blade),
    /// `mesh` by mesh stages (VK_EXT_mesh_shader), `auto` the one measured
    /// faster: mesh wherever the device has it.
    #[arg(long, global = true, value_enum, default_value_t = PipelineChoice::Auto)]
    pub pipeline: PipelineChoice,
    /// Factor on the light before the tone map (natural look).
    #[arg(long, global = true, default_value_t = 1.0, value_parser = range(0.01, 100.0))]
    pub exposure: f32,
    /// Aerial perspective: fog density per unit of distance (natural look).
    #[arg(long, global = true, default_value_t = LookSettings::default().fog_density, value_parser = range(0.0, 1.0))]
    pub fog_density: f32,
    /// Size of the clumps blades grow in, scene units (natural look) [default: 1.6
    /// times the scene's blade size].
    #[arg(long, global = true, value_parser = range(0.01, 1e4))]
    pub clump_size: Option<f32>,
    /// A tiled field's distance every blade is kept within, scene units; beyond, the
    /// field thins [default: 48 times the scene's blade size on a GPU, 4.5 on a
    /// software device].
    #[arg(long, global = true, value_parser = range(0.1, 1e5))]
    pub full_distance: Option<f32>,
    /// Start without the ball (the B key brings it back in the viewer).
    #[arg(long, global = true)]
    pub no_ball: bool,
    /// Enable VK_LAYER_KHRONOS_validation (also GRASS_VALIDATION=1); `render` then
    /// fails on any validation error.
    #[arg(long, global = true)]
    pub validation: bool,
    /// The validation layer's checks beside its core ones; naming any implies
    /// --validation [default: synchronization].
    #[arg(long, global = true, value_enum)]
    pub validation_checks: Option<ValidationChecks>,
}

/// The culling tests, their thresholds, the level of detail and the grass view.
#[derive(Args, Debug, Clone)]
pub struct CullArgs {
    /// Do not remove blades seen edge-on.
    #[arg(long, global = true)]
    pub no_cull_orientation: bool,
    /// Do not remove blades outside the view frustum.
    #[arg(long, global = true)]
    pub no_cull_frustum: bool,
    /// Do not thin the field with distance.
    #[arg(long, global = true)]
    pub no_cull_distance: bool,
    /// Do not remove blades hidden behind the scene's surfaces (Hi-Z test).
    #[arg(long, global = true)]
    pub no_cull_occlusion: bool,
    /// Full detail at every distance.
    #[arg(long, global = true)]
    pub no_lod: bool,
    /// Orientation test: remove a blade when |view · width direction| exceeds this.
    #[arg(long, global = true, default_value_t = 0.9, value_parser = range(0.0, 1.0))]
    pub orientation_threshold: f32,
    /// Orientation test: remove such a blade only where it is narrower than this many
    /// pixels on screen (three quarters of that in the natural look, whose blades
    /// stand out more); 0 removes every one (the paper's test).
    #[arg(long, global = true, default_value_t = shared::settings::EDGE_ON_PIXELS, value_parser = range(0.0, 1000.0))]
    pub edge_on_pixels: f32,
    /// Frustum test: slack around the view volume, in clip-space units.
    #[arg(long, global = true, default_value_t = 0.5, value_parser = range(0.0, 10.0))]
    pub frustum_tolerance: f32,
    /// Distance test: nothing drawn beyond this [default: from the scene's size].
    #[arg(long, global = true, value_parser = range(0.1, 1e6))]
    pub max_distance: Option<f32>,
    /// Distance test: buckets thinning the field between the camera and the maximum.
    #[arg(long, global = true, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub buckets: u32,
    /// LOD: tessellation level along the blade near the camera (1 to 9).
    #[arg(long, global = true, default_value_t = 7.0, value_parser = range(1.0, shared::cull::lod::MAX_LEVEL))]
    pub lod_most: f32,
    /// LOD: tessellation level far away (1 to 9).
    #[arg(long, global = true, default_value_t = 1.0, value_parser = range(1.0, shared::cull::lod::MAX_LEVEL))]
    pub lod_fewest: f32,
    /// LOD: screen pixels per segment along a blade (a blade this tall or shorter is
    /// one segment).
    #[arg(long, global = true, default_value_t = shared::cull::lod::PIXELS_PER_SEGMENT, value_parser = range(1.0, 1e4))]
    pub lod_pixels: f32,
    /// Blades shorter than this on screen (pixels) are drawn by the compute rasterizer
    /// instead of the hardware pipeline; 0 turns it off [default: 16 on a GPU with
    /// 64-bit atomics, 0 on a software device].
    #[arg(long, global = true, value_parser = range(0.0, 1e4))]
    pub compute_raster_below: Option<f32>,
    /// How the grass is drawn.
    #[arg(long, global = true, value_enum, default_value_t = View::Shaded)]
    pub view: View,
}

impl CullArgs {
    /// The enabled tests.
    pub fn tests(&self) -> CullTests {
        CullTests {
            orientation: !self.no_cull_orientation,
            frustum: !self.no_cull_frustum,
            distance: !self.no_cull_distance,
            occlusion: !self.no_cull_occlusion,
        }
    }
}

pub(crate) fn parse_species(s: &str) -> Result<shared::species::Mix, String> {
    s.parse()
}

pub(crate) fn parse_point(s: &str) -> Result<Vec3, String> {
    parse_coordinates::<3>(s).map(Vec3::from_array)
}

pub(crate) fn parse_msaa(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n @ (1 | 2 | 4 | 8)) => Ok(n),
        _ => Err(format!("{s:?} is not 1, 2, 4 or 8")),
    }
}

pub(crate) fn parse_shadow_size(s: &str) -> Result<u32, String> {
    use shared::settings::SHADOW_SIZES;
    match s.trim().parse::<u32>() {
        Ok(n) if SHADOW_SIZES.contains(&n) => Ok(n),
        _ => Err(format!("{s:?} is not one of {SHADOW_SIZES:?}")),
    }
}

pub(crate) fn parse_density(s: &str) -> Result<f32, String> {
    range(1e-3, 1e6)(s)
}

impl Common {
    /// The scene asked for.
    pub fn scene_kind(&self) -> SceneKind {
        SceneKind::parse(&self.scene)
    }

    /// The blade count asked for, if any (else the device's default).
    pub fn blade_count(&self) -> Option<BladeCount> {
        match (self.density, self.blades) {
            (Some(d), _) => Some(BladeCount::Density(d)),
            (None, Some(n)) => Some(BladeCount::Total(n)),
            (None, None) => None,
        }
    }

    /// Checks what clap cannot check one option at a time: the level of detail far away
    /// may not be above the one near the camera.
    pub fn check(&self) -> anyhow::Result<()> {
        let c = &self.cull;
        if c.lod_fewest > c.lod_most {
            anyhow::bail!(
                "--lod-fewest {} is above --lod-most {}: the level far away cannot be \
                 higher than the level near the camera",
                c.lod_fewest,
                c.lod_most
            );
        }
        Ok(())
    }

    /// Validation from the flag, from naming its checks, or from GRASS_VALIDATION=1.
    pub fn validation_requested(&self) -> bool {
        self.validation
            || self.validation_checks.is_some()
            || std::env::var("GRASS_VALIDATION")
                .is_ok_and(|v| matches!(v.trim(), "1" | "true" | "yes" | "on"))
    }

    /// The validation layer's checks beside its core ones.
    pub fn checks(&self) -> ValidationChecks {
        self.validation_checks.unwrap_or_default()
    }
}

/// `--pipeline`: a grass pipeline, or the device's faster one.
#[derive(clap::ValueEnum, Copy, Clone, Debug, PartialEq, Eq)]
pub enum PipelineChoice {
    /// Tessellation: one patch per blade.
    Tess,
    /// Task and mesh stages: meshlets of blade strips.
    Mesh,
    /// The one measured faster on this kind of device and look, among those it has.
    Auto,
}

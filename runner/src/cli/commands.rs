//! The options of each command: soak, bench, render, record, query and the viewer.

use super::common::*;
use crate::parse::range;
use clap::{Args, ValueEnum};
use glam::{Vec2, Vec3};
use shared::cull::blade as cull;
use shared::settings::{CullTests, Look};
use shared::sim::impulse::{IMPULSE_BLAST, IMPULSE_DOWNWASH, Impulse};
use std::path::PathBuf;

/// Options of the soak run.
#[derive(Args, Debug, Clone)]
pub struct SoakArgs {
    /// Frames to run.
    #[arg(long, default_value_t = 20_000, value_parser = clap::value_parser!(u32).range(100..=100_000_000))]
    pub frames: u32,
    /// Frames between memory readings; the image alternates between two sizes at each
    /// reading, and the switches change four times in between.
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(10..=1_000_000))]
    pub every: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub height: u32,
    /// Host memory (resident set) the run may gain, in MiB: the lowest reading of the
    /// last third against the highest of the first third.
    #[arg(long, default_value_t = 8.0, value_parser = range(0.0, 1e6))]
    pub host_slack_mib: f32,
    /// Run without the validation layer (where it is not installed).
    #[arg(long)]
    pub no_validation: bool,
}

/// Options of the benchmark.
#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Blade counts to sweep, comma-separated (`--blades N` runs one) [default: powers
    /// of two from 1,024 to 4,194,304 that the device holds; up to 8,192 on a
    /// software device].
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u32).range(1..=(1 << 26)))]
    pub counts: Vec<u32>,
    /// Configurations, comma-separated [default: all].
    #[arg(long, value_delimiter = ',', value_enum)]
    pub configs: Vec<BenchConfig>,
    /// Looks to time, comma-separated; with both, the report sets the natural look's
    /// frame against the paper's. Without --msaa the paper look is timed at one sample
    /// per pixel (as the paper drew it), the natural one at the device's default
    /// [default: the one --look names].
    #[arg(long, value_delimiter = ',', value_enum)]
    pub looks: Vec<Look>,
    /// Grass pipelines to time, comma-separated, each at every point [default: the
    /// one --pipeline names]
    #[arg(long, value_delimiter = ',', value_enum)]
    pub pipelines: Vec<PipelineChoice>,
    /// Compute-rasterizer thresholds to time (pixels; 0 off), comma-separated, each at
    /// every point [default: the one --compute-raster-below gives]
    #[arg(long, value_delimiter = ',', value_parser = range(0.0, 1e4))]
    pub compute_raster: Vec<f32>,
    /// Camera preset.
    #[arg(long, value_enum, default_value_t = CameraPreset::Edge)]
    pub camera: CameraPreset,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1920, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 1080, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub height: u32,
    /// Measured frames per point.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Frames run before measuring each point.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub warmup: u32,
    /// CSV file of the results; the charts (`_frame`, `_passes`, `_configs`) and the
    /// preset's picture (`.view.png`) are written next to it.
    #[arg(long, default_value = "bench.csv")]
    pub out: PathBuf,
}

/// What runs in a benchmark configuration.
#[derive(ValueEnum, Copy, Clone, Debug, PartialEq, Eq)]
pub enum BenchConfig {
    /// No culling, no LOD.
    None,
    /// The orientation test alone.
    Orientation,
    /// The frustum test alone.
    Frustum,
    /// The distance test alone.
    Distance,
    /// The occlusion test alone.
    Occlusion,
    /// Orientation, frustum and distance.
    Culls,
    /// Those three and LOD.
    CullsLod,
    /// Every test and LOD.
    CullsLodOcclusion,
}

impl BenchConfig {
    /// Every configuration, in the order of the report.
    pub const ALL: [BenchConfig; 8] = [
        BenchConfig::None,
        BenchConfig::Orientation,
        BenchConfig::Frustum,
        BenchConfig::Distance,
        BenchConfig::Occlusion,
        BenchConfig::Culls,
        BenchConfig::CullsLod,
        BenchConfig::CullsLodOcclusion,
    ];

    /// (enabled tests, LOD on).
    pub fn switches(self) -> (CullTests, bool) {
        let only = |mask| CullTests::from_mask(mask);
        match self {
            BenchConfig::None => (CullTests::NONE, false),
            BenchConfig::Orientation => (only(cull::ORIENTATION), false),
            BenchConfig::Frustum => (only(cull::FRUSTUM), false),
            BenchConfig::Distance => (only(cull::DISTANCE), false),
            BenchConfig::Occlusion => (only(cull::OCCLUSION), false),
            BenchConfig::Culls => (CullTests::PAPER, false),
            BenchConfig::CullsLod => (CullTests::PAPER, true),
            BenchConfig::CullsLodOcclusion => (CullTests::ALL, true),
        }
    }
}

/// Where the benchmark's camera stands.
#[derive(ValueEnum, Copy, Clone, Debug, PartialEq, Eq)]
pub enum CameraPreset {
    /// At the field's edge, two units up, looking across it.
    Edge,
    /// High above, the whole field in view.
    Overview,
    /// On the valley: a walker's eye flying down the path, 6 units a second
    /// (`scene::valley_camera`).
    Flight,
}

/// How the viewer's frames reach its window (`--present`).
#[derive(ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum PresentPath {
    /// The window's shared memory for a software device under X11, else a swapchain.
    #[default]
    Auto,
    /// A Vulkan swapchain.
    Swapchain,
    /// Each frame copied into the window's shared memory (MIT-SHM on X11): Mesa's X11
    /// swapchain sends each frame of a software device through the X server's socket
    /// where the server has no DRI3 (Xvfb, VNC servers).
    SharedMemory,
}

impl PresentPath {
    /// The way taken: `Auto` is the shared memory for a `software` device whose window
    /// is on `x11`, else the swapchain.
    pub fn resolve(self, software: bool, x11: bool) -> Self {
        match self {
            Self::Auto if software && x11 => Self::SharedMemory,
            Self::Auto => Self::Swapchain,
            chosen => chosen,
        }
    }

    /// As the overlay names it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "chosen by the device",
            Self::Swapchain => "swapchain",
            Self::SharedMemory => "shared-memory frames",
        }
    }
}

/// Options of the viewer.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Window width in pixels.
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// Window height in pixels.
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub height: u32,
    /// Quit after this many frames (for scripted runs).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Resize, minimise and restore the window by script while drawing (for tests).
    #[arg(long)]
    pub resize_storm: bool,
    /// Take a screenshot (as the K key does) once this many frames are drawn; several
    /// comma-separated.
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u64).range(1..))]
    pub screenshot_at: Vec<u64>,
    /// Where screenshots and saved settings go (`grass-<seconds since 1970>.png`, a
    /// number added when two come in the same second): a folder that exists.
    #[arg(long, default_value = ".")]
    pub screenshot_dir: PathBuf,
    /// Start with the overlay hidden (the O key shows it).
    #[arg(long)]
    pub no_overlay: bool,
    /// How frames reach the window.
    #[arg(long, value_enum, default_value_t = PresentPath::Auto)]
    pub present: PresentPath,
}

impl Default for ViewArgs {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            frames: None,
            resize_storm: false,
            screenshot_at: Vec::new(),
            screenshot_dir: PathBuf::from("."),
            no_overlay: false,
            present: PresentPath::Auto,
        }
    }
}

/// Options of the headless renderer.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Frames to simulate and draw (1/60 s each); the last one is written.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub frames: u32,
    /// Output PNG.
    #[arg(long, default_value = "shot.png")]
    pub out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub height: u32,
    /// Where the camera stands and how it moves.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Wind impulses.
    #[command(flatten)]
    pub events: ImpulseArgs,
}

/// Options of `grass quality`.
#[derive(Args, Debug, Clone)]
pub struct QualityArgs {
    /// The CSV written (method, samples, still, turning, shimmer, reference_shimmer).
    #[arg(long, default_value = "quality.csv")]
    pub out: PathBuf,
    /// Image width in pixels of the measured frames.
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(16..=4096))]
    pub width: u32,
    /// Image height in pixels of the measured frames.
    #[arg(long, default_value_t = 360, value_parser = clap::value_parser!(u32).range(16..=4096))]
    pub height: u32,
    /// The reference's supersampling: this many times the width and the height.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(2..=8))]
    pub scale: u32,
    /// Frames of the turning camera (a third of a pixel each).
    #[arg(long, default_value_t = 12, value_parser = clap::value_parser!(u32).range(2..=1000))]
    pub frames: u32,
    /// Frames (1/60 s each) the field settles for before anything is measured.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub settle: u32,
    /// A folder for one cropped side-by-side per method (reference left), as PNGs.
    #[arg(long)]
    pub crops: Option<PathBuf>,
    /// Where the camera stands.
    #[command(flatten)]
    pub camera: CameraArgs,
}

/// Options of `grass query`.
#[derive(Args, Debug, Clone)]
pub struct QueryArgs {
    /// Frames to simulate (1/60 s each); the last two ask the questions, and the last
    /// one's answers are printed.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub frames: u32,
    /// Ask about the grass around the ground below "x,z": the blades rooted within
    /// --radius, their mean height and bend. Repeat it (all questions: at most 16).
    #[arg(long = "at", allow_hyphen_values = true, value_parser = parse_ground_point)]
    pub at: Vec<Vec2>,
    /// Radius of each --at, world units.
    #[arg(long, default_value_t = 0.5, value_parser = range(0.01, 100.0))]
    pub radius: f32,
    /// Ask how hidden a line of sight is, "x,z:x,z": from --eye-height above the
    /// ground below the first point to as high above the ground below the second.
    /// Repeat it.
    #[arg(long = "sight", allow_hyphen_values = true, value_parser = parse_sight)]
    pub sight: Vec<(Vec2, Vec2)>,
    /// Height of a sight's ends above the ground, world units.
    #[arg(long, default_value_t = 1.0, value_parser = range(0.0, 100.0))]
    pub eye_height: f32,
    /// Radius of a line of sight (a blade crossing it hides its width over twice
    /// this), world units.
    #[arg(long, default_value_t = 0.25, value_parser = range(0.01, 10.0))]
    pub sight_radius: f32,
    /// Also read the blades back after the last frame and answer on the host
    /// (`shared::query`); fail where the two answers differ beyond rounding.
    #[arg(long)]
    pub check: bool,
    /// Where the camera stands (a tiled field simulates the blades around it).
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Wind impulses.
    #[command(flatten)]
    pub events: ImpulseArgs,
}

/// Parses a ground point "x,z".
fn parse_ground_point(s: &str) -> Result<Vec2, String> {
    crate::parse::parse_coordinates::<2>(s).map(Vec2::from_array)
}

/// Parses a line of sight "x,z:x,z" between two ground points.
fn parse_sight(s: &str) -> Result<(Vec2, Vec2), String> {
    let (from, to) = s
        .split_once(':')
        .ok_or(format!("{s:?}: expected \"x,z:x,z\""))?;
    Ok((parse_ground_point(from)?, parse_ground_point(to)?))
}

/// Options of a clip.
#[derive(Args, Debug, Clone)]
pub struct RecordArgs {
    /// The clip: a `.gif` (encoded here), an `.mp4` (through `ffmpeg`, which must be
    /// installed) or a folder of numbered PNGs.
    #[arg(long, default_value = "clip.gif")]
    pub out: PathBuf,
    /// Frames of the clip, each one step of the fixed frame time (1 / --fps).
    #[arg(long, default_value_t = 90, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Frames a second of the clip, and of the simulation's clock while recording.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub fps: u32,
    /// Frames simulated before the first recorded one (the blades settle).
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub settle: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 480, value_parser = clap::value_parser!(u32).range(16..=4096))]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 270, value_parser = clap::value_parser!(u32).range(16..=4096))]
    pub height: u32,
    /// Where the camera stands and how it moves.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Wind impulses.
    #[command(flatten)]
    pub events: ImpulseArgs,
}

/// Wind impulses at set times of a headless run (`shared::sim::impulse`).
#[derive(Args, Debug, Clone, Default)]
pub struct ImpulseArgs {
    /// A wind impulse, "blast,x,z,start" (an explosion) or "downwash,x,z,start" (a
    /// rotor hovering): centred on the ground below x,z from `start` seconds of
    /// simulated time, optionally followed by ",strength,radius,lifetime" [default:
    /// a blast 60,8,2.5; a downwash 30,6,8]. Repeat it for up to 8.
    #[arg(long = "impulse", value_parser = ImpulseSpec::parse)]
    pub impulses: Vec<ImpulseSpec>,
}

/// One `--impulse`: its kind, where on the ground (x, z), and the
/// `shared::sim::impulse::Impulse` fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpulseSpec {
    /// The ground point below its centre.
    pub at: Vec2,
    /// The impulse, its centre's height not yet known (0).
    pub impulse: Impulse,
}

impl ImpulseSpec {
    /// Parses "blast,x,z,start" or "downwash,x,z,start", optionally followed by
    /// ",strength,radius,lifetime".
    pub fn parse(s: &str) -> Result<Self, String> {
        let form = "\"blast,x,z,start\" or \"downwash,x,z,start\", optionally followed \
                    by \",strength,radius,lifetime\"";
        let (kind, numbers) = s.split_once(',').ok_or(format!("{s:?}: expected {form}"))?;
        let kind = match kind.trim() {
            "blast" => IMPULSE_BLAST,
            "downwash" => IMPULSE_DOWNWASH,
            other => return Err(format!("{other:?}: an impulse is a blast or a downwash")),
        };
        let numbers = numbers
            .split(',')
            .map(|n| n.trim().parse::<f32>().map_err(|e| format!("{n:?}: {e}")))
            .collect::<Result<Vec<f32>, String>>()?;
        let (x, z, start) = match numbers[..] {
            [x, z, start] | [x, z, start, _, _, _] => (x, z, start),
            _ => return Err(format!("{s:?}: expected {form}")),
        };
        let mut impulse = Impulse::of_kind(kind, Vec3::ZERO, start);
        if let [_, _, _, strength, radius, lifetime] = numbers[..] {
            (impulse.strength, impulse.radius, impulse.lifetime) = (strength, radius, lifetime);
        }
        let at = Vec2::new(x, z);
        let problem = if !at.is_finite() || start < 0.0 {
            Some("its place must be finite and its start at least 0")
        } else {
            impulse.problem()
        };
        match problem {
            Some(problem) => Err(format!("{s:?}: {problem}")),
            None => Ok(Self { at, impulse }),
        }
    }
}

/// The headless camera: the scene's framing changed by these.
#[derive(Args, Debug, Clone)]
pub struct CameraArgs {
    /// Camera closer (above 1) or further (below 1) than the view framing the scene.
    #[arg(long, default_value_t = 1.0, value_parser = range(0.05, 50.0))]
    pub zoom: f32,
    /// Camera angle around the vertical, degrees [default: the scene's framing].
    #[arg(long, allow_hyphen_values = true, value_parser = range(-360.0, 360.0))]
    pub yaw: Option<f32>,
    /// Camera angle above the horizon, degrees, 1 to 85 [default: the scene's framing].
    #[arg(long, value_parser = range(1.0, 85.0))]
    pub pitch: Option<f32>,
    /// Fly the valley's path at the bench's flight speed (6 units a second) over the
    /// frames instead of standing still (`--scene valley`); the flight sets the camera.
    #[arg(long, conflicts_with_all = ["zoom", "yaw", "pitch", "orbit"])]
    pub flight: bool,
    /// Turn the camera around the scene by this many degrees a second.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = range(-720.0, 720.0))]
    pub orbit: f32,
}

//! Command line: the viewer by default, `render` for a headless image.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Real-time grass after Jahrmann & Wimmer (I3D 2017): Rust shaders, Vulkan through ash.
#[derive(Parser, Debug)]
#[command(name = "grass", version, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to run; the interactive viewer when left out.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Options of every command.
    #[command(flatten)]
    pub common: Common,
    /// Viewer options, when no command is named.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Open a window with an orbit camera (the default).
    View(ViewArgs),
    /// Render offscreen, without any window system, and write a PNG.
    Render(RenderArgs),
}

/// Options every command takes.
#[derive(Args, Debug, Clone)]
pub struct Common {
    /// Number of blades [default: 131072 on a GPU, 2048 on a software device].
    #[arg(long, global = true, value_parser = clap::value_parser!(u32).range(1..=(1 << 26)))]
    pub blades: Option<u32>,
    /// Seed of the random field: the same seed gives the same blades.
    #[arg(long, global = true, default_value_t = 1)]
    pub seed: u64,
    /// Enable VK_LAYER_KHRONOS_validation (also GRASS_VALIDATION=1); `render` then
    /// fails on any validation error.
    #[arg(long, global = true)]
    pub validation: bool,
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
}

impl Default for ViewArgs {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            frames: None,
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
}

impl Common {
    /// Validation from the flag or from GRASS_VALIDATION=1.
    pub fn validation_requested(&self) -> bool {
        self.validation
            || std::env::var("GRASS_VALIDATION")
                .is_ok_and(|v| matches!(v.trim(), "1" | "true" | "yes" | "on"))
    }
}

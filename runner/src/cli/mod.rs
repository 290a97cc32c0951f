//! Command line: the viewer by default, `render` for a headless image.

pub mod commands;
pub mod common;

use clap::{Parser, Subcommand};
pub use commands::*;
pub use common::*;

/// Real-time grass after Jahrmann & Wimmer (I3D 2017): Rust shaders, Vulkan through ash.
#[derive(Parser, Debug)]
#[command(
    name = "grass",
    version,
    args_conflicts_with_subcommands = true,
    args_override_self = true
)]
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
    /// Warnings and errors only in the log (RUST_LOG, when set, decides instead; e.g.
    /// `RUST_LOG=runner=debug`).
    #[arg(long, short, global = true)]
    pub quiet: bool,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Open a window with an orbit camera (the default).
    View(ViewArgs),
    /// Render offscreen, without any window system, and write a PNG.
    Render(RenderArgs),
    /// Time blade counts and culling configurations headless; print a table and
    /// write a CSV.
    Bench(BenchArgs),
    /// Run many frames headless with the validation layer, cycling every switch, and
    /// check that host and device memory stay flat and the layer says nothing.
    Soak(SoakArgs),
    /// Record a clip headless at a fixed frame time: a GIF, an MP4 (ffmpeg) or PNGs.
    Record(RecordArgs),
    /// Measure each anti-aliasing method against a supersampled reference: still, on a
    /// turning camera, and its shimmer; print a table and write a CSV.
    Quality(QualityArgs),
    /// Ask the grass questions a game asks, after some frames: the blades around
    /// ground points, how hidden lines of sight are, the colliders in the grass.
    Query(QueryArgs),
    /// Print every setting at its default as a commented TOML file (for --config).
    Config,
}

impl Given {
    /// The options `args` (the program's, its name first, before the settings file is
    /// merged) give on the command line, and the settings file's `file_keys`.
    pub fn new(args: &[std::ffi::OsString], file_keys: Vec<String>) -> Self {
        use clap::CommandFactory as _;
        let mut command = Cli::command();
        command.build();
        let mut command_line = std::collections::BTreeSet::new();
        if let Ok(matches) = command.clone().try_get_matches_from(args) {
            typed(&matches, &command, &mut command_line);
        }
        Self {
            command_line,
            file: file_keys.into_iter().collect(),
        }
    }
}

//! The application shells: the window viewer and the headless renderer.

pub mod render;
pub mod viewer;

use crate::cli::{Cli, Command, Common};
use crate::vulkan::Context;
use anyhow::Result;

/// Blades of the default field on a hardware GPU.
pub const DEFAULT_BLADES_GPU: u32 = 1 << 17;
/// Blades of the default field on a software device (lavapipe draws about half a
/// million triangles a second on two cores).
pub const DEFAULT_BLADES_SOFTWARE: u32 = 2048;

/// Runs what the command line asks for.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Command::Render(args)) => render::run(&cli.common, &args).map(|_| ()),
        Some(Command::View(args)) => viewer::run(&cli.common, &args),
        None => viewer::run(&cli.common, &cli.view),
    }
}

/// The blade count asked for, or the default for this device.
pub fn blade_count(common: &Common, ctx: &Context) -> u32 {
    match common.blades {
        Some(n) => n,
        None if ctx.is_software() => {
            log::info!(
                "software device {}: {DEFAULT_BLADES_SOFTWARE} blades by default \
                 (--blades to change)",
                ctx.device_name()
            );
            DEFAULT_BLADES_SOFTWARE
        }
        None => DEFAULT_BLADES_GPU,
    }
}

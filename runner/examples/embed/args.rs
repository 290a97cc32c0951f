//! The command line: what to draw, and where.

use shared::settings::Look;

use super::stage::*;

/// The command line: what to draw, and where.
#[derive(clap::Parser, Debug, Clone)]
#[command(
    name = "embed",
    about = "Grass in your own Vulkan program: a cube of its own and runner::embed's field"
)]
pub struct Args {
    /// The PNG to write (headless); without it, a window opens.
    #[arg(long)]
    pub out: Option<std::path::PathBuf>,
    /// Frames to draw: headless, the last is written [default: 90]; in a window, it
    /// closes after them [default: when closed].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Headless image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = size)]
    pub size: (u32, u32),
    /// The field's look (the natural one headless only).
    #[arg(long, value_enum, default_value_t = Look::Paper)]
    pub look: Look,
    /// Blades of a stored field.
    #[arg(long, default_value_t = BLADES, value_parser = clap::value_parser!(u32).range(1..=(1 << 24)))]
    pub blades: u32,
    /// A tiled field, generated tile by tile around the camera to the horizon.
    #[arg(long)]
    pub tiled: bool,
    /// Sizes to go through first, WxH,WxH,...: headless, a frame each before --size; in
    /// a window, the window asks for each in turn, 10 frames apart (the field follows
    /// its targets' size either way).
    #[arg(long, value_delimiter = ',', value_parser = size)]
    pub resize_through: Vec<(u32, u32)>,
    /// The validation layer on (core and synchronization), its errors counted.
    #[arg(long)]
    pub validation: bool,
}

impl Default for Args {
    fn default() -> Self {
        Self {
            out: None,
            frames: None,
            size: (640, 360),
            look: Look::Paper,
            blades: BLADES,
            tiled: false,
            resize_through: Vec::new(),
            validation: false,
        }
    }
}

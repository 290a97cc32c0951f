//! Grass in a wgpu program (`runner::embed` through wgpu-hal's Vulkan interop): wgpu
//! draws the program's own scene (a spinning cube, `shared::example::cube`, its
//! shaders Rust compiled to SPIR-V by rust-gpu and passed through), and a
//! `GrassField` on the same `VkDevice` draws the grass into wgpu's colour and depth
//! textures, depth-tested against the cube, which also pushes the blades aside.
//!
//! ```text
//! cargo run --release --example wgpu -- --out frame.png    # headless, one PNG
//! cargo run --release --example wgpu -- --help             # every option
//! ```
//!
//! How: `runner::embed::wgpu` makes the `VkDevice` with ash, with wgpu's features
//! and the grass's, and hands it to wgpu ([`device`]); each frame wgpu records its
//! pass, the grass goes into a command buffer of its own through wgpu-hal, and both
//! are submitted together ([`scene::draw_frame`]).

mod device;
mod scene;
#[path = "../embed/stage.rs"]
mod stage;
#[path = "../embed/validation.rs"]
mod validation;

use anyhow::{Context as _, Result, bail};
use glam::Vec2;
use runner::embed::{FieldDesc, GrassField, Ground};
use std::sync::atomic::Ordering;

pub use device::{Devices, VALIDATION_ERRORS};
use scene::{COLOR, CubePass, Textures, draw_frame};
use stage::{BLADES, Stage};

/// The command line.
#[derive(clap::Parser, Debug, Clone)]
#[command(
    name = "wgpu",
    about = "Grass in a wgpu program: wgpu draws a cube, runner::embed the grass, in one frame"
)]
pub struct Args {
    /// The PNG to write.
    #[arg(long)]
    pub out: std::path::PathBuf,
    /// Frames simulated; the last is written.
    #[arg(long, default_value_t = 90, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = stage::size)]
    pub size: (u32, u32),
    /// Blades in the field.
    #[arg(long, default_value_t = BLADES, value_parser = clap::value_parser!(u32).range(1..=(1 << 24)))]
    pub blades: u32,
    /// The validation layer on, its errors counted.
    #[arg(long)]
    pub validation: bool,
}

/// One run's picture.
pub struct Shot {
    /// RGBA8 (sRGB) pixels, row by row.
    pub rgba: Vec<u8>,
    /// (width, height).
    pub size: (u32, u32),
    /// Blades the last frame drew.
    pub drawn: u32,
    /// The cube's corners in pixels, in the last frame.
    pub cube_corners: Vec<Vec2>,
}

#[allow(dead_code)] // Also compiled into `runner/tests/embed.rs`, which has its own main.
fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = <Args as clap::Parser>::parse();
    match run(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Renders as `args` ask and writes the PNG.
fn run(args: &Args) -> Result<()> {
    runner::files::check_output(&args.out, &["png"])?;
    let shot = render(args)?;
    runner::files::save_png(&args.out, &shot.rgba, shot.size, image::ColorType::Rgba8)?;
    let errors = VALIDATION_ERRORS.load(Ordering::SeqCst);
    println!(
        "wrote {}: {} blades drawn, {errors} validation errors",
        args.out.display(),
        shot.drawn
    );
    if errors > 0 {
        bail!("validation reported {errors} errors");
    }
    Ok(())
}

/// `args.frames` frames of `args.size`, the last one read back.
pub fn render(args: &Args) -> Result<Shot> {
    let devices = Devices::new(COLOR, args.validation)?;
    let desc = FieldDesc {
        ground: Ground::Hills,
        blades: args.blades,
        seed: 1,
        species: shared::species::Mix::GRASS,
        color_format: ash::vk::Format::R8G8B8A8_SRGB,
        draw_ground: true,
        tiled: false,
        reverse_z: false,
    };
    let gpu = &devices.gpu;
    let mut field = GrassField::new(gpu.grass(), &gpu.features, desc)?;
    let stage = Stage::new(&field);
    let cube = CubePass::new(&gpu.device)?;
    let (width, height) = args.size;
    let textures = Textures::new(&gpu.device, args.size);
    // Rows of the read-back buffer are padded to wgpu's copy alignment.
    let row = (4 * width).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read back"),
        size: u64::from(row * height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    for k in 0..args.frames {
        let copy = (k + 1 == args.frames).then(|| {
            let mut copy = gpu.device.create_command_encoder(&Default::default());
            copy.copy_texture_to_buffer(
                textures.color.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &readback,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: None,
                    },
                },
                textures.color.size(),
            );
            copy
        });
        draw_frame(&devices, (&cube, &mut field, &stage), &textures, copy)?;
        // One frame in flight: the field's counters are read after it.
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .context("wait for the frame")?;
    }
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .context("read back")?;
    let rgba = slice
        .get_mapped_range()
        .chunks(row as usize)
        .flat_map(|r| r[..4 * width as usize].to_vec())
        .collect();
    let shot = Shot {
        rgba,
        size: args.size,
        drawn: field.counts()?.drawn,
        cube_corners: stage.cube_corners_px(field.time(), args.size),
    };
    // The field goes first: wgpu destroys the device with its last handle.
    drop(field);
    Ok(shot)
}

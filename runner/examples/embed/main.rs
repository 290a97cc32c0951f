//! Grass in your own Vulkan program (`runner::embed`): this program makes its own
//! instance, device, queue, allocator, images and command buffers, draws its own
//! object (a spinning cube, `shared::cube`), and has a `GrassField` draw the grass
//! into the same colour and depth images, depth-tested against the cube. The cube is
//! also a collider: the blades under it bend away.
//!
//! ```text
//! cargo run --release --example embed                       # a window
//! cargo run --release --example embed -- --out frame.png    # headless, one PNG
//! cargo run --release --example embed -- --help             # every option
//! ```
//!
//! `--resize-through` goes through those sizes first (headless, a frame at each; in
//! a window, asked of the window 10 frames apart).
//!
//! `--look natural` (headless) draws the natural look into a linear HDR image
//! (`R16G16B16A16_SFLOAT`), as an engine with its own tone map would, and tone-maps
//! it on the host (`shared::draw::look::sky::tone_map`) for the PNG. `--tiled` makes the field a
//! tiled one, generated tile by tile around the camera out to the horizon.
//!
//! Headless, `--frames` (90 by default) are simulated and the last one written; in a
//! window, `--frames` closes it after that many (else it runs until closed).

mod args;
mod cube;
mod frame;
mod gpu;
mod headless;
mod stage;
mod validation;
mod window;

use anyhow::{Result, bail};
pub use args::Args;
pub use gpu::{Gpu, VALIDATION_ERRORS};
pub use headless::{HEADLESS_FORMAT, render_headless};
use shared::settings::Look;
use std::sync::atomic::Ordering;

#[allow(dead_code)] // Also compiled into `runner/tests/embed.rs`, which has its own main.
fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    // A usage error (or --help) ends here, as clap says it.
    let args = <Args as clap::Parser>::parse();
    match run(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Draws as `args` ask: a window, or one PNG headless.
fn run(args: &Args) -> Result<()> {
    let Some(out) = &args.out else {
        if args.look != Look::Paper {
            bail!("the window draws the paper look; --look natural needs --out (headless)");
        }
        return window::run(args);
    };
    runner::files::check_output(out, &["png"])?;
    let shot = render_headless(args)?;
    runner::files::save_png(out, &shot.rgba, shot.size, image::ColorType::Rgba8)?;
    let out = out.display();
    let errors = VALIDATION_ERRORS.load(Ordering::SeqCst);
    println!(
        "wrote {out}: {} blades drawn, {errors} validation errors",
        shot.drawn
    );
    if shot.software {
        println!("(a software device: its timestamps do not time passes, none is printed)");
    } else if let Some(t) = shot.times {
        let per_blade = 1e6 * t.total / f64::from(shot.drawn.max(1));
        println!(
            "the field's GPU time in the last frame: simulate and cull {:.3} ms, shadow map \
             {:.3}, grass {:.3}, ground {:.3}; {:.3} ms in all, {per_blade:.1} ns a drawn blade",
            t.depth_pyramid + t.simulate_cull,
            t.shadow,
            t.grass,
            t.ground,
            t.total
        );
    }
    if errors > 0 {
        bail!("validation reported {errors} errors");
    }
    Ok(())
}

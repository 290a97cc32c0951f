//! The library from your own program: the built-in hills, two seconds simulated,
//! the last frame written as a PNG (the crate guide's example, runnable).
//!
//! `cargo run --release --example headless -- [out.png]`

use runner::app::driver::FrameDriver;
use runner::app::headless::{FORMAT, Offscreen};
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use runner::vulkan::{Context, ContextOptions};

fn main() -> anyhow::Result<()> {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "headless.png".into());
    let ctx = Context::new(ContextOptions {
        validation: false,
        checks: Default::default(),
        surface_extensions: &[],
        window: None,
    })?;
    // 20,000 blades on the built-in hills; a `SceneKind::File` loads glTF or OBJ.
    let scene = Scene::build(
        &SceneKind::Hills,
        None,
        BladeCount::Total(20_000),
        1,
        |_| Ok(()),
    )?;
    let (width, height) = (640, 360);
    let mut target = Offscreen::new(&ctx, width, height)?;
    let mut driver = FrameDriver::new(&ctx, Renderer::new(&ctx, &scene.meshes(), FORMAT)?)?;
    let settings = scene.settings();
    let eye = scene.camera().viewpoint(target.size());
    // Two seconds at 60 frames a second, the last one captured.
    for frame in 0..120 {
        let request = settings.request(&eye, &[]);
        driver.run(&mut target, 1.0 / 60.0, |_| request.clone(), frame == 119)?;
    }
    driver.finish()?;
    let rgba = target.pixels()?;
    image::save_buffer(&out, &rgba, width, height, image::ColorType::Rgba8)?;
    println!("wrote {out}");
    Ok(())
}

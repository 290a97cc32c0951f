//! The ash renderer of the grass field.
//!
//! The file tree reads like the frame: [`vulkan`] is the low layer (the only raw
//! Vulkan calls), [`field`] the GPU buffers of the blades, [`passes`] the passes of a
//! frame in order, [`renderer`] records one frame start to end, and [`app`] the
//! frame driver (`app::driver`: slots, submission, presentation or capture, the
//! simulation clock, read-back) and the shells that use it (window viewer, `render`,
//! `bench`, `soak`); [`tiles`] the tiled field's host side (issue 19) and [`paint`]
//! its painted maps.
//! The settings are typed (`shared::settings`) and become the
//! shaders' numbers in one place, `Settings::uniforms`.
//!
//! # Rendering from your own program
//!
//! The library drives a frame the way `grass render` does: a [`vulkan::Context`] (the
//! device), a [`scene::Scene`] (the surface and its blades, or a tiled field), a
//! [`renderer::Renderer`] made for it, and a frame driver
//! ([`app::driver::FrameDriver`]) that steps the simulation at a fixed step and
//! records, submits and reads back each frame, here into an offscreen image
//! ([`app::headless::Offscreen`]):
//!
//! ```no_run
//! use runner::app::driver::FrameDriver;
//! use runner::app::headless::{FORMAT, Offscreen};
//! use runner::renderer::Renderer;
//! use runner::scene::{BladeCount, Scene, SceneKind};
//! use runner::vulkan::{Context, ContextOptions};
//!
//! # fn main() -> anyhow::Result<()> {
//! let ctx = Context::new(ContextOptions {
//!     validation: false,
//!     checks: Default::default(),
//!     surface_extensions: &[],
//!     window: None,
//! })?;
//! // 20,000 blades on the built-in hills; a `SceneKind::File` loads glTF or OBJ.
//! let scene = Scene::build(&SceneKind::Hills, None, BladeCount::Total(20_000), 1, |_| Ok(()))?;
//! let mut target = Offscreen::new(&ctx, 640, 360)?;
//! let mut driver = FrameDriver::new(&ctx, Renderer::new(&ctx, &scene.meshes(), FORMAT)?)?;
//! let settings = scene.settings();
//! let eye = scene.camera().viewpoint(target.size());
//! // Two seconds at 60 frames a second, the last one captured.
//! for frame in 0..120 {
//!     let uniforms = settings.uniforms(&eye, scene.blade_count(), &[]);
//!     driver.run(&mut target, 1.0 / 60.0, |_| uniforms, frame == 119)?;
//! }
//! driver.finish()?;
//! let rgba: Vec<u8> = target.pixels()?; // 640 x 360, sRGB, row by row
//! # let _ = rgba;
//! # Ok(())
//! # }
//! ```
//!
//! Drawing this grass into a frame of your own device and targets is not offered yet
//! (issue 20).

pub mod app;
pub mod camera;
pub mod cli;
pub mod collider;
pub mod config;
pub mod field;
pub mod paint;
pub mod parse;
pub mod passes;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod tiles;
pub mod vulkan;

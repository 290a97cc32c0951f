//! The ash renderer of the grass field.
//!
//! The file tree reads like the frame: [`vulkan`] is the low layer (the only raw
//! Vulkan calls), [`field`] the GPU buffers of the blades, [`passes`] the passes of a
//! frame in order, [`renderer`] records one frame start to end, and [`app`] the
//! frame driver (`app::driver`: slots, submission, presentation or capture, the
//! simulation clock, read-back) and the shells that use it (window viewer, `render`,
//! `bench`, `soak`); [`tiles`] the tiled field's host side and [`paint`]
//! its painted maps; [`embed`] the field in someone else's frame.
//! The settings are typed (`shared::settings`); a frame is asked for with them
//! (`shared::plan::FrameRequest`), the renderer plans it (`shared::plan::FramePlan`,
//! which it branches on) and builds the shaders' numbers in one place,
//! `Settings::uniforms`.
//!
//! # Features
//!
//! - `app` (default): the `grass` program and what only it uses: the window viewer
//!   and its egui overlay, the headless commands and their charts, and the frame
//!   driver ([`app`]). Without it (`default-features = false`) the library keeps
//!   the renderer and [`embed`], and builds with far fewer crates.
//! - `rebuild-shaders`: the shaders compiled from `shaders-rs` by rust-gpu (the
//!   pinned nightly) instead of the SPIR-V kept in `runner/spirv`.
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
//!     let request = settings.request(&eye, &[]);
//!     driver.run(&mut target, 1.0 / 60.0, |_| request.clone(), frame == 119)?;
//! }
//! driver.finish()?;
//! let rgba: Vec<u8> = target.pixels()?; // 640 x 360, sRGB, row by row
//! # let _ = rgba;
//! # Ok(())
//! # }
//! ```
//!
//! # Grass in your own renderer
//!
//! [`embed::GrassField`] puts the grass into a frame of your own ash program: your
//! instance, device, queue, gpu-allocator, command buffer and colour and depth
//! images. The field says what it needs before anything is made, and what is
//! missing; [`embed`] has the whole contract, `runner/examples/embed/` a whole
//! program (a spinning cube of its own and the grass, in a window or headless).
//!
//! ```no_run
//! use ash::vk;
//! use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
//! use runner::embed::{self, FieldDesc, Frame, GrassField, Ground, Targets};
//! use shared::sim::collide::Collider;
//! use std::sync::{Arc, Mutex};
//!
//! # fn your_renderer(
//! #     entry: ash::Entry,
//! #     instance: ash::Instance,
//! #     physical: vk::PhysicalDevice,
//! #     queue_family: u32,
//! #     (cmd, color, depth, extent): (vk::CommandBuffer, vk::ImageView, vk::ImageView, vk::Extent2D),
//! #     (view, proj): (glam::Mat4, glam::Mat4),
//! # ) -> anyhow::Result<()> {
//! let format = vk::Format::B8G8R8A8_SRGB; // your colour images'
//! // 1. What the grass needs of this device, asked before anything is made: the
//! //    features to enable, or an error naming everything it lacks.
//! let mut features = embed::requirements(&instance, physical, format)?;
//!
//! // 2. Your device, made with them (add your own features and extensions).
//! let priorities = [1.0];
//! let queues = [vk::DeviceQueueCreateInfo::default()
//!     .queue_family_index(queue_family)
//!     .queue_priorities(&priorities)];
//! let extensions: Vec<_> = features.extensions().iter().map(|e| e.as_ptr()).collect();
//! let info = vk::DeviceCreateInfo::default()
//!     .queue_create_infos(&queues)
//!     .enabled_extension_names(&extensions);
//! let device = unsafe { instance.create_device(physical, &features.enable(info), None)? };
//! let allocator = Arc::new(Mutex::new(Allocator::new(&AllocatorCreateDesc {
//!     instance: instance.clone(),
//!     device: device.clone(),
//!     physical_device: physical,
//!     debug_settings: Default::default(),
//!     buffer_device_address: false,
//!     allocation_sizes: Default::default(),
//! })?));
//!
//! // 3. The field: 100,000 blades on the built-in hills (or `Ground::Mesh(yours)`).
//! let queue = unsafe { device.get_device_queue(queue_family, 0) };
//! let device = embed::Device { entry, instance, physical, device, queue_family, queue, allocator };
//! let desc = FieldDesc {
//!     ground: Ground::Hills,
//!     blades: 100_000,
//!     seed: 1,
//!     species: shared::species::Mix::GRASS, // or e.g. Mix::new([12, 0, 2, 3]): flowers, seed grass
//!     color_format: format,
//!     draw_ground: true,
//!     tiled: false, // true: generated tile by tile around the camera, to the horizon
//!     reverse_z: false, // true: your depth is 1 near, 0 far
//! };
//! let mut field = GrassField::new(device, &features, desc)?;
//!
//! // 4. Each frame, after your own drawing into `color` and `depth` (D32_SFLOAT),
//! //    outside a rendering scope: simulate, cull and draw the blades over it.
//! field.record(cmd, &Frame {
//!     targets: Targets { color, depth, extent },
//!     camera: embed::viewpoint(view, proj, extent.height),
//!     seconds: 1.0 / 60.0,
//!     // A ball: centre, radius (capsules and boxes too).
//!     colliders: &[Collider::sphere(glam::Vec3::new(0.0, 1.0, 0.0), 1.5)],
//! })?;
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod answers;
#[cfg(feature = "app")]
pub mod app;
#[cfg(feature = "bevy")]
pub mod bevy;
pub mod camera;
pub mod cli;
pub mod collider;
pub mod config;
pub mod embed;
pub mod field;
pub mod files;
pub mod paint;
pub mod parse;
pub mod passes;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod tiles;
pub mod vulkan;
pub mod walkers;

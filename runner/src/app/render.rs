//! Headless rendering: an offscreen colour image, N frames at 1/60 s, a PNG of the last.

use crate::cli::{Common, RenderArgs};
use crate::collider::Ball;
use crate::renderer::{CullCounts, FrameInput, PassTimes, Renderer, Target};
use crate::vulkan::{Buffer, Context, Image};
use anyhow::{Context as _, Result, bail};
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::layout::SimulatePush;
use shared::simulate::SimClock;
use std::sync::Arc;

/// Colour format of the offscreen image (written to PNG as is).
pub const FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// What a headless render produced.
pub struct RenderReport {
    /// RGBA8 pixels, sRGB, row-major.
    pub pixels: Vec<u8>,
    /// Visible blades in the last frame.
    pub visible: u32,
    /// What the culling tests did in the last frame.
    pub counts: CullCounts,
    /// GPU time per pass of the last frame, where the device has timestamps.
    pub times: Option<PassTimes>,
    /// Blades in the field.
    pub blades: u32,
    /// Validation errors reported (0 without validation).
    pub validation_errors: u32,
    /// World to clip of the camera, for tests that locate things in the image.
    pub view_proj: glam::Mat4,
}

/// Renders as `args` asks and writes the PNG.
pub fn run(common: &Common, args: &RenderArgs) -> Result<RenderReport> {
    super::check_output(&args.out, &["png"])?;
    let report = render(common, args)?;
    image::save_buffer(
        &args.out,
        &report.pixels,
        args.width,
        args.height,
        image::ColorType::Rgba8,
    )
    .with_context(|| format!("write {}", args.out.display()))?;
    log::info!(
        "wrote {} ({}x{}, {} frames, {} of {} blades visible)",
        args.out.display(),
        args.width,
        args.height,
        args.frames,
        report.visible,
        report.blades
    );
    log::info!("last frame: {}", describe(&report.counts));
    if let Some(t) = report.times {
        log::info!(
            "GPU ms: uploads + depth pyramid {:.3}, simulate+cull {:.3}, ground {:.3}, grass {:.3}, total {:.3}",
            t.depth_pyramid,
            t.simulate_cull,
            t.ground,
            t.grass,
            t.total
        );
    }
    if report.validation_errors > 0 {
        bail!(
            "{} validation errors (see the log above)",
            report.validation_errors
        );
    }
    Ok(report)
}

/// "N drawn, removed: orientation a, frustum b, ... (total T)".
pub fn describe(c: &CullCounts) -> String {
    let removed: Vec<String> = c
        .by_test()
        .iter()
        .map(|(name, n)| format!("{name} {n}"))
        .collect();
    format!(
        "{} drawn, removed by {} (total {})",
        c.drawn,
        removed.join(", "),
        c.examined
    )
}

/// An offscreen colour target and the host-visible buffer its pixels are copied to.
pub struct Offscreen {
    /// The colour image.
    pub color: Image,
    /// Receives the pixels of a frame that asks for them.
    pub capture: Buffer,
}

impl Offscreen {
    /// A `width` × `height` target in [`FORMAT`].
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32) -> Result<Self> {
        let extent = vk::Extent2D { width, height };
        let color = Image::new(
            ctx,
            "offscreen colour",
            extent,
            FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let capture = Buffer::new(
            ctx,
            "capture",
            u64::from(width) * u64::from(height) * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self { color, capture })
    }

    /// The frame target (left ready for the capture copy).
    pub fn target(&self) -> Target {
        Target {
            image: self.color.image,
            view: self.color.view,
            extent: self.color.extent,
            final_layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        }
    }

    /// RGBA8 pixels of the last frame that asked for a capture (wait for it first).
    pub fn pixels(&self) -> Result<Vec<u8>> {
        let e = self.color.extent;
        self.capture.read::<u8>((e.width * e.height * 4) as usize)
    }
}

/// Renders as `args` asks and returns the pixels of the last frame, writing nothing.
pub fn render(common: &Common, args: &RenderArgs) -> Result<RenderReport> {
    let (file, ctx) = super::open_headless(common)?;
    let (scene, settings) = super::prepare(common, &ctx, file)?;
    let count = scene.blade_count();
    let mut camera = scene.camera();
    camera.distance /= args.zoom;
    camera.yaw = args.yaw.map_or(camera.yaw, f32::to_radians);
    camera.pitch = args.pitch.map_or(camera.pitch, f32::to_radians);
    // Made before the renderer, so it is dropped after it: the renderer's drop waits
    // for the GPU, which may still be drawing into it when a frame fails.
    let offscreen = Offscreen::new(&ctx, args.width, args.height)?;
    let mut renderer = Renderer::new(&ctx, &scene, FORMAT)?;
    let target = offscreen.target();
    let aspect = args.width as f32 / args.height as f32;
    let mut clock = SimClock::default();
    let progress_every = (args.frames / 10).max(1);
    for frame in 0..args.frames {
        let slot = renderer.begin_frame()?;
        let (first_step, steps) = clock.advance(1.0 / 60.0);
        let last = frame + 1 == args.frames;
        let push = SimulatePush { first_step, steps };
        // The ball's place at this frame's time along its path.
        let ball = common.collider_path.as_ref().and_then(|path| {
            let travelled = common.collider_speed * clock.time();
            Ball::dropped(&scene.solid, path.at(travelled), common.collider_radius)
        });
        let balls: Vec<_> = ball.iter().map(Ball::sphere).collect();
        let uniforms = settings.uniforms(&camera, (args.width, args.height), &scene, &balls);
        let input = FrameInput {
            capture: last.then_some(&offscreen.capture),
            ..FrameInput::headless(target, uniforms, push)
        };
        renderer.render(slot, input)?;
        if args.frames >= 100 && (frame + 1) % progress_every == 0 {
            log::info!("frame {}/{}", frame + 1, args.frames);
        }
    }
    renderer.finish()?;
    Ok(RenderReport {
        pixels: offscreen.pixels()?,
        visible: renderer.visible().unwrap_or(0),
        counts: renderer.counts.unwrap_or_default(),
        times: renderer.times,
        blades: count,
        validation_errors: ctx.validation_errors(),
        view_proj: camera.view_proj(aspect),
    })
}

//! `grass quality`: how close each anti-aliasing method comes to a supersampled
//! reference, measured rather than judged by eye.
//!
//! The reference is the same frame rendered `--scale` times larger in each axis with
//! the most samples the device has, then averaged down (a box filter over linear
//! light), from the same simulation state: the field settles for `--settle` frames,
//! then every frame measured is one of no time, the blades standing as they are. Each
//! method (temporal anti-aliasing, and 1, 2 and 4 samples per pixel, each once the
//! device's samples lower it) is measured three ways:
//!
//! - still: the mean difference (0..255 per channel) from the reference, camera still
//!   (temporal anti-aliasing once its history settled, `temporal::SETTLE_FRAMES`);
//! - turning: the same while the camera turns about the vertical by a third of a pixel
//!   a frame, over `--frames` frames (the temporal history carried from frame to
//!   frame, from the settled still one);
//! - shimmer: the mean difference between consecutive frames of that turn, beside the
//!   reference's own (what is left is the method's flicker).

use super::bench::mean_difference;
use super::driver::FrameDriver;
use super::headless::Offscreen;
use super::render::Headless;
use crate::cli::{Common, QualityArgs};
use anyhow::{Context as _, Result};
use glam::Quat;
use shared::draw::shade::{linear_to_srgb, srgb_to_linear};
use shared::settings::{Antialiasing, Settings, Viewpoint};
use std::fmt::Write as _;

/// One method's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodQuality {
    /// Its name (`msaa4`).
    pub method: String,
    /// Samples per pixel it drew with (lowered to what the device has).
    pub samples: u32,
    /// Mean difference from the reference, camera still.
    pub still: f64,
    /// Mean difference from the reference over the turn.
    pub turning: f64,
    /// Mean difference between consecutive frames of the turn.
    pub shimmer: f64,
    /// The reference's own over the same turn.
    pub reference_shimmer: f64,
}

/// Measures as `args` asks, prints the table and writes the CSV (and the crops).
pub fn run(common: &Common, args: &QualityArgs) -> Result<Vec<MethodQuality>> {
    crate::files::check_output(&args.out, &["csv"])?;
    if common.msaa.is_some() || common.aa.is_some() {
        anyhow::bail!(
            "--aa, --msaa: quality measures temporal anti-aliasing and 1, 2 and 4 samples \
             per pixel itself"
        );
    }
    if args.camera.orbit != 0.0 {
        anyhow::bail!("--orbit: quality turns the camera itself, a third of a pixel a frame");
    }
    let size = (args.width, args.height);
    let mut run = Headless::open(common, size, &args.camera, &Default::default())?;
    let big = (args.width * args.scale, args.height * args.scale);
    let mut reference_target = Offscreen::new(&run.ctx, big.0, big.1)
        .with_context(|| format!("a reference target of {}x{}", big.0, big.1))?;
    for _ in 0..args.settle {
        run.frame(1.0 / 60.0, false)?;
    }
    let base = (run.eye_at)(0.0);
    // A third of a pixel a frame: the horizontal field of view over the width.
    let aspect = args.width as f32 / args.height as f32;
    let fov_x = 2.0 * ((0.5 * base.fov_y).tan() * aspect).atan();
    let step = fov_x / args.width as f32 / 3.0;
    let turn: Vec<f32> = (0..=args.frames).map(|k| k as f32 * step).collect();
    let most = run.ctx.supported_samples(8);
    let mut reference_settings = run.settings;
    reference_settings.look.aa = Antialiasing::Msaa;
    reference_settings.look.msaa = most;
    // Drawn at its own size, whatever --render-scale asks of the methods.
    reference_settings.look.render_scale = 1.0;
    // The orientation test's guard counts the shown frame's pixels: the reference
    // removes the same edge-on blades.
    reference_settings.cull.edge_on_pixels *= args.scale as f32;
    log::info!(
        "reference: {}x{} at {most} samples, averaged down to {}x{}",
        big.0,
        big.1,
        args.width,
        args.height
    );
    let mut reference = Vec::new();
    for &angle in &turn {
        let eye = turned(&base, angle, big.1);
        let pixels = still(
            &mut run.driver,
            &mut reference_target,
            &reference_settings,
            eye,
        )?;
        reference.push(downsample(&pixels, big, args.scale));
    }
    let mut results: Vec<MethodQuality> = Vec::new();
    let methods = [
        (Antialiasing::Taa, 1),
        (Antialiasing::Msaa, 1),
        (Antialiasing::Msaa, 2),
        (Antialiasing::Msaa, 4),
    ];
    for (aa, samples) in methods {
        let drawn = run.ctx.supported_samples(samples);
        let method = match aa {
            Antialiasing::Taa => "taa".to_owned(),
            _ => format!("msaa{samples}"),
        };
        let msaa = aa == Antialiasing::Msaa;
        if msaa
            && results
                .iter()
                .any(|r| r.method != "taa" && r.samples == drawn)
        {
            log::warn!("{method}: the device draws it with {drawn} samples, measured already");
            continue;
        }
        let mut settings = run.settings;
        settings.look.aa = aa;
        settings.look.msaa = samples;
        let mut frames = Vec::new();
        for (k, &angle) in turn.iter().enumerate() {
            let eye = turned(&base, angle, args.height);
            let request = settings.request(&eye, &[]);
            // The history settles on the still camera, then follows the turn.
            frames.push(if k == 0 {
                super::bench::still(&mut run.driver, &mut run.offscreen, request)?
            } else {
                one_frame(&mut run.driver, &mut run.offscreen, request)?
            });
        }
        let quality = measure(method, drawn, &frames, &reference);
        if let Some(dir) = &args.crops {
            write_crop(dir, &quality.method, &reference[0], &frames[0], size)?;
        }
        results.push(quality);
    }
    let errors = run.ctx.validation_errors();
    if errors > 0 {
        anyhow::bail!("{errors} validation errors (see the log above)");
    }
    print!("{}", table(&results, args));
    std::fs::write(&args.out, csv(&results))
        .with_context(|| format!("write {}", args.out.display()))?;
    log::info!("wrote {}", args.out.display());
    Ok(results)
}

/// One frame of no time of `settings` seen from `eye` into `target`, its pixels.
fn still(
    driver: &mut FrameDriver,
    target: &mut Offscreen,
    settings: &Settings,
    eye: Viewpoint,
) -> Result<Vec<u8>> {
    one_frame(driver, target, settings.request(&eye, &[]))
}

/// One frame of no time of `request` into `target`, its pixels.
fn one_frame(
    driver: &mut FrameDriver,
    target: &mut Offscreen,
    request: shared::plan::FrameRequest,
) -> Result<Vec<u8>> {
    driver.run(target, 0.0, |_| request.clone(), true)?;
    driver.finish()?;
    target.pixels()
}

/// `base` turned about the vertical by `angle` radians, for a target `height` pixels
/// high (the same place and field of view).
fn turned(base: &Viewpoint, angle: f32, height: u32) -> Viewpoint {
    let rotation = glam::Mat4::from_translation(base.position)
        * glam::Mat4::from_quat(Quat::from_rotation_y(angle))
        * glam::Mat4::from_translation(-base.position);
    Viewpoint {
        view_proj: base.view_proj * rotation.inverse(),
        forward: Quat::from_rotation_y(angle) * base.forward,
        height,
        ..*base
    }
}

/// The figures of `frames` (the still frame first, then the turn) against the
/// `reference` frames of the same cameras.
pub fn measure(
    method: String,
    samples: u32,
    frames: &[Vec<u8>],
    reference: &[Vec<u8>],
) -> MethodQuality {
    let mean = |pairs: Vec<f64>| pairs.iter().sum::<f64>() / pairs.len().max(1) as f64;
    let turning = mean(
        (1..frames.len())
            .map(|k| mean_difference(&frames[k], &reference[k]))
            .collect(),
    );
    let shimmer_of = |f: &[Vec<u8>]| {
        mean(
            (2..f.len())
                .map(|k| mean_difference(&f[k], &f[k - 1]))
                .collect(),
        )
    };
    MethodQuality {
        method,
        samples,
        still: mean_difference(&frames[0], &reference[0]),
        turning,
        shimmer: shimmer_of(frames),
        reference_shimmer: shimmer_of(reference),
    }
}

/// RGBA8 sRGB `pixels` of `size` averaged down by `scale` in each axis, in linear
/// light (a box filter).
pub fn downsample(pixels: &[u8], (width, height): (u32, u32), scale: u32) -> Vec<u8> {
    let table: Vec<f32> = (0..=255u8)
        .map(|c| srgb_to_linear(f32::from(c) / 255.0))
        .collect();
    let (w, h, s) = (width / scale, height / scale, scale as usize);
    let mut out = vec![255u8; (w * h * 4) as usize];
    let weight = 1.0 / (s * s) as f32;
    for y in 0..h as usize {
        for x in 0..w as usize {
            let mut sum = [0.0f32; 3];
            for dy in 0..s {
                let row = (y * s + dy) * width as usize;
                for dx in 0..s {
                    let p = &pixels[(row + x * s + dx) * 4..][..3];
                    for c in 0..3 {
                        sum[c] += table[p[c] as usize];
                    }
                }
            }
            let o = &mut out[(y * w as usize + x) * 4..][..3];
            for c in 0..3 {
                o[c] = (linear_to_srgb((sum[c] * weight).clamp(0.0, 1.0)) * 255.0).round() as u8;
            }
        }
    }
    out
}

/// Writes `dir/quality-<method>.png`: the middle third of the reference and of the
/// method's frame side by side, each pixel shown as a 3x3 block.
fn write_crop(
    dir: &std::path::Path,
    method: &str,
    reference: &[u8],
    frame: &[u8],
    (width, height): (u32, u32),
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
    let (cw, ch, zoom) = (width / 3, height / 3, 3u32);
    let (x0, y0) = (width / 3, height / 3);
    let out_w = 2 * cw * zoom;
    let mut out = vec![0u8; (out_w * ch * zoom * 4) as usize];
    for (side, image) in [reference, frame].into_iter().enumerate() {
        for y in 0..ch * zoom {
            for x in 0..cw * zoom {
                let src = (((y0 + y / zoom) * width + x0 + x / zoom) * 4) as usize;
                let dst = ((y * out_w + side as u32 * cw * zoom + x) * 4) as usize;
                out[dst..dst + 4].copy_from_slice(&image[src..src + 4]);
            }
        }
    }
    let path = dir.join(format!("quality-{method}.png"));
    crate::files::save_png(&path, &out, (out_w, ch * zoom), image::ColorType::Rgba8)
}

/// The table printed.
fn table(results: &[MethodQuality], args: &QualityArgs) -> String {
    let mut s = format!(
        "anti-aliasing against a {}x supersampled reference, {}x{}, {} frames turning a \
         third of a pixel each (mean difference, 0..255):\n",
        args.scale, args.width, args.height, args.frames
    );
    let _ = writeln!(
        s,
        "{:<8} {:>7} {:>7} {:>8} {:>8} {:>10}",
        "method", "samples", "still", "turning", "shimmer", "reference"
    );
    for r in results {
        let _ = writeln!(
            s,
            "{:<8} {:>7} {:>7.3} {:>8.3} {:>8.3} {:>10.3}",
            r.method, r.samples, r.still, r.turning, r.shimmer, r.reference_shimmer
        );
    }
    s
}

/// The CSV written.
fn csv(results: &[MethodQuality]) -> String {
    let mut s = String::from("method,samples,still,turning,shimmer,reference_shimmer\n");
    for r in results {
        let _ = writeln!(
            s,
            "{},{},{:.4},{:.4},{:.4},{:.4}",
            r.method, r.samples, r.still, r.turning, r.shimmer, r.reference_shimmer
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_linear_light() {
        // A 2x2 block of black and white averages to half the light: sRGB 188.
        let px = |v: u8| [v, v, v, 255];
        let pixels: Vec<u8> = [px(0), px(255), px(255), px(0)].concat();
        let out = downsample(&pixels, (2, 2), 2);
        assert_eq!(&out[..3], &[188, 188, 188]);
        // Uniform blocks stay what they are.
        let grey: Vec<u8> = [px(90); 4].concat();
        assert_eq!(&downsample(&grey, (2, 2), 2)[..3], &[90, 90, 90]);
    }

    #[test]
    fn the_figures_by_hand() {
        let frame = |v: u8| vec![v, v, v, 255];
        let frames = [frame(10), frame(20), frame(10)];
        let reference = [frame(10), frame(10), frame(10)];
        let q = measure("m".into(), 1, &frames, &reference);
        assert_eq!(q.still, 0.0);
        // Turned frames 20 and 10 against 10 and 10.
        assert_eq!(q.turning, 5.0);
        // One step between turned frames: 20 to 10.
        assert_eq!(q.shimmer, 10.0);
        assert_eq!(q.reference_shimmer, 0.0);
    }
}

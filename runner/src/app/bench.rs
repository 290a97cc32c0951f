//! `grass bench`: headless sweeps of blade counts and culling configurations from
//! fixed camera presets, timed per pass by GPU timestamps and per frame on the CPU,
//! reported as medians and 95th percentiles in a table and a CSV file.

use super::render::{FORMAT, Offscreen};
use crate::camera::OrbitCamera;
use crate::cli::{BenchArgs, BenchConfig, CameraPreset, Common};
use crate::field::Field;
use crate::renderer::{FrameInput, PassTimes, Renderer};
use crate::scene::{BladeCount, Scene, Settings};
use crate::vulkan::Context;
use anyhow::{Context as _, Result};
use glam::Vec3;
use shared::layout::SimulatePush;
use shared::simulate::SimClock;
use std::io::Write;
use std::time::Instant;

/// Most blades swept by default on a software device (lavapipe draws about half a
/// million triangles a second).
pub const SOFTWARE_MAX_BLADES: u32 = 1 << 13;

/// The median and 95th percentile of some samples.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Spread {
    /// 50th percentile.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
}

impl Spread {
    /// Nearest-rank percentiles of `samples` (zero when empty).
    pub fn of(samples: &[f64]) -> Self {
        let mut sorted: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        let rank = |p: f64| {
            if sorted.is_empty() {
                0.0
            } else {
                let i = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
                sorted[i - 1]
            }
        };
        Self {
            median: rank(0.5),
            p95: rank(0.95),
        }
    }
}

/// One measured point of the sweep.
#[derive(Clone, Debug)]
pub struct Point {
    /// Configuration.
    pub config: BenchConfig,
    /// Blades in the field.
    pub blades: u32,
    /// Blades drawn (median).
    pub drawn: f64,
    /// CPU time between frames.
    pub cpu: Spread,
    /// Whole frame on the GPU.
    pub gpu: Spread,
    /// Uniform uploads, depth pre-pass and pyramid.
    pub pyramid: Spread,
    /// Simulate, cull, compact.
    pub simulate_cull: Spread,
    /// Ground.
    pub ground: Spread,
    /// Grass.
    pub grass: Spread,
}

/// The camera of `preset` over `scene`.
pub fn camera(scene: &Scene, preset: CameraPreset) -> OrbitCamera {
    let (centre, radius) = scene.bounds;
    let mut camera = scene.camera();
    camera.target = centre + Vec3::new(0.0, 0.5, 0.0);
    match preset {
        // Just outside the field's edge, about two units up, looking across it.
        CameraPreset::Edge => {
            camera.distance = radius * 0.75 + 1.0;
            camera.pitch = (2.0 / camera.distance).atan();
        }
        // High above, the whole field in view.
        CameraPreset::Overview => {
            camera.pitch = 55f32.to_radians();
            camera.distance = radius / (0.5 * camera.fov_y).sin() * 1.05;
        }
    }
    camera
}

/// The settings of `config`: which tests run and whether LOD does.
pub fn configure(settings: &mut Settings, config: BenchConfig) {
    let (mask, lod) = config.switches();
    settings.cull = mask;
    settings.lod = lod;
}

/// The blade counts to sweep: as asked, else powers of two from 2^10 to 2^22, up to
/// what the device's buffers hold (and [`SOFTWARE_MAX_BLADES`] on a software device).
fn counts(common: &Common, args: &BenchArgs, ctx: &Context) -> Vec<u32> {
    if let Some(n) = common.blades {
        return vec![n];
    }
    if !args.counts.is_empty() {
        return args.counts.clone();
    }
    let cap = if ctx.is_software() {
        log::info!(
            "software device {}: sweeping up to {SOFTWARE_MAX_BLADES} blades (--counts to choose)",
            ctx.device_name()
        );
        SOFTWARE_MAX_BLADES
    } else {
        u32::MAX
    };
    (10..=22)
        .map(|p| 1u32 << p)
        .filter(|&n| n <= cap && Field::check_limits(ctx, u64::from(n)).is_ok())
        .collect()
}

/// Runs the sweep, prints the table and writes the CSV.
pub fn run(common: &Common, args: &BenchArgs) -> Result<Vec<Point>> {
    let (file, ctx) = super::open_headless(common)?;
    let counts = counts(common, args, &ctx);
    for &n in &counts {
        Field::check_limits(&ctx, u64::from(n))?;
    }
    let configs = if args.configs.is_empty() {
        BenchConfig::ALL.to_vec()
    } else {
        args.configs.clone()
    };
    let total = counts.len() * configs.len();
    let offscreen = Offscreen::new(&ctx, args.width, args.height)?;
    let aspect = args.width as f32 / args.height as f32;
    let mut points = Vec::new();
    let mut reference = None;
    let progress = Progress::new(total);
    for &n in &counts {
        // The file was checked before the device opened; read again for each count.
        let file = if file.is_some() {
            common.scene_kind().read()?
        } else {
            None
        };
        let scene = Scene::build(
            &common.scene_kind(),
            file,
            BladeCount::Total(n),
            common.seed,
            |_| Ok(()),
        )?;
        let base = super::settings(common, &scene);
        let camera = camera(&scene, args.camera);
        let mut renderer = Renderer::new(&ctx, &scene, FORMAT)?;
        for &config in &configs {
            progress.show(points.len(), &format!("{config:?} at {n} blades"));
            let mut settings = base;
            configure(&mut settings, config);
            let uniforms = settings.uniforms(&camera, aspect, &scene, &[]);
            // The last frame of the last point is kept: the preset's picture.
            let capture = points.len() + 1 == total;
            let point = measure(
                &mut renderer,
                &offscreen,
                uniforms,
                args,
                config,
                n,
                capture,
            )?;
            points.push(point);
        }
        if Some(&n) == counts.last() {
            reference = renderer.copy_bandwidth(10)?.map(|gbs| (n, gbs));
        }
    }
    progress.done(total);
    let device = ctx.device_name();
    print_table(&device, args, &points);
    if let Some((n, gbs)) = reference {
        print_bandwidth(n, gbs, &points);
    }
    write_csv(&args.out, &device, common, args, &points)
        .with_context(|| format!("write {}", args.out.display()))?;
    log::info!("wrote {}", args.out.display());
    let title = format!(
        "{device}, {}x{}, camera {:?}",
        args.width, args.height, args.camera
    );
    let charts = super::charts::write(&args.out, &title, &points).context("draw the charts")?;
    let view = args.out.with_extension("view.png");
    let (w, h) = (args.width, args.height);
    image::save_buffer(&view, &offscreen.pixels()?, w, h, image::ColorType::Rgba8)
        .with_context(|| format!("write {}", view.display()))?;
    for path in charts.iter().chain([&view]) {
        log::info!("wrote {}", path.display());
    }
    Ok(points)
}

/// Warm-up, then `args.frames` frames of one configuration.
fn measure(
    renderer: &mut Renderer,
    offscreen: &Offscreen,
    uniforms: shared::layout::FrameUniforms,
    args: &BenchArgs,
    config: BenchConfig,
    blades: u32,
    capture: bool,
) -> Result<Point> {
    let mut clock = SimClock::default();
    let (mut cpu, mut times, mut drawn) = (Vec::new(), Vec::<PassTimes>::new(), Vec::new());
    let mut last = Instant::now();
    let slots = crate::renderer::FRAMES_IN_FLIGHT as u32;
    // Each slot's read-back is of its previous frame: skip those of the warm-up.
    let frames = args.warmup + args.frames + slots;
    for frame in 0..frames {
        let slot = renderer.begin_frame()?;
        let now = Instant::now();
        if frame >= args.warmup + slots {
            cpu.push(now.duration_since(last).as_secs_f64() * 1000.0);
            times.extend(renderer.times);
            drawn.extend(renderer.counts.map(|c| f64::from(c.drawn)));
        }
        last = now;
        let (first_step, steps) = clock.advance(1.0 / 60.0);
        let input = FrameInput {
            target: offscreen.target(),
            uniforms,
            push: SimulatePush { first_step, steps },
            wait: None,
            signal: None,
            capture: (capture && frame + 1 == frames).then_some(&offscreen.capture),
            overlay: None,
        };
        renderer.render(slot, input)?;
    }
    renderer.finish()?;
    let pass = |f: fn(&PassTimes) -> f64| Spread::of(&times.iter().map(f).collect::<Vec<_>>());
    Ok(Point {
        config,
        blades,
        drawn: Spread::of(&drawn).median,
        cpu: Spread::of(&cpu),
        gpu: pass(|t| t.total),
        pyramid: pass(|t| t.depth_pyramid),
        simulate_cull: pass(|t| t.simulate_cull),
        ground: pass(|t| t.ground),
        grass: pass(|t| t.grass),
    })
}

/// A progress bar on stderr.
struct Progress {
    total: usize,
    start: Instant,
}

impl Progress {
    fn new(total: usize) -> Self {
        Self {
            total,
            start: Instant::now(),
        }
    }

    fn show(&self, done: usize, what: &str) {
        let width = 30;
        let filled = done * width / self.total.max(1);
        eprint!(
            "\r[{}{}] {done}/{} {:.0} s, {what}          ",
            "#".repeat(filled),
            "-".repeat(width - filled),
            self.total,
            self.start.elapsed().as_secs_f64()
        );
        let _ = std::io::stderr().flush();
    }

    fn done(&self, total: usize) {
        self.show(total, "done");
        eprintln!();
    }
}

/// Bytes the simulate-and-cull pass moves for `blades` blades of which `drawn` survive:
/// each blade and its collision strength read and written (2 × 68 bytes), each
/// survivor written once more (64 bytes).
pub fn compute_bytes(blades: u32, drawn: f64) -> f64 {
    2.0 * 68.0 * f64::from(blades) + 64.0 * drawn
}

/// The compute pass's bandwidth at `blades` against the copy shader's `reference`.
fn print_bandwidth(blades: u32, reference: f64, points: &[Point]) {
    let line = format!(
        "bandwidth reference: the copy shader moves {reference:.0} GB/s over {blades} blades"
    );
    println!("{line}");
    log::info!("{line}");
    for p in points.iter().filter(|p| p.blades == blades) {
        let gbs = compute_bytes(blades, p.drawn) / (p.simulate_cull.median * 1e-3) / 1e9;
        println!(
            "  {:<20} simulate+cull {gbs:>7.0} GB/s, {:>5.1} % of the reference",
            format!("{:?}", p.config),
            100.0 * gbs / reference
        );
    }
}

fn print_table(device: &str, args: &BenchArgs, points: &[Point]) {
    println!(
        "{device}, {}x{}, camera {:?}, {} frames per point (median, p95 in brackets)",
        args.width, args.height, args.camera, args.frames
    );
    println!(
        "{:<20} {:>9} {:>9} {:>18} {:>18} {:>18} {:>18}",
        "config", "blades", "drawn", "simulate+cull ms", "grass ms", "GPU frame ms", "CPU frame ms"
    );
    let cell = |s: Spread| format!("{:.3} ({:.3})", s.median, s.p95);
    for p in points {
        println!(
            "{:<20} {:>9} {:>9.0} {:>18} {:>18} {:>18} {:>18}",
            format!("{:?}", p.config),
            p.blades,
            p.drawn,
            cell(p.simulate_cull),
            cell(p.grass),
            cell(p.gpu),
            cell(p.cpu)
        );
    }
}

fn write_csv(
    path: &std::path::Path,
    device: &str,
    common: &Common,
    args: &BenchArgs,
    points: &[Point],
) -> Result<()> {
    let mut out = String::from(
        "device,scene,camera,width,height,frames,config,blades,drawn,\
         cpu_ms_median,cpu_ms_p95,gpu_ms_median,gpu_ms_p95,\
         uploads_pyramid_ms_median,simulate_cull_ms_median,simulate_cull_ms_p95,\
         ground_ms_median,grass_ms_median,grass_ms_p95\n",
    );
    for p in points {
        out += &format!(
            "\"{device}\",{},{:?},{},{},{},{:?},{},{:.0},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}\n",
            common.scene,
            args.camera,
            args.width,
            args.height,
            args.frames,
            p.config,
            p.blades,
            p.drawn,
            p.cpu.median,
            p.cpu.p95,
            p.gpu.median,
            p.gpu.p95,
            p.pyramid.median,
            p.simulate_cull.median,
            p.simulate_cull.p95,
            p.ground.median,
            p.grass.median,
            p.grass.p95,
        );
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, out)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compute_bytes_by_hand() {
        // 1,000 blades × 136 bytes + 500 survivors × 64 bytes.
        assert_eq!(compute_bytes(1000, 500.0), 136_000.0 + 32_000.0);
    }

    #[test]
    fn percentiles_by_nearest_rank() {
        let samples: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(
            Spread::of(&samples),
            Spread {
                median: 10.0,
                p95: 19.0
            }
        );
        assert_eq!(
            Spread::of(&[3.0]),
            Spread {
                median: 3.0,
                p95: 3.0
            }
        );
        assert_eq!(Spread::of(&[]), Spread::default());
        // Order and non-finite samples do not matter.
        let shuffled = [5.0, f64::NAN, 1.0, 4.0, 2.0, 3.0];
        assert_eq!(Spread::of(&shuffled).median, 3.0);
    }
}

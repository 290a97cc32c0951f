//! `grass bench`: headless sweeps of blade counts and culling configurations from
//! fixed camera presets, timed per pass by GPU timestamps and per frame on the CPU,
//! reported as medians and 95th percentiles in a table and a CSV file.

use super::progress::Progress;
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
    /// Triangles the grass draw generated (median; pipeline statistics, where the
    /// device has them).
    pub triangles: Option<f64>,
    /// Mean difference from the same still frame with no culling and no LOD, in 8-bit
    /// levels averaged over the pixels' colour channels.
    pub difference: f64,
}

/// What this device does at most, measured in the same run with the largest field.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct References {
    /// The copy shader's bandwidth, GB/s.
    pub copy_gbs: Option<f64>,
    /// The throughput reference's cost per patch, ms.
    pub patch_ms: f64,
    /// Its cost per triangle, ms.
    pub triangle_ms: f64,
    /// Its best triangles per second (at the highest level).
    pub triangles_per_s: f64,
}

impl References {
    /// Per-patch and per-triangle cost from the reference's times `t_low` and `t_high`
    /// (ms) for `patches` patches of `low` and `high` triangles each:
    /// t = patches · (patch + triangles · triangle). Neither is below zero (timing
    /// noise on a software device can make a straight fit say so).
    pub fn fit(patches: f64, (low, t_low): (f64, f64), (high, t_high): (f64, f64)) -> (f64, f64) {
        let triangle = ((t_high - t_low) / (patches * (high - low))).max(0.0);
        let patch = (t_low / patches - low * triangle).max(0.0);
        (patch, triangle)
    }

    /// What the reference would take to draw `patches` patches making `triangles`.
    pub fn grass_ms(&self, patches: f64, triangles: f64) -> f64 {
        patches * self.patch_ms + triangles * self.triangle_ms
    }
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
    super::check_output(&args.out, &["csv"])?;
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
    let mut points = Vec::new();
    let mut references = References::default();
    let (mut view, mut unculled) = (Vec::new(), Vec::new());
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
        let uniforms = |config| {
            let mut settings = base;
            configure(&mut settings, config);
            settings.uniforms(&camera, (args.width, args.height), &scene, &[])
        };
        let first = points.len();
        for &config in &configs {
            progress.show(points.len(), &format!("{config:?} at {n} blades"));
            let point = measure(&mut renderer, &offscreen, uniforms(config), args, config, n)?;
            points.push(point);
        }
        // The blades as the sweep left them, without culling or LOD, then each
        // configuration in the same state.
        unculled = still(&mut renderer, &offscreen, uniforms(BenchConfig::None))?;
        for point in &mut points[first..] {
            view = still(&mut renderer, &offscreen, uniforms(point.config))?;
            point.difference = mean_difference(&view, &unculled);
        }
        if Some(&n) == counts.last() {
            progress.show(points.len(), "references");
            references = measure_references(&mut renderer, &offscreen, n)?;
        }
    }
    progress.done(total);
    let device = ctx.device_name();
    print_table(&device, args, &points);
    print_references(counts.last().copied().unwrap_or(0), &references, &points);
    write_csv(&args.out, &device, common, args, &points, &references)
        .with_context(|| format!("write {}", args.out.display()))?;
    log::info!("wrote {}", args.out.display());
    let title = format!(
        "{device}, {}x{}, camera {:?}",
        args.width, args.height, args.camera
    );
    let mut written =
        super::charts::write(&args.out, &title, &points).context("draw the charts")?;
    let (w, h) = (args.width, args.height);
    for (pixels, extension) in [(&view, "view.png"), (&unculled, "unculled.png")] {
        let path = args.out.with_extension(extension);
        image::save_buffer(&path, pixels, w, h, image::ColorType::Rgba8)
            .with_context(|| format!("write {}", path.display()))?;
        written.push(path);
    }
    for path in &written {
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
) -> Result<Point> {
    let mut clock = SimClock::default();
    let (mut cpu, mut times, mut drawn) = (Vec::new(), Vec::<PassTimes>::new(), Vec::new());
    let mut triangles = Vec::new();
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
            triangles.extend(renderer.triangles.map(|t| t as f64));
        }
        last = now;
        let (first_step, steps) = clock.advance(1.0 / 60.0);
        let push = SimulatePush { first_step, steps };
        renderer.render(
            slot,
            FrameInput::headless(offscreen.target(), uniforms, push),
        )?;
    }
    renderer.finish()?;
    let triangles = (!triangles.is_empty()).then(|| Spread::of(&triangles).median);
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
        triangles,
        difference: 0.0,
    })
}

/// One frame with no simulation step, captured: the picture of `uniforms` with the
/// blades exactly as they are.
fn still(
    renderer: &mut Renderer,
    offscreen: &Offscreen,
    uniforms: shared::layout::FrameUniforms,
) -> Result<Vec<u8>> {
    let slot = renderer.begin_frame()?;
    let still = SimulatePush {
        first_step: 0,
        steps: 0,
    };
    let input = FrameInput {
        capture: Some(&offscreen.capture),
        ..FrameInput::headless(offscreen.target(), uniforms, still)
    };
    renderer.render(slot, input)?;
    renderer.finish()?;
    offscreen.pixels()
}

/// Mean absolute difference of two RGBA8 images of one size, over the pixels' red,
/// green and blue channels, in 8-bit levels (0 to 255).
pub fn mean_difference(a: &[u8], b: &[u8]) -> f64 {
    let (sum, count) = a
        .as_chunks::<4>()
        .0
        .iter()
        .zip(b.as_chunks::<4>().0)
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c]) as u64))
        .fold((0u64, 0u64), |(s, n), d| (s + d, n + 1));
    if count == 0 {
        0.0
    } else {
        sum as f64 / count as f64
    }
}

/// Tessellation levels the throughput reference is timed at: the fewest and the most
/// segments a blade gets.
const REFERENCE_LEVELS: [f32; 2] = [1.0, shared::lod::MAX_LEVEL];

/// The bandwidth and triangle-throughput references over a field of `blades`.
fn measure_references(
    renderer: &mut Renderer,
    offscreen: &Offscreen,
    blades: u32,
) -> Result<References> {
    let repeats = 10;
    let copy_gbs = renderer.copy_bandwidth(repeats)?;
    let target = offscreen.target();
    let mut timed = Vec::new();
    for level in REFERENCE_LEVELS {
        let Some((ms, counted)) = renderer.triangle_throughput(&target, blades, level, repeats)?
        else {
            return Ok(References {
                copy_gbs,
                ..Default::default()
            });
        };
        // Per patch as counted, else as the tessellation rules give it.
        let triangles = counted.map_or(
            f64::from(shared::reference::triangles_per_patch(level)),
            |t| t as f64 / f64::from(blades),
        );
        log::info!(
            "triangle reference at level {level}: {triangles} triangles per patch, {ms:.3} ms"
        );
        timed.push((triangles, ms));
    }
    let patches = f64::from(blades);
    let (patch_ms, triangle_ms) = References::fit(patches, timed[0], timed[1]);
    let (most, ms) = timed[1];
    Ok(References {
        copy_gbs,
        patch_ms,
        triangle_ms,
        triangles_per_s: patches * most / (ms * 1e-3),
    })
}
/// Bytes the simulate-and-cull pass moves for `blades` blades of which `drawn` survive:
/// each blade and its collision strength read and written (2 × 68 bytes), each
/// survivor's index written (4 bytes).
pub fn compute_bytes(blades: u32, drawn: f64) -> f64 {
    2.0 * 68.0 * f64::from(blades) + 4.0 * drawn
}

/// The compute pass against the copy shader's bandwidth, and the grass draw against
/// the throughput reference, for every point of the largest count, `blades`.
fn print_references(blades: u32, r: &References, points: &[Point]) {
    let mut lines = Vec::new();
    if let Some(copy) = r.copy_gbs {
        lines.push(format!(
            "bandwidth reference: the copy shader moves {copy:.0} GB/s over {blades} blades"
        ));
    }
    if r.triangles_per_s > 0.0 {
        lines.push(format!(
            "triangle reference: {:.0} M triangles/s at {} segments; {:.2} ns per patch + {:.3} ns per triangle",
            r.triangles_per_s / 1e6,
            shared::lod::MAX_SEGMENTS,
            r.patch_ms * 1e6,
            r.triangle_ms * 1e6
        ));
    }
    for line in &lines {
        println!("{line}");
        log::info!("{line}");
    }
    for p in points.iter().filter(|p| p.blades == blades) {
        let mut line = format!("  {:<20}", format!("{:?}", p.config));
        if let Some(copy) = r.copy_gbs {
            let gbs = compute_gbs(p);
            line += &format!(
                " simulate+cull {gbs:>6.0} GB/s ({:>5.1} % of the copy)",
                100.0 * gbs / copy
            );
        }
        if let (Some(triangles), true) = (p.triangles, r.triangles_per_s > 0.0) {
            let ideal = r.grass_ms(p.drawn, triangles);
            line += &format!(
                "; grass {:.1} M triangles, reference {ideal:.3} ms ({:>5.1} % of its speed)",
                triangles / 1e6,
                100.0 * ideal / p.grass.median
            );
        }
        println!("{line}");
    }
}

/// The simulate-and-cull pass's bandwidth at point `p`, GB/s.
fn compute_gbs(p: &Point) -> f64 {
    compute_bytes(p.blades, p.drawn) / (p.simulate_cull.median * 1e-3) / 1e9
}

fn print_table(device: &str, args: &BenchArgs, points: &[Point]) {
    println!(
        "{device}, {}x{}, camera {:?}, {} frames per point (median, p95 in brackets; \
         diff: mean difference from no culling and no LOD, 0-255)",
        args.width, args.height, args.camera, args.frames
    );
    println!(
        "{:<20} {:>9} {:>9} {:>11} {:>18} {:>18} {:>18} {:>18} {:>6}",
        "config",
        "blades",
        "drawn",
        "triangles",
        "simulate+cull ms",
        "grass ms",
        "GPU frame ms",
        "CPU frame ms",
        "diff"
    );
    let cell = |s: Spread| format!("{:.3} ({:.3})", s.median, s.p95);
    for p in points {
        println!(
            "{:<20} {:>9} {:>9.0} {:>11} {:>18} {:>18} {:>18} {:>18} {:>6.2}",
            format!("{:?}", p.config),
            p.blades,
            p.drawn,
            p.triangles.map_or("-".into(), |t| format!("{t:.0}")),
            cell(p.simulate_cull),
            cell(p.grass),
            cell(p.gpu),
            cell(p.cpu),
            p.difference
        );
    }
}

fn write_csv(
    path: &std::path::Path,
    device: &str,
    common: &Common,
    args: &BenchArgs,
    points: &[Point],
    r: &References,
) -> Result<()> {
    let mut out = String::from(
        "device,scene,camera,width,height,frames,config,blades,drawn,\
         cpu_ms_median,cpu_ms_p95,gpu_ms_median,gpu_ms_p95,\
         uploads_pyramid_ms_median,simulate_cull_ms_median,simulate_cull_ms_p95,\
         ground_ms_median,grass_ms_median,grass_ms_p95,triangles,mean_difference,\
         simulate_cull_gb_s,copy_reference_gb_s,grass_reference_ms\n",
    );
    let optional =
        |v: Option<f64>, digits: usize| v.map_or(String::new(), |v| format!("{v:.digits$}"));
    for p in points {
        let reference_ms = p
            .triangles
            .filter(|_| r.triangles_per_s > 0.0)
            .map(|t| r.grass_ms(p.drawn, t));
        out += &format!(
            "\"{device}\",{},{:?},{},{},{},{:?},{},{:.0},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{:.3},{:.0},{},{}\n",
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
            optional(p.triangles, 0),
            p.difference,
            compute_gbs(p),
            optional(r.copy_gbs, 0),
            optional(reference_ms, 4),
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
        // 1,000 blades × 136 bytes + 500 survivors × 4 bytes.
        assert_eq!(compute_bytes(1000, 500.0), 136_000.0 + 2_000.0);
    }

    #[test]
    fn mean_difference_by_hand() {
        let black = [0, 0, 0, 255, 0, 0, 0, 255];
        // One pixel off by (30, 60, 90), alpha ignored: 180 / 6 channels.
        let other = [30, 60, 90, 0, 0, 0, 0, 255];
        assert_eq!(mean_difference(&black, &other), 30.0);
        assert_eq!(mean_difference(&other, &other), 0.0);
        assert_eq!(mean_difference(&[], &[]), 0.0);
    }

    #[test]
    fn reference_costs_from_two_levels() {
        // 1,000 patches: 0.01 ms each, plus 0.001 ms per triangle.
        let t = |triangles: f64| 1000.0 * (0.01 + triangles * 0.001);
        let (patch, triangle) = References::fit(1000.0, (2.0, t(2.0)), (18.0, t(18.0)));
        assert!((patch - 0.01).abs() < 1e-12 && (triangle - 0.001).abs() < 1e-12);
        let r = References {
            patch_ms: patch,
            triangle_ms: triangle,
            ..Default::default()
        };
        assert!((r.grass_ms(500.0, 4000.0) - (5.0 + 4.0)).abs() < 1e-9);
        // Noise that makes the higher level faster is no negative cost.
        assert_eq!(References::fit(10.0, (2.0, 5.0), (18.0, 4.0)), (0.5, 0.0));
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

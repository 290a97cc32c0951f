//! `grass bench`: headless sweeps of blade counts and culling configurations from
//! fixed camera presets, timed per pass by GPU timestamps and per frame on the CPU,
//! reported as medians and 95th percentiles in a table and a CSV file.
//!
//! This module drives the renderer through the sweep; [`stats`] holds the plain data
//! and arithmetic, [`report`] the table and the CSV file, [`charts`] the PNG charts.

pub mod charts;
mod references;
pub mod report;
pub mod stats;
pub mod table;

pub use stats::{Point, References, Spread, TriangleReference, compute_bytes, mean_difference};

use super::driver::{FRAMES_IN_FLIGHT, FrameDriver, FrameSpec};
use super::headless::{FORMAT, Offscreen};
use super::progress::Progress;
use crate::camera::OrbitCamera;
use crate::cli::{BenchArgs, BenchConfig, CameraPreset, Common};
use crate::field::Field;
use crate::renderer::{PassTimes, Renderer};
use crate::scene::{BladeCount, Scene, SceneKind};
use crate::vulkan::Context;
use anyhow::{Context as _, Result};
use glam::Vec3;
use report::{print_looks, print_raster, print_references, print_table, write_csv};
use shared::plan::FrameRequest;
use shared::settings::{Antialiasing, Look, Settings};
use shared::sim::simulate::SimClock;
use std::time::Instant;

/// Most blades swept by default on a software device (lavapipe draws about half a
/// million triangles a second).
pub const SOFTWARE_MAX_BLADES: u32 = 1 << 13;

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
        CameraPreset::Flight => return crate::scene::valley_camera(0.0),
    }
    camera
}

/// Units a second the flight camera travels down the valley's path.
pub const FLIGHT_SPEED: f32 = 6.0;

/// The settings of `config`: which tests run and whether LOD does.
pub fn configure(settings: &mut Settings, config: BenchConfig) {
    let (tests, lod) = config.switches();
    settings.cull.tests = tests;
    settings.lod.on = lod;
}

/// The blade counts to sweep: `--blades` or `--density` alone, else `--counts`, else
/// powers of two from 2^10 to 2^22, up to what the device's buffers hold (and
/// [`SOFTWARE_MAX_BLADES`] on a software device). A tiled field is one world: its
/// count is its tiles'.
fn counts(common: &Common, args: &BenchArgs, ctx: &Context) -> Result<Vec<BladeCount>> {
    let tiled = super::tiled(common, &common.scene_kind());
    if !args.counts.is_empty() {
        if tiled {
            anyhow::bail!("--counts: a tiled field is one world, its blades its tiles'");
        }
        if common.blade_count().is_some() {
            anyhow::bail!("--counts conflicts with --blades and --density (one count)");
        }
        for &n in &args.counts {
            Field::check_limits(ctx, u64::from(n))?;
        }
        return Ok(args.counts.iter().map(|&n| BladeCount::Total(n)).collect());
    }
    if let Some(count) = common.blade_count() {
        return Ok(vec![count]);
    }
    // The stored blades of a count of one are dropped for the tiles.
    if tiled {
        return Ok(vec![BladeCount::Total(1)]);
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
    Ok((10..=22)
        .map(|p| 1u32 << p)
        .filter(|&n| n <= cap && Field::check_limits(ctx, u64::from(n)).is_ok())
        .map(BladeCount::Total)
        .collect())
}

/// Runs the sweep, prints the table and writes the CSV.
pub fn run(common: &Common, args: &BenchArgs) -> Result<Vec<Point>> {
    crate::files::check_output(&args.out, &["csv"])?;
    let (file, ctx) = super::open_headless(common, common.validation_requested())?;
    let counts = counts(common, args, &ctx)?;
    let configs = if args.configs.is_empty() {
        BenchConfig::ALL.to_vec()
    } else {
        args.configs.clone()
    };
    let looks = if args.looks.is_empty() {
        vec![common.look]
    } else {
        args.looks.clone()
    };
    let choices = if args.pipelines.is_empty() {
        vec![common.pipeline]
    } else {
        args.pipelines.clone()
    };
    let pipelines = choices
        .iter()
        .map(|&choice| super::grass_pipeline(choice, &ctx.capabilities()))
        .collect::<Result<Vec<_>>>()?;
    let rasters = if args.compute_raster.is_empty() {
        vec![None]
    } else {
        args.compute_raster.iter().map(|&b| Some(b)).collect()
    };
    if let (true, Err(why)) = (
        rasters.iter().flatten().any(|&b| b > 0.0),
        &ctx.int64_atomics,
    ) {
        anyhow::bail!("--compute-raster: {why} (64-bit atomics for its visibility buffer)");
    }
    // With walkers or mowers, each point runs without them first, then with them.
    let crowds = if common.walkers > 0 || common.mowers > 0 {
        vec![false, true]
    } else {
        vec![false]
    };
    let total =
        counts.len() * configs.len() * looks.len() * pipelines.len() * rasters.len() * crowds.len();
    let mut offscreen = Offscreen::new(&ctx, args.width, args.height)?;
    let mut points = Vec::new();
    let mut references = References::default();
    let (mut view, mut unculled) = (Vec::new(), Vec::new());
    let progress = Progress::new(total);
    let mut last_count = 0;
    for (at, &count) in counts.iter().enumerate() {
        // The file was checked before the device opened; read again for each count.
        let file = if file.is_some() {
            common.scene_kind().read()?
        } else {
            None
        };
        if args.camera == CameraPreset::Flight && common.scene_kind() != SceneKind::Valley {
            anyhow::bail!("--camera flight flies over the valley: add --scene valley");
        }
        // Painted, tiled, grown as every command's scene is.
        let mut scene = super::build_scene(common, &ctx, file, count)?;
        let n = scene.blade_count();
        last_count = n;
        let base = super::device_settings(common, &scene, &ctx)?;
        let walkers = crate::walkers::Walkers::new(&scene, common.walkers);
        // The point with the crowd: the walkers and the mowers; without: none.
        let crowd_of = |crowd: bool| {
            let (w, m) = (common.walkers, common.mowers);
            walkers
                .with_count(if crowd { w } else { 0 })
                .with_mowers(if crowd { m } else { 0 })
        };
        let size = offscreen.size();
        let still_camera = camera(&scene, args.camera);
        let preset = args.camera;
        let eye = move |frame| match preset {
            CameraPreset::Flight => {
                crate::scene::valley_camera(FLIGHT_SPEED * frame as f32 / 60.0).viewpoint(size)
            }
            _ => still_camera.viewpoint(size),
        };
        for &look in &looks {
            // Each look on its own field, grown at its blade size.
            let _ = scene.rescale(scene.scale_for(look));
            let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT)?;
            let mut driver = FrameDriver::new(&ctx, renderer)?;
            // The paper look as the paper (and every figure before the natural look)
            // drew it, one sample per pixel and nothing blended, unless --aa or
            // --msaa says.
            let aa = match (look, common.aa, common.msaa) {
                (Look::Paper, None, None) => Antialiasing::None,
                _ => base.look.aa,
            };
            let msaa = if aa == Antialiasing::Msaa {
                base.look.msaa
            } else {
                1
            };
            let request = |(config, pipeline), raster: Option<f32>, crowd, frame: u32| {
                let mut settings = base;
                settings.look.style = look;
                settings.look.aa = aa;
                settings.look.msaa = msaa;
                settings.pipeline = pipeline;
                if let Some(below) = raster {
                    settings.compute_raster_below = below;
                }
                configure(&mut settings, config);
                // The measured frames step 1/60 s each from a clock started anew.
                let time = frame as f32 / 60.0;
                let walkers = crowd_of(crowd).colliders(&scene, time, 1.0 / 60.0);
                settings.request(&eye(frame), &[]).with_colliders(&walkers)
            };
            let first = points.len();
            for &config in &configs {
                for &pipeline in &pipelines {
                    for (&raster, &crowd) in rasters
                        .iter()
                        .flat_map(|r| crowds.iter().map(move |c| (r, c)))
                    {
                        let what = format!(
                            "{config:?}, {look:?} look, {pipeline:?}, at {n} blades{}",
                            if crowd {
                                ", with walkers and mowers"
                            } else {
                                ""
                            }
                        );
                        progress.show(points.len(), &what);
                        let frames = (&mut driver, &mut offscreen);
                        let frame = |f| request((config, pipeline), raster, crowd, f);
                        let mut point = measure(frames, &frame, args, config, n)?;
                        point.look = look;
                        point.pipeline = pipeline;
                        point.samples = ctx.supported_samples(msaa);
                        point.aa = aa;
                        point.walkers = crowd_of(crowd).count();
                        point.mowers = crowd_of(crowd).mowers();
                        points.push(point);
                    }
                }
            }
            // The blades as the sweep left them, without culling or LOD and all through
            // the hardware, then each configuration in the same state.
            let unculled_by: Vec<_> = pipelines
                .iter()
                .map(|&p| {
                    let frame = request((BenchConfig::None, p), Some(0.0), false, 0);
                    still(&mut driver, &mut offscreen, frame)
                })
                .collect::<Result<_>>()?;
            unculled = unculled_by[0].clone();
            for point in &mut points[first..] {
                let raster = Some(point.compute_below);
                view = still(
                    &mut driver,
                    &mut offscreen,
                    request(
                        (point.config, point.pipeline),
                        raster,
                        point.walkers + point.mowers > 0,
                        0,
                    ),
                )?;
                let at = pipelines.iter().position(|&p| p == point.pipeline);
                let unculled = &unculled_by[at.unwrap_or(0)];
                point.difference = mean_difference(&view, unculled);
            }
            if at + 1 == counts.len() && look == looks[0] {
                progress.show(points.len(), "references");
                references = references::measure_references(
                    &mut driver.renderer,
                    &offscreen,
                    n,
                    &pipelines,
                )?;
            }
        }
    }
    progress.done(total);
    let device = ctx.device_name();
    print_table(&device, args, &points);
    print_looks(&points);
    report::print_walkers(&points);
    print_raster(&points);
    print_references(last_count, &references, &points);
    write_csv(&args.out, &device, common, args, &points, &references)
        .with_context(|| format!("write {}", args.out.display()))?;
    log::info!("wrote {}", args.out.display());
    let title = format!(
        "{device}, {}x{}, camera {:?}",
        args.width, args.height, args.camera
    );
    // The charts show the first look's and pipeline's points.
    let charted: Vec<Point> = points
        .iter()
        .filter(|p| p.look == looks[0] && p.pipeline == pipelines[0])
        .cloned()
        .collect();
    let mut written = charts::write(&args.out, &title, &charted).context("draw the charts")?;
    let (w, h) = (args.width, args.height);
    for (pixels, extension) in [(&view, "view.png"), (&unculled, "unculled.png")] {
        let path = args.out.with_extension(extension);
        crate::files::save_png(&path, pixels, (w, h), image::ColorType::Rgba8)?;
        written.push(path);
    }
    for path in &written {
        log::info!("wrote {}", path.display());
    }
    Ok(points)
}

/// Warm-up, then `args.frames` frames of one configuration, each simulating 1/60 s
/// from a clock started anew; `request(k)` is the k-th measured frame (the warm-up
/// runs the first).
fn measure(
    (driver, offscreen): (&mut FrameDriver, &mut Offscreen),
    request: &dyn Fn(u32) -> FrameRequest,
    args: &BenchArgs,
    config: BenchConfig,
    blades: u32,
) -> Result<Point> {
    driver.clock = SimClock::default();
    let (mut cpu, mut times, mut drawn) = (Vec::new(), Vec::<PassTimes>::new(), Vec::new());
    let (mut compute_drawn, mut covered, mut written) = (Vec::new(), Vec::new(), Vec::new());
    let (mut far_tiles, mut far_blades) = (Vec::new(), Vec::new());
    let (mut triangles, mut spilled, mut casters) = (Vec::new(), Vec::new(), Vec::new());
    let mut collided = Vec::new();
    let mut last = Instant::now();
    let slots = FRAMES_IN_FLIGHT as u32;
    // Each slot's read-back is of its previous frame: skip those of the warm-up.
    let frames = args.warmup + args.frames + slots;
    for frame in 0..frames {
        let Some(started) = driver.begin(offscreen, 1.0 / 60.0)? else {
            continue;
        };
        let now = Instant::now();
        if frame >= args.warmup + slots {
            let r = &driver.readback;
            cpu.push(now.duration_since(last).as_secs_f64() * 1000.0);
            times.extend(r.times);
            drawn.extend(r.counts.map(|c| f64::from(c.drawn)));
            compute_drawn.extend(r.counts.map(|c| f64::from(c.compute)));
            far_tiles.extend(r.counts.map(|c| f64::from(c.far_tiles)));
            far_blades.extend(r.counts.map(|c| f64::from(c.far_blades)));
            covered.extend(r.counts.map(|c| f64::from(c.raster_covered)));
            written.extend(r.counts.map(|c| f64::from(c.raster_written)));
            triangles.extend(r.triangles.map(|t| t as f64));
            spilled.extend(r.counts.map(|c| c.spilled).filter(|&s| s > 0));
            casters.extend(r.counts.map(|c| f64::from(c.casters)));
            collided.extend(r.counts.map(|c| f64::from(c.collided)));
        }
        last = now;
        let measured = frame.saturating_sub(args.warmup);
        driver.submit(started, offscreen, FrameSpec::plain(request(measured)))?;
    }
    driver.finish()?;
    if let Some(most) = spilled.iter().max() {
        log::info!(
            "{config:?} at {blades} blades: in {} of {} frames blades spilled out of their \
             bucket of the binned list (at most {most})",
            spilled.len(),
            args.frames
        );
    }
    // Lavapipe counts no clipping invocations for mesh stages: none counted while
    // blades were drawn is no count.
    let drawn_any = drawn.iter().any(|&d| d > 0.0);
    let triangles = (!triangles.is_empty())
        .then(|| Spread::of(&triangles).median)
        .filter(|&t| t > 0.0 || !drawn_any);
    let pass = |f: fn(&PassTimes) -> f64| Spread::of(&times.iter().map(f).collect::<Vec<_>>());
    let potential = driver
        .renderer
        .tiles
        .as_ref()
        .map_or(0.0, |t| t.spec().potential_blades());
    Ok(Point {
        potential,
        far_tiles: Spread::of(&far_tiles).median,
        far_blades: Spread::of(&far_blades).median,
        casters: Spread::of(&casters).median,
        collided: Spread::of(&collided).median,
        look: shared::settings::Look::default(),
        pipeline: Default::default(),
        samples: 1,
        aa: Antialiasing::None,
        compute_below: request(0).settings.compute_raster_below,
        render_scale: request(0).plan().scale,
        compute_drawn: Spread::of(&compute_drawn).median,
        raster_covered: Spread::of(&covered).median,
        raster_written: Spread::of(&written).median,
        config,
        walkers: 0,
        mowers: 0,
        blades,
        drawn: Spread::of(&drawn).median,
        cpu: Spread::of(&cpu),
        gpu: pass(|t| t.total),
        pyramid: pass(|t| t.depth_pyramid),
        simulate_cull: pass(|t| t.simulate_cull),
        shadow: pass(|t| t.shadow),
        ground: pass(|t| t.ground),
        grass: pass(|t| t.grass),
        raster: pass(|t| t.raster),
        resolve: pass(|t| t.resolve),
        shade: pass(|t| t.shade),
        tone_map: pass(|t| t.tone_map),
        triangles,
        difference: 0.0,
    })
}

/// One frame of no time (no simulation step), captured: the picture of `request`
/// with the blades exactly as they are (with temporal anti-aliasing, once its history
/// has settled over `temporal::SETTLE_FRAMES` such frames).
pub(crate) fn still(
    driver: &mut FrameDriver,
    offscreen: &mut Offscreen,
    request: FrameRequest,
) -> Result<Vec<u8>> {
    // Temporal anti-aliasing shows a still frame once its history has settled.
    if request.plan().taa {
        for _ in 1..shared::draw::temporal::SETTLE_FRAMES {
            driver.run(offscreen, 0.0, |_| request.clone(), false)?;
        }
    }
    driver.run(offscreen, 0.0, |_| request.clone(), true)?;
    driver.finish()?;
    offscreen.pixels()
}

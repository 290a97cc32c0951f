//! `grass soak`: thousands of frames headless with the validation layer on, every
//! switch cycled (culling tests, LOD, view, wind, blade shape, look, MSAA, shadows,
//! pipeline, frame times from 0.1 ms to 2 s, two image sizes), a ball circling through
//! the grass, asked about every other half second; it reads host and device memory as
//! it goes and fails unless both stay flat and the layer says nothing.

use super::driver::{Frame, FrameDriver};
use super::headless::{FORMAT, Offscreen};
use super::progress::Progress;
use crate::cli::{Common, SoakArgs};
use crate::collider::Ball;
use crate::renderer::Renderer;
use anyhow::{Result, bail};
use glam::{Vec2, Vec3Swizzles};
use shared::settings::{
    Antialiasing, BladeShape, CullTests, GrassPipeline, Look, Settings, View, WindField,
};

/// Phases (changes of the switches) between two memory readings.
pub const PHASES_PER_READING: u32 = 4;

/// Frame times the phases cycle through, in seconds: a normal frame, a very fast one,
/// a slow one and one at the simulation's two-second cap.
pub const FRAME_TIMES: [f64; 4] = [1.0 / 60.0, 1e-4, 0.25, 2.0];

/// Bytes the live device allocations may differ by between readings at the same
/// image size: the allocator counts alignment padding, which depends on where each
/// allocation lands (the H100 run differs by 672 bytes).
pub const DEVICE_SLACK: u64 = 64 * 1024;

/// One memory reading.
#[derive(Copy, Clone, Debug)]
pub struct Reading {
    /// Frames done.
    pub frame: u32,
    /// Image size in use.
    pub size: (u32, u32),
    /// Host memory resident, bytes (`None` where /proc is not there).
    pub host: Option<u64>,
    /// Device memory in live allocations, bytes.
    pub device: u64,
    /// Device memory in the allocator's blocks, bytes.
    pub device_blocks: u64,
    /// Validation messages so far.
    pub messages: u32,
}

/// What the soak found.
#[derive(Clone, Debug)]
pub struct SoakReport {
    /// The readings, one per `--every` frames.
    pub readings: Vec<Reading>,
    /// Seconds the run took.
    pub seconds: f64,
    /// Validation was on.
    pub validation: bool,
    /// The slowest frame the GPU's timestamps measured, where the device has them.
    pub slowest: Option<SlowFrame>,
}

/// A frame's GPU time and its longest pass.
#[derive(Copy, Clone, Debug)]
pub struct SlowFrame {
    /// The whole frame, milliseconds.
    pub total: f64,
    /// Its longest pass's name and milliseconds (`PassTimes::longest`).
    pub pass: (&'static str, f64),
}

impl SoakReport {
    /// Host memory gained over the run, bytes (may be negative): the lowest reading of
    /// the last third above the highest of the first third. Memory that swings up and
    /// down (allocator pools, a driver's caches) gains nothing this way; a leak raises
    /// even the lowest late reading above every early one. With fewer than three
    /// readings it is the last against the first.
    pub fn host_growth(&self) -> i64 {
        let host: Vec<i64> = self
            .readings
            .iter()
            .filter_map(|r| r.host.map(|h| h as i64))
            .collect();
        let third = (host.len() / 3).max(1);
        match (
            host[..third.min(host.len())].iter().max(),
            host[host.len().saturating_sub(third)..].iter().min(),
        ) {
            (Some(early), Some(late)) => late - early,
            _ => 0,
        }
    }

    /// Readings whose device memory differs from the first reading at the same size:
    /// other memory blocks, or live allocations more than [`DEVICE_SLACK`] apart.
    pub fn device_changes(&self) -> Vec<(Reading, Reading)> {
        let mut changes = Vec::new();
        for (i, r) in self.readings.iter().enumerate() {
            let first = self.readings[..i].iter().find(|f| f.size == r.size);
            let changed = |f: &&Reading| {
                f.device_blocks != r.device_blocks || f.device.abs_diff(r.device) > DEVICE_SLACK
            };
            if let Some(f) = first.filter(changed) {
                changes.push((*f, *r));
            }
        }
        changes
    }
}

/// Runs the soak; an error if memory grew or the validation layer spoke.
pub fn run(common: &Common, args: &SoakArgs) -> Result<SoakReport> {
    let report = soak(common, args)?;
    let messages = report.readings.last().map_or(0, |r| r.messages);
    let growth = report.host_growth();
    let changes = report.device_changes();
    let mib = |b: f64| b / (1024.0 * 1024.0);
    println!(
        "soak: {} frames in {:.0} s{}; host memory {:+.1} MiB (lowest of the last third of \
         the readings against the highest of the first third); device memory {}; {}",
        args.frames,
        report.seconds,
        report.slowest.map_or(String::new(), |s| format!(
            ", the slowest on the GPU {:.1} ms ({} {:.1} ms)",
            s.total, s.pass.0, s.pass.1
        )),
        mib(growth as f64),
        if changes.is_empty() {
            "the same at every reading of the same size".to_string()
        } else {
            format!("changed {} times", changes.len())
        },
        if report.validation {
            format!("{messages} validation messages")
        } else {
            "validation off".to_string()
        }
    );
    if messages > 0 {
        bail!("the validation layer reported {messages} messages (see the log)");
    }
    if let Some((a, b)) = changes.first() {
        bail!(
            "device memory changed between frame {} ({} bytes) and frame {} ({} bytes)",
            a.frame,
            a.device,
            b.frame,
            b.device
        );
    }
    // After the device's check: a software device's memory is host memory too.
    if mib(growth as f64) > f64::from(args.host_slack_mib) {
        let readings: Vec<String> = report
            .readings
            .iter()
            .filter_map(|r| r.host.map(|h| format!("{}: {:.1}", r.frame, mib(h as f64))))
            .collect();
        bail!(
            "host memory grew by {:.1} MiB, more than --host-slack-mib {} (MiB by frame: {})",
            mib(growth as f64),
            args.host_slack_mib,
            readings.join(", ")
        );
    }
    Ok(report)
}

/// The switches of phase `phase`: every subset of the culling tests in turn, LOD on
/// and off, each view, wind and shape; both looks, no anti-aliasing, temporal
/// (phases 1 mod 4) and 4x multisampling (3 mod 4), shadows on and off, the compute
/// rasterizer off, at 12 and at 48 pixels. Phases 3 mod 4 (where the memory is read)
/// always have the natural look at 4 samples, so the draw's images are the same at
/// every reading.
pub fn phase_settings(base: &Settings, phase: u32) -> Settings {
    let mut s = *base;
    let p = phase as usize;
    s.cull.tests = CullTests::from_mask(phase % (shared::cull::blade::ALL + 1));
    s.lod.on = phase.is_multiple_of(2);
    s.view = View::ALL[p % View::ALL.len()];
    s.wind.field = WindField::ALL[p % WindField::ALL.len()];
    s.shape = BladeShape::ALL[(p / 2) % BladeShape::ALL.len()];
    s.look.style = Look::ALL[(p / 2) % 2];
    s.look.aa = match p % 4 {
        1 => Antialiasing::Taa,
        3 => Antialiasing::Msaa,
        _ => Antialiasing::None,
    };
    s.look.msaa = 4;
    s.look.shadows = (p / 4).is_multiple_of(2);
    // Both pipelines (the renderer draws tessellation where the device has no mesh
    // stages); the readings' phases keep one.
    if p % 4 != 3 {
        s.pipeline = GrassPipeline::ALL[(p / 4) % 2];
        // The compute rasterizer off, on far blades, and on most of them (where the
        // device has it; the renderer turns it off where it has not).
        s.compute_raster_below = [0.0, 12.0, 48.0][(p / 4) % 3];
    }
    s
}

/// Frames of the soak's flight over the valley flown once, unread, before the run.
pub const REHEARSAL: u32 = 480;

/// Units a second the soak's camera flies over the valley (at least a sixtieth of a
/// second a frame: frames of no time still move it).
pub const SOAK_FLIGHT_SPEED: f32 = 30.0;

/// Where along the valley's path the soak's camera is after a frame of `dt` seconds
/// from `travelled`: back to the start before the path leaves the world.
fn fly(travelled: f32, dt: f64) -> f32 {
    (travelled + SOAK_FLIGHT_SPEED * (dt as f32).max(1.0 / 60.0)) % 900.0
}

fn soak(common: &Common, args: &SoakArgs) -> Result<SoakReport> {
    if args.no_validation && (common.validation || common.validation_checks.is_some()) {
        anyhow::bail!("--no-validation conflicts with --validation and --validation-checks");
    }
    // Validated unless --no-validation, whatever GRASS_VALIDATION says.
    let validation = !args.no_validation;
    let (file, ctx) = super::open_headless(common, validation)?;
    let (scene, base) = super::prepare(common, &ctx, file)?;
    let sizes = [
        (args.width, args.height),
        ((args.width * 3 / 4).max(16), (args.height / 2).max(16)),
    ];
    // Made before the driver, so it is dropped after it (see `render`).
    let mut offscreen = Offscreen::new(&ctx, sizes[0].0, sizes[0].1)?;
    let mut driver = FrameDriver::new(&ctx, Renderer::new(&ctx, &scene.meshes(), FORMAT)?)?;
    let mut camera = scene.camera();
    let circle = camera.distance * 0.2;
    // Over the valley the camera flies down its path instead of turning, so tiles
    // keep entering and leaving the pool while the memory is read.
    let flying = scene.kind == crate::scene::SceneKind::Valley;
    let mut travelled = 0.0;
    let progress = Progress::new(args.frames as usize);
    let mut readings = Vec::new();
    let phase_frames = (args.every / PHASES_PER_READING).max(1);
    // One frame of `settings` at `size` seen by `camera`, `dt` seconds on, with the ball
    // circling the camera's target and the walkers (`--walkers`) wandering.
    let walkers = crate::walkers::Walkers::new(&scene, common.walkers).with_mowers(common.mowers);
    let mut slowest = None;
    let mut draw = |driver: &mut FrameDriver,
                    offscreen: &mut Offscreen,
                    settings: &Settings,
                    camera: &crate::camera::OrbitCamera,
                    dt: f64| {
        let size = offscreen.size();
        let request = |f: &Frame| {
            let angle = f.time * 0.7;
            let around = camera.target.xz() + Vec2::from_angle(angle) * circle;
            let ball = Ball::dropped(&scene.solid, around, common.collider_radius)
                .filter(|_| !common.no_ball);
            let balls: Vec<_> = ball.iter().map(Ball::sphere).collect();
            let eye = camera.viewpoint(size);
            // Every other half second of simulated time the frame asks about the ball
            // (`shared::query`) and marks the colliders touching blades.
            let asking = (f.time * 2.0) as u32 % 2 == 1;
            let questions = ball
                .filter(|_| asking)
                .map_or(vec![], |b| b.questions(eye.position).to_vec());
            settings
                .request(&eye, &balls)
                .with_balls_cutting(common.ball_cuts)
                .with_colliders(&walkers.colliders(&scene, f.time, f.seconds()))
                .with_questions(&questions)
                .with_contacts(asking)
        };
        driver.run(offscreen, dt, request, false)?;
        // The newest frame read back (a slot's older frame, with no wait).
        if let Some(t) = driver.readback.times
            && slowest.is_none_or(|s: SlowFrame| t.total > s.total)
        {
            slowest = Some(SlowFrame {
                total: t.total,
                pass: t.longest(),
            });
        }
        Ok::<(), anyhow::Error>(())
    };
    // Warm-up, before the first frame counted: at each size, one frame of every phase
    // the run will meet, and the same with every blade drawn at the most segments (no
    // culling, no LOD: the largest draw the phase's pipelines can be asked for). A
    // driver's caches and pools grow to the largest draw they have met and keep that
    // size (lavapipe's rasteriser: 2 to 4 MiB the first time the CI soak met the quad
    // shape in one combination of switches, 200 frames in, and once again 8,000 frames
    // into a 20,000-frame soak); after the warm-up they have the size this run needs,
    // and growth is growth.
    let phases = args.frames.div_ceil(phase_frames);
    for (i, &size) in sizes.iter().enumerate() {
        for phase in 0..phases {
            if offscreen.size() != size {
                driver.finish()?;
                offscreen = Offscreen::new(&ctx, size.0, size.1)?;
            }
            let dt = FRAME_TIMES[phase as usize % FRAME_TIMES.len()];
            let settings = phase_settings(&base, phase);
            let mut largest = settings;
            largest.cull.tests = CullTests::NONE;
            largest.lod.on = false;
            for s in [settings, largest] {
                draw(&mut driver, &mut offscreen, &s, &camera, dt)?;
            }
        }
        progress.show(0, &format!("warming up {} of 2", i + 1));
    }
    // Over the valley the run's own frames are flown once before it, unread (at most
    // REHEARSAL of them): a driver's pools also grow with the ground in view, and the
    // 2-s frames of one phase jump the camera onto ground no other phase flies over
    // (lavapipe: one step of 0 to 30 MiB at frame 200 of the CI soak, flat after).
    let rehearsal = if flying {
        args.frames.min(REHEARSAL)
    } else {
        0
    };
    // Frame `frame` of the run: its phase's switches, its frame time and image size.
    let at = |frame: u32| {
        let phase = frame / phase_frames;
        let dt = FRAME_TIMES[phase as usize % FRAME_TIMES.len()];
        let size = sizes[(frame / args.every) as usize % 2];
        (phase_settings(&base, phase), dt, size)
    };
    let start = camera;
    for frame in 0..rehearsal {
        let (settings, dt, size) = at(frame);
        if offscreen.size() != size {
            driver.finish()?;
            offscreen = Offscreen::new(&ctx, size.0, size.1)?;
        }
        travelled = fly(travelled, dt);
        camera = crate::scene::valley_camera(travelled);
        draw(&mut driver, &mut offscreen, &settings, &camera, dt)?;
    }
    if rehearsal > 0 {
        progress.show(0, "flown once");
    }
    (travelled, camera) = (0.0, start);
    for frame in 0..args.frames {
        let (settings, dt, size) = at(frame);
        if offscreen.size() != size {
            driver.finish()?;
            offscreen = Offscreen::new(&ctx, size.0, size.1)?;
        }
        if flying {
            travelled = fly(travelled, dt);
            camera = crate::scene::valley_camera(travelled);
        } else {
            camera.yaw += 0.003;
        }
        draw(&mut driver, &mut offscreen, &settings, &camera, dt)?;
        if (frame + 1) % args.every == 0 || frame + 1 == args.frames {
            driver.finish()?;
            let (device, device_blocks) = ctx.device_memory();
            let reading = Reading {
                frame: frame + 1,
                size,
                host: host_resident(),
                device,
                device_blocks,
                messages: ctx.validation_messages(),
            };
            log::info!("{}", describe(&reading));
            readings.push(reading);
            progress.show(frame as usize + 1, "running");
        }
    }
    driver.finish()?;
    progress.done(args.frames as usize);
    Ok(SoakReport {
        readings,
        seconds: progress.seconds(),
        validation,
        slowest,
    })
}

/// "frame N, WxH: host X MiB, device Y MiB in Z MiB of blocks, M validation messages".
pub fn describe(r: &Reading) -> String {
    let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
    format!(
        "frame {}, {}x{}: host {}, device {:.2} MiB in {:.2} MiB of blocks, {} validation messages",
        r.frame,
        r.size.0,
        r.size.1,
        r.host
            .map_or("unknown".to_string(), |h| format!("{:.1} MiB", mib(h))),
        mib(r.device),
        mib(r.device_blocks),
        r.messages
    )
}

/// This process's resident host memory, from /proc/self/status (Linux).
pub fn host_resident() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

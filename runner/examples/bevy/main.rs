//! Grass in a Bevy app (`runner::bevy`, the `bevy` feature): a small Bevy scene (a
//! ground plane, a ball walking across it, a sun, a camera with Bevy's HDR target and
//! tone map), the grass growing on the plane's mesh and drawn into Bevy's frame,
//! depth-tested against the ball, which pushes the blades down and leaves a trail.
//! Headless: the frame after `--frames` is read back and written as a PNG.
//!
//! ```text
//! cargo run --release --features bevy --example bevy -- --out frame.png
//! cargo run --release --features bevy --example bevy -- --help
//! ```

use anyhow::{Context as _, Result, bail};
use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::camera::Hdr;
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::TextureFormat;
use bevy::time::TimeUpdateStrategy;
use bevy::window::ExitCondition;
use runner::bevy::{Grass, GrassCamera, GrassCollider, GrassPlugin};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The command line.
#[derive(clap::Parser, Debug, Clone)]
#[command(
    name = "bevy",
    about = "Grass in a Bevy app: a ball walking through the field, headless, one PNG"
)]
pub struct Args {
    /// The PNG to write.
    #[arg(long)]
    pub out: std::path::PathBuf,
    /// Frames simulated (60 a second); the frame after them is written.
    #[arg(long, default_value_t = 120, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = size)]
    pub size: (u32, u32),
    /// Blades on the plane.
    #[arg(long, default_value_t = 40_000, value_parser = clap::value_parser!(u32).range(1..=(1 << 22)))]
    pub blades: u32,
    /// The species and their weights, as `grass --species` takes them
    /// (`grass=12,flower=2`; grass alone by default).
    #[arg(long, default_value = "grass=1")]
    pub species: shared::species::Mix,
    /// The ball stays at the end of its walk (no trail).
    #[arg(long)]
    pub still: bool,
    /// The validation layer on.
    #[arg(long)]
    pub validation: bool,
}

/// The ball's radius.
pub const BALL: f32 = 1.2;
/// Half the plane's side.
pub const HALF: f32 = 6.0;
/// The camera's place and what it looks at.
pub const EYE: Vec3 = Vec3::new(0.0, 8.0, 11.0);
/// What the camera looks at.
pub const LOOK_AT: Vec3 = Vec3::new(0.0, 0.0, 1.0);
/// The camera's vertical field of view (Bevy's default), radians.
pub const FOV_Y: f32 = std::f32::consts::FRAC_PI_4;

/// Where the ball is after `seconds` of a walk of `total` seconds (`--still`: always
/// at its end): from left to right across the plane, 3 units a second, starting 5
/// units left.
pub fn ball_at(seconds: f32, total: f32, still: bool) -> Vec3 {
    let t = if still { total } else { seconds.min(total) };
    Vec3::new((-5.0 + 3.0 * t).min(5.0), BALL, 1.5)
}

/// One run's picture.
pub struct Shot {
    /// RGBA8 (sRGB) pixels, row by row.
    pub rgba: Vec<u8>,
    /// (width, height).
    pub size: (u32, u32),
}

/// `WIDTHxHEIGHT`, both from 16 to 4096.
fn size(text: &str) -> Result<(u32, u32), String> {
    let parsed = text
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    match parsed {
        Some((w, h)) if (16..=4096).contains(&w) && (16..=4096).contains(&h) => Ok((w, h)),
        _ => Err(format!(
            "{text:?} is no size: WIDTHxHEIGHT, each 16 to 4096"
        )),
    }
}

fn main() -> std::process::ExitCode {
    let args = <Args as clap::Parser>::parse();
    let code = match run(&args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e:#}");
            1
        }
    };
    end(code)
}

/// Ends the process with `code`, the app and its device already gone. On Unix
/// without the C library's exit handlers: on the NVIDIA driver 580.159.04 (H100) a
/// Bevy 0.19 app of its own, without any grass, crashed in them after its last frame
/// in 3 runs of 3 (SIGSEGV), and ended cleanly without them in 3 of 3.
fn end(code: i32) -> std::process::ExitCode {
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    #[cfg(unix)]
    unsafe {
        libc::_exit(code)
    }
    #[cfg(not(unix))]
    std::process::ExitCode::from(code as u8)
}

/// Renders as `args` ask and writes the PNG.
fn run(args: &Args) -> Result<()> {
    runner::files::check_output(&args.out, &["png"])?;
    let shot = render(args)?;
    runner::files::save_png(&args.out, &shot.rgba, shot.size, image::ColorType::Rgba8)?;
    println!("wrote {}", args.out.display());
    Ok(())
}

/// What the app is asked, and where its picture goes.
#[derive(Resource, Clone)]
struct Run {
    args: Args,
    image: Handle<Image>,
    picture: Arc<Mutex<Option<Vec<u8>>>>,
}

/// Runs the app for `args.frames` frames and reads the next one back.
pub fn render(args: &Args) -> Result<Shot> {
    let (render, grass) = GrassPlugin::new(args.validation)?;
    let picture = Arc::new(Mutex::new(None));
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(render).set(WindowPlugin {
        primary_window: None,
        exit_condition: ExitCondition::DontExit,
        ..default()
    }))
    .add_plugins((ScheduleRunnerPlugin::run_loop(Duration::ZERO), grass))
    .insert_resource(ClearColor(Color::srgb(0.42, 0.62, 0.86)))
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 60.0,
    )))
    .insert_resource(Run {
        args: args.clone(),
        image: Handle::default(),
        picture: Arc::clone(&picture),
    })
    .add_systems(Startup, setup)
    .add_systems(Update, (walk, read_back));
    let exit = app.run();
    if let AppExit::Error(code) = exit {
        bail!("the app exited with {code}");
    }
    let rgba = picture
        .lock()
        .ok()
        .and_then(|mut p| p.take())
        .context("no picture read back")?;
    let (w, h) = args.size;
    // Rows come padded to wgpu's copy alignment.
    let row = (4 * w as usize).next_multiple_of(256);
    let rgba = rgba
        .chunks(row)
        .take(h as usize)
        .flat_map(|r| r[..4 * w as usize].to_vec())
        .collect();
    Ok(Shot {
        rgba,
        size: args.size,
    })
}

/// The scene: the plane with its grass, the ball, the sun, the camera into an image.
fn setup(
    mut commands: Commands,
    mut run: ResMut<Run>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let (w, h) = run.args.size;
    let mut target = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    target.texture_descriptor.usage |= bevy::render::render_resource::TextureUsages::COPY_SRC;
    run.image = images.add(target);
    let plane = Plane3d::default()
        .mesh()
        .size(2.0 * HALF, 2.0 * HALF)
        .subdivisions(8);
    commands.spawn((
        Mesh3d(meshes.add(plane)),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.25, 0.2, 0.12),
            perceptual_roughness: 1.0,
            ..default()
        })),
        Transform::default(),
        Grass {
            blades: run.args.blades,
            seed: 1,
            species: run.args.species,
        },
    ));
    commands.spawn((
        Mesh3d(meshes.add(Sphere::new(BALL).mesh().uv(32, 16))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.85, 0.08, 0.05),
            ..default()
        })),
        Transform::from_translation(ball_at(0.0, total(&run.args), run.args.still)),
        GrassCollider { radius: BALL },
        Ball,
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 3000.0,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_xyz(4.0, 6.0, -3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            fov: FOV_Y,
            ..default()
        }),
        RenderTarget::Image(run.image.clone().into()),
        Hdr,
        Msaa::Off,
        GrassCamera,
        Transform::from_translation(EYE).looking_at(LOOK_AT, Vec3::Y),
    ));
}

/// The walking ball.
#[derive(Component)]
struct Ball;

/// Seconds of the whole walk.
fn total(args: &Args) -> f32 {
    args.frames as f32 / 60.0
}

/// The ball to where it is now.
fn walk(run: Res<Run>, time: Res<Time>, mut balls: Query<&mut Transform, With<Ball>>) {
    for mut at in &mut balls {
        at.translation = ball_at(time.elapsed_secs(), total(&run.args), run.args.still);
    }
}

/// After the frames, the image read back once; the app ends when it has come.
fn read_back(
    mut commands: Commands,
    run: Res<Run>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    *frame += 1;
    if *frame == run.args.frames {
        let picture = Arc::clone(&run.picture);
        commands
            .spawn(Readback::texture(run.image.clone()))
            .observe(move |done: On<ReadbackComplete>, mut commands: Commands| {
                if let Ok(mut p) = picture.lock() {
                    p.get_or_insert_with(|| done.data.clone());
                }
                commands.entity(done.entity).despawn();
            });
    }
    let have = run.picture.lock().map(|p| p.is_some()).unwrap_or(true);
    if have || *frame > run.args.frames + 30 {
        exit.write(AppExit::Success);
    }
}

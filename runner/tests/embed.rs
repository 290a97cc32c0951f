//! The embedding examples run headless, in this process: `runner/examples/embed/`
//! (its own device and cube, and the grass of `runner::embed` in the same frame) and
//! `runner/examples/wgpu/` (the cube drawn by wgpu, the grass on wgpu's device), with
//! the validation layer (core and synchronization) silent where it is installed (CI).
//!
//! Checked by content: the host projects the cube's corners with the matrices the
//! example gave the GPU; inside that silhouette the cube's magenta must show (grass in
//! front of it hides some), outside it the grass's green must cover much of the
//! picture, and magenta must not show outside it.

#[path = "../examples/embed/main.rs"]
#[allow(dead_code)]
mod example;

// Both examples take their stage from `examples/embed/stage.rs`.
#[path = "../examples/wgpu/main.rs"]
#[allow(dead_code, clippy::duplicate_mod)]
mod wgpu_example;

use glam::Vec2;
use runner::vulkan::gpu_required;
use runner::vulkan::probe::{Probe, runs_here};
use shared::settings::Look;
use std::sync::atomic::Ordering;

/// Magenta, as the cube's faces are lit (sRGB bytes): red and blue far above green.
fn is_cube(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(f32::from);
    r > 1.6 * g + 20.0 && b > 1.3 * g + 10.0
}

/// The grass's green: green above red and blue.
fn is_grass(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(i32::from);
    g > r + 8 && g > b + 8
}

/// The convex hull of `points`, counter-clockwise in a y-down frame seen as y-up
/// (Andrew's monotone chain).
fn hull(mut points: Vec<Vec2>) -> Vec<Vec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut lower: Vec<Vec2> = Vec::new();
    for &p in &points {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<Vec2> = Vec::new();
    for &p in points.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Signed distance of `p` inside the convex polygon `hull` (negative outside),
/// pixels.
fn inside_by(hull: &[Vec2], p: Vec2) -> f32 {
    (0..hull.len())
        .map(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
            (b - a).perp_dot(p - a) / (b - a).length()
        })
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn the_example_draws_its_cube_and_the_grass_in_one_frame() {
    check_the_frame(Look::Paper, false);
}

/// The same after the targets changed size: tall, one pixel, wide, then the asked
/// size (the field makes its own images again each time).
#[test]
fn the_field_follows_its_targets_size() {
    check_frame(&example::Args {
        resize_through: vec![(97, 203), (1, 1), (400, 100)],
        ..frame_args(Look::Paper, false)
    });
}

/// The same with a tiled field: generated tile by tile around the camera.
#[test]
fn a_tiled_field_in_your_frame() {
    check_the_frame(Look::Paper, true);
}

/// The same with the natural look, drawn into the example's HDR image and tone-mapped
/// on the host.
#[test]
fn the_natural_look_into_your_hdr_image() {
    check_the_frame(Look::Natural, false);
}

/// The example's frame in `look`, tiled or not, with the validation layer where CI
/// has it.
fn frame_args(look: Look, tiled: bool) -> example::Args {
    example::Args {
        size: (320, 180),
        frames: Some(30),
        look,
        tiled,
        validation: Probe::once().validation_layer,
        ..Default::default()
    }
}

/// Renders the example's frame in `look` and checks it by content (module docs).
fn check_the_frame(look: Look, tiled: bool) {
    check_frame(&frame_args(look, tiled));
}

/// Renders the example's frame as `args` ask and checks it by content (module docs).
fn check_frame(args: &example::Args) {
    let (look, tiled) = (args.look, args.tiled);
    if !runs_here("the embed example", &[]) {
        return;
    }
    let shot = example::render_headless(args).unwrap_or_else(|e| panic!("embed example: {e:#}"));
    let errors = example::VALIDATION_ERRORS.load(Ordering::SeqCst);
    assert_eq!(errors, 0, "validation errors in the embed example");
    let picture = Picture {
        rgba: &shot.rgba,
        size: shot.size,
        cube_corners: &shot.cube_corners,
        drawn: shot.drawn,
    };
    check_picture(&format!("{look:?}, tiled {tiled}"), &picture, tiled);
}

/// A frame of the cube and the grass, as the examples read it back.
struct Picture<'a> {
    /// RGBA8 (sRGB), row by row.
    rgba: &'a [u8],
    size: (u32, u32),
    /// The cube's corners in pixels.
    cube_corners: &'a [Vec2],
    /// Blades drawn.
    drawn: u32,
}

/// Checks `shot` by content (module docs), a tiled field's (sparser far out) or not.
fn check_picture(name: &str, shot: &Picture, tiled: bool) {
    let (w, h) = shot.size;
    assert_eq!(shot.rgba.len(), (w * h * 4) as usize);
    let silhouette = hull(shot.cube_corners.to_vec());
    let (mut inside, mut cube_inside, mut outside, mut grass_outside, mut cube_outside) =
        (0, 0, 0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let i = ((y * w + x) * 4) as usize;
            let p = [shot.rgba[i], shot.rgba[i + 1], shot.rgba[i + 2]];
            let depth = inside_by(&silhouette, Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            // A pixel's width of slack at the edge, for the rasterizer's coverage rule.
            if depth > 1.0 {
                inside += 1;
                cube_inside += usize::from(is_cube(p));
            } else if depth < -1.0 {
                outside += 1;
                grass_outside += usize::from(is_grass(p));
                cube_outside += usize::from(is_cube(p));
            }
        }
    }
    let cube_share = cube_inside as f32 / inside as f32;
    let grass_share = grass_outside as f32 / outside as f32;
    eprintln!(
        "{name}: cube: {inside} px inside its silhouette, {:.1} % magenta; outside: {:.1} % grass, \
         {cube_outside} magenta px; {} blades drawn",
        100.0 * cube_share,
        100.0 * grass_share,
        shot.drawn
    );
    assert!(inside > 400, "the cube covers {inside} px");
    assert!(
        cube_share > 0.8,
        "the cube shows in {:.1} % of its silhouette",
        100.0 * cube_share
    );
    // A tiled field on a software device keeps its full density to 4.5 units only
    // (`scene::tiled_spec`): farther, fewer and wider blades.
    let floor = if tiled { 0.3 } else { 0.4 };
    assert!(
        grass_share > floor,
        "grass covers {:.1} % outside the cube",
        100.0 * grass_share
    );
    assert!(
        cube_outside < 20,
        "{cube_outside} magenta px outside the cube"
    );
    let least = if tiled { 200 } else { 1000 };
    assert!(shot.drawn > least, "{} blades drawn", shot.drawn);
}

/// The wgpu example (`runner/examples/wgpu/`): wgpu draws the cube on a device made
/// for wgpu and the grass, the field draws the grass into wgpu's textures; checked by
/// content as the embed example's frame is, with the validation layer silent.
#[test]
fn the_wgpu_example_draws_its_cube_and_the_grass_in_one_frame() {
    if !runs_here("the wgpu example", &[]) {
        return;
    }
    let args = wgpu_example::Args {
        out: "unused.png".into(),
        frames: 30,
        size: (320, 180),
        blades: 20_000,
        validation: Probe::once().validation_layer,
    };
    let shot = wgpu_example::render(&args).unwrap_or_else(|e| panic!("wgpu example: {e:#}"));
    let errors = wgpu_example::VALIDATION_ERRORS.load(Ordering::SeqCst);
    assert_eq!(errors, 0, "validation errors in the wgpu example");
    let picture = Picture {
        rgba: &shot.rgba,
        size: shot.size,
        cube_corners: &shot.cube_corners,
        drawn: shot.drawn,
    };
    check_picture("wgpu", &picture, false);
}

/// What the field needs is asked before anything is made, and what a device lacks is
/// named: a compressed colour format (never a colour attachment), and a feature taken
/// away by fault injection (in a child process: the fault is read once a process).
#[test]
fn requirements_name_what_is_missing() {
    if !runs_here("requirements_name_what_is_missing", &[]) {
        return;
    }
    let entry = unsafe { ash::Entry::load() }.expect("the Vulkan loader");
    let app = ash::vk::ApplicationInfo::default().api_version(ash::vk::API_VERSION_1_3);
    let info = ash::vk::InstanceCreateInfo::default().application_info(&app);
    let instance = unsafe { entry.create_instance(&info, None) }.expect("instance");
    let devices = unsafe { instance.enumerate_physical_devices() }.unwrap_or_default();
    for &physical in &devices {
        let format = ash::vk::Format::BC1_RGB_UNORM_BLOCK;
        let missing = runner::embed::requirements(&instance, physical, format)
            .err()
            .expect("BC1 is no colour attachment");
        let text = missing.to_string();
        assert!(
            text.contains("format BC1_RGB_UNORM_BLOCK as a colour attachment"),
            "{text}"
        );
    }
    unsafe { instance.destroy_instance(None) };
    assert!(!devices.is_empty(), "no Vulkan device");

    let grass = std::path::Path::new(env!("CARGO_BIN_EXE_grass"));
    let example = grass.with_file_name("examples").join("embed");
    if !example.exists() {
        assert!(!gpu_required(), "{} not built", example.display());
        return;
    }
    let out = std::env::temp_dir().join(format!("grass-embed-{}.png", std::process::id()));
    let run = std::process::Command::new(&example)
        .args(["--out", out.to_str().expect("utf-8"), "--frames", "1"])
        .env("GRASS_FAULT", "missing-feature:tessellationShader")
        .output()
        .expect("run the example");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "ran without tessellation: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("lacks what the grass renderer needs: feature tessellationShader"),
        "{stderr}"
    );
    assert!(!out.exists(), "an image was written");
}

/// A field on the caller's own triangles (`Ground::Mesh`): a bad mesh is refused with
/// the problem named, a good one grows its blades where the mesh is; a frame the
/// field cannot draw (too many colliders, targets of no size) is refused before
/// anything is recorded.
#[test]
fn a_field_on_your_own_mesh() {
    use glam::{Vec3, Vec4};
    use runner::embed::Ground;
    use shared::world::mesh::SurfaceMesh;
    if !runs_here("a_field_on_your_own_mesh", &[]) {
        return;
    }
    let made = example::Gpu::instance(&[], false).and_then(|instance| {
        example::Gpu::new(instance, false, |_, _| Some(example::HEADLESS_FORMAT), &[])
    });
    let (gpu, format) = made.unwrap_or_else(|e| panic!("{e:#}"));
    // A 10 x 10 square at height 3, around (20, 3, -5).
    let square = |y: f32| SurfaceMesh {
        positions: vec![
            Vec3::new(15.0, 3.0, -10.0),
            Vec3::new(15.0, y, 0.0),
            Vec3::new(25.0, 3.0, 0.0),
            Vec3::new(25.0, 3.0, -10.0),
        ],
        normals: Vec::new(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        uvs: Vec::new(),
    };
    let error = gpu
        .grass(Ground::Mesh(square(f32::NAN)), 1000, false, format)
        .err()
        .expect("a NaN position is refused");
    let text = format!("{error:#}");
    assert!(
        text.contains("your mesh") && text.contains("vertex 1"),
        "{text}"
    );

    let mut field = gpu
        .grass(Ground::Mesh(square(3.0)), 1000, false, format)
        .expect("a field on a square");
    assert_eq!(field.blade_count(), 1000);
    let (centre, _) = field.bounds();
    assert!(
        centre.distance(Vec3::new(20.0, 3.0, -5.0)) < 2.0,
        "{centre}"
    );
    let ground = field
        .ground_at(20.0, -5.0)
        .expect("ground under the middle");
    assert!((ground.y - 3.0).abs() < 1e-4, "{ground}");
    assert!(
        field.ground_at(40.0, -5.0).is_none(),
        "ground beyond the square"
    );

    // Refused before recording: the null command buffer is never touched.
    let frame = |colliders| runner::embed::Frame {
        targets: runner::embed::Targets {
            color: ash::vk::ImageView::null(),
            depth: ash::vk::ImageView::null(),
            extent: ash::vk::Extent2D::default(),
        },
        camera: runner::embed::viewpoint(glam::Mat4::IDENTITY, glam::Mat4::IDENTITY, 1),
        seconds: 0.0,
        colliders,
    };
    let ball = shared::sim::collide::Collider::from_sphere(Vec4::ONE);
    let many = [ball; shared::sim::collide::MAX_COLLIDERS + 1];
    let error = field
        .record(ash::vk::CommandBuffer::null(), &frame(&many))
        .expect_err("too many colliders");
    assert!(error.to_string().contains("colliders"), "{error}");
    let error = field
        .record(ash::vk::CommandBuffer::null(), &frame(&[]))
        .expect_err("targets of no size");
    assert!(error.to_string().contains("0x0"), "{error}");

    // Wind impulses: a blast felt inside its radius once its front arrives, refused
    // where a number is out of range or the frame's room is full.
    use shared::sim::impulse::{IMPULSE_BLAST, Impulse, MAX_IMPULSES};
    let at = Vec3::new(20.0, 3.0, -5.0);
    let calm_wind = field.wind_at(at + Vec3::X);
    let calm_beyond = field.wind_at(at + 9.0 * Vec3::X);
    // Started a tenth of a second ago: its front has passed a unit out.
    let blast = Impulse::new(IMPULSE_BLAST, at, field.time() - 0.1, 60.0, 8.0, 2.5);
    field.add_impulse(blast).expect("a blast");
    // The blast's own push there (`Impulse::push`, hand-checked in `shared`): 50.5
    // along +x; GrassField::wind_at leaving the impulses out failed.
    let blown = field.wind_at(at + Vec3::X) - calm_wind;
    let push = blast.push(at + Vec3::X, field.time(), Vec3::NEG_Y);
    assert!(push.x > 50.0, "{push}");
    assert!((blown - push).length() < 1e-4, "{blown} against {push}");
    assert_eq!(field.wind_at(at + 9.0 * Vec3::X), calm_beyond);
    let bad = Impulse {
        radius: 0.0,
        ..blast
    };
    let error = field.add_impulse(bad).expect_err("a radius of 0");
    assert!(error.to_string().contains("radius"), "{error}");
    for _ in 1..MAX_IMPULSES {
        field.add_impulse(blast).expect("room for another");
    }
    let error = field.add_impulse(blast).expect_err("no room");
    assert!(error.to_string().contains("blowing already"), "{error}");
    drop(field);
}

/// The example's command line is clap's: `--help` lists every option, and a wrong
/// option or value is a usage error (exit code 2) that names it, never a backtrace.
/// No device is needed.
#[test]
fn the_example_s_command_line_says_what_is_wrong() {
    let grass = std::path::Path::new(env!("CARGO_BIN_EXE_grass"));
    let example = grass.with_file_name("examples").join("embed");
    if !example.exists() {
        assert!(!gpu_required(), "{} not built", example.display());
        return;
    }
    let run = |args: &[&str]| {
        let o = std::process::Command::new(&example)
            .args(args)
            .env("RUST_BACKTRACE", "1")
            .output()
            .expect("run the example");
        let text = String::from_utf8_lossy(&o.stdout) + String::from_utf8_lossy(&o.stderr);
        (o.status.code(), text.into_owned())
    };
    let (code, help) = run(&["--help"]);
    assert_eq!(code, Some(0), "{help}");
    for option in [
        "--out",
        "--frames",
        "--size",
        "--look",
        "--blades",
        "--tiled",
        "--resize-through",
        "--validation",
    ] {
        assert!(help.contains(option), "{option} missing: {help}");
    }
    for (args, expected) in [
        (&["--bogus"][..], "--bogus"),
        (&["--look", "glossy"], "glossy"),
        (&["--size", "0x5"], "0x5"),
        (&["--resize-through", "10x10,big"], "big"),
        (&["--frames", "0"], "--frames"),
    ] {
        let (code, text) = run(args);
        assert_eq!(code, Some(2), "{args:?}: {text}");
        assert!(text.contains(expected), "{args:?}: {text}");
        assert!(
            !text.contains("backtrace") && !text.contains("panicked"),
            "{args:?}: {text}"
        );
    }
    // An output it cannot write is refused before any device is made.
    let (code, text) = run(&["--out", "/nonexistent/frame.png"]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("does not exist"), "{text}");
}

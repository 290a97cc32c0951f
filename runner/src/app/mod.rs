//! The application shells (the window viewer, `render`, `bench`, `soak`) and the frame
//! driver they share: each says what its frames show, the driver runs them on a
//! presenter (a window's swapchain) or an offscreen image.

pub mod bench;
pub mod driver;
pub mod headless;
pub mod overlay;
pub mod presenter;
pub mod progress;
pub mod quality;
pub mod query;
pub mod record;
pub mod render;
pub mod shm;
pub mod soak;
pub mod storm;
pub mod viewer;

use crate::cli::{Cli, Command, Common, FieldChoice, PipelineChoice};
use crate::field::Field;
use crate::scene::{BladeCount, Scene, SceneFile, SceneKind};
use crate::vulkan::Context;
use crate::vulkan::probe::Capabilities;
use anyhow::Result;
use shared::settings::{
    Antialiasing, GrassPipeline, SHADOW_SIZE, SHADOW_SIZE_SOFTWARE, Settings, WindField,
};

/// Blades of the default field on a hardware GPU.
pub const DEFAULT_BLADES_GPU: u32 = 1 << 17;
/// Blades of the default field on a software device (lavapipe draws about half a
/// million triangles a second on two cores).
pub const DEFAULT_BLADES_SOFTWARE: u32 = 2048;

/// The options that do not act in a command, and why: (command, options, why). Each is
/// refused where typed, and noted in the log where a settings file sets it.
pub const NOT_ACTING: &[(&str, &[&str], &str)] = &[
    (
        "soak",
        &[
            "look",
            "aa",
            "msaa",
            "shadows",
            "no-shadows",
            "shape",
            "view",
            "wind",
            "no-cull-orientation",
            "no-cull-frustum",
            "no-cull-distance",
            "no-cull-occlusion",
            "no-lod",
        ],
        "soak cycles it itself, with every other switch",
    ),
    (
        "soak",
        &["collider-path", "collider-speed"],
        "soak's ball circles the camera's target (--collider-radius sizes it, --no-ball \
         leaves it out)",
    ),
    (
        "bench",
        &[
            "no-cull-orientation",
            "no-cull-frustum",
            "no-cull-distance",
            "no-cull-occlusion",
            "no-lod",
        ],
        "bench sets the culling and level of detail of each --configs entry",
    ),
    (
        "bench",
        &[
            "collider-path",
            "collider-radius",
            "collider-speed",
            "ball-cuts",
        ],
        "bench runs without a ball",
    ),
    (
        "quality",
        &[
            "collider-path",
            "collider-radius",
            "collider-speed",
            "trample-decay",
            "walkers",
            "mowers",
            "ball-cuts",
            "regrow",
        ],
        "quality measures a still field, without a ball, walkers or mowers",
    ),
    (
        "query",
        &[
            "look",
            "aa",
            "msaa",
            "shadows",
            "no-shadows",
            "shadow-size",
            "view",
            "render-scale",
            "exposure",
            "fog-density",
            "no-cull-orientation",
            "no-cull-frustum",
            "no-cull-distance",
            "no-cull-occlusion",
            "no-lod",
            "pipeline",
            "compute-raster-below",
        ],
        "query's answers do not depend on how the frame is drawn",
    ),
];

/// Refuses (or notes) what [`NOT_ACTING`] lists for `command`, every setting for
/// `grass config` (which prints the defaults), and what does not apply to the field:
/// all before any device is opened.
fn check_options(command: &str, common: &Common) -> Result<()> {
    let given = &common.given;
    for (_, options, why) in NOT_ACTING.iter().filter(|(c, _, _)| *c == command) {
        given.refuse(options, why)?;
    }
    if command == "bench" && common.walkers == 0 {
        given.refuse(
            &["trample-decay"],
            "bench runs without a ball; with --walkers it acts",
        )?;
    }
    // The viewer's B key brings a ball back; render and record roll one only along
    // a path.
    if common.no_ball && command != "view" {
        given.refuse(&["ball-cuts"], "there is no ball (--no-ball)")?;
    }
    if common.collider_path.is_none() && matches!(command, "render" | "record") {
        given.refuse(&["ball-cuts"], "there is no ball without --collider-path")?;
    }
    if matches!(command, "render" | "record" | "soak") && common.mowers == 0 && !common.ball_cuts {
        given.refuse(
            &["regrow"],
            "nothing cuts; with --mowers or --ball-cuts it acts",
        )?;
    }
    if command == "bench" && common.mowers == 0 {
        given.refuse(&["regrow"], "bench cuts nothing; with --mowers it acts")?;
    }
    if command == "config" {
        let every: Vec<String> = crate::config::settable()
            .iter()
            .filter_map(|a| a.get_long().map(str::to_owned))
            .collect();
        let every: Vec<&str> = every.iter().map(String::as_str).collect();
        return given.refuse(
            &every,
            "grass config prints every setting at its default (the viewer's \"save \
             settings\" writes the running ones)",
        );
    }
    // The viewer can switch to the turbulent wind (W, the overlay) and the soak
    // cycles through every field: elsewhere the wind stays as given.
    let switches_wind = command == "view" || command == "soak";
    if !switches_wind && common.wind != WindField::Turbulent {
        given.refuse(
            &["gust-speed"],
            "the gust speed acts on the turbulent wind only (--wind turbulent)",
        )?;
    }
    let kind = common.scene_kind();
    if tiled(common, &kind) {
        given.refuse(
            &["density"],
            "a tiled field's blades come from its tiles, at their own density",
        )?;
        let sized = [
            SceneKind::Plane,
            SceneKind::Hills,
            SceneKind::Walls,
            SceneKind::Planet,
        ];
        if !sized.contains(&kind) {
            given.refuse(
                &["blades"],
                "a tiled field's blades come from its tiles, and this scene has its own \
                 size (--blades sizes the built-in plane, hills, walls and planet)",
            )?;
        }
    } else {
        given.refuse(
            &["full-distance", "far-at-rest"],
            "a stored field has no far tiles: it applies to a tiled field (--field tiles)",
        )?;
    }
    Ok(())
}

/// Runs what the command line asks for.
pub fn run(cli: Cli) -> Result<()> {
    cli.common.check()?;
    let name = match &cli.command {
        Some(Command::Render(_)) => "render",
        Some(Command::Bench(_)) => "bench",
        Some(Command::Soak(_)) => "soak",
        Some(Command::Record(_)) => "record",
        Some(Command::Quality(_)) => "quality",
        Some(Command::Query(_)) => "query",
        Some(Command::Config) => "config",
        Some(Command::View(_)) | None => "view",
    };
    check_options(name, &cli.common)?;
    match cli.command {
        Some(Command::Render(args)) => render::run(&cli.common, &args).map(|_| ()),
        Some(Command::Bench(args)) => bench::run(&cli.common, &args).map(|_| ()),
        Some(Command::Soak(args)) => soak::run(&cli.common, &args).map(|_| ()),
        Some(Command::Record(args)) => record::run(&cli.common, &args).map(|_| ()),
        Some(Command::Quality(args)) => quality::run(&cli.common, &args).map(|_| ()),
        Some(Command::Query(args)) => query::run(&cli.common, &args).map(|_| ()),
        Some(Command::Config) => {
            print!("{}", crate::config::defaults());
            Ok(())
        }
        Some(Command::View(args)) => viewer::run(&cli.common, &args),
        None => viewer::run(&cli.common, &cli.view),
    }
}

/// What to do about an error whose cause is one of the Vulkan results a user can meet
/// at run time (device lost, out of memory, a GPU that stopped answering).
pub fn advice(error: &anyhow::Error) -> Option<&'static str> {
    use ash::vk::Result as R;
    let result = error
        .chain()
        .find_map(|c| c.downcast_ref::<ash::vk::Result>())?;
    Some(match *result {
        R::ERROR_DEVICE_LOST => {
            "the GPU device was lost (VK_ERROR_DEVICE_LOST): the driver reset it, it was \
             removed, or it crashed. The viewer makes it again up to three times; here \
             nothing more can be drawn: start grass again, and if it repeats, try fewer \
             blades (--blades) or another driver"
        }
        R::ERROR_OUT_OF_DEVICE_MEMORY => {
            "the GPU ran out of memory (VK_ERROR_OUT_OF_DEVICE_MEMORY): ask for fewer \
             blades (--blades, --density) or a smaller image (--width, --height)"
        }
        R::ERROR_OUT_OF_HOST_MEMORY => {
            "the driver ran out of host memory (VK_ERROR_OUT_OF_HOST_MEMORY): ask for fewer \
             blades (--blades, --density)"
        }
        R::TIMEOUT => {
            "the GPU did not finish a frame within a minute (ten on a software device): \
             it is hung or far too slow for this field; ask for fewer blades (--blades)"
        }
        R::ERROR_SURFACE_LOST_KHR => "the window's surface was lost (the window system went away)",
        _ => return None,
    })
}

/// The scene file (read and checked first, so a bad file fails without a GPU), then a
/// headless context, validated if `validation`: how `render`, `bench` and `soak` start.
pub fn open_headless(
    common: &Common,
    validation: bool,
) -> Result<(Option<SceneFile>, std::sync::Arc<Context>)> {
    let file = common.scene_kind().read()?;
    let ctx = Context::new(crate::vulkan::ContextOptions {
        validation,
        checks: common.checks(),
        ..Default::default()
    })?;
    Ok((file, ctx))
}

/// The blade count asked for, or the default for this device.
pub fn blade_count(common: &Common, ctx: &Context) -> BladeCount {
    match common.blade_count() {
        Some(n) => n,
        None if ctx.is_software() => {
            log::info!(
                "software device {}: {DEFAULT_BLADES_SOFTWARE} blades by default \
                 (--blades to change)",
                ctx.device_name()
            );
            BladeCount::Total(DEFAULT_BLADES_SOFTWARE)
        }
        None => BladeCount::Total(DEFAULT_BLADES_GPU),
    }
}

/// The scene and settings the command line asks for, within `ctx`'s limits; `file`
/// is the scene's file, read before the device was opened.
pub fn prepare(
    common: &Common,
    ctx: &Context,
    file: Option<SceneFile>,
) -> Result<(Scene, Settings)> {
    let scene = build_scene(common, ctx, file, blade_count(common, ctx))?;
    let settings = device_settings(common, &scene, ctx)?;
    Ok((scene, settings))
}

/// The scene the command line asks for with `count` blades: built, grown at the look's
/// blade size, painted, tiled where asked.
pub fn build_scene(
    common: &Common,
    ctx: &Context,
    file: Option<SceneFile>,
    count: BladeCount,
) -> Result<Scene> {
    let kind = common.scene_kind();
    let mut scene = Scene::build(&kind, file, count, common.seed, |n| {
        Field::check_limits(ctx, n)
    })?;
    let scale = scene.scale_for(common.look);
    let _ = scene.rescale(scale);
    if scene.degenerate > 0 {
        log::warn!(
            "scene {}: skipped {} degenerate (zero-area) triangles",
            scene.name,
            scene.degenerate
        );
    }
    scene.species = common.species.unwrap_or_default();
    scene.paint = crate::paint::load_all(
        common.density_map.as_deref(),
        common.height_map.as_deref(),
        common.colour_map.as_deref(),
        common.type_map.as_deref(),
    )?;
    if tiled(common, &scene.kind) {
        let mut spec = crate::scene::tiled_spec(&scene, ctx.is_software(), scale);
        if let Some(distance) = common.full_distance {
            spec.params.full_distance = distance;
        }
        log::info!(
            "scene {}: tiled field, {:.2} M blades in the world, a pool of {} tiles \
             ({} blades simulated), room for {} far blades",
            scene.name,
            spec.potential_blades() / 1e6,
            spec.pool_tiles,
            spec.pool_blades(),
            spec.far_blades
        );
        scene.make_tiled(spec);
    } else {
        scene.apply_paint();
        log::info!("scene {}: {} blades", scene.name, scene.blade_count());
    }
    Ok(scene)
}

/// The settings the command line asks for on `scene`, with what it leaves to the
/// device `ctx` decided ([`settings`]).
pub fn device_settings(common: &Common, scene: &Scene, ctx: &Context) -> Result<Settings> {
    settings(common, scene, &ctx.capabilities())
}

/// Whether the field is tiled: `--field`, else on the valley only. Every scene can
/// be tiled: the plane and the valley from their formulas, the others (built-in
/// meshes and loaded files) over their triangles (`shared::surface`).
pub fn tiled(common: &Common, kind: &SceneKind) -> bool {
    match common.field {
        Some(choice) => choice == FieldChoice::Tiles,
        None => *kind == SceneKind::Valley,
    }
}

/// The settings the command line asks for on `scene`, each made once: what it gives,
/// and what it leaves to the `device` (`device_defaults`).
pub fn settings(common: &Common, scene: &Scene, device: &Capabilities) -> Result<Settings> {
    let mut s = scene.settings();
    s.wind.field = common.wind;
    s.wind.strength = common.wind_strength;
    s.wind.direction = common.wind_direction;
    s.wind.gust_speed = common.gust_speed;
    s.shape = common.shape;
    s.tip_start = common.tip_start;
    s.trample_decay = common.trample_decay;
    s.regrow = common.regrow;
    s.stiffness = common.stiffness;
    s.gravity.acceleration = common.gravity;
    if let Some(c) = common.gravity_centre {
        s.gravity.centre = c;
        s.gravity.centre_blend = 1.0;
    }
    let cull = &common.cull;
    s.cull.tests = cull.tests();
    s.cull.orientation_threshold = cull.orientation_threshold;
    s.cull.edge_on_pixels = cull.edge_on_pixels;
    s.cull.frustum_tolerance = cull.frustum_tolerance;
    s.cull.max_distance = cull.max_distance.unwrap_or(s.cull.max_distance);
    s.cull.buckets = cull.buckets;
    s.lod.on = !cull.no_lod;
    s.lod.most = cull.lod_most;
    s.lod.fewest = cull.lod_fewest;
    s.lod.pixels_per_segment = cull.lod_pixels;
    s.view = cull.view;
    s.look.style = common.look;
    s.far_sway = !common.far_at_rest;
    s.look.exposure = common.exposure;
    s.look.fog_density = common.fog_density;
    if let Some(size) = common.clump_size {
        s.look.clump_size = size;
    }
    s.look.seed = common.seed as u32;
    device_defaults(&mut s, common, device)?;
    if scene.tiles.is_some() && device.software && s.cull.tests.occlusion {
        // Lavapipe spent 15 ms of a 720p valley frame on the occluders' depth and
        // pyramid, to remove 67 of 3,338 blades (docs/tiled-world.md).
        s.cull.tests.occlusion = false;
        log::info!(
            "software device, tiled field: occlusion test off (its pre-pass costs more than it saves)"
        );
    }
    Ok(s)
}

/// What the command line leaves to the device: the grass pipeline
/// ([`grass_pipeline`]), samples per pixel ([`msaa`]), sun shadows (`--shadows`,
/// `--no-shadows`, else on a GPU only: lavapipe spends about a tenth of the natural
/// look's frame on them and would fall below the viewer's 20 fps) and the shadow
/// map's side (`--shadow-size`, else `SHADOW_SIZE` on a GPU, `SHADOW_SIZE_SOFTWARE`
/// on a software device).
fn device_defaults(settings: &mut Settings, common: &Common, device: &Capabilities) -> Result<()> {
    settings.pipeline = grass_pipeline(common.pipeline, device)?;
    settings.compute_raster_below = match (common.cull.compute_raster_below, &device.int64_atomics)
    {
        (Some(below), Err(why)) if below > 0.0 => {
            anyhow::bail!(
                "--compute-raster-below: {why} (64-bit atomics for its visibility buffer)"
            )
        }
        (Some(below), _) => below,
        (None, Ok(())) if !device.software => DEFAULT_COMPUTE_RASTER_BELOW_GPU,
        (None, _) => 0.0,
    };
    (settings.look.aa, settings.look.msaa) = antialiasing(common, device.software)?;
    let software_taa = device.software && settings.look.aa == Antialiasing::Taa;
    settings.look.render_scale = match common.render_scale {
        Some(scale) => scale,
        None if software_taa => {
            log::info!(
                "software device, temporal anti-aliasing: the scene drawn at \
                 {RENDER_SCALE_SOFTWARE_TAA} of the output's size (--render-scale 1: all of it)"
            );
            RENDER_SCALE_SOFTWARE_TAA
        }
        None => 1.0,
    };
    settings.look.shadows = if common.no_shadows {
        false
    } else {
        common.shadows || !device.software
    };
    settings.look.shadow_size = common.shadow_size.unwrap_or(if device.software {
        SHADOW_SIZE_SOFTWARE
    } else {
        SHADOW_SIZE
    });
    Ok(())
}

/// The grass pipeline `choice` names on `device`: `mesh` is an error naming what the
/// device lacks; `auto` takes the mesh path wherever the device has it, measured the
/// faster on every device and look (docs/pipelines.md, "Measured": lavapipe 2.9 to 4.5 times,
/// the NVIDIA H100 1.6 to 1.7 times with the paper look at the edge camera and 1.1 to
/// 1.2 times with the natural look), else tessellation. The log says which it took
/// and why.
pub fn grass_pipeline(choice: PipelineChoice, device: &Capabilities) -> Result<GrassPipeline> {
    let missing = device.mesh_shader.as_ref().err().map(String::as_str);
    let (pipeline, why) = match (choice, missing) {
        (PipelineChoice::Tess, _) => (GrassPipeline::Tess, "--pipeline tess"),
        (PipelineChoice::Mesh, None) => (GrassPipeline::Mesh, "--pipeline mesh"),
        (PipelineChoice::Mesh, Some(why)) => {
            anyhow::bail!("--pipeline mesh: {why} (use --pipeline tess or auto)")
        }
        (PipelineChoice::Auto, Some(why)) => {
            log::info!("grass pipeline: tessellation ({why})");
            return Ok(GrassPipeline::Tess);
        }
        (PipelineChoice::Auto, None) => (GrassPipeline::Mesh, "auto: the faster path"),
    };
    log::info!("grass pipeline: {pipeline:?} ({why})");
    Ok(pipeline)
}

/// The anti-aliasing and the samples of multisampling: `--aa` and `--msaa` (more
/// than one sample means multisampling), else the default of a device, `software`
/// or not: temporal on a GPU (`docs/look.md`, "Anti-aliasing quality": closer to the
/// supersampled reference than 4x MSAA, and cheaper), none on a software device,
/// whose every pass costs it a share of the frame.
pub fn antialiasing(common: &Common, software: bool) -> Result<(Antialiasing, u32)> {
    let samples = common.msaa.unwrap_or(DEFAULT_MSAA);
    let many = samples > 1;
    Ok(match (common.aa, common.msaa) {
        (Some(Antialiasing::Msaa), _) => (Antialiasing::Msaa, samples),
        (Some(aa), Some(_)) if many => {
            anyhow::bail!(
                "--aa {}: --msaa {samples} asks for multisampling (use --aa msaa)",
                clap::ValueEnum::to_possible_value(&aa)
                    .map_or_else(String::new, |v| v.get_name().into())
            )
        }
        (Some(aa), _) => (aa, samples),
        (None, Some(_)) if many => (Antialiasing::Msaa, samples),
        (None, Some(_)) => (Antialiasing::None, 1),
        (None, None) if software => (Antialiasing::None, samples),
        (None, None) => (Antialiasing::Taa, samples),
    })
}

/// Blades shorter than this on screen (pixels) go to the compute rasterizer on a GPU
/// with 64-bit atomics when `--compute-raster-below` is not given. Where blades are
/// about a pixel wide, two samplings of one field differ pixel by pixel however they
/// are drawn; at this threshold the frame differs from the all-hardware frame less than
/// that frame differs from itself with the camera turned by a third of a pixel, from
/// 640x360 up (`tests/tests/raster.rs`: 1.83 and 1.42 against 3.37 and 3.59 in the
/// paper and natural looks; 24 pixels gave 4.44). On the NVIDIA H100 it draws 4 M
/// blades at the edge in 3.6 ms against 6.2 without (docs/compute-rasterizer.md).
/// Off on a software device, where it gained nothing measured.
pub const DEFAULT_COMPUTE_RASTER_BELOW_GPU: f32 = 16.0;

/// The render scale of temporal anti-aliasing on a software device when
/// `--render-scale` is not given: a software rasteriser pays for every pixel of every
/// pass, and the resolve adds two passes over the frame (docs/look.md,
/// "Anti-aliasing on a software device").
pub const RENDER_SCALE_SOFTWARE_TAA: f32 = 0.5;

/// Samples per pixel of multisampling when `--msaa` is not given.
pub const DEFAULT_MSAA: u32 = 4;

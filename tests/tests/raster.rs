//! The compute rasterizer of far blades (issue 18) on the device against the host.

use runner::app::driver::FrameDriver;
use runner::app::headless::{FORMAT, Offscreen};
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use shared::layout::far_slot;
use shared::raster::{Coverage, EMPTY, pixel_index, raster_blade, unpack};
use shared::settings::Look;
use tests::grass_share;

/// The visibility buffer the GPU wrote for a frame with every visible blade far,
/// against the host running `shared::raster` on the same blades: equal per pixel but
/// where two blades tie (at most 1 % of the covered pixels; measured on lavapipe: 0 of
/// 3,110; a rasterizer storing v a 255th off made all 3,110 differ).
#[test]
fn visibility_buffer_equals_the_hosts() {
    tests::with_device("visibility_buffer_equals_the_hosts", |ctx| {
        if let Err(why) = &ctx.int64_atomics {
            println!("skipped: {why}");
            return;
        }
        let scene = Scene::build(&SceneKind::Plane, None, BladeCount::Total(2048), 5, |_| {
            Ok(())
        })
        .unwrap();
        let mut settings = scene.settings();
        settings.look.style = Look::Paper;
        settings.compute_raster_below = 1e4;
        let (width, height) = (160, 120);
        let mut target = Offscreen::new(&ctx, width, height).unwrap();
        let renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).unwrap();
        let mut driver = FrameDriver::new(&ctx, renderer).unwrap();
        let eye = scene.camera().viewpoint(target.size());
        let mut uniforms = settings.uniforms(&eye, scene.blade_count(), &[]);
        driver.run(&mut target, 0.0, |_| uniforms, false).unwrap();
        driver.finish().unwrap();
        let counts = driver.readback.counts.expect("counts");
        let renderer = &driver.renderer;
        let pixels = (width * height) as usize;
        let gpu: Vec<u64> = renderer
            .download(renderer.visibility().expect("visibility buffer"), pixels)
            .unwrap();
        let visible: Vec<u32> = renderer
            .download(&renderer.field.visible, scene.blades.len())
            .unwrap();
        uniforms.raster.width = width;
        uniforms.raster.height = height;
        let mut host = vec![EMPTY; pixels];
        let camera = &uniforms.camera;
        for k in 0..counts.compute {
            let index = visible[far_slot(k, scene.blade_count()) as usize];
            let blade = &scene.blades[index as usize];
            let shape = (uniforms.grass.shape, uniforms.grass.tip_start);
            let coverage = Coverage::of(blade, index, shape, camera.position, camera.focal_pixels);
            raster_blade(
                blade,
                k,
                &coverage,
                camera.view_proj,
                &uniforms.raster,
                |x, y, p| {
                    let i = pixel_index(x, y, width);
                    host[i] = host[i].min(p);
                },
            );
        }
        let covered = host.iter().filter(|&&p| p != EMPTY).count();
        let differ = gpu.iter().zip(&host).filter(|(g, h)| g != h).count();
        let gpu_covered = gpu.iter().filter(|&&p| p != EMPTY).count();
        println!(
            "{counts:?}: {covered} pixels covered on the host, {gpu_covered} on the GPU, {differ} differ"
        );
        assert_eq!(counts.drawn, 0, "every visible blade is far");
        assert!(counts.compute > 100, "{counts:?}");
        assert!(covered > 100, "the far blades cover {covered} pixels");
        // A pixel may differ where float rounding moves a curve's step by one pixel or
        // orders two blades at nearly one depth differently.
        for (i, (g, h)) in gpu
            .iter()
            .zip(&host)
            .enumerate()
            .filter(|(_, (g, h))| g != h)
            .take(5)
        {
            println!("pixel {i}: GPU {:?}, host {:?}", unpack(*g), unpack(*h));
        }
        assert!(
            differ * 100 <= covered,
            "{differ} of {covered} covered pixels differ from the host's"
        );
    });
}

/// The same frame with the compute rasterizer off and drawing the blades below
/// `below` pixels, in each built-in scene and both looks: (difference, the share of
/// drawn blades the compute rasterizer took, coverage off and on).
fn off_and_on(args: &str, below: f32) -> (tests::Difference, f64, f64, f64) {
    let (off_report, off) = tests::render_image(&format!("{args} --compute-raster-below 0"));
    let (on_report, on) = tests::render_image(&format!("{args} --compute-raster-below {below}"));
    let (off_c, on_c) = (off_report.counts, on_report.counts);
    assert_eq!(off_c.compute, 0, "{args}: off draws nothing by compute");
    assert_eq!(
        off_c.drawn,
        on_c.drawn + on_c.compute,
        "{args}: the same blades drawn"
    );
    let share = f64::from(on_c.compute) / f64::from(off_c.drawn.max(1));
    let (diff, _) = tests::difference(&off, &on);
    (diff, share, grass_share(&off), grass_share(&on))
}

/// The frame with the compute rasterizer drawing the blades under 28 pixels tall (two
/// thirds of them at 320x240) against the hardware drawing all, on lavapipe, through
/// the tessellator: per-case mean limits (the measured mean plus about 30 %), an
/// outlier share of 0.035 (measured at most 0.020) and the grass coverage within 5 %
/// (measured at most 3.0 %). Planted faults: the resolve shading every far pixel in
/// the root's colour gave a mean of 2.96 on the plane (limit 2.0); a rasterizer
/// drawing nothing 2.51, and 11 % less grass. Dropping half the far blades passes: the
/// far field is covered several times over at this density, so the image barely
/// changes; the rasterizer itself is checked pixel by pixel against the host above.
#[test]
fn the_compute_rasterizer_draws_the_field_the_hardware_draws() {
    let Some(_gpu) = tests::device_available("the_compute_rasterizer_draws_the_field") else {
        return;
    };
    let size = "--blades 8192 --width 320 --height 240 --frames 3";
    for (name, args, mean) in [
        ("plane paper", "--look paper --pitch 10", 2.0),
        ("plane natural", "--look natural --pitch 10", 1.65),
        ("hills", "--scene hills --look paper", 4.6),
        ("walls", "--scene walls --look paper --pitch 8", 1.55),
        ("planet", "--scene planet --look paper", 1.3),
    ] {
        let (diff, share, off, on) = off_and_on(&format!("{size} {args}"), 28.0);
        let coverage = (on / off.max(1e-9) - 1.0).abs();
        println!(
            "{name}: {:.1} % of the drawn blades by compute; mean {:.3}, outliers {:.4}; grass {off:.4} against {on:.4}",
            100.0 * share,
            diff.mean,
            diff.outliers
        );
        assert!(share > 0.3, "{name}: only {share} by compute");
        assert!(
            diff.mean < mean,
            "{name}: mean {} (limit {mean})",
            diff.mean
        );
        assert!(diff.outliers < 0.035, "{name}: outliers {}", diff.outliers);
        assert!(coverage < 0.05, "{name}: coverage {off} against {on}");
    }
}

/// Mean absolute difference between consecutive frames (0-255 per channel) of the
/// plane seen with its camera turned by `step` radians a frame (a fraction of a
/// pixel), nothing moving but the camera, with blades under `below` pixels drawn by
/// the compute rasterizer.
fn frame_to_frame(ctx: &std::sync::Arc<runner::vulkan::Context>, below: f32, step: f32) -> f64 {
    let scene = Scene::build(&SceneKind::Plane, None, BladeCount::Total(8192), 5, |_| {
        Ok(())
    })
    .unwrap();
    let mut settings = scene.settings();
    settings.look.style = Look::Paper;
    settings.compute_raster_below = below;
    let (width, height) = (320, 240);
    let mut target = Offscreen::new(ctx, width, height).unwrap();
    let renderer = Renderer::new(ctx, &scene.meshes(), FORMAT).unwrap();
    let mut driver = FrameDriver::new(ctx, renderer).unwrap();
    let mut camera = scene.camera();
    camera.pitch = 10f32.to_radians();
    let mut frames: Vec<Vec<u8>> = Vec::new();
    for _ in 0..6 {
        let eye = camera.viewpoint(target.size());
        let uniforms = settings.uniforms(&eye, scene.blade_count(), &[]);
        // No time: no simulation step, the blades stand still.
        driver.run(&mut target, 0.0, |_| uniforms, true).unwrap();
        driver.finish().unwrap();
        frames.push(target.pixels().unwrap());
        camera.yaw += step;
    }
    let pairs: Vec<f64> = frames
        .windows(2)
        .map(|w| shared_mean_difference(&w[0], &w[1]))
        .collect();
    pairs.iter().sum::<f64>() / pairs.len() as f64
}

/// Mean absolute difference of two RGBA8 images over their colour channels.
fn shared_mean_difference(a: &[u8], b: &[u8]) -> f64 {
    runner::app::bench::mean_difference(a, b)
}

/// Temporal stability: with the camera turning by about a third of a pixel a frame
/// and nothing else moving, consecutive frames with the far blades drawn by the
/// compute rasterizer differ no more than the hardware's own do (the hardware's
/// sub-pixel triangles flicker as the pixel centres move over them; the rasterizer's
/// coverage comes from a hash of the blade and the step along it, not of the frame).
/// Measure: the mean absolute difference of consecutive frames over the whole image
/// (0-255 per channel), at most 1.05 times the hardware's; measured on lavapipe 0.571
/// against 0.807. A coverage hash that changed with the camera gave 1.002 and failed.
#[test]
fn the_compute_rasterizer_flickers_no_more_than_the_hardware() {
    tests::with_device("the_compute_rasterizer_flickers_no_more", |ctx| {
        if let Err(why) = &ctx.int64_atomics {
            println!("skipped: {why}");
            return;
        }
        // A third of a pixel at 240 pixels high and a 45° field of view.
        let step = 0.33 * 45f32.to_radians() / 240.0;
        let hardware = frame_to_frame(&ctx, 0.0, step);
        let compute = frame_to_frame(&ctx, 28.0, step);
        println!("frame to frame: hardware {hardware:.4}, compute {compute:.4}");
        assert!(
            compute <= 1.05 * hardware,
            "the compute rasterizer flickers more: {compute} against {hardware}"
        );
    });
}

/// Pixels of a grey surface (the walls' rock: channels within 16 levels of each other).
fn grey(p: &image::Rgba<u8>) -> bool {
    let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
    hi - lo < 16
}

/// Occlusion still holds: in the walls scene with the occlusion test off (so the
/// blades the walls hide reach the draw) and every drawn blade given to the compute
/// rasterizer, the upper halves of the walls in the hardware's frame are still walls:
/// the resolve's depth test keeps far blades behind them (no blade stands in front of
/// a wall that high). Measure: the share of those wall pixels that show grass with the
/// compute rasterizer, at most 1 % (measured on lavapipe: 7 of 3,384). A resolve writing
/// the nearest depth (0) instead of the blade's failed it (795 of 3,384).
#[test]
fn a_blade_behind_a_wall_is_drawn_by_neither_path() {
    let Some(_gpu) = tests::device_available("a_blade_behind_a_wall") else {
        return;
    };
    let args = "--scene walls --look paper --blades 8192 --width 320 --height 240 --frames 3 \
                --pitch 6 --no-cull-occlusion";
    let (_, hardware) = tests::render_image(&format!("{args} --compute-raster-below 0"));
    let (report, compute) = tests::render_image(&format!("{args} --compute-raster-below 10000"));
    assert_eq!(
        report.counts.drawn, 0,
        "every blade by compute: {:?}",
        report.counts
    );
    // The upper half of each column's run of wall pixels: no blade stands in front of
    // a wall that high, so grass there could only come from behind it.
    let mut walls = Vec::new();
    for x in 0..hardware.width() {
        let column: Vec<u32> = (0..hardware.height())
            .filter(|&y| grey(hardware.get_pixel(x, y)))
            .collect();
        let upper = column.len() / 2;
        walls.extend(column[..upper].iter().map(|&y| (x, y)));
    }
    let grassy = walls
        .iter()
        .filter(|&&(x, y)| {
            let p = compute.get_pixel(x, y);
            p[1] > p[0] && p[1] > p[2]
        })
        .count();
    let share = grassy as f64 / walls.len().max(1) as f64;
    println!(
        "{} wall pixels, {grassy} of them grass with the compute rasterizer",
        walls.len()
    );
    assert!(walls.len() > 500, "the walls cover {} pixels", walls.len());
    assert!(
        share < 0.01,
        "{grassy} of {} wall pixels show grass",
        walls.len()
    );
}

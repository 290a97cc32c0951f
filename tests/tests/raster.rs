//! The compute rasterizer of far blades (issue 18) on the device against the host.

use runner::app::driver::FrameDriver;
use runner::app::headless::{FORMAT, Offscreen};
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use shared::layout::far_slot;
use shared::raster::{EMPTY, paper_covers, pixel_index, raster_blade, unpack};
use shared::settings::Look;

/// The visibility buffer the GPU wrote for a frame with every visible blade far,
/// against the host running `shared::raster` on the same blades: equal per pixel but
/// where two blades tie.
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
            if paper_covers(blade, index, camera.position, camera.focal_pixels) {
                raster_blade(blade, k, camera.view_proj, &uniforms.raster, |x, y, p| {
                    let i = pixel_index(x, y, width);
                    host[i] = host[i].min(p);
                });
            }
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

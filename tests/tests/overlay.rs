//! The viewer's overlay laid over a frame: its opaque part (the window's fill) copied
//! into the target gives the same pixels as blending the whole layer over the frame,
//! in the paper look (drawn straight into the target) and the natural look (whose
//! tone map then leaves the copied pixels out).

use egui::{Pos2, RawInput, Rect, Vec2};
use runner::app::driver::{FRAMES_IN_FLIGHT, FrameDriver, FrameSpec};
use runner::app::headless::{FORMAT, Offscreen};
use runner::app::overlay::{opaque_part, panel};
use runner::passes::overlay::OverlayFrame;
use runner::renderer::Renderer;
use runner::scene::{BladeCount, Scene, SceneKind};
use shared::settings::{Antialiasing, Look};
use tests::with_device;

const SIZE: (u32, u32) = (320, 200);

/// egui's picture of a window like the viewer's (text, a graph's dark box, controls)
/// after its sizing pass, with the textures both passes asked for, and the window's
/// opaque part.
fn picture() -> (
    Vec<egui::ClippedPrimitive>,
    egui::TexturesDelta,
    Option<Rect>,
) {
    let ctx = egui::Context::default();
    let input = || RawInput {
        screen_rect: Some(Rect::from_min_size(
            Pos2::ZERO,
            Vec2::new(SIZE.0 as f32, SIZE.1 as f32),
        )),
        ..Default::default()
    };
    let mut textures = egui::TexturesDelta::default();
    let mut shown = None;
    let mut shapes = Vec::new();
    for _ in 0..2 {
        let output = ctx.run_pass(input(), |ctx| {
            let window = panel().default_width(150.0).show(ctx, |ui| {
                ui.label("3.7 fps, 281.19 ms");
                let (rect, _) =
                    ui.allocate_exact_size(Vec2::new(140.0, 30.0), egui::Sense::hover());
                ui.painter()
                    .rect_filled(rect, 0.0, egui::Color32::from_gray(10));
                let mut on = true;
                ui.checkbox(&mut on, "orientation");
                let mut x = 0.5f32;
                ui.add(egui::Slider::new(&mut x, 0.0..=1.0).text("exposure"));
            });
            shown = window.map(|w| w.response.rect);
        });
        textures.append(output.textures_delta);
        shapes = output.shapes;
    }
    let primitives = ctx.tessellate(shapes, 1.0);
    let opaque = shown.and_then(|rect| opaque_part(&ctx.global_style(), rect));
    (primitives, textures, opaque)
}

/// For each look, one still frame with the overlay blended over all it covers and
/// the same frame with its opaque part copied: equal to within one level of 255 in
/// every channel (sRGB blending of an opaque pixel rounds), with the copied part at
/// least a tenth of the frame and the panel's dark fill over most of it.
#[test]
fn the_overlay_s_copied_part_matches_it_blended() {
    with_device("the_overlay_s_copied_part_matches_it_blended", |ctx| {
        let (primitives, textures, opaque) = picture();
        let opaque = opaque.expect("the window's fill is opaque");
        let share = opaque.area() / (SIZE.0 * SIZE.1) as f32;
        assert!(share > 0.1, "the opaque part is {share} of the frame");
        let scene = Scene::build(&SceneKind::Plane, None, BladeCount::Total(2048), 1, |_| {
            Ok(())
        })
        .expect("scene");
        for look in [Look::Paper, Look::Natural] {
            let mut settings = scene.settings();
            settings.look.style = look;
            // One sample, nothing carried from frame to frame.
            settings.look.aa = Antialiasing::None;
            let eye = scene.camera().viewpoint(SIZE);
            let mut target = Offscreen::new(&ctx, SIZE.0, SIZE.1).expect("target");
            let mut renderer = Renderer::new(&ctx, &scene.meshes(), FORMAT).expect("renderer");
            renderer.enable_overlay(FRAMES_IN_FLIGHT).expect("overlay");
            let mut driver = FrameDriver::new(&ctx, renderer).expect("frame driver");
            let mut shots = Vec::new();
            for (k, copy) in [false, true].into_iter().enumerate() {
                target.transfer_dst = copy;
                let empty = egui::TexturesDelta::default();
                let overlay = OverlayFrame {
                    changed: k == 0,
                    primitives: &primitives,
                    textures: if k == 0 { &textures } else { &empty },
                    pixels_per_point: 1.0,
                    opaque: Some(opaque),
                };
                // No time: the blades stand as they are.
                let frame = driver
                    .begin(&mut target, 0.0)
                    .expect("begin")
                    .expect("image");
                let spec = FrameSpec {
                    request: settings.request(&eye, &[]),
                    overlay: Some(overlay),
                    capture: true,
                };
                driver.submit(frame, &mut target, spec).expect("frame");
                driver.finish().expect("finish");
                shots.push(target.pixels().expect("pixels"));
            }
            let (blended, copied) = (&shots[0], &shots[1]);
            let worst = blended
                .iter()
                .zip(copied)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap_or(0);
            let differing = blended
                .chunks(4)
                .zip(copied.chunks(4))
                .filter(|(a, b)| a != b)
                .count();
            // The panel's fill (grey 27) over the opaque part.
            let (mut dark, mut inside) = (0, 0);
            for y in opaque.min.y.ceil() as u32..opaque.max.y.floor() as u32 {
                for x in opaque.min.x.ceil() as u32..opaque.max.x.floor() as u32 {
                    let p = &copied[4 * (y * SIZE.0 + x) as usize..][..3];
                    dark += usize::from(p.iter().all(|&c| c < 70));
                    inside += 1;
                }
            }
            println!(
                "{look:?}: opaque part {share:.3} of the frame, {differing} pixels differ, at most by {worst}, dark {dark} of {inside}"
            );
            assert!(
                worst <= 1,
                "{look:?}: copied and blended differ by {worst} ({differing} pixels)"
            );
            assert!(
                dark * 2 > inside,
                "{look:?}: {dark} of {inside} pixels of the panel dark"
            );
        }
    });
}

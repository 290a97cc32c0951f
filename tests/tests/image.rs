//! Headless renders: a fixed small scene against a committed reference image, its
//! content, and a render with the validation layer on.

use image::{Rgba, RgbaImage};
use runner::app::render::{RenderReport, render};
use runner::cli::{Common, RenderArgs};
use tests::{check_reference, device_available, render_options, save_failure};

const WIDTH: u32 = 256;
const HEIGHT: u32 = 256;

fn scene(validation: bool) -> (Common, RenderArgs) {
    let (mut common, args) = render_options(&[
        "--blades", "2048", "--seed", "1", "--frames", "30", "--width", "256", "--height", "256",
    ]);
    common.validation = validation;
    (common, args)
}

fn to_image(report: &RenderReport) -> RgbaImage {
    RgbaImage::from_raw(WIDTH, HEIGHT, report.pixels.clone()).expect("image size")
}

#[test]
fn headless_render_matches_the_reference_and_shows_grass_and_ground() {
    let Some(_gpu) = device_available("headless_render_matches_the_reference") else {
        return;
    };
    let (common, args) = scene(false);
    let report = render(&common, &args).expect("render");
    let image = to_image(&report);

    // Content: grass (green dominant), ground (brown: red over blue, dim) and sky.
    let (mut grass, mut ground, mut sky) = (0, 0, 0);
    for Rgba([r, g, b, _]) in image.pixels() {
        let (r, g, b) = (*r as i32, *g as i32, *b as i32);
        if g > r + 10 && g > b + 10 {
            grass += 1;
        } else if b > r + 30 && b > g {
            sky += 1;
        } else if r > b + 8 && r + g + b < 400 {
            ground += 1;
        }
    }
    let total = (WIDTH * HEIGHT) as f64;
    let shares = (
        grass as f64 / total,
        ground as f64 / total,
        sky as f64 / total,
    );
    println!(
        "grass {:.3}, ground {:.3}, sky {:.3}; {} of {} blades visible",
        shares.0, shares.1, shares.2, report.visible, report.blades
    );
    let content_ok = shares.0 > 0.10 && shares.1 > 0.005 && shares.2 > 0.05;
    assert!(
        content_ok,
        "grass/ground/sky shares {shares:?}; {}",
        save_failure("field_content", &image, None)
    );

    check_reference("field_256", &image);
}

#[test]
fn render_with_validation_reports_no_error() {
    let Some(_gpu) = device_available("render_with_validation_reports_no_error") else {
        return;
    };
    // The plane, and the meadow (two surface meshes) with a ball and gusts.
    let (common, mut args) = scene(true);
    args.frames = 5;
    let (mut meadow, _) = render_options(&[
        "--scene",
        "meadow",
        "--blades",
        "1024",
        "--wind",
        "gusts",
        "--collider-path",
        "0,0;3,3",
    ]);
    meadow.validation = true;
    for common in [common, meadow] {
        let report = render(&common, &args).expect("render with validation");
        assert_eq!(
            report.validation_errors, 0,
            "{}: validation errors (see the log)",
            common.scene
        );
    }
}

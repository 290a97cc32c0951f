//! The mesh-shader pipeline (issue 17) against the tessellation path on the device:
//! the same frame through both, for every blade shape, the LOD view, a scene whose
//! walls hide grass (occlusion) and the natural look. The strips' rows are not the
//! tessellator's fractional-odd rows (`shared::meshlet`), so blade edges move by a
//! fraction of a pixel: the images agree within the stated tolerance, not exactly.

use tests::{Difference, device_available, difference, render_image, save_failure};

/// Small images: lavapipe tessellates slowly.
const SIZE: &str = "192";
/// Share of pixels allowed to differ by more than `tests::OUTLIER_LEVEL` (measured:
/// at most 0.028; dropping every fourth blade gave up to 0.042).
const OUTLIERS: f64 = 0.035;

/// Relative difference allowed between the two paths' grass coverage (the share of
/// green pixels; measured: at most 2.2 %; dropping every fourth blade gave up to 10.7 %).
const COVERAGE: f64 = 0.04;

/// Share of the image's pixels that show grass: green above red and blue.
fn grass_share(image: &image::RgbaImage) -> f64 {
    let green = image
        .pixels()
        .filter(|p| p[1] > p[0] && p[1] > p[2])
        .count();
    green as f64 / f64::from(image.width() * image.height())
}

/// The frame of `args` through both pipelines: their difference, whose mean must stay
/// under `mean` (0..255 per channel).
fn both(name: &str, args: &str, mean: f64) -> Difference {
    let (tess_report, tess) = render_image(&format!("{args} --pipeline tess"));
    let (mesh_report, mesh) = render_image(&format!("{args} --pipeline mesh"));
    assert_eq!(
        tess_report.counts.drawn, mesh_report.counts.drawn,
        "{name}: the same blades reach the draw"
    );
    let (diff, picture) = difference(&tess, &mesh);
    let (cover_tess, cover_mesh) = (grass_share(&tess), grass_share(&mesh));
    let coverage = (cover_mesh / cover_tess.max(1e-9) - 1.0).abs();
    println!(
        "{name}: mean difference {:.3}, outlier share {:.4}, grass {:.4} against {:.4} ({:.2} %)",
        diff.mean,
        diff.outliers,
        cover_mesh,
        cover_tess,
        100.0 * coverage
    );
    assert!(
        cover_tess > 0.05 && coverage < COVERAGE,
        "{name}: grass covers {cover_mesh:.4} of the mesh path's image against {cover_tess:.4}; {}",
        save_failure(&format!("mesh_{name}"), &mesh, Some(&picture))
    );
    assert!(
        diff.mean < mean && diff.outliers < OUTLIERS,
        "{name}: mesh against tessellation: mean {:.3} (max {mean}), outliers {:.4} \
         (max {OUTLIERS}); {}",
        diff.mean,
        diff.outliers,
        save_failure(&format!("mesh_{name}"), &mesh, Some(&picture))
    );
    diff
}

#[test]
fn mesh_and_tessellation_draw_the_same_field() {
    let Some(_gpu) = device_available("mesh_and_tessellation_draw_the_same_field") else {
        return;
    };
    let common =
        format!("--blades 2048 --frames 12 --width {SIZE} --height {SIZE} --wind calm --zoom 1.6");
    // Each limit is the mean measured on lavapipe (Mesa 25.0.7) plus about 30 %. A mesh
    // path that dropped every fourth blade measured 4.2, 5.1, 5.2, 4.2, 4.5, 4.6, 3.9
    // and 5.9 in these cases and fails each; one whose blades came out 10 % short
    // measured 1.55 for the quad (failing) and passes the others.
    let shapes = [
        ("quad", 1.5),
        ("triangle", 2.9),
        ("quadratic", 2.4),
        ("triangle-tip", 2.1),
        ("dandelion", 3.3),
    ];
    for (shape, mean) in shapes {
        both(shape, &format!("{common} --shape {shape}"), mean);
    }
    both("lod_view", &format!("{common} --view lod"), 1.9);
    both("walls", &format!("{common} --scene walls"), 3.5);
    both(
        "natural",
        &format!("{common} --look natural --scene hills"),
        5.5,
    );
}

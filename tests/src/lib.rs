//! Helpers of the integration tests in `tests/tests/`.

use runner::vulkan::{Context, ContextOptions};
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

pub use runner::vulkan::gpu_required;
pub use runner::vulkan::probe::{Need, runs_here};

/// One GPU test at a time in a test binary. Debian's validation layer (1.3.239) dies of
/// a segmentation fault on the NVIDIA driver when validated instances work in several
/// threads at once (seen on the H100: the culling and image tests crashed run in
/// parallel, and passed one at a time and each alone).
static GPU: Mutex<()> = Mutex::new(());

/// Holds the GPU for one test until dropped.
pub type GpuGuard = MutexGuard<'static, ()>;

fn gpu_lock() -> GpuGuard {
    // A test that failed while holding it poisons it; the next one may still run.
    GPU.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Runs `test` with a Vulkan context under the validation layer (core and
/// synchronization validation), then fails if the layer said anything, warnings too;
/// skips it where [`runs_here`] says so. Holds the GPU lock throughout.
pub fn with_device(name: &str, test: impl FnOnce(Arc<Context>)) {
    with_device_needing(name, &[], test);
}

/// [`with_device`] for a test that also needs `needs` (mesh shaders, 64-bit atomics).
pub fn with_device_needing(name: &str, needs: &[Need], test: impl FnOnce(Arc<Context>)) {
    if !runs_here(name, needs) {
        return;
    }
    let _gpu = gpu_lock();
    run_with_device(name, test);
}

fn run_with_device(name: &str, test: impl FnOnce(Arc<Context>)) {
    // Validation messages go to the log; show them in the test output.
    let _ = env_logger::builder().is_test(true).try_init();
    let options = ContextOptions {
        validation: true,
        ..Default::default()
    };
    let ctx = Context::new(options)
        .unwrap_or_else(|e| panic!("{name}: the probe found a device, but: {e:#}"));
    test(ctx.clone());
    let messages = ctx.validation_messages();
    assert_eq!(
        messages, 0,
        "{name}: the validation layer spoke (see the log)"
    );
}

/// For tests that create their own contexts: the GPU lock, to hold for the whole test,
/// where [`runs_here`] says the test runs; `None` where it skips.
pub fn device_available(name: &str) -> Option<GpuGuard> {
    device_needing(name, &[])
}

/// [`device_available`] for a test that also needs `needs`.
pub fn device_needing(name: &str, needs: &[Need]) -> Option<GpuGuard> {
    runs_here(name, needs).then(gpu_lock)
}

/// Folder where failing tests leave the images they compared.
pub fn artifact_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/test-artifacts");
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(|t| PathBuf::from(t).join("test-artifacts"))
        .unwrap_or(dir);
    std::fs::create_dir_all(&dir).expect("create test artifact folder");
    dir
}

/// The options of `grass render <args>`, parsed as the command line would: tests
/// describe their scenes in the user's words.
pub fn render_options(args: &[&str]) -> (runner::cli::Common, runner::cli::RenderArgs) {
    use clap::Parser;
    // The references before the natural look are the paper's: tests name the look
    // they want, the paper's unless they say, and the pipeline, tessellation unless
    // they say.
    let paper: &[&str] = if args.contains(&"--look") {
        &[]
    } else {
        &["--look", "paper"]
    };
    // The references were drawn through the tessellator; tests of the mesh path name
    // it.
    let tess: &[&str] = if args.contains(&"--pipeline") {
        &[]
    } else {
        &["--pipeline", "tess"]
    };
    // What the device would choose otherwise, as a software device chooses it, so
    // every device draws the references' frames: no compute rasterizer, one sample
    // per pixel, no sun shadows (tests that want them say) and a shadow map 512
    // texels a side.
    let device: Vec<&str> = [
        (
            "--compute-raster-below",
            &["--compute-raster-below", "0"][..],
        ),
        ("--msaa", &["--msaa", "1"]),
        ("--shadow-size", &["--shadow-size", "512"]),
        ("--shadows", &["--no-shadows"]),
    ]
    .into_iter()
    .filter(|(flag, _)| {
        !args.contains(flag) && !(*flag == "--shadows" && args.contains(&"--no-shadows"))
    })
    .flat_map(|(_, words)| words.iter().copied())
    .collect();
    let argv = ["grass", "render"]
        .iter()
        .chain(paper)
        .chain(tess)
        .chain(&device)
        .chain(args);
    let cli = runner::cli::Cli::try_parse_from(argv).unwrap_or_else(|e| panic!("{args:?}: {e}"));
    match cli.command {
        Some(runner::cli::Command::Render(render)) => (cli.common, render),
        _ => unreachable!("parsed as render"),
    }
}

/// A channel difference above this makes a pixel an outlier.
pub const OUTLIER_LEVEL: u8 = 64;

/// How far an image may be from its reference: the mean absolute difference per
/// channel (0..255) and the share of pixels off by more than [`OUTLIER_LEVEL`] in
/// some channel. References are rendered by lavapipe (Mesa 25.0.7, which CI runs and
/// which draws them again exactly); another device's rasteriser rounds blade edges
/// differently, hence a tolerance for each kind of frame, about 5 times the largest
/// difference measured on the NVIDIA H100 (`cargo test -p tests -- --nocapture`
/// prints every difference).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Tolerance {
    /// Largest mean difference.
    pub mean: f64,
    /// Largest outlier share.
    pub outliers: f64,
}

/// Frames of either look, through every path (the natural look's shadow map pinned
/// to 512 texels a side, as a software device draws it): measured on the NVIDIA H100
/// at most 0.058 in the paper look (`shape_quad`) and 0.105 in the natural look
/// (`natural_trail`), 0.01 % outliers. A step of the simulation taken explicitly
/// instead of semi-implicitly moved the paper look's frames by 0.5 to 1.2; leaves lit
/// through at 1.0 instead of 1.4 moved the natural look's by 0.26 to 1.38.
pub const FRAME_TOLERANCE: Tolerance = Tolerance {
    mean: 0.3,
    outliers: 0.0005,
};

/// The wireframe view: how a line is rasterised is the driver's (Vulkan's non-strict
/// lines); measured on the H100 2.97, no outlier.
pub const WIREFRAME_TOLERANCE: Tolerance = Tolerance {
    mean: 4.5,
    outliers: 0.0005,
};

/// The tolerance of reference `name`.
pub fn tolerance_of(name: &str) -> Tolerance {
    if name.contains("wireframe") {
        WIREFRAME_TOLERANCE
    } else {
        FRAME_TOLERANCE
    }
}

/// How two images differ.
#[derive(Copy, Clone, Debug)]
pub struct Difference {
    /// Mean absolute difference per channel, 0..255.
    pub mean: f64,
    /// Share of pixels off by more than [`OUTLIER_LEVEL`] in some channel.
    pub outliers: f64,
}

impl Difference {
    /// Within `tolerance`.
    pub fn within(&self, tolerance: Tolerance) -> bool {
        self.mean <= tolerance.mean && self.outliers <= tolerance.outliers
    }

    /// Apart by more than `floor` on both measures (for images that must differ).
    pub fn beyond(&self, floor: Tolerance) -> bool {
        self.mean > floor.mean && self.outliers > floor.outliers
    }
}

/// The difference of two images of the same size, and a picture of it (×4).
pub fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (Difference, image::RgbaImage) {
    assert_eq!(a.dimensions(), b.dimensions(), "image sizes differ");
    let mut picture = image::RgbaImage::new(a.width(), a.height());
    let (mut sum, mut outliers) = (0u64, 0u64);
    for (x, y, p) in a.enumerate_pixels() {
        let q = b.get_pixel(x, y);
        let d: [u8; 3] = std::array::from_fn(|c| p[c].abs_diff(q[c]));
        sum += d.iter().map(|&v| u64::from(v)).sum::<u64>();
        outliers += u64::from(d.iter().any(|&v| v > OUTLIER_LEVEL));
        let [r, g, b] = d.map(|v| v.saturating_mul(4));
        picture.put_pixel(x, y, image::Rgba([r, g, b, 255]));
    }
    let pixels = f64::from(a.width() * a.height());
    let diff = Difference {
        mean: sum as f64 / (pixels * 3.0),
        outliers: outliers as f64 / pixels,
    };
    (diff, picture)
}

/// Saves `image` (and `diff`) under [`artifact_dir`]; returns a message saying where.
pub fn save_failure(
    name: &str,
    image: &image::RgbaImage,
    diff: Option<&image::RgbaImage>,
) -> String {
    let dir = artifact_dir();
    let out = dir.join(format!("{name}.png"));
    image.save(&out).expect("save test image");
    let mut msg = format!("image written to {}", out.display());
    if let Some(diff) = diff {
        let d = dir.join(format!("{name}_diff.png"));
        diff.save(&d).expect("save diff image");
        msg += &format!(", difference to {}", d.display());
    }
    msg
}

/// The committed reference image `tests/reference/<name>.png`.
pub fn reference_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("reference/{name}.png"))
}

/// Compares `image` with its reference within the stated tolerance, or rewrites the
/// reference when GRASS_UPDATE_REFERENCE is set. Returns the difference, or a message
/// saying how far off it is and where the image and the difference were written.
pub fn compare_reference(name: &str, image: &image::RgbaImage) -> Result<Difference, String> {
    let path = reference_path(name);
    if std::env::var_os("GRASS_UPDATE_REFERENCE").is_some() {
        image.save(&path).expect("write reference");
        eprintln!("reference updated: {}", path.display());
        return Ok(Difference {
            mean: 0.0,
            outliers: 0.0,
        });
    }
    let reference = image::open(&path)
        .unwrap_or_else(|e| panic!("open reference {}: {e}", path.display()))
        .to_rgba8();
    let (diff, picture) = difference(image, &reference);
    println!(
        "{name}: mean difference {:.3}, outlier share {:.4}",
        diff.mean, diff.outliers
    );
    let tolerance = tolerance_of(name);
    if diff.within(tolerance) {
        return Ok(diff);
    }
    Err(format!(
        "{name} differs from {}: mean {:.3} (max {}), outliers {:.4} (max {}); {}",
        path.display(),
        diff.mean,
        tolerance.mean,
        diff.outliers,
        tolerance.outliers,
        save_failure(name, image, Some(&picture))
    ))
}

/// [`compare_reference`], failing the test when the image is off.
pub fn check_reference(name: &str, image: &image::RgbaImage) -> Difference {
    compare_reference(name, image).unwrap_or_else(|message| panic!("{message}"))
}

/// Renders with the options of `grass render <args>` (split at whitespace) and
/// returns the report and the image.
pub fn render_image(args: &str) -> (runner::app::render::RenderReport, image::RgbaImage) {
    let args: Vec<&str> = args.split_whitespace().collect();
    let (mut common, render) = render_options(&args);
    // Under the validation layer, core and synchronization: no error allowed.
    common.validation = true;
    let report = runner::app::render::render(&common, &render)
        .unwrap_or_else(|e| panic!("render {args:?}: {e:#}"));
    assert_eq!(
        report.validation_errors, 0,
        "render {args:?}: validation errors (see the log)"
    );
    let image = image::RgbaImage::from_raw(render.width, render.height, report.pixels.clone())
        .expect("image size");
    (report, image)
}

/// Share of the image's pixels that show grass: green above red and blue.
pub fn grass_share(image: &image::RgbaImage) -> f64 {
    let green = image
        .pixels()
        .filter(|p| p[1] > p[0] && p[1] > p[2])
        .count();
    green as f64 / f64::from(image.width() * image.height())
}

//! The viewer in a real window under Xvfb, through a storm of resizes: tiny, huge,
//! several at once, minimised, 0x0 and back (`--resize-storm`, runner/src/app/storm.rs).
//! It must draw every frame asked for, with the validation layer silent, and quit on
//! its own. The test starts its own Xvfb; CI installs it (`xvfb`).

mod common;

use common::{gpu_required, scratch};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A private X server, killed when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    /// Starts Xvfb on a display no other run (nor this run's other `slot`s) uses;
    /// `None` where it is not installed. A display whose lock file is there (another
    /// server, or one killed without cleaning up) is passed over, and a server that
    /// quits at once (it found the display taken) makes the next one be tried.
    fn start(slot: u32) -> Option<Self> {
        let first = 200 + (std::process::id() % 400) * 2 + slot;
        for number in (first..first + 400).step_by(2) {
            let lock = format!("/tmp/.X{number}-lock");
            if std::path::Path::new(&lock).exists() {
                continue;
            }
            let mut child = Command::new("Xvfb")
                .args([
                    &format!(":{number}"),
                    "-screen",
                    "0",
                    "1280x800x24",
                    "-nolisten",
                    "tcp",
                ])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .ok()?;
            let socket = format!("/tmp/.X11-unix/X{number}");
            let start = Instant::now();
            let mut quit = false;
            while !std::path::Path::new(&socket).exists() {
                if matches!(child.try_wait(), Ok(Some(_))) {
                    quit = true;
                    break;
                }
                assert!(
                    start.elapsed() < Duration::from_secs(20),
                    "Xvfb did not start"
                );
                std::thread::sleep(Duration::from_millis(50));
            }
            if quit || matches!(child.try_wait(), Ok(Some(_))) {
                continue;
            }
            return Some(Self {
                child,
                display: format!(":{number}"),
            });
        }
        panic!("no free X display from :{first}");
    }
}

impl Xvfb {
    /// [`Xvfb::start`] for a test: where it is not installed, the test is skipped
    /// (`None`), or fails when a GPU is required (CI installs it).
    fn for_test(slot: u32) -> Option<Self> {
        let x = Self::start(slot);
        if x.is_none() {
            assert!(!gpu_required(), "Xvfb is required (apt-get install xvfb)");
            eprintln!("skipped: no Xvfb");
        }
        x
    }
}

impl Drop for Xvfb {
    /// Ends the server with SIGTERM, so it removes its lock file and socket (SIGKILL
    /// leaves them, and a later run on the same display number would find them).
    fn drop(&mut self) {
        let terminated = Command::new("kill")
            .arg(self.child.id().to_string())
            .status()
            .is_ok_and(|s| s.success());
        if !terminated {
            let _ = self.child.kill();
        }
        let _ = self.child.wait();
    }
}

/// Runs `grass` with `args` and `env` on `display`; fails the test if it has not quit
/// by `limit`.
fn run_viewer(
    display: &str,
    args: &[&str],
    env: &[(&str, &str)],
    limit: Duration,
) -> (bool, String) {
    let grass = Path::new(env!("CARGO_BIN_EXE_grass"));
    run_program(grass, display, args, env, limit)
}

/// Runs `program` with `args` and `env` on `display`; fails the test if it has not
/// quit by `limit`. Its log is standard error and output together.
fn run_program(
    program: &Path,
    display: &str,
    args: &[&str],
    env: &[(&str, &str)],
    limit: Duration,
) -> (bool, String) {
    let name = program.display();
    let mut child = Command::new(program)
        .args(args)
        .env("DISPLAY", display)
        .env("RUST_LOG", "info")
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("run {name}: {e}"));
    let stderr = child.stderr.take().expect("stderr");
    let stdout = child.stdout.take().expect("stdout");
    let reader = std::thread::spawn(move || std::io::read_to_string(stderr).unwrap_or_default());
    let out_reader =
        std::thread::spawn(move || std::io::read_to_string(stdout).unwrap_or_default());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the program") {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let log = reader.join().unwrap_or_default();
            panic!("{name} {args:?} hung for {limit:?}: {log}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let log = reader.join().unwrap_or_default() + &out_reader.join().unwrap_or_default();
    assert!(!log.contains("panicked"), "{name} {args:?} panicked: {log}");
    (status.success(), log)
}

#[test]
fn the_viewer_draws_through_a_resize_storm() {
    let Some(x) = Xvfb::for_test(0) else {
        return;
    };
    // The natural look with shadows and 4x MSAA: every image of the frame is made
    // again at each size.
    let args = [
        "--frames",
        "150",
        "--resize-storm",
        "--validation",
        "--blades",
        "256",
        "--look",
        "natural",
        "--shadows",
        "--msaa",
        "4",
    ];
    let (ok, log) = run_viewer(&x.display, &args, &[], Duration::from_secs(300));
    if !ok && !gpu_required() && log.contains("device") {
        eprintln!("skipped, no device: {log}");
        return;
    }
    assert!(ok, "{log}");
    assert!(!log.contains("validation:"), "validation messages: {log}");
    // Every gust of the script came (and more), each changed size made a swapchain,
    // and the hidden phases came and went.
    let summary = log
        .lines()
        .find(|l| l.contains("frames drawn"))
        .unwrap_or_else(|| panic!("no summary: {log}"));
    let number = |word: &str| -> u64 {
        let before = summary.split(word).next().unwrap_or("");
        let n = before.split_whitespace().last().unwrap_or("0");
        n.parse().unwrap_or_else(|_| panic!("{word} in {summary}"))
    };
    assert_eq!(number("frames drawn"), 150, "{summary}");
    let gusts = number("storm gusts");
    assert!(
        gusts >= runner::app::storm::SCRIPT.len() as u64,
        "{summary}"
    );
    assert!(number("swapchains made") >= 12, "{summary}");
    for expected in [
        "storm: Zero",
        "storm: Minimise",
        "storm: restored",
        "swapchain 1x1",
    ] {
        assert!(log.contains(expected), "no \"{expected}\": {log}");
    }
}

#[test]
fn a_lost_device_is_made_again_and_the_viewer_carries_on() {
    let Some(x) = Xvfb::for_test(1) else {
        return;
    };
    let args = ["--frames", "80", "--validation", "--blades", "256"];
    let fault = [("GRASS_FAULT", "device-lost:30")];
    let (ok, log) = run_viewer(&x.display, &args, &fault, Duration::from_secs(300));
    if !ok && !gpu_required() && log.contains("device") && !log.contains("made again") {
        eprintln!("skipped, no device: {log}");
        return;
    }
    assert!(ok, "{log}");
    assert!(
        log.contains("The GPU device was lost and has been made again (1 of 3)"),
        "no recovery: {log}"
    );
    assert!(log.contains("80 frames drawn"), "{log}");
    assert!(!log.contains("validation:"), "validation messages: {log}");
}

/// The screenshot key's path (`--screenshot-at`, as K does it): one PNG of the
/// window's size in the asked folder, with the validation layer silent, showing the
/// frame: at least 5 % of its pixels grass green (green above red and blue by 20) and
/// at least 0.2 % the ball's orange (red above green by 60), as lavapipe draws the
/// default scene. Planted fault: the swapchain's BGRA saved as RGBA failed (the ball
/// came out blue: 0 orange pixels).
#[test]
fn a_screenshot_is_the_window_s_frame() {
    let Some(x) = Xvfb::for_test(2) else {
        return;
    };
    let dir = scratch("screenshot");
    let dir_arg = dir.to_str().expect("utf-8 path");
    let args = [
        "--frames",
        "12",
        "--screenshot-at",
        "6",
        "--screenshot-dir",
        dir_arg,
        "--validation",
        "--width",
        "800",
        "--height",
        "450",
    ];
    let (ok, log) = run_viewer(&x.display, &args, &[], Duration::from_secs(300));
    if !ok && !gpu_required() && log.contains("device") {
        eprintln!("skipped, no device: {log}");
        return;
    }
    assert!(ok, "{log}");
    assert!(!log.contains("validation:"), "validation messages: {log}");
    let shots: Vec<_> = std::fs::read_dir(&dir)
        .expect("the folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    assert_eq!(shots.len(), 1, "{shots:?}");
    let image = image::open(&shots[0]).expect("a PNG").to_rgba8();
    assert_eq!(image.dimensions(), (800, 450));
    let share = |f: &dyn Fn(i32, i32, i32) -> bool| {
        let n = image
            .pixels()
            .filter(|p| f(i32::from(p[0]), i32::from(p[1]), i32::from(p[2])))
            .count();
        n as f32 / (800.0 * 450.0)
    };
    let green = share(&|r, g, b| g > r + 20 && g > b + 20);
    let orange = share(&|r, g, _| r > g + 60);
    println!("grass green {green}, ball orange {orange}");
    assert!(
        green > 0.05 && orange > 0.002,
        "green {green}, orange {orange}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The embedding example (`runner/examples/embed.rs`) in a window: its own swapchain,
/// cube and the grass of `runner::embed`, 60 frames with the validation layer
/// (core and synchronization) silent, through four window sizes (one of 1x1). `cargo test` builds the example beside `grass`.
#[test]
fn the_embed_example_runs_in_a_window() {
    let Some(x) = Xvfb::for_test(3) else {
        return;
    };
    let grass = Path::new(env!("CARGO_BIN_EXE_grass"));
    let example = grass.with_file_name("examples").join("embed");
    if !example.exists() {
        assert!(!gpu_required(), "{} not built", example.display());
        eprintln!("skipped: the example is not built (cargo test --examples builds it)");
        return;
    }
    let sizes = "300x200,97x203,1x1,500x150";
    let args = ["--frames", "60", "--validation", "--resize-through", sizes];
    let (ok, log) = run_program(&example, &x.display, &args, &[], Duration::from_secs(300));
    if !ok && !gpu_required() && log.contains("device") {
        eprintln!("skipped, no device: {log}");
        return;
    }
    assert!(ok, "{log}");
    assert!(log.contains("drew 60 frames, 0 validation errors"), "{log}");
    // The window went through each size asked, the swapchain and the field after it.
    for size in sizes.split(',') {
        assert!(
            log.contains(&format!("swapchain {size}")),
            "no {size}: {log}"
        );
    }
    assert!(!log.contains("validation:"), "validation messages: {log}");
}

//! The viewer in a real window under Xvfb, through a storm of resizes: tiny, huge,
//! several at once, minimised, 0x0 and back (`--resize-storm`, runner/src/app/storm.rs).
//! It must draw every frame asked for, with the validation layer silent, and quit on
//! its own. The tests share one Xvfb ([`x_server`]); CI installs it (`xvfb`).

mod common;

use common::{gpu_required, runs_here, scratch};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError, mpsc};
use std::time::{Duration, Instant};

/// The window tests' X server: one for this test binary, started by the first window
/// test. Xvfb picks a free display itself and says which once it accepts clients
/// (`-displayfd`), so no start can race another's for a display number, and a wait
/// that gives up kills the server it started. It ends with the test binary: its parent
/// thread lives as long as the process, and the kernel sends it SIGTERM when that
/// thread dies (`PR_SET_PDEATHSIG`), so it removes its lock file and socket.
fn x_server() -> &'static Result<String, String> {
    static SERVER: OnceLock<Result<String, String>> = OnceLock::new();
    SERVER.get_or_init(|| {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let started = start_xvfb();
            let _ = tx.send(started);
            // The server's parent: it must outlive every test.
            loop {
                std::thread::park();
            }
        });
        rx.recv()
            .unwrap_or_else(|_| Err("the X server's thread died".into()))
    })
}

/// How long Xvfb may take to accept clients. On a loaded two-core machine it took
/// over 20 s; it is started before any window test renders, so this is generous.
const XVFB_START: Duration = Duration::from_secs(120);

/// Starts Xvfb and returns its display (":N") once it accepts clients; kills it if it
/// does not within [`XVFB_START`].
fn start_xvfb() -> Result<String, String> {
    use std::io::Read as _;
    use std::os::fd::AsRawFd as _;
    use std::os::unix::process::CommandExt as _;
    let (mut reader, writer) = std::io::pipe().map_err(|e| format!("pipe: {e}"))?;
    let fd = writer.as_raw_fd();
    let mut command = Command::new("Xvfb");
    command
        .args([
            "-displayfd",
            "3",
            "-screen",
            "0",
            "1280x800x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(move || {
            // The write end as fd 3 (dup2 clears its close-on-exec flag).
            if libc::dup2(fd, 3) < 0 || libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) < 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let mut child = command.spawn().map_err(|e| format!("Xvfb: {e}"))?;
    drop(writer);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        // The display number and a newline; end of file if the server quit first.
        let mut said = Vec::new();
        let mut byte = [0u8; 1];
        while let Ok(1) = reader.read(&mut byte) {
            if byte[0] == b'\n' {
                break;
            }
            said.push(byte[0]);
        }
        let _ = tx.send(String::from_utf8_lossy(&said).trim().to_owned());
    });
    match rx.recv_timeout(XVFB_START) {
        Ok(number) if number.parse::<u32>().is_ok() => Ok(format!(":{number}")),
        outcome => {
            let _ = child.kill();
            let status = child.wait();
            Err(match outcome {
                Ok(_) => format!("Xvfb quit without a display ({status:?})"),
                Err(_) => format!("Xvfb did not start in {XVFB_START:?}"),
            })
        }
    }
}

/// The display for a window test, and the lock that runs the window tests one at a
/// time (each draws on the one software device; four at once on two cores slowed
/// every one of them); `None` where Xvfb is not installed and no GPU is required (the
/// test is skipped). A server that does not start fails the test.
fn display_for(test: &str) -> Option<(MutexGuard<'static, ()>, String)> {
    static WINDOWS: Mutex<()> = Mutex::new(());
    if !runs_here(test, &[]) {
        return None;
    }
    let installed = Command::new("Xvfb")
        .arg("-help")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok();
    if !installed {
        assert!(
            !gpu_required(),
            "{test}: Xvfb is required (apt-get install xvfb)"
        );
        eprintln!("{test}: skipped: no Xvfb");
        return None;
    }
    let lock = WINDOWS.lock().unwrap_or_else(PoisonError::into_inner);
    match x_server() {
        Ok(display) => Some((lock, display.clone())),
        Err(why) => panic!("{test}: {why}"),
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

/// [`run_viewer`] without an environment, calling `watch` with each line of standard
/// error as it comes.
fn run_viewer_watched(
    display: &str,
    args: &[&str],
    limit: Duration,
    watch: impl FnMut(&str) + Send + 'static,
) -> (bool, String) {
    let grass = Path::new(env!("CARGO_BIN_EXE_grass"));
    run_watched(grass, display, args, &[], limit, watch)
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
    run_watched(program, display, args, env, limit, |_| {})
}

/// [`run_program`], calling `watch` with each line of standard error as it comes.
fn run_watched(
    program: &Path,
    display: &str,
    args: &[&str],
    env: &[(&str, &str)],
    limit: Duration,
    mut watch: impl FnMut(&str) + Send + 'static,
) -> (bool, String) {
    use std::io::BufRead as _;
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
    let reader = std::thread::spawn(move || {
        let mut log = String::new();
        for line in std::io::BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            watch(&line);
            log.push_str(&line);
            log.push('\n');
        }
        log
    });
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
    resize_storm("swapchain", "swapchain");
}

/// The storm with frames put into the window through its shared memory
/// (`runner::app::shm`, what a software device under X11 takes by itself).
#[test]
fn the_viewer_draws_through_a_resize_storm_in_shared_memory() {
    resize_storm("shared-memory", "shared-memory frames");
}

/// Runs the viewer through its resize storm, frames reaching the window by `present`,
/// whose every size the log names after `made`.
fn resize_storm(present: &str, made: &str) {
    let Some((_windows, display)) = display_for(&format!(
        "the_viewer_draws_through_a_resize_storm ({present})"
    )) else {
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
        "--present",
        present,
    ];
    let (ok, log) = run_viewer(&display, &args, &[], Duration::from_secs(300));
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
    assert!(number("window targets made") >= 12, "{summary}");
    for expected in [
        "storm: Zero",
        "storm: Minimise",
        "storm: restored",
        &format!("{made} 1x1"),
    ] {
        assert!(log.contains(expected), "no \"{expected}\": {log}");
    }
}

#[test]
fn a_lost_device_is_made_again_and_the_viewer_carries_on() {
    let Some((_windows, display)) =
        display_for("a_lost_device_is_made_again_and_the_viewer_carries_on")
    else {
        return;
    };
    let args = ["--frames", "80", "--validation", "--blades", "256"];
    let fault = [("GRASS_FAULT", "device-lost:30")];
    let (ok, log) = run_viewer(&display, &args, &fault, Duration::from_secs(300));
    assert!(ok, "{log}");
    assert!(
        log.contains("The GPU device was lost and has been made again (1 of 3)"),
        "no recovery: {log}"
    );
    assert!(log.contains("80 frames drawn"), "{log}");
    assert!(!log.contains("validation:"), "validation messages: {log}");
}

/// The screenshot key's path (`--screenshot-at`, as K does it): PNGs of the window's
/// size in the asked folder, with the validation layer silent, showing the frame: at
/// least 5 % of its pixels grass green (green above red and blue by 20) and at least
/// 0.2 % the ball's orange (red above green by 60), as lavapipe draws the default
/// scene. Planted fault: the swapchain's BGRA saved as RGBA failed (the ball came out
/// blue: 0 orange pixels). The overlay's panel is in each shot, which lays its kept
/// picture over the frame (planted fault: the picture laid over only in frames where
/// the interface ran: none of the corner dark in the second shot), and not with
/// `--no-overlay`. Names never collide: every name a shot of the next minutes
/// would take first is already there, and the two shots go beside them, leaving them
/// as they were.
#[test]
fn screenshots_are_the_window_s_frame_and_never_overwrite() {
    let Some((_windows, display)) = display_for("screenshots_are_the_window_s_frame") else {
        return;
    };
    let dir = scratch("screenshot");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the folder");
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .expect("the clock")
        .as_secs();
    let taken: Vec<_> = (now..now + 600)
        .map(|t| dir.join(format!("grass-{t}.png")))
        .collect();
    for path in &taken {
        std::fs::write(path, b"taken").expect("a taken name");
    }
    let dir_arg = dir.to_str().expect("utf-8 path");
    let args = [
        "--frames",
        "12",
        "--screenshot-at",
        "6,7",
        "--screenshot-dir",
        dir_arg,
        "--validation",
        "--width",
        "800",
        "--height",
        "450",
    ];
    let (ok, log) = run_viewer(&display, &args, &[], Duration::from_secs(300));
    assert!(ok, "{log}");
    assert!(!log.contains("validation:"), "validation messages: {log}");
    for path in &taken {
        assert_eq!(std::fs::read(path).expect("still there"), b"taken");
    }
    let shots: Vec<_> = std::fs::read_dir(&dir)
        .expect("the folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| !taken.contains(p))
        .collect();
    assert_eq!(shots.len(), 2, "{shots:?}");
    for shot in &shots {
        let image = image::open(shot).expect("a PNG").to_rgba8();
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
        println!(
            "{}: grass green {green}, ball orange {orange}",
            shot.display()
        );
        assert!(
            green > 0.05 && orange > 0.002,
            "green {green}, orange {orange}"
        );
        let panel = panel_share(&image);
        println!("{}: overlay panel {panel}", shot.display());
        assert!(
            panel > 0.8,
            "the overlay's panel covers {panel} of its corner"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
    // Hidden from the start, no panel.
    let _ = std::fs::create_dir_all(&dir);
    let args = [
        "--frames",
        "3",
        "--screenshot-at",
        "2",
        "--screenshot-dir",
        dir_arg,
        "--width",
        "800",
        "--height",
        "450",
        "--no-overlay",
    ];
    let (ok, log) = run_viewer(&display, &args, &[], Duration::from_secs(300));
    assert!(ok, "{log}");
    let shot = std::fs::read_dir(&dir)
        .expect("the folder")
        .find_map(|e| e.ok().map(|e| e.path()))
        .expect("a screenshot");
    let panel = panel_share(&image::open(&shot).expect("a PNG").to_rgba8());
    println!("{}: overlay panel {panel} (hidden)", shot.display());
    assert!(panel < 0.05, "hidden, yet {panel} of the corner is dark");
    let _ = std::fs::remove_dir_all(&dir);
}

/// What the X server shows of the viewer's window when its frames go through the
/// window's shared memory (`--present shared-memory`, `runner::app::shm`): read from
/// the server (`GetImage` of the window's place on the root) when the viewer has taken
/// a screenshot at frame 40, it is the default scene (at least 5 % of its pixels grass
/// green, 0.2 % the ball's orange, as in the screenshot test) and within a mean of 1.5
/// (of 255; 0.16 to 0.31 measured) of the screenshot, a frame or two apart (the grass sways). Planted
/// fault: the window's buffer not presented (a black window: no green pixel).
#[test]
fn the_x_server_shows_the_shared_memory_frames() {
    let Some((_windows, display)) = display_for("the_x_server_shows_the_shared_memory_frames")
    else {
        return;
    };
    let dir = scratch("shm-window");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the folder");
    let dir_arg = dir.to_str().expect("utf-8 path").to_string();
    let (width, height) = (640u16, 360u16);
    let args = [
        "--frames",
        "120",
        "--screenshot-at",
        "40",
        "--screenshot-dir",
        &dir_arg,
        "--width",
        "640",
        "--height",
        "360",
        "--no-overlay",
        "--present",
        "shared-memory",
    ];
    let (sender, shown) = mpsc::channel();
    let server = display.clone();
    let (ok, log) = run_viewer_watched(&display, &args, Duration::from_secs(300), move |line| {
        if line.contains("screenshot: ") {
            let _ = sender.send(screen(&server, (width, height)));
        }
    });
    assert!(ok, "{log}");
    assert!(log.contains("by SharedMemory"), "{log}");
    let shown = shown
        .try_recv()
        .expect("the screen read when the screenshot was taken");
    let shot = std::fs::read_dir(&dir)
        .expect("the folder")
        .find_map(|e| e.ok().map(|e| e.path()))
        .expect("a screenshot");
    let shot = image::open(&shot).expect("a PNG").to_rgb8();
    let pixels = f32::from(width) * f32::from(height);
    let share = |f: &dyn Fn(i32, i32, i32) -> bool| {
        let n = shown
            .as_chunks::<3>()
            .0
            .iter()
            .filter(|p| f(i32::from(p[0]), i32::from(p[1]), i32::from(p[2])))
            .count();
        n as f32 / pixels
    };
    let green = share(&|r, g, b| g > r + 20 && g > b + 20);
    let orange = share(&|r, g, _| r > g + 60);
    let apart = shown
        .iter()
        .zip(shot.as_raw())
        .map(|(a, b)| f64::from(a.abs_diff(*b)))
        .sum::<f64>()
        / shown.len() as f64;
    println!(
        "the window on the X server: grass green {green}, ball orange {orange}, {apart} from the screenshot"
    );
    assert!(
        green > 0.05 && orange > 0.002,
        "green {green}, orange {orange}"
    );
    assert!(apart < 1.5, "the window is {apart} from the screenshot");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The RGB pixels the X server on `display` shows in the root window's top-left
/// `size` (where an X server without a window manager puts the viewer's window).
fn screen(display: &str, (width, height): (u16, u16)) -> Vec<u8> {
    use x11rb::connection::Connection as _;
    use x11rb::protocol::xproto::{ConnectionExt as _, ImageFormat};
    let (conn, screen) = x11rb::connect(Some(display)).expect("connect to the X server");
    let root = conn.setup().roots[screen].root;
    let image = conn
        .get_image(ImageFormat::Z_PIXMAP, root, 0, 0, width, height, !0)
        .expect("ask for the screen")
        .reply()
        .expect("the screen");
    // Depth 24 in 32-bit words: B, G, R and a pad byte a pixel.
    image
        .data
        .as_chunks::<4>()
        .0
        .iter()
        .flat_map(|p| [p[2], p[1], p[0]])
        .collect()
}

/// The share of the pixels in the frame's top-left corner (x 20 to 200, y 40 to 200)
/// as dark as the overlay's panel (every channel under 70); the default scene's sky
/// and grass there are lighter.
fn panel_share(image: &image::RgbaImage) -> f32 {
    let (mut dark, mut all) = (0, 0);
    for y in 40..200 {
        for x in 20..200 {
            let p = image.get_pixel(x, y);
            dark += usize::from(p[0] < 70 && p[1] < 70 && p[2] < 70);
            all += 1;
        }
    }
    dark as f32 / all as f32
}

/// A screenshot that cannot be written (its folder removed while the viewer runs) is
/// said in the log and the overlay, and the viewer draws on to its last frame.
#[test]
fn a_screenshot_that_cannot_be_written_ends_nothing() {
    let Some((_windows, display)) = display_for("a_screenshot_that_cannot_be_written") else {
        return;
    };
    let dir = scratch("screenshot-gone");
    std::fs::create_dir_all(&dir).expect("the folder");
    let dir_arg = dir.to_str().expect("utf-8 path").to_owned();
    let args = [
        "--frames",
        "20",
        "--screenshot-at",
        "10",
        "--screenshot-dir",
        &dir_arg,
        "--width",
        "320",
        "--height",
        "180",
    ];
    // The folder goes once the viewer has its device (it was checked before).
    let gone = dir.to_path_buf();
    let remove = move |line: &str| {
        if line.contains("device:") {
            let _ = std::fs::remove_dir_all(&gone);
        }
    };
    let (ok, log) = run_viewer_watched(&display, &args, Duration::from_secs(300), remove);
    assert!(ok, "{log}");
    assert!(!dir.exists(), "the folder was not removed: {log}");
    assert!(log.contains("screenshot not saved"), "{log}");
    assert!(log.contains("20 frames drawn"), "{log}");
}

/// The embedding example (`runner/examples/embed/`) in a window: its own swapchain,
/// cube and the grass of `runner::embed`, 60 frames with the validation layer
/// (core and synchronization) silent, through four window sizes (one of 1x1). `cargo test` builds the example beside `grass`.
#[test]
fn the_embed_example_runs_in_a_window() {
    let Some((_windows, display)) = display_for("the_embed_example_runs_in_a_window") else {
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
    let (ok, log) = run_program(&example, &display, &args, &[], Duration::from_secs(300));
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

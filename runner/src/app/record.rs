//! Clips (`grass record`): frames rendered headless at a fixed frame time, along the
//! camera's path and the ball's, into a GIF (the `gif` crate), an MP4 (`ffmpeg`, when
//! it is installed) or a folder of numbered PNGs.

use super::progress::Progress;
use super::render::Headless;
use crate::cli::{Common, RecordArgs};
use anyhow::{Context as _, Result, bail};
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Where a clip goes.
#[derive(Debug)]
pub enum Clip {
    /// A GIF file, encoded here.
    Gif(PathBuf),
    /// An MP4 file, encoded by `ffmpeg`.
    Mp4(PathBuf),
    /// A folder of `frame_00000.png`, ...
    Pngs(PathBuf),
}

impl Clip {
    /// The clip `out` names: by its extension, a folder otherwise (made if missing,
    /// its parent must exist). Checked before anything is rendered.
    pub fn of(out: &Path) -> Result<Self> {
        let shown = out.display();
        let extension = out.extension().and_then(|e| e.to_str()).unwrap_or("");
        let file = |clip: fn(PathBuf) -> Clip| -> Result<Clip> {
            crate::files::check_output(out, &["gif", "mp4"])?;
            Ok(clip(out.to_path_buf()))
        };
        match extension.to_ascii_lowercase().as_str() {
            "gif" => file(Clip::Gif),
            "mp4" => file(Clip::Mp4),
            "" => {
                if out.exists() && !out.is_dir() {
                    bail!("output {shown}: not a folder (name a .gif, a .mp4 or a folder)");
                }
                std::fs::create_dir_all(out)
                    .with_context(|| format!("output {shown}: cannot make the folder"))?;
                Ok(Clip::Pngs(out.to_path_buf()))
            }
            other => {
                bail!("output {shown}: .{other} is not a clip (name a .gif, a .mp4 or a folder)")
            }
        }
    }
}

/// Takes the clip's frames one by one.
enum Sink {
    Gif(gif::Encoder<std::io::BufWriter<std::fs::File>>),
    Mp4(std::process::Child),
    Pngs(PathBuf),
}

impl Sink {
    /// Opens `clip` for frames of `width` x `height` at `fps`.
    fn open(clip: &Clip, (width, height): (u32, u32), fps: u32) -> Result<Self> {
        Ok(match clip {
            Clip::Gif(path) => {
                let file = crate::files::create(path)
                    .with_context(|| format!("write {}", path.display()))?;
                let mut encoder = gif::Encoder::new(
                    std::io::BufWriter::new(file),
                    width as u16,
                    height as u16,
                    &[],
                )?;
                encoder.set_repeat(gif::Repeat::Infinite)?;
                Sink::Gif(encoder)
            }
            Clip::Mp4(path) => {
                let child = std::process::Command::new("ffmpeg")
                    .args([
                        "-loglevel",
                        "error",
                        "-y",
                        "-f",
                        "rawvideo",
                        "-pix_fmt",
                        "rgba",
                    ])
                    .args(["-s", &format!("{width}x{height}"), "-r", &fps.to_string()])
                    .args(["-i", "-", "-pix_fmt", "yuv420p", "-vf"])
                    .arg("pad=ceil(iw/2)*2:ceil(ih/2)*2")
                    .arg(path)
                    .stdin(std::process::Stdio::piped())
                    .spawn();
                match child {
                    Ok(child) => Sink::Mp4(child),
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
                        "{}: an MP4 needs ffmpeg, which is not installed (record to a .gif \
                         or a folder of PNGs instead)",
                        path.display()
                    ),
                    Err(e) => return Err(e).context("start ffmpeg"),
                }
            }
            Clip::Pngs(dir) => Sink::Pngs(dir.clone()),
        })
    }

    /// Adds frame `index`: RGBA8 pixels, row by row.
    fn add(&mut self, index: u32, pixels: &mut [u8], (w, h): (u32, u32), fps: u32) -> Result<()> {
        match self {
            Sink::Gif(encoder) => {
                // NeuQuant at speed 10: a palette per frame, quickly.
                let mut frame = gif::Frame::from_rgba_speed(w as u16, h as u16, pixels, 10);
                frame.delay = (100 / fps).max(1) as u16;
                encoder.write_frame(&frame).context("encode the GIF")?;
            }
            Sink::Mp4(child) => {
                let stdin = child.stdin.as_mut().context("ffmpeg's input")?;
                stdin
                    .write_all(pixels)
                    .context("ffmpeg stopped taking frames")?;
            }
            Sink::Pngs(dir) => {
                let path = dir.join(format!("frame_{index:05}.png"));
                crate::files::save_png(&path, pixels, (w, h), image::ColorType::Rgba8)?;
            }
        }
        Ok(())
    }

    /// Finishes the clip.
    fn finish(self) -> Result<()> {
        if let Sink::Mp4(mut child) = self {
            drop(child.stdin.take());
            let status = child.wait().context("wait for ffmpeg")?;
            if !status.success() {
                bail!("ffmpeg failed ({status})");
            }
        }
        Ok(())
    }
}

/// Records the clip `args` asks for; returns how many frames it holds.
pub fn run(common: &Common, args: &RecordArgs) -> Result<u32> {
    let clip = Clip::of(&args.out)?;
    let mut run = Headless::open(
        common,
        (args.width, args.height),
        &args.camera,
        &args.events,
    )?;
    let size = run.offscreen.size();
    let mut sink = Sink::open(&clip, size, args.fps)?;
    // The frames are encoded on their own thread (a GIF's palettes are slow), while
    // the next ones render; one waits at most, in order.
    let fps = args.fps;
    let (frames, taken) = std::sync::mpsc::sync_channel::<(u32, Vec<u8>)>(1);
    let encoder = std::thread::spawn(move || -> Result<()> {
        for (index, mut pixels) in taken {
            sink.add(index, &mut pixels, size, fps)?;
        }
        sink.finish()
    });
    let step = 1.0 / f64::from(args.fps);
    let total = args.settle + args.frames;
    let progress = Progress::new(total as usize);
    for frame in 0..total {
        let recorded = frame >= args.settle;
        run.frame(step, recorded)?;
        if recorded {
            run.driver.finish()?;
            let pixels = run.offscreen.pixels()?;
            if frames.send((frame - args.settle, pixels)).is_err() {
                // The encoder stopped: its error is the one to report.
                break;
            }
        }
        progress.show(
            frame as usize + 1,
            if recorded { "recording" } else { "settling" },
        );
    }
    drop(frames);
    encoder
        .join()
        .map_err(|_| anyhow::anyhow!("the clip's encoder panicked"))??;
    progress.done(total as usize);
    let errors = run.ctx.validation_errors();
    if errors > 0 {
        bail!("{errors} validation errors (see the log above)");
    }
    log::info!(
        "wrote {} ({} frames of {}x{} at {} fps)",
        args.out.display(),
        args.frames,
        args.width,
        args.height,
        args.fps
    );
    Ok(args.frames)
}

//! The one guard every file the program reads or writes goes through: scene files,
//! settings files, painted maps, images, clips, the bench's CSV and charts.
//!
//! A file is opened once, without blocking, and must be a regular file after links
//! are followed; a file read has its size checked against a limit before a byte is
//! read, and the read is capped there. So a link to `/dev/zero`, a named pipe (with no
//! writer, or no reader), or a file that grows while it is read costs neither unbounded
//! memory nor a hang; each is refused by name.

use anyhow::{Context as _, Result, bail};
use std::fs::File;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// Why a file cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum Problem {
    /// Nothing at that path.
    #[error("file not found")]
    NotFound,
    /// The path names a directory.
    #[error("is a directory")]
    IsDirectory,
    /// The path names something that is not a regular file, after following links.
    #[error("is a {what}, not a regular file")]
    NotRegular {
        /// What it is: a named pipe, a device, a socket.
        what: &'static str,
    },
    /// The file is larger than the limit for its kind.
    #[error("{bytes} bytes, more than the {limit} allowed")]
    TooBig {
        /// Its size.
        bytes: u64,
        /// The limit.
        limit: u64,
    },
    /// The file grew past the limit while it was read.
    #[error("grew past {limit} bytes while it was read")]
    Grew {
        /// The limit.
        limit: u64,
    },
    /// The operating system refused.
    #[error("{0}")]
    Io(io::Error),
}

/// Options for an open that cannot block (a named pipe without its other end).
fn options() -> std::fs::OpenOptions {
    let mut options = std::fs::OpenOptions::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options
}

/// `file` as a regular file, or what it is instead.
fn regular(file: File) -> Result<File, Problem> {
    let kind = file.metadata().map_err(Problem::Io)?.file_type();
    if kind.is_dir() {
        return Err(Problem::IsDirectory);
    }
    if !kind.is_file() {
        return Err(Problem::NotRegular {
            what: describe(kind),
        });
    }
    Ok(file)
}

/// What an open's error says about the path.
fn opened(result: io::Result<File>, path: &Path) -> Result<File, Problem> {
    result.map_err(|error| match error.kind() {
        io::ErrorKind::NotFound => Problem::NotFound,
        io::ErrorKind::IsADirectory => Problem::IsDirectory,
        // A named pipe opened for writing without blocking has no reader (ENXIO).
        _ if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) => {
            Problem::NotRegular {
                what: std::fs::metadata(path).map_or("special file", |m| describe(m.file_type())),
            }
        }
        _ => Problem::Io(error),
    })
}

/// Opens `path` for reading and returns it with its size, or why it cannot be read:
/// nothing there, a directory, or anything else that is not a regular file (a named
/// pipe, a device, a socket), after following symbolic links. A named pipe is opened
/// without waiting for a writer, then refused.
pub fn open(path: &Path) -> Result<(File, u64), Problem> {
    let file = regular(opened(options().read(true).open(path), path)?)?;
    let size = file.metadata().map_err(Problem::Io)?.len();
    Ok((file, size))
}

/// The bytes of `reader`, which said it holds `size` bytes, refused before reading
/// when `size` is over `limit`, and refused when more than `limit` bytes turn up.
pub fn read_capped(reader: impl Read, size: u64, limit: u64) -> Result<Vec<u8>, Problem> {
    if size > limit {
        return Err(Problem::TooBig { bytes: size, limit });
    }
    let mut data = Vec::with_capacity(size as usize);
    reader
        .take(limit + 1)
        .read_to_end(&mut data)
        .map_err(Problem::Io)?;
    if data.len() as u64 > limit {
        return Err(Problem::Grew { limit });
    }
    Ok(data)
}

/// The whole file at `path`, at most `limit` bytes ([`open`], [`read_capped`]).
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, Problem> {
    let (file, size) = open(path)?;
    read_capped(file, size, limit)
}

/// The file at `path` as UTF-8 text, at most `limit` bytes; errors name `what` and the
/// path ("settings file grass.toml: is a named pipe (FIFO), not a regular file").
pub fn read_text(path: &Path, limit: u64, what: &str) -> Result<String> {
    let shown = path.display();
    let bytes = read(path, limit).with_context(|| format!("{what} {shown}"))?;
    String::from_utf8(bytes).map_err(|_| anyhow::anyhow!("{what} {shown}: not UTF-8 text"))
}

/// Opens `path` for writing, made or emptied: refused where it names a directory or
/// something that is not a regular file (a pipe, a device), after links; never blocks.
pub fn create(path: &Path) -> Result<File, Problem> {
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Problem::IsDirectory);
        }
        if !meta.is_file() {
            return Err(Problem::NotRegular {
                what: describe(meta.file_type()),
            });
        }
    }
    let file = opened(
        options().write(true).create(true).truncate(true).open(path),
        path,
    )?;
    regular(file)
}

/// Makes a file at `path` that was not there: `None` where something already is.
pub fn create_new(path: &Path) -> Result<Option<File>, Problem> {
    match options().write(true).create_new(true).open(path) {
        Ok(file) => regular(file).map(Some),
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Ok(None),
        Err(e) => opened(Err(e), path).map(Some),
    }
}

/// Writes `bytes` as the file `path` ([`create`]).
pub fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    let shown = path.display();
    let mut file = create(path).with_context(|| format!("write {shown}"))?;
    file.write_all(bytes)
        .with_context(|| format!("write {shown}"))
}

/// Writes `pixels` (`color` texels, row by row) as a PNG to `file`, named `path` in
/// errors.
fn png_into(
    file: File,
    path: &Path,
    pixels: &[u8],
    size: (u32, u32),
    color: image::ColorType,
) -> Result<()> {
    let mut out = io::BufWriter::new(file);
    image::write_buffer_with_format(
        &mut out,
        pixels,
        size.0,
        size.1,
        color,
        image::ImageFormat::Png,
    )
    .and_then(|()| out.flush().map_err(image::ImageError::IoError))
    .with_context(|| format!("write {}", path.display()))
}

/// Writes `pixels` (`color` texels, row by row) as the PNG `path` ([`create`]).
pub fn save_png(
    path: &Path,
    pixels: &[u8],
    size: (u32, u32),
    color: image::ColorType,
) -> Result<()> {
    let file = create(path).with_context(|| format!("write {}", path.display()))?;
    png_into(file, path, pixels, size, color)
}

/// Writes `pixels` as a new PNG in `folder` named `<stem>.png`, or `<stem>-2.png`,
/// `<stem>-3.png`, ... where that is taken: never over another file. Returns its path.
pub fn save_png_new(
    folder: &Path,
    stem: &str,
    pixels: &[u8],
    size: (u32, u32),
    color: image::ColorType,
) -> Result<PathBuf> {
    for n in 1..10_000u32 {
        let name = match n {
            1 => format!("{stem}.png"),
            n => format!("{stem}-{n}.png"),
        };
        let path = folder.join(name);
        let made = create_new(&path).with_context(|| format!("write {}", path.display()))?;
        if let Some(file) = made {
            png_into(file, &path, pixels, size, color)?;
            return Ok(path);
        }
    }
    bail!("{}: no free name for {stem}.png", folder.display())
}

/// Checks before any work that `path` can be written as a file with one of
/// `extensions`: a folder that exists, not a folder itself, nor a special file.
pub fn check_output(path: &Path, extensions: &[&str]) -> Result<()> {
    let shown = path.display();
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !extensions.iter().any(|e| e.eq_ignore_ascii_case(extension)) {
        bail!(
            "output {shown}: expected a .{} file",
            extensions.join(" or .")
        );
    }
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            bail!("output {shown}: is a directory");
        }
        if !meta.is_file() {
            bail!(
                "output {shown}: is a {}, not a regular file",
                describe(meta.file_type())
            );
        }
    }
    match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(parent) if !parent.is_dir() => {
            bail!("output {shown}: folder {} does not exist", parent.display())
        }
        _ => Ok(()),
    }
}

/// Checks that `folder` is a folder this program may write files into: it exists, is a
/// directory (after links) and takes a new file (one is made and removed again).
pub fn check_folder(folder: &Path, what: &str) -> Result<()> {
    let shown = folder.display();
    match std::fs::metadata(folder) {
        Err(_) => bail!("{what} {shown}: does not exist"),
        Ok(meta) if !meta.is_dir() => bail!("{what} {shown}: not a folder"),
        Ok(_) => {}
    }
    let probe = folder.join(format!(".grass-write-check-{}", std::process::id()));
    match create_new(&probe) {
        Ok(Some(_)) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Ok(None) => Ok(()),
        Err(e) => bail!("{what} {shown}: cannot write in it ({e})"),
    }
}

/// What a file that is neither a regular file nor a directory is.
fn describe(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "named pipe (FIFO)";
        }
        if kind.is_char_device() {
            return "character device";
        }
        if kind.is_block_device() {
            return "block device";
        }
        if kind.is_socket() {
            return "socket";
        }
    }
    let _ = kind;
    "special file"
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch path in the temporary folder, removed (as a file or a folder) first.
    fn scratch(name: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!("grass-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let _ = std::fs::remove_dir_all(&path);
        path
    }

    /// A named pipe at a scratch path.
    fn fifo(name: &str) -> PathBuf {
        let path = scratch(name);
        let made = std::process::Command::new("mkfifo").arg(&path).status();
        assert!(made.expect("run mkfifo").success());
        path
    }

    /// Reading and writing refuse a pipe at once (no writer, no reader), a device
    /// behind a link, and a folder; nothing waits.
    #[test]
    fn special_files_are_refused_without_waiting() {
        let started = std::time::Instant::now();
        let pipe = fifo("pipe");
        let problem = |r: Result<(), Problem>| r.unwrap_err().to_string();
        assert_eq!(
            problem(read(&pipe, 100).map(drop)),
            "is a named pipe (FIFO), not a regular file"
        );
        assert_eq!(
            problem(create(&pipe).map(drop)),
            "is a named pipe (FIFO), not a regular file"
        );
        let link = scratch("zero-link");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        assert_eq!(
            problem(read(&link, 100).map(drop)),
            "is a character device, not a regular file"
        );
        assert_eq!(
            problem(create(&link).map(drop)),
            "is a character device, not a regular file"
        );
        assert_eq!(
            problem(read(&std::env::temp_dir(), 1).map(drop)),
            "is a directory"
        );
        assert_eq!(
            problem(create(&std::env::temp_dir()).map(drop)),
            "is a directory"
        );
        let error = format!("{:#}", check_output(&pipe, &["png"]).unwrap_err());
        assert!(error.contains("expected a .png"), "{error}");
        let png = scratch("pipe.png");
        std::os::unix::fs::symlink(&pipe, &png).unwrap();
        let error = format!("{:#}", check_output(&png, &["png"]).unwrap_err());
        assert!(error.contains("named pipe"), "{error}");
        for path in [pipe, link, png] {
            let _ = std::fs::remove_file(path);
        }
        assert!(started.elapsed().as_secs() < 5, "{:?}", started.elapsed());
    }

    /// A file over its limit is refused by its size before a byte is read.
    #[test]
    fn a_file_over_its_limit_is_refused_unread() {
        let path = scratch("big");
        let file = File::create(&path).unwrap();
        // Sparse: the size is there, no byte is written or read.
        file.set_len(1 << 40).unwrap();
        let error = read(&path, 1 << 20).unwrap_err().to_string();
        assert_eq!(
            error,
            format!("{} bytes, more than the {} allowed", 1u64 << 40, 1 << 20)
        );
        let _ = std::fs::remove_file(path);
    }

    /// New names never land on an existing file; a folder is checked for writing.
    #[test]
    fn new_pngs_never_overwrite() {
        let folder = scratch("shots");
        assert!(check_folder(&folder, "screenshot folder").is_err());
        std::fs::create_dir_all(&folder).unwrap();
        check_folder(&folder, "screenshot folder").unwrap();
        let pixel = [0u8, 255, 0, 255];
        let shot = |_| save_png_new(&folder, "grass-1", &pixel, (1, 1), image::ColorType::Rgba8);
        let paths: Vec<PathBuf> = (0..3).map(shot).collect::<Result<_>>().unwrap();
        let names: Vec<_> = paths
            .iter()
            .map(|p| p.file_name().unwrap().to_owned())
            .collect();
        assert_eq!(names, ["grass-1.png", "grass-1-2.png", "grass-1-3.png"]);
        for path in &paths {
            assert_eq!(image::open(path).unwrap().to_rgba8().as_raw(), &pixel);
        }
        let file = folder.join("grass-1.png");
        let error = format!(
            "{:#}",
            check_folder(&file, "screenshot folder").unwrap_err()
        );
        assert!(error.contains("not a folder"), "{error}");
        let _ = std::fs::remove_dir_all(folder);
    }
}

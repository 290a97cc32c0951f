//! Opening a file the loader reads (a scene file, or a glTF buffer of its own) through
//! the program's file guard ([`crate::files`]): once, without blocking, a regular file only (after following links), its size checked
//! against [`MAX_FILE_BYTES`] before a byte is read, and the read capped there, so a
//! link to `/dev/zero`, a named pipe or a file that grows while it is read can cost
//! neither unbounded memory nor a hang.

use super::error::SceneErrorKind;
use crate::files::{self, Problem};
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Most bytes a scene file may have: a file of the most vertices and triangles a scene
/// may have ([`MAX_VERTICES`](super::MAX_VERTICES), [`MAX_TRIANGLES`](super::MAX_TRIANGLES)),
/// written out as OBJ text with a normal per vertex, is about 540 MB.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

impl From<Problem> for SceneErrorKind {
    fn from(problem: Problem) -> Self {
        match problem {
            Problem::NotFound => SceneErrorKind::NotFound,
            Problem::IsDirectory => SceneErrorKind::IsDirectory,
            Problem::NotRegular { what } => SceneErrorKind::NotRegular { what },
            Problem::TooBig { bytes, limit } => SceneErrorKind::TooBig { bytes, limit },
            Problem::Grew { limit } => SceneErrorKind::Grew { limit },
            Problem::Io(error) => SceneErrorKind::Read { error },
        }
    }
}

/// Opens `path` for reading through the program's file guard ([`files::open`]).
pub(super) fn open(path: &Path) -> Result<(File, u64), SceneErrorKind> {
    Ok(files::open(path)?)
}

/// The bytes of `reader`, capped at `limit` ([`files::read_capped`]).
pub(super) fn read_capped(
    reader: impl Read,
    size: u64,
    limit: u64,
) -> Result<Vec<u8>, SceneErrorKind> {
    Ok(files::read_capped(reader, size, limit)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load::tests::TempFile;

    /// A symbolic link in the temp directory to `target`, removed when dropped.
    struct Link(std::path::PathBuf);

    impl Link {
        fn to(target: &str, name: &str) -> Self {
            let path =
                std::env::temp_dir().join(format!("grass-link-{}-{name}", std::process::id()));
            let _ = std::fs::remove_file(&path);
            std::os::unix::fs::symlink(target, &path).expect("make a link");
            Self(path)
        }
    }

    impl Drop for Link {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.0);
        }
    }

    /// Why the file at `path` cannot be read whole within [`MAX_FILE_BYTES`].
    fn problem(path: &Path) -> String {
        open(path)
            .and_then(|(file, size)| read_capped(file, size, MAX_FILE_BYTES))
            .map(|_| ())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn links_to_devices_are_refused_before_any_read() {
        let zero = Link::to("/dev/zero", "zero.obj");
        assert_eq!(
            problem(&zero.0),
            "is a character device, not a regular file"
        );
        let random = Link::to("/dev/urandom", "random.glb");
        assert_eq!(
            problem(&random.0),
            "is a character device, not a regular file"
        );
        let dir = Link::to("/tmp", "dir.obj");
        assert_eq!(problem(&dir.0), "is a directory, not a scene file");
        let dangling = Link::to("/nonexistent/grass", "dangling.obj");
        assert_eq!(problem(&dangling.0), "file not found");
    }

    #[test]
    fn a_named_pipe_is_refused_without_waiting_for_a_writer() {
        let path = std::env::temp_dir().join(format!("grass-fifo-{}.obj", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let status = std::process::Command::new("mkfifo")
            .arg(&path)
            .status()
            .expect("run mkfifo");
        assert!(status.success());
        let started = std::time::Instant::now();
        let message = problem(&path);
        let _ = std::fs::remove_file(&path);
        assert_eq!(message, "is a named pipe (FIFO), not a regular file");
        assert!(started.elapsed().as_secs() < 5, "the pipe held the loader");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_by_its_size() {
        // Sparse: the size is there, no byte is written or read.
        let file = TempFile::new("big.obj", b"");
        let handle = std::fs::OpenOptions::new()
            .write(true)
            .open(&file.0)
            .unwrap();
        handle.set_len(MAX_FILE_BYTES + 1).unwrap();
        assert_eq!(
            problem(&file.0),
            format!(
                "{} bytes, more than the {MAX_FILE_BYTES} a scene file may have",
                MAX_FILE_BYTES + 1
            )
        );
    }

    #[test]
    fn a_file_that_grows_while_it_is_read_is_cut_off() {
        let file = TempFile::new("growing.obj", b"v 0 0 0\n");
        let (reader, size) = open(&file.0).unwrap();
        assert_eq!(size, 8);
        // It grows after its size was taken, past the limit.
        std::fs::write(&file.0, vec![b'#'; 100]).unwrap();
        let error = read_capped(reader, size, 64).unwrap_err();
        assert_eq!(error.to_string(), "grew past 64 bytes while it was read");
        // Within the limit, what is there is read.
        let (reader, size) = open(&file.0).unwrap();
        assert_eq!(read_capped(reader, size, 100).unwrap().len(), 100);
    }
}

//! What the command-line tests share: running the `grass` binary and scratch folders.

#![allow(dead_code, unused_imports)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A test's scratch folder, removed with what is in it when the test ends without a
/// panic (a failed test's files stay for a look).
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A scratch folder for this test's files, named after `name` (one name a test: the
/// tests of a binary run in parallel in one process).
pub fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("grass-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    Scratch(dir)
}

pub use runner::vulkan::gpu_required;
pub use runner::vulkan::probe::{Need, runs_here};

/// Runs `grass` with `args` and extra environment variables.
pub fn grass_with(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grass"))
        .args(args)
        .env("RUST_LOG", "warn")
        .envs(env.iter().copied())
        .output()
        .expect("run grass")
}

/// Runs `grass` with `args`.
pub fn grass(args: &[&str]) -> Output {
    grass_with(args, &[])
}

/// The run's standard error, checked to hold no panic.
pub fn stderr_of(args: &[&str], output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(
        !stderr.contains("panicked"),
        "grass {args:?} panicked: {stderr}"
    );
    stderr
}

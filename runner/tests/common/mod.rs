//! What the command-line tests share: running the `grass` binary and scratch folders.

#![allow(dead_code, unused_imports)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// A scratch folder for this test's files.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("grass-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    dir
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

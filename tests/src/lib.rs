//! Helpers of the integration tests in `tests/tests/`.

use runner::vulkan::{Context, ContextOptions};
use std::path::PathBuf;
use std::sync::Arc;

/// True when GRASS_REQUIRE_GPU=1: tests that need a Vulkan device then fail instead
/// of skipping (CI sets it).
pub fn gpu_required() -> bool {
    std::env::var("GRASS_REQUIRE_GPU").is_ok_and(|v| v.trim() == "1")
}

/// Runs `test` with a Vulkan context, or skips it (printing why) when there is no
/// usable device, unless GRASS_REQUIRE_GPU=1, where that is a failure.
pub fn with_device(name: &str, test: impl FnOnce(Arc<Context>)) {
    // Validation messages go to the log; show them in the test output.
    let _ = env_logger::builder().is_test(true).try_init();
    match Context::new(ContextOptions::default()) {
        Ok(ctx) => test(ctx),
        Err(e) if gpu_required() => {
            panic!("{name}: GRASS_REQUIRE_GPU=1 but no usable Vulkan device: {e:#}")
        }
        Err(e) => eprintln!("{name}: skipped, no usable Vulkan device: {e:#}"),
    }
}

/// Like [`with_device`] for tests that create their own context: says whether a
/// device exists (skipping or failing as above when not).
pub fn device_available(name: &str) -> bool {
    let mut found = false;
    with_device(name, |_| found = true);
    found
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

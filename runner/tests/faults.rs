//! Device trouble through the real command line: no driver, a device without a
//! feature the renderer needs, a device lost in the middle of a run. Each must end in
//! a message naming the problem and a non-zero exit, never a panic or a hang.
//! `GRASS_FAULT` (runner/src/vulkan/fault.rs) stands in for the hardware we cannot
//! summon in CI.

mod common;

use common::{grass_with, runs_here, scratch, stderr_of};

/// A tiny headless render of 8 frames, with `env` set.
fn render(env: &[(&str, &str)]) -> (Option<i32>, String) {
    let dir = scratch("faults-shot");
    let out = dir.join("shot.png");
    let out = out.to_str().unwrap().to_string();
    let args = [
        "render", "--frames", "8", "--blades", "64", "--width", "32", "--height", "32", "--out",
        &out,
    ];
    let o = grass_with(&args, env);
    (o.status.code(), stderr_of(&args, &o))
}

/// True (and the test should stop) where the probe finds no device and none is
/// required.
fn no_device_here(test: &str) -> bool {
    !runs_here(test, &[])
}

#[test]
fn no_driver_is_a_clear_error() {
    // The loader finds no driver manifest at all.
    let env = [
        ("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        ("VK_ICD_FILENAMES", "/nonexistent/icd.json"),
    ];
    let (code, stderr) = render(&env);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("no Vulkan driver found") || stderr.contains("no Vulkan device found"),
        "{stderr}"
    );
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
}

#[test]
fn a_missing_feature_is_named() {
    if no_device_here("a_missing_feature_is_named") {
        return;
    }
    for feature in [
        "tessellationShader",
        "vulkanMemoryModelDeviceScope",
        "fillModeNonSolid",
    ] {
        let fault = format!("missing-feature:{feature}");
        let (code, stderr) = render(&[("GRASS_FAULT", &fault)]);
        assert_eq!(code, Some(1), "{stderr}");
        assert!(
            stderr.contains("no usable Vulkan device") && stderr.contains(feature),
            "{feature}: {stderr}"
        );
    }
}

#[test]
fn a_lost_device_ends_the_run_with_advice() {
    if no_device_here("a_lost_device_ends_the_run_with_advice") {
        return;
    }
    let (code, stderr) = render(&[("GRASS_FAULT", "device-lost:5")]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("wait for frame 5"), "{stderr}");
    assert!(stderr.contains("VK_ERROR_DEVICE_LOST"), "{stderr}");
    assert!(stderr.contains("start grass again"), "{stderr}");
}

#[test]
fn the_mesh_pipeline_without_mesh_shaders_is_named_and_auto_falls_back() {
    if no_device_here("the_mesh_pipeline_without_mesh_shaders_is_named_and_auto_falls_back") {
        return;
    }
    let dir = scratch("faults-mesh");
    let out = dir.join("mesh.png");
    let out = out.to_str().unwrap().to_string();
    let env = [("GRASS_FAULT", "missing-feature:meshShader")];
    let run = |pipeline: &str| {
        let args = [
            "render",
            "--frames",
            "4",
            "--blades",
            "64",
            "--width",
            "32",
            "--height",
            "32",
            "--pipeline",
            pipeline,
            "--out",
            &out,
        ];
        // The fallback is said at the info level.
        let env = [env[0], ("RUST_LOG", "info")];
        let o = grass_with(&args, &env);
        (o.status.code(), stderr_of(&args, &o))
    };
    let (code, stderr) = run("mesh");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("--pipeline mesh") && stderr.contains("VK_EXT_mesh_shader"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    let (code, stderr) = run("auto");
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains("grass pipeline: tessellation (the device has no VK_EXT_mesh_shader)"),
        "{stderr}"
    );
}

#[test]
fn the_compute_rasterizer_without_64_bit_atomics_is_named_and_the_default_runs() {
    if no_device_here("the_compute_rasterizer_without_64_bit_atomics_is_named_and_the_default_runs")
    {
        return;
    }
    let dir = scratch("faults-raster");
    let out = dir.join("raster.png");
    let out = out.to_str().unwrap().to_string();
    let env = [("GRASS_FAULT", "missing-feature:shaderBufferInt64Atomics")];
    let run = |below: Option<&str>| {
        let mut args = vec![
            "render", "--frames", "4", "--blades", "64", "--width", "32", "--height", "32",
            "--out", &out,
        ];
        if let Some(below) = below {
            args.extend(["--compute-raster-below", below]);
        }
        let o = grass_with(&args, &env);
        (o.status.code(), stderr_of(&args, &o))
    };
    let (code, stderr) = run(Some("8"));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("--compute-raster-below") && stderr.contains("shaderBufferInt64Atomics"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    let (code, stderr) = run(None);
    assert_eq!(code, Some(0), "{stderr}");
}

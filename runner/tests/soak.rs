//! A short `grass soak` in CI: the validation layer silent, device memory flat and host
//! memory within 8 MiB over every switch, both image sizes and frame times from 0.1 ms
//! to 2 s; and the same run with a planted leak of 0.1 MB a frame, which must fail.
//! After the soak's warm-up host memory is flat on lavapipe (+0.0 MiB by the check,
//! which compares the lowest of the last third of the readings with the highest of
//! the first third); the leak raises it by about 19 MiB.

mod common;

use common::{grass, grass_with, runs_here, stderr_of};

/// 480 frames of a small field, a reading every 40, at most 8 MiB of host growth.
const CI_SOAK: [&str; 13] = [
    "soak",
    "--frames",
    "480",
    "--every",
    "40",
    "--blades",
    "256",
    "--width",
    "64",
    "--height",
    "64",
    "--host-slack-mib",
    "8",
];

/// Runs `grass <args>` (a soak) and checks it passed: no validation message, device
/// memory the same at every reading of a size (skipped where the probe finds no device,
/// unless one is required).
fn silent_and_flat(args: &[&str]) {
    if !runs_here(&format!("grass {args:?}"), &[]) {
        return;
    }
    let o = grass(args);
    let stderr = stderr_of(args, &o);
    assert!(o.status.success(), "{stderr}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("0 validation messages")
            && stdout.contains("the same at every reading of the same size"),
        "{stdout}"
    );
}

#[test]
fn a_short_soak_is_silent_and_flat() {
    let args = CI_SOAK;
    silent_and_flat(&args);
}

#[test]
fn a_planted_leak_of_a_tenth_of_a_megabyte_a_frame_fails_the_soak() {
    let args = CI_SOAK;
    if !runs_here("a_planted_leak_fails_the_soak", &[]) {
        return;
    }
    let o = grass_with(&args, &[("GRASS_FAULT", "leak:100000")]);
    let stderr = stderr_of(&args, &o);
    assert!(!o.status.success(), "the leak went unnoticed: {stderr}");
    assert!(stderr.contains("host memory grew by"), "{stderr}");
}

/// A planted device leak, a 64 KiB buffer made every frame and never destroyed, fails
/// the soak's device-memory check (the host's cannot see it).
#[test]
fn a_planted_device_leak_fails_the_soak() {
    let args = CI_SOAK;
    if !runs_here("a_planted_device_leak_fails_the_soak", &[]) {
        return;
    }
    let o = grass_with(&args, &[("GRASS_FAULT", "device-leak:65536")]);
    let stderr = stderr_of(&args, &o);
    assert!(!o.status.success(), "the leak went unnoticed: {stderr}");
    assert!(stderr.contains("device memory changed"), "{stderr}");
}

/// The soak over the valley's tiled field: the camera flies down the path (tiles
/// entering and leaving the pool every frame), device memory the same at every
/// reading, the layer silent, host memory within the default 8 MiB (+0.0 to +0.1 MiB
/// on lavapipe since the soak flies the path once before its run). Planted faults: a
/// 64 KiB device buffer leaked every frame failed ("device memory changed between
/// frame 40 and frame 120"); a leak of 0.1 MB a frame read +19.1 MiB and failed.
#[test]
fn a_flight_over_the_valley_keeps_device_memory_flat() {
    let args = [
        "soak", "--scene", "valley", "--frames", "480", "--every", "40", "--width", "64",
        "--height", "64",
    ];
    silent_and_flat(&args);
}

//! Faults injected on purpose, so tests can drive the paths a real device takes
//! rarely: `GRASS_FAULT=missing-feature:<name>` makes every device lack that feature,
//! `GRASS_FAULT=device-lost:<frame>` makes the wait for that frame report
//! `VK_ERROR_DEVICE_LOST`, `GRASS_FAULT=leak:<bytes>` leaks that much host memory a
//! frame and `GRASS_FAULT=device-leak:<bytes>` a device buffer of that size a frame
//! (what the soak's memory checks must catch). Unset (the normal case), nothing
//! changes.

use ash::vk;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

/// The injected device loss has happened (it happens once a run).
static LOST: AtomicBool = AtomicBool::new(false);

/// The fault asked for in `GRASS_FAULT`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Every device reports this feature (by its Vulkan name) as missing.
    MissingFeature(String),
    /// The device is lost when the renderer waits for this frame (counted from 0),
    /// once a run.
    DeviceLost(u64),
    /// This many bytes of host memory are leaked (written, never freed) every frame.
    Leak(usize),
    /// A device buffer of this many bytes is leaked (made, never destroyed) every
    /// frame.
    DeviceLeak(u64),
}

impl Fault {
    /// Parses `missing-feature:<name>`, `device-lost:<frame>`, `leak:<bytes>` or
    /// `device-leak:<bytes>`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s.trim().split_once(':') {
            Some(("missing-feature", name)) if !name.is_empty() => {
                Ok(Fault::MissingFeature(name.to_string()))
            }
            Some(("device-lost", frame)) => frame
                .parse()
                .map(Fault::DeviceLost)
                .map_err(|_| format!("GRASS_FAULT: \"{frame}\" is not a frame number")),
            Some(("leak", bytes)) => bytes
                .parse()
                .map(Fault::Leak)
                .map_err(|_| format!("GRASS_FAULT: \"{bytes}\" is not a byte count")),
            Some(("device-leak", bytes)) => bytes
                .parse()
                .map(Fault::DeviceLeak)
                .map_err(|_| format!("GRASS_FAULT: \"{bytes}\" is not a byte count")),
            _ => Err(format!(
                "GRASS_FAULT: \"{s}\" is none of missing-feature:<name>, device-lost:<frame>, \
                 leak:<bytes>, device-leak:<bytes>"
            )),
        }
    }
}

/// The fault of this run, read from the environment once; a malformed value is
/// reported and ignored.
pub fn injected() -> Option<&'static Fault> {
    static FAULT: OnceLock<Option<Fault>> = OnceLock::new();
    FAULT
        .get_or_init(|| {
            let value = std::env::var("GRASS_FAULT").ok()?;
            Fault::parse(&value).inspect_err(|e| log::warn!("{e}")).ok()
        })
        .as_ref()
}

/// True when `GRASS_FAULT` takes `feature` away.
pub fn feature_removed(feature: &str) -> bool {
    matches!(injected(), Some(Fault::MissingFeature(f)) if f == feature)
}

/// `Err(ERROR_DEVICE_LOST)` when `GRASS_FAULT` loses the device at `frame`; leaks
/// the frame's bytes when it asks for a leak.
pub fn check_frame(frame: u64) -> Result<(), vk::Result> {
    match injected() {
        // Once a run: a viewer that makes its device again starts counting anew.
        Some(Fault::DeviceLost(at)) if *at == frame && !LOST.swap(true, Ordering::SeqCst) => {
            Err(vk::Result::ERROR_DEVICE_LOST)
        }
        Some(Fault::Leak(bytes)) => {
            // Written, so the pages count in the resident set; never freed.
            std::mem::forget(vec![1u8; *bytes]);
            Ok(())
        }
        _ => Ok(()),
    }
}

/// Leaks a device buffer when `GRASS_FAULT` asks for `device-leak:<bytes>`: made in
/// device memory and never destroyed.
pub fn leak_device(ctx: &std::sync::Arc<super::Context>) -> anyhow::Result<()> {
    if let Some(Fault::DeviceLeak(bytes)) = injected() {
        let buffer = super::Buffer::new(
            ctx,
            "planted device leak",
            *bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu_allocator::MemoryLocation::GpuOnly,
        )?;
        std::mem::forget(buffer);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_parse_and_bad_values_are_named() {
        assert_eq!(
            Fault::parse("missing-feature:tessellationShader"),
            Ok(Fault::MissingFeature("tessellationShader".into()))
        );
        assert_eq!(Fault::parse("device-lost:12"), Ok(Fault::DeviceLost(12)));
        assert_eq!(
            Fault::parse("device-leak:65536"),
            Ok(Fault::DeviceLeak(65536))
        );
        assert!(
            Fault::parse("device-lost:soon")
                .unwrap_err()
                .contains("soon")
        );
        assert!(Fault::parse("meteor").unwrap_err().contains("meteor"));
        assert!(Fault::parse("missing-feature:").is_err());
    }
}

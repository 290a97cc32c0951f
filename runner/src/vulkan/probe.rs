//! What this machine's Vulkan offers, found without making a device: the device
//! [`super::Context::new`] would pick, its optional paths, and the validation layer.
//! Tests ask it once, before they run anything, whether they can run here
//! ([`Probe::lacks`]); a run that then fails is a failure, never a skip.

pub use super::context::Capabilities;
use super::context::{VALIDATION_LAYER, pick_device};
use super::features::{DeviceFeatures, name_of};
use ash::{khr, vk};
use std::sync::OnceLock;

/// What a test needs of the machine.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Need {
    /// A Vulkan device with everything the renderer requires.
    Device,
    /// `VK_LAYER_KHRONOS_validation` (tests run under it).
    ValidationLayer,
    /// The mesh path (`VK_EXT_mesh_shader` with the limits it declares).
    MeshShaders,
    /// 64-bit storage-buffer atomics (the compute rasterizer).
    Int64Atomics,
}

/// What Vulkan offers on this machine.
#[derive(Clone, Debug)]
pub struct Probe {
    /// The device, or why there is none (no loader, no driver, none suitable).
    pub device: Result<Capabilities, String>,
    /// The validation layer is installed.
    pub validation_layer: bool,
}

impl Probe {
    /// Looks at the loader, the instance's layers and the devices; makes no device.
    pub fn run() -> Self {
        let entry = match unsafe { ash::Entry::load() } {
            Ok(entry) => entry,
            Err(e) => {
                return Self {
                    device: Err(format!("no Vulkan loader ({e})")),
                    validation_layer: false,
                };
            }
        };
        let validation_layer = unsafe { entry.enumerate_instance_layer_properties() }
            .unwrap_or_default()
            .iter()
            .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        Self {
            device: probe_device(&entry),
            validation_layer,
        }
    }

    /// The probe of this process, run once.
    pub fn once() -> &'static Self {
        static PROBE: OnceLock<Probe> = OnceLock::new();
        PROBE.get_or_init(Self::run)
    }

    /// What of `needs` this machine lacks, in words; `None` when it has all of it.
    pub fn lacks(&self, needs: &[Need]) -> Option<String> {
        let mut lacking: Vec<String> = Vec::new();
        for need in needs {
            let why = match (need, &self.device) {
                (Need::ValidationLayer, _) if !self.validation_layer => Some(format!(
                    "no {} (apt-get install vulkan-validationlayers)",
                    VALIDATION_LAYER.to_string_lossy()
                )),
                (Need::ValidationLayer, _) => None,
                (_, Err(why)) => Some(why.clone()),
                (Need::Device, Ok(_)) => None,
                (Need::MeshShaders, Ok(d)) => d.mesh_shader.clone().err(),
                (Need::Int64Atomics, Ok(d)) => d.int64_atomics.clone().err(),
            };
            if let Some(why) = why.filter(|w| !lacking.contains(w)) {
                lacking.push(why);
            }
        }
        (!lacking.is_empty()).then(|| lacking.join("; "))
    }
}

/// Whether a test that needs `needs` (beside a device and the validation layer, which
/// every GPU test needs) can run here, decided once by [`Probe::once`]: `true` when the
/// machine has all of it; `false`, printing why, when it lacks some and
/// `GRASS_REQUIRE_GPU` is not 1; a failure (panic) when it is. For test suites: a test
/// asks before it runs anything, and a run that then fails is a failure, never a skip
/// read from a failure's text.
pub fn runs_here(test: &str, needs: &[Need]) -> bool {
    let needs: Vec<Need> = [Need::Device, Need::ValidationLayer]
        .into_iter()
        .chain(needs.iter().copied())
        .collect();
    match Probe::once().lacks(&needs) {
        None => true,
        Some(why) if super::gpu_required() => panic!("{test}: GRASS_REQUIRE_GPU=1 but {why}"),
        Some(why) => {
            eprintln!("{test}: skipped: {why}");
            false
        }
    }
}

/// The device [`super::Context::new`] would pick without a window, or why none.
fn probe_device(entry: &ash::Entry) -> Result<Capabilities, String> {
    let app = vk::ApplicationInfo::default()
        .application_name(c"grass probe")
        .api_version(vk::API_VERSION_1_3);
    let info = vk::InstanceCreateInfo::default().application_info(&app);
    let instance = unsafe { entry.create_instance(&info, None) }
        .map_err(|e| format!("no Vulkan driver (create instance: {e})"))?;
    let surface_fn = khr::surface::Instance::new(entry, &instance);
    let found = pick_device(&instance, &surface_fn, None)
        .map_err(|e| format!("{e:#}"))
        .and_then(|(physical, _)| {
            let features = DeviceFeatures::query(&instance, physical).map_err(|e| e.to_string())?;
            let props = unsafe { instance.get_physical_device_properties(physical) };
            Ok(Capabilities {
                name: name_of(&props),
                software: props.device_type == vk::PhysicalDeviceType::CPU,
                mesh_shader: features.mesh_shader,
                int64_atomics: features.int64_atomics,
            })
        });
    unsafe { instance.destroy_instance(None) };
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(device: Result<Capabilities, String>, validation_layer: bool) -> Probe {
        Probe {
            device,
            validation_layer,
        }
    }

    /// Each need is answered from its own part of the probe, and every lack named.
    #[test]
    fn lacks_names_each_missing_need() {
        let lavapipe = Capabilities {
            name: "llvmpipe".into(),
            software: true,
            mesh_shader: Ok(()),
            int64_atomics: Err("the device has no shaderBufferInt64Atomics".into()),
        };
        let p = probe(Ok(lavapipe), true);
        assert_eq!(p.lacks(&[Need::Device, Need::MeshShaders]), None);
        assert_eq!(
            p.lacks(&[Need::Device, Need::Int64Atomics]).as_deref(),
            Some("the device has no shaderBufferInt64Atomics")
        );
        let none = probe(Err("no Vulkan driver".into()), false);
        let why = none
            .lacks(&[Need::Device, Need::MeshShaders, Need::ValidationLayer])
            .unwrap();
        assert!(
            why.contains("no Vulkan driver") && why.contains("validation"),
            "{why}"
        );
        // One reason once, however many needs it fails.
        assert_eq!(why.matches("no Vulkan driver").count(), 1, "{why}");
    }
}

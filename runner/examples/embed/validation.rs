//! The validation layer's messages, in the embedding examples (`embed`, `wgpu`):
//! errors counted, every message printed.

use anyhow::Result;
use ash::vk;
use std::ffi::c_void;
use std::sync::atomic::{AtomicU32, Ordering};

/// Validation errors the layer reported (with `--validation`).
pub static VALIDATION_ERRORS: AtomicU32 = AtomicU32::new(0);

/// Counts the validation layer's errors and prints every message.
pub fn debug_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
) -> Result<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)> {
    unsafe extern "system" fn callback(
        severity: vk::DebugUtilsMessageSeverityFlagsEXT,
        _types: vk::DebugUtilsMessageTypeFlagsEXT,
        data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
        _user: *mut c_void,
    ) -> vk::Bool32 {
        let message = unsafe { data.as_ref() }
            .and_then(|d| unsafe { d.message_as_c_str() })
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            VALIDATION_ERRORS.fetch_add(1, Ordering::SeqCst);
        }
        eprintln!("validation: {message}");
        vk::FALSE
    }
    use vk::DebugUtilsMessageSeverityFlagsEXT as Sev;
    use vk::DebugUtilsMessageTypeFlagsEXT as Ty;
    let utils = ash::ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(Sev::ERROR | Sev::WARNING)
        .message_type(Ty::GENERAL | Ty::VALIDATION)
        .pfn_user_callback(Some(callback));
    let messenger = unsafe { utils.create_debug_utils_messenger(&info, None)? };
    Ok((utils, messenger))
}

//! The debug-utils messenger: validation messages go to `log` and are counted.

use ash::vk;
use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicU64, Ordering};

/// Counts the warning and error messages the validation layer sent.
///
/// Tests read it after the context and every resource are dropped (so that leak reports at
/// device destruction are counted too) and assert that both counts stayed at zero.
#[derive(Debug, Default)]
pub struct ValidationCounter {
    errors: AtomicU64,
    warnings: AtomicU64,
}

impl ValidationCounter {
    /// Number of error-severity validation or performance messages so far.
    pub fn errors(&self) -> u64 {
        self.errors.load(Ordering::Relaxed)
    }

    /// Number of warning-severity validation or performance messages so far.
    pub fn warnings(&self) -> u64 {
        self.warnings.load(Ordering::Relaxed)
    }

    /// Errors plus warnings.
    pub fn total(&self) -> u64 {
        self.errors() + self.warnings()
    }
}

/// The messenger's create info, pointing its user data at `counter`.
///
/// The counter must outlive the messenger (the context keeps an `Arc` of it).
pub(crate) fn messenger_info(counter: &ValidationCounter) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(counter as *const ValidationCounter as *mut c_void)
}

/// Called by the loader and the layers, possibly from several threads at once.
unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the loader passes a valid callback-data pointer whose message is a NUL-terminated
    // string for the duration of the call; a null pointer is checked for.
    let message = unsafe {
        data.as_ref()
            .filter(|d| !d.p_message.is_null())
            .map(|d| CStr::from_ptr(d.p_message).to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    // GENERAL messages come from the loader (e.g. about other ICDs on the system): logged, not
    // counted. VALIDATION and PERFORMANCE messages are what a test must keep at zero.
    let counted =
        kind.intersects(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE);
    // SAFETY: `user` is the `ValidationCounter` the context keeps alive in an `Arc` for as long
    // as the messenger exists (see `messenger_info`).
    let counter = unsafe { (user as *const ValidationCounter).as_ref() };
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        log::error!(target: "umbra_vk::validation", "[{kind:?}] {message}");
        if let (true, Some(c)) = (counted, counter) {
            c.errors.fetch_add(1, Ordering::Relaxed);
        }
    } else if !counted {
        // Loader and driver notes (other ICDs on the system, Mesa's SPIR-V front end, …).
        log::debug!(target: "umbra_vk::validation", "[{kind:?}] {message}");
    } else {
        log::warn!(target: "umbra_vk::validation", "[{kind:?}] {message}");
        if let (true, Some(c)) = (counted, counter) {
            c.warnings.fetch_add(1, Ordering::Relaxed);
        }
    }
    vk::FALSE
}

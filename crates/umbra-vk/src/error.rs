//! The one error type of `umbra-vk`.

use ash::vk;

/// Everything that can go wrong in umbra's Vulkan layer.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    /// The Vulkan loader library could not be loaded.
    #[error("cannot load the Vulkan loader: {0}")]
    Loading(#[from] ash::LoadingError),
    /// A Vulkan call returned an error code.
    #[error("{call} failed: {result}")]
    Call {
        /// The Vulkan entry point that failed.
        call: &'static str,
        /// The result code it returned.
        result: vk::Result,
    },
    /// No physical device matched the selection (or none is usable).
    #[error("no usable Vulkan device{}; devices seen:\n{}", wanted.as_ref().map(|w| format!(" matches UMBRA_DEVICE={w:?}")).unwrap_or_default(), available.join("\n"))]
    NoDevice {
        /// The `UMBRA_DEVICE` filter, when one was set.
        wanted: Option<String>,
        /// One line per device the loader reported, with why it was not taken.
        available: Vec<String>,
    },
    /// The `UMBRA_DEVICE` filter fits more than one device: they differ in name or driver.
    #[error("UMBRA_DEVICE={wanted:?} fits more than one device; name one by more of its name or driver (`-` reads as a space, e.g. llvmpipe-mesa-25):\n{}", matching.join("\n"))]
    AmbiguousDevice {
        /// The `UMBRA_DEVICE` filter.
        wanted: String,
        /// One line per device it fits: name, type and driver.
        matching: Vec<String>,
    },
    /// `UMBRA_VALIDATION=1` asked for the Khronos validation layer but it is not installed.
    #[error("UMBRA_VALIDATION=1 but the layer VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)")]
    ValidationLayerMissing,
    /// A feature the caller asked for is not supported (or not enabled) on this device.
    #[error("unsupported on {device}: {what}")]
    Unsupported {
        /// The device name.
        device: String,
        /// What was asked for.
        what: String,
    },
    /// A resource description is invalid (zero size, over a device limit, …).
    #[error("invalid {what}: {why}")]
    InvalidDesc {
        /// The kind of object being described.
        what: &'static str,
        /// Why it is invalid.
        why: String,
    },
    /// A resource needs more than a device limit allows (its size, checked before it is
    /// created).
    #[error("{what}, but {limit} on {device}")]
    DeviceLimit {
        /// What was asked for and by what (`image "shadow map light 0": width 8256`, …).
        what: String,
        /// The limit it breaks, with its value.
        limit: crate::Limit,
        /// The device name.
        device: String,
    },
    /// Device memory for a resource could not be allocated.
    #[error("allocating {} for {name:?} failed: {source}", crate::human_bytes(*bytes))]
    Allocation {
        /// The debug name of the buffer or image the memory was for.
        name: String,
        /// The bytes asked for.
        bytes: u64,
        /// What the allocator said.
        source: gpu_allocator::AllocationError,
    },
    /// A window's raw handles could not be had (the window is gone or unsupported).
    #[error("window handle: {0}")]
    Window(String),
    /// A lock guarding shared state was poisoned by a panic on another thread.
    #[error("a lock inside umbra-vk was poisoned by a panic on another thread")]
    Poisoned,
}

/// `Result` with [`VkError`].
pub type VkResult<T> = Result<T, VkError>;

/// Maps a raw `vk::Result` error to [`VkError::Call`], naming the call.
pub(crate) trait CallContext<T> {
    /// Attaches the Vulkan entry point's name to the error.
    fn call(self, call: &'static str) -> VkResult<T>;
}

impl<T> CallContext<T> for Result<T, vk::Result> {
    fn call(self, call: &'static str) -> VkResult<T> {
        self.map_err(|result| VkError::Call { call, result })
    }
}

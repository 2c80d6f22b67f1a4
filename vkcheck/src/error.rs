//! Errors, the install commands and the helpers that build errors.

use std::ffi::CStr;
use std::fmt::Write as _;
use std::sync::{Mutex, MutexGuard, PoisonError};

use ash::vk;

/// The validation layer this crate enables.
pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Debian command that installs the Khronos validation layer.
pub const INSTALL_VALIDATION_LAYER: &str = "apt-get install -y vulkan-validationlayers";
/// Debian command that installs the Vulkan loader and lavapipe (Mesa's CPU driver).
pub const INSTALL_LAVAPIPE: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

/// How long [`Validator::run_compute`] waits for its dispatch before giving up.
pub(crate) const FENCE_TIMEOUT_NS: u64 = 120_000_000_000;

/// Everything that can go wrong in this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VkError {
    /// `libvulkan.so.1` could not be opened.
    #[error(
        "could not load the Vulkan loader (libvulkan.so.1): {0}; install it with `{INSTALL_LAVAPIPE}`"
    )]
    Loader(String),
    /// `VK_LAYER_KHRONOS_validation` is not installed.
    #[error(
        "the Vulkan validation layer VK_LAYER_KHRONOS_validation is not installed; install it with `{INSTALL_VALIDATION_LAYER}`"
    )]
    MissingLayer,
    /// A required instance extension (normally provided by the validation layer) is missing.
    #[error(
        "the Vulkan instance extension {0} is not available (the validation layer provides it: `{INSTALL_VALIDATION_LAYER}`)"
    )]
    MissingExtension(String),
    /// No physical device, or none whose name matches `WGPU_ADAPTER_NAME`.
    #[error(
        "no Vulkan device{}; devices found: {available:?}; install lavapipe with `{INSTALL_LAVAPIPE}`",
        .requested.as_ref().map(|r| format!(" whose name contains {r:?} (case-insensitive)")).unwrap_or_default()
    )]
    NoDevice {
        /// The requested name fragment, if any.
        requested: Option<String>,
        /// Names of all devices the loader reported.
        available: Vec<String>,
    },
    /// The chosen device has no queue family supporting both graphics and compute.
    #[error("Vulkan device {0:?} has no queue family with both graphics and compute")]
    NoQueue(String),
    /// The chosen device supports neither Vulkan 1.3 nor `VK_KHR_dynamic_rendering`.
    #[error(
        "Vulkan device {0:?} supports neither Vulkan 1.3 nor VK_KHR_dynamic_rendering, needed for graphics pipelines"
    )]
    NoDynamicRendering(String),
    /// No memory type is both host-visible and host-coherent for a buffer.
    #[error("no host-visible, host-coherent memory type for a storage buffer")]
    NoHostMemory,
    /// A Vulkan call returned an error (`VK_ERROR_VALIDATION_FAILED_EXT` when the validation
    /// layer refused it); `messages` are the validation messages captured during the operation.
    #[error("{call} failed with {result:?}{}", format_messages(.messages))]
    Vulkan {
        /// The Vulkan function that failed.
        call: &'static str,
        /// Its result code.
        result: vk::Result,
        /// Validation messages captured during the whole operation.
        messages: Vec<String>,
    },
    /// The words are not usable SPIR-V (see [`local_size`](crate::local_size)).
    #[error("SPIR-V: {0}")]
    Spirv(String),
    /// The device cannot report compiler statistics
    /// (`VK_KHR_pipeline_executable_properties` or its `pipelineExecutableInfo` feature
    /// is missing).
    #[error(
        "Vulkan device {0:?} does not report pipeline executable statistics \
         (VK_KHR_pipeline_executable_properties); Mesa's RADV does: `{INSTALL_LAVAPIPE}`"
    )]
    NoPipelineStatistics(String),
    /// An argument cannot be passed to Vulkan (entry name with a NUL, too many workgroups, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// Formats captured messages as an indented list (empty string when there are none).
pub(crate) fn format_messages(messages: &[String]) -> String {
    let mut out = String::new();
    if !messages.is_empty() {
        out.push_str("; validation messages:");
        for m in messages {
            let _ = write!(out, "\n  - {m}");
        }
    }
    out
}

/// Shorthand for mapping an `ash` error of `call` into [`VkError::Vulkan`].
pub(crate) fn vk_err(call: &'static str) -> impl FnOnce(vk::Result) -> VkError {
    move |result| VkError::Vulkan {
        call,
        result,
        messages: Vec::new(),
    }
}

/// Locks a mutex, ignoring poisoning (the protected data stays meaningful after a panic).
pub(crate) fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

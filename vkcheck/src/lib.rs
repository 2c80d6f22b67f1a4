//! `vkcheck`: raw Vulkan (through [`ash`]) with the Khronos validation layer, for volfog's tests.
//!
//! Two uses:
//!
//! * **Layout checks** — [`Validator::compute_pipeline`] and [`Validator::graphics_pipeline`]
//!   build a pipeline from SPIR-V plus the descriptor set layouts the caller says it will use,
//!   destroy it again, and return every WARNING / ERROR message the validation layer produced
//!   meanwhile. An empty vector means the layer found nothing to complain about; a shader that
//!   uses a binding the layout lacks, or declares it with another descriptor type or stage,
//!   yields messages such as `VUID-VkComputePipelineCreateInfo-layout-00703` (VUIDs and wording
//!   differ between layer versions, so tests should assert that messages exist, not their text).
//! * **Running compute shaders** from other compilers (Slang, glslang, naga) —
//!   [`Validator::run_compute`] binds an input and an output storage buffer, dispatches, and
//!   returns the output bytes so that numbers can be compared across compilers.
//!
//! It is meant for lavapipe (Mesa's CPU Vulkan driver) on CI machines without a GPU, but works
//! on any Vulkan 1.3 device (or 1.2 with `VK_KHR_dynamic_rendering`). Requirements (Debian):
//!
//! ```text
//! apt-get install -y mesa-vulkan-drivers libvulkan1 vulkan-validationlayers
//! ```
//!
//! The loader `libvulkan.so.1` is opened at run time (`ash`'s `loaded` feature), so building
//! needs none of these; [`Validator::new`] reports what is missing with the command that installs it.
//!
//! # Validation errors stop the call
//!
//! The debug-utils callback returns `VK_TRUE` for ERROR-severity *validation* messages. The
//! layer then skips the offending call and returns `VK_ERROR_VALIDATION_FAILED_EXT` instead of
//! passing invalid input to the driver (lavapipe 22.3.6 segfaults on, e.g., a compute pipeline
//! whose layout lacks a binding the shader uses). The pipeline checks treat such a skipped call as
//! the expected outcome and return the messages; [`Validator::run_compute`] returns an error
//! holding them. While the device is being destroyed nothing is refused, so a leak report cannot
//! stop `vkDestroyDevice` itself.
//!
//! # Environment
//!
//! * `WGPU_ADAPTER_NAME` — case-insensitive substring of the device name to use (same variable
//!   as volfog's wgpu tests); unset or empty: the first device.
//! * `MESA_SHADER_CACHE_DISABLE=true` — what CI sets; recommended so lavapipe compiles every
//!   pipeline afresh and writes no cache under `$HOME`.

#![warn(missing_docs)]

mod spirv;

pub use ash::vk;
pub use spirv::local_size;

use std::ffi::{CStr, CString, c_void};
use std::fmt::Write as _;
use std::ops::{BitOr, BitOrAssign};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// The validation layer this crate enables.
const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Debian command that installs the Khronos validation layer.
pub const INSTALL_VALIDATION_LAYER: &str = "apt-get install -y vulkan-validationlayers";
/// Debian command that installs the Vulkan loader and lavapipe (Mesa's CPU driver).
pub const INSTALL_LAVAPIPE: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

/// How long [`Validator::run_compute`] waits for its dispatch before giving up.
const FENCE_TIMEOUT_NS: u64 = 120_000_000_000;

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
    /// The words are not usable SPIR-V (see [`local_size`]).
    #[error("SPIR-V: {0}")]
    Spirv(String),
    /// An argument cannot be passed to Vulkan (entry name with a NUL, too many workgroups, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// Formats captured messages as an indented list (empty string when there are none).
fn format_messages(messages: &[String]) -> String {
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
fn vk_err(call: &'static str) -> impl FnOnce(vk::Result) -> VkError {
    move |result| VkError::Vulkan {
        call,
        result,
        messages: Vec::new(),
    }
}

/// Locks a mutex, ignoring poisoning (the protected data stays meaningful after a panic).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Shader stages a descriptor binding is visible to (a small bit set; combine with `|`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Stages(u8);

impl Stages {
    /// No stage.
    pub const NONE: Stages = Stages(0);
    /// The compute stage.
    pub const COMPUTE: Stages = Stages(1);
    /// The vertex stage.
    pub const VERTEX: Stages = Stages(2);
    /// The fragment stage.
    pub const FRAGMENT: Stages = Stages(4);
    /// Vertex and fragment stages.
    pub const VERTEX_FRAGMENT: Stages = Stages(2 | 4);

    /// Both sets of stages.
    pub const fn union(self, other: Stages) -> Stages {
        Stages(self.0 | other.0)
    }

    /// Whether every stage of `other` is in `self`.
    pub const fn contains(self, other: Stages) -> bool {
        self.0 & other.0 == other.0
    }

    /// The equivalent Vulkan stage flags.
    pub fn to_vk(self) -> vk::ShaderStageFlags {
        let mut flags = vk::ShaderStageFlags::empty();
        if self.contains(Stages::COMPUTE) {
            flags |= vk::ShaderStageFlags::COMPUTE;
        }
        if self.contains(Stages::VERTEX) {
            flags |= vk::ShaderStageFlags::VERTEX;
        }
        if self.contains(Stages::FRAGMENT) {
            flags |= vk::ShaderStageFlags::FRAGMENT;
        }
        flags
    }
}

impl BitOr for Stages {
    type Output = Stages;
    fn bitor(self, rhs: Stages) -> Stages {
        self.union(rhs)
    }
}

impl BitOrAssign for Stages {
    fn bitor_assign(&mut self, rhs: Stages) {
        *self = self.union(rhs);
    }
}

/// The type of a descriptor (one array element, `descriptorCount = 1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DescriptorKind {
    /// `VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER` (WGSL `var<uniform>`, GLSL `uniform` block).
    UniformBuffer,
    /// `VK_DESCRIPTOR_TYPE_STORAGE_BUFFER` (WGSL `var<storage>`, GLSL `buffer` block).
    StorageBuffer,
    /// `VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE` (WGSL `texture_*`, GLSL `texture2D`).
    SampledImage,
    /// `VK_DESCRIPTOR_TYPE_STORAGE_IMAGE` (WGSL `texture_storage_*`, GLSL `image2D`).
    StorageImage,
    /// `VK_DESCRIPTOR_TYPE_SAMPLER` (WGSL `sampler`, GLSL `sampler`).
    Sampler,
    /// `VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER` (GLSL `sampler2D`; HLSL/Slang `Sampler2D`).
    CombinedImageSampler,
}

impl DescriptorKind {
    /// The equivalent Vulkan descriptor type.
    pub fn to_vk(self) -> vk::DescriptorType {
        match self {
            DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
            DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
            DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
            DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        }
    }
}

/// One binding of a descriptor set layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DescriptorBinding {
    /// Binding number within its set.
    pub binding: u32,
    /// Descriptor type.
    pub kind: DescriptorKind,
    /// Stages that may access it.
    pub stages: Stages,
}

impl DescriptorBinding {
    /// A binding of `kind` at `binding`, visible to `stages`.
    pub const fn new(binding: u32, kind: DescriptorKind, stages: Stages) -> Self {
        DescriptorBinding {
            binding,
            kind,
            stages,
        }
    }
}

/// A shader stage's code and entry point name.
#[derive(Clone, Copy, Debug)]
pub struct ShaderEntry<'a> {
    /// SPIR-V words.
    pub spirv: &'a [u32],
    /// Entry point name (`OpEntryPoint` name).
    pub entry: &'a str,
}

/// One vertex attribute read from a vertex buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexAttribute {
    /// Shader input location.
    pub location: u32,
    /// Format of the data in the buffer.
    pub format: vk::Format,
    /// Byte offset within one element.
    pub offset: u32,
}

/// One vertex buffer binding (its index in [`GraphicsDesc::vertex_buffers`] is its binding number).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexBuffer {
    /// Bytes between consecutive elements.
    pub stride: u32,
    /// Advance per instance instead of per vertex.
    pub per_instance: bool,
    /// Attributes read from this buffer.
    pub attributes: Vec<VertexAttribute>,
}

/// Blend equation of one channel group: `result = src * src_factor <op> dst * dst_factor`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlendComponent {
    /// Factor applied to the fragment shader's output.
    pub src_factor: vk::BlendFactor,
    /// Factor applied to the attachment's current value.
    pub dst_factor: vk::BlendFactor,
    /// How the two are combined.
    pub op: vk::BlendOp,
}

/// Blending of the colour attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Blend {
    /// RGB channels.
    pub color: BlendComponent,
    /// Alpha channel.
    pub alpha: BlendComponent,
}

impl Blend {
    /// Non-premultiplied "over" (wgpu's `BlendState::ALPHA_BLENDING`).
    pub const ALPHA: Blend = Blend {
        color: BlendComponent {
            src_factor: vk::BlendFactor::SRC_ALPHA,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
        alpha: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
    };
    /// Premultiplied "over" (wgpu's `BlendState::PREMULTIPLIED_ALPHA_BLENDING`).
    pub const PREMULTIPLIED_ALPHA: Blend = Blend {
        color: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
        alpha: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
    };
}

/// Everything [`Validator::graphics_pipeline`] needs. The topology is a triangle list, there is
/// one colour attachment and no depth/stencil; viewport and scissor are dynamic.
#[derive(Clone, Debug)]
pub struct GraphicsDesc<'a> {
    /// Vertex shader.
    pub vertex: ShaderEntry<'a>,
    /// Fragment shader.
    pub fragment: ShaderEntry<'a>,
    /// Descriptor set layouts used by both stages (index = set number; empty sets allowed).
    pub sets: &'a [Vec<DescriptorBinding>],
    /// Vertex buffers (may be empty, e.g. for a full-screen triangle built from the vertex index).
    pub vertex_buffers: &'a [VertexBuffer],
    /// Format of the single colour attachment.
    pub color_format: vk::Format,
    /// Blending of the colour attachment; `None` writes the output unblended.
    pub blend: Option<Blend>,
}

/// What the debug-utils callback writes into (shared through an `Arc`, passed as `user_data`).
struct MessageSink {
    /// Every WARNING / ERROR message since the last clear, formatted.
    messages: Mutex<Vec<String>>,
    /// Whether ERROR-severity validation messages make the layer skip the call (`VK_TRUE`).
    /// Off during teardown, so that a leak report cannot stop `vkDestroyDevice` itself.
    refuse_errors: AtomicBool,
}

/// A Vulkan instance with `VK_LAYER_KHRONOS_validation`, a debug messenger that records every
/// WARNING and ERROR message, and a logical device with one graphics+compute queue.
///
/// Every method clears the recorded messages first and returns the ones produced while it ran.
/// Methods take `&self` and are serialised by an internal lock, so one `Validator` may be shared
/// between threads (e.g. in a `static OnceLock`) without mixing up whose messages are whose.
///
/// The device enables every core feature (Vulkan 1.0–1.3) that it supports, so SPIR-V
/// capabilities such as `Float16` or `StorageImageWriteWithoutFormat` are judged against what the
/// device can do rather than rejected as "feature not enabled".
pub struct Validator {
    _entry: ash::Entry,
    instance: ash::Instance,
    debug_utils: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    device_name: String,
    dynamic_rendering: bool,
    memory_properties: vk::PhysicalDeviceMemoryProperties,
    max_workgroups_x: u32,
    /// Written by the debug callback through a raw pointer (`Arc::as_ptr`), read by the methods.
    sink: Arc<MessageSink>,
    creation_messages: Vec<String>,
    /// Serialises the methods (queue access and message attribution).
    call_lock: Mutex<()>,
    torn_down: bool,
}

impl std::fmt::Debug for Validator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Validator")
            .field("device_name", &self.device_name)
            .field("dynamic_rendering", &self.dynamic_rendering)
            .finish_non_exhaustive()
    }
}

/// The debug-utils callback: formats WARNING/ERROR messages into the [`MessageSink`] behind
/// `user_data`. Returns `VK_TRUE` (skip the call) for ERROR-severity validation messages.
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user_data.is_null() {
        return vk::FALSE;
    }
    // Never unwind into the Vulkan layer.
    let recorded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: `user_data` is `Arc::as_ptr` of the Validator's sink, which outlives the
        // instance and messenger; `data` is valid for the duration of the callback.
        let (sink, data) = unsafe { (&*(user_data as *const MessageSink), &*data) };
        let text = unsafe { data.message_as_c_str() }
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        let id = unsafe { data.message_id_name_as_c_str() }
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            "ERROR"
        } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
            "WARNING"
        } else {
            "INFO"
        };
        let kind = if types.contains(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION) {
            "validation"
        } else if types.contains(vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE) {
            "performance"
        } else {
            "general"
        };
        let line = if id.is_empty() || text.contains(&id) {
            format!("{level} [{kind}] {text}")
        } else {
            format!("{level} [{kind}] [{id}] {text}")
        };
        lock(&sink.messages).push(line);
        sink.refuse_errors.load(Ordering::SeqCst)
    }));
    let is_validation_error = severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        && types.contains(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION);
    if matches!(recorded, Ok(true)) && is_validation_error {
        vk::TRUE
    } else {
        vk::FALSE
    }
}

/// Index of the device to use: the first whose name contains `requested` (case-insensitive),
/// or the first one when nothing is requested.
fn select_device(names: &[String], requested: Option<&str>) -> Option<usize> {
    match requested {
        None => (!names.is_empty()).then_some(0),
        Some(req) => {
            let req = req.to_lowercase();
            names.iter().position(|n| n.to_lowercase().contains(&req))
        }
    }
}

impl Validator {
    /// Creates the instance with `VK_LAYER_KHRONOS_validation` and a `VK_EXT_debug_utils`
    /// messenger recording every WARNING and ERROR message (validation and general types), and
    /// a device: the first whose name contains `$WGPU_ADAPTER_NAME` (case-insensitive) when the
    /// variable is set and non-empty, else the first device.
    ///
    /// Errors name the apt command that fixes them: [`INSTALL_VALIDATION_LAYER`] when the layer
    /// is missing, [`INSTALL_LAVAPIPE`] when the loader or any device is missing.
    pub fn new() -> Result<Self, VkError> {
        let requested = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .filter(|s| !s.trim().is_empty());
        Self::with_adapter(requested.as_deref())
    }

    /// Like [`Validator::new`] with the device name fragment given explicitly (`None`: first
    /// device), ignoring `WGPU_ADAPTER_NAME`.
    pub fn with_adapter(requested: Option<&str>) -> Result<Self, VkError> {
        // SAFETY: loading the system Vulkan loader; no other Vulkan state exists yet.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;

        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .map_err(vk_err("vkEnumerateInstanceLayerProperties"))?;
        if !layers
            .iter()
            .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
        {
            return Err(VkError::MissingLayer);
        }
        let debug_utils_name = ash::ext::debug_utils::NAME;
        let has_debug_utils = [None, Some(VALIDATION_LAYER)].into_iter().any(|layer| {
            unsafe { entry.enumerate_instance_extension_properties(layer) }
                .unwrap_or_default()
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(debug_utils_name))
        });
        if !has_debug_utils {
            return Err(VkError::MissingExtension(
                debug_utils_name.to_string_lossy().into_owned(),
            ));
        }

        let sink = Arc::new(MessageSink {
            messages: Mutex::new(Vec::new()),
            refuse_errors: AtomicBool::new(true),
        });
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION,
            )
            .pfn_user_callback(Some(debug_callback))
            .user_data(Arc::as_ptr(&sink) as *mut c_void);

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"vkcheck")
            .engine_name(c"vkcheck")
            .api_version(vk::API_VERSION_1_3);
        let layer_names = [VALIDATION_LAYER.as_ptr()];
        let extension_names = [debug_utils_name.as_ptr()];
        // The messenger info chained here also reports messages of vkCreateInstance and
        // vkDestroyInstance (where the persistent messenger does not exist).
        let instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&extension_names)
            .push_next(&mut messenger_info);
        // SAFETY: valid create info; `sink` outlives the instance (it is stored in Self).
        let instance =
            unsafe { entry.create_instance(&instance_info, None) }.map_err(|result| {
                let messages = std::mem::take(&mut *lock(&sink.messages));
                if result == vk::Result::ERROR_INCOMPATIBLE_DRIVER {
                    // The loader found no driver (ICD) at all.
                    VkError::NoDevice {
                        requested: requested.map(str::to_owned),
                        available: Vec::new(),
                    }
                } else {
                    VkError::Vulkan {
                        call: "vkCreateInstance",
                        result,
                        messages,
                    }
                }
            })?;
        let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
        let messenger =
            match unsafe { debug_utils.create_debug_utils_messenger(&messenger_info, None) } {
                Ok(m) => m,
                Err(result) => {
                    unsafe { instance.destroy_instance(None) };
                    return Err(vk_err("vkCreateDebugUtilsMessengerEXT")(result));
                }
            };

        let mut partial = Partial {
            instance: &instance,
            debug_utils: &debug_utils,
            messenger,
            device: None,
        };
        let setup = create_device(&instance, requested, &mut partial)?;
        partial.device = None; // ownership moves into Self
        std::mem::forget(partial);

        let creation_messages = std::mem::take(&mut *lock(&sink.messages));
        Ok(Validator {
            _entry: entry,
            instance,
            debug_utils,
            messenger,
            device: setup.device,
            queue: setup.queue,
            queue_family: setup.queue_family,
            device_name: setup.device_name,
            dynamic_rendering: setup.dynamic_rendering,
            memory_properties: setup.memory_properties,
            max_workgroups_x: setup.max_workgroups_x,
            sink,
            creation_messages,
            call_lock: Mutex::new(()),
            torn_down: false,
        })
    }

    /// Name of the chosen device, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub fn device_name(&self) -> String {
        self.device_name.clone()
    }

    /// WARNING/ERROR messages produced while creating the instance and device (normally none).
    pub fn creation_messages(&self) -> &[String] {
        &self.creation_messages
    }

    /// Creates a compute pipeline from `spirv` and its entry point `entry`, with a pipeline layout
    /// made of one descriptor set layout per element of `sets` (index = set number; an empty
    /// `Vec` is an empty set layout; each binding has `descriptorCount = 1`), destroys
    /// everything again, and returns the validation messages produced meanwhile
    /// (`Ok(vec![])` = clean).
    ///
    /// A call the layer refused (`VK_ERROR_VALIDATION_FAILED_EXT`, see the crate docs) is a
    /// normal outcome here and yields `Ok(messages)`; any other failing `VkResult` is an `Err`.
    pub fn compute_pipeline(
        &self,
        spirv: &[u32],
        entry: &str,
        sets: &[Vec<DescriptorBinding>],
    ) -> Result<Vec<String>, VkError> {
        let entry = entry_name(entry)?;
        let (result, messages) = self.capture(|s| {
            let module = s.shader_module(spirv)?;
            let layout = s.pipeline_layout(sets)?;
            s.compute_pipeline(module, &entry, layout)?;
            Ok(())
        });
        pipeline_outcome(result, messages)
    }

    /// Like [`Validator::compute_pipeline`] for a graphics pipeline: vertex and fragment shaders,
    /// the descriptor sets of both, the vertex buffers, one colour attachment of
    /// `desc.color_format` with optional blending, no depth/stencil, triangle list, dynamic
    /// viewport and scissor, created for dynamic rendering (no render pass object).
    ///
    /// Errors with [`VkError::NoDynamicRendering`] on a device that cannot do dynamic rendering.
    pub fn graphics_pipeline(&self, desc: &GraphicsDesc<'_>) -> Result<Vec<String>, VkError> {
        if !self.dynamic_rendering {
            return Err(VkError::NoDynamicRendering(self.device_name.clone()));
        }
        let vertex_entry = entry_name(desc.vertex.entry)?;
        let fragment_entry = entry_name(desc.fragment.entry)?;
        let (result, messages) = self.capture(|s| {
            let vertex = s.shader_module(desc.vertex.spirv)?;
            let fragment = s.shader_module(desc.fragment.spirv)?;
            let layout = s.pipeline_layout(desc.sets)?;
            s.graphics_pipeline(
                desc,
                [(vertex, &vertex_entry), (fragment, &fragment_entry)],
                layout,
            )?;
            Ok(())
        });
        pipeline_outcome(result, messages)
    }

    /// Runs the compute entry point `entry` of `spirv` once and returns the output buffer and the
    /// validation messages produced meanwhile.
    ///
    /// Descriptor set 0 holds two storage buffers, visible to the compute stage:
    /// * binding 0: `input` (the shader should declare it read-only; an empty input is bound as
    ///   4 zero bytes),
    /// * binding 1: `output_bytes` zeroed bytes (at least 4 are allocated; exactly
    ///   `output_bytes` are returned).
    ///
    /// The workgroup size is read from the SPIR-V (see [`local_size`]); the dispatch is
    /// `ceil(invocations / local_size_x) × 1 × 1` workgroups, so the shader must guard against
    /// invocations past the end of its data. Memory is host-visible and coherent.
    ///
    /// Unlike the pipeline checks, a call refused by the validation layer is an error
    /// ([`VkError::Vulkan`] with `VK_ERROR_VALIDATION_FAILED_EXT` and the messages), since
    /// nothing ran.
    pub fn run_compute(
        &self,
        spirv: &[u32],
        entry: &str,
        input: &[u8],
        output_bytes: usize,
        invocations: u32,
    ) -> Result<(Vec<u8>, Vec<String>), VkError> {
        let [local_x, _, _] = local_size(spirv, entry)?;
        if local_x == 0 {
            return Err(VkError::Spirv(format!("{entry:?} has local_size_x = 0")));
        }
        let groups = invocations.div_ceil(local_x);
        if groups > self.max_workgroups_x {
            return Err(VkError::InvalidArgument(format!(
                "{invocations} invocations need {groups} workgroups of {local_x}, more than the \
                 device's maxComputeWorkGroupCount[0] = {}",
                self.max_workgroups_x
            )));
        }
        let entry = entry_name(entry)?;
        let (result, messages) = self.capture(|s| {
            let storage = DescriptorBinding::new(0, DescriptorKind::StorageBuffer, Stages::COMPUTE);
            let sets = [vec![
                storage,
                DescriptorBinding {
                    binding: 1,
                    ..storage
                },
            ]];
            let module = s.shader_module(spirv)?;
            let layout = s.pipeline_layout(&sets)?;
            let pipeline = s.compute_pipeline(module, &entry, layout)?;

            let input_buffer = s.host_buffer(input.len(), &self.memory_properties)?;
            // SAFETY: the mapping is at least input.len() bytes long (and at least 4).
            unsafe { std::ptr::copy_nonoverlapping(input.as_ptr(), input_buffer.ptr, input.len()) };
            let output_buffer = s.host_buffer(output_bytes, &self.memory_properties)?;

            let set = s.descriptor_set(s.set_layouts[0], &[&input_buffer, &output_buffer])?;
            let command_buffer = s.command_buffer(self.queue_family)?;
            let device = s.device;
            unsafe {
                device
                    .begin_command_buffer(
                        command_buffer,
                        &vk::CommandBufferBeginInfo::default()
                            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                    )
                    .map_err(vk_err("vkBeginCommandBuffer"))?;
                device.cmd_bind_pipeline(command_buffer, vk::PipelineBindPoint::COMPUTE, pipeline);
                device.cmd_bind_descriptor_sets(
                    command_buffer,
                    vk::PipelineBindPoint::COMPUTE,
                    layout,
                    0,
                    &[set],
                    &[],
                );
                device.cmd_dispatch(command_buffer, groups, 1, 1);
                // Make the shader's writes visible to the host read after the fence.
                let barrier = vk::MemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::SHADER_WRITE)
                    .dst_access_mask(vk::AccessFlags::HOST_READ);
                device.cmd_pipeline_barrier(
                    command_buffer,
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &[barrier],
                    &[],
                    &[],
                );
                device
                    .end_command_buffer(command_buffer)
                    .map_err(vk_err("vkEndCommandBuffer"))?;
            }
            s.submit_and_wait(self.queue, command_buffer)?;
            // SAFETY: the fence signalled, the barrier made the writes host-visible, and the
            // mapping is coherent and at least output_bytes long.
            let out =
                unsafe { std::slice::from_raw_parts(output_buffer.ptr, output_bytes) }.to_vec();
            Ok(out)
        });
        match result {
            Ok(out) => Ok((out, messages)),
            Err(e) => Err(with_messages(e, messages)),
        }
    }

    /// Destroys the device and instance now and returns the messages the layer produced while
    /// doing so (leaked-object reports appear here; `vec![]` = nothing leaked).
    /// Dropping a `Validator` does the same and prints such messages to stderr.
    pub fn close(mut self) -> Vec<String> {
        self.teardown()
    }

    /// Clears the recorded messages, runs `f` with a fresh [`Scratch`], destroys every object it
    /// created, and returns `f`'s result with the messages produced in the meantime.
    fn capture<T>(
        &self,
        f: impl FnOnce(&mut Scratch<'_>) -> Result<T, VkError>,
    ) -> (Result<T, VkError>, Vec<String>) {
        let _serialised = lock(&self.call_lock);
        lock(&self.sink.messages).clear();
        let result = {
            let mut scratch = Scratch::new(&self.device);
            f(&mut scratch)
            // `scratch` is dropped here, destroying its objects while messages are still captured.
        };
        let messages = std::mem::take(&mut *lock(&self.sink.messages));
        (result, messages)
    }

    /// Destroys device, messenger and instance (once) and returns the messages of the teardown.
    fn teardown(&mut self) -> Vec<String> {
        if self.torn_down {
            return Vec::new();
        }
        self.torn_down = true;
        self.sink.refuse_errors.store(false, Ordering::SeqCst);
        lock(&self.sink.messages).clear();
        // SAFETY: every object created from the device was destroyed by its Scratch; the
        // messenger is destroyed before the instance, whose chained messenger still reports.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_device(None);
            self.debug_utils
                .destroy_debug_utils_messenger(self.messenger, None);
            self.instance.destroy_instance(None);
        }
        std::mem::take(&mut *lock(&self.sink.messages))
    }
}

impl Drop for Validator {
    fn drop(&mut self) {
        let messages = self.teardown();
        if !messages.is_empty() {
            eprintln!("vkcheck: validation messages while destroying the device:");
            for m in &messages {
                eprintln!("  - {m}");
            }
        }
    }
}

/// The device-level state [`Validator::with_adapter`] builds after the instance.
struct DeviceSetup {
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    device_name: String,
    dynamic_rendering: bool,
    memory_properties: vk::PhysicalDeviceMemoryProperties,
    max_workgroups_x: u32,
}

/// Destroys a half-built Validator's objects when `with_adapter` fails after the instance.
struct Partial<'a> {
    instance: &'a ash::Instance,
    debug_utils: &'a ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    device: Option<ash::Device>,
}

impl Drop for Partial<'_> {
    fn drop(&mut self) {
        // SAFETY: nothing else uses these objects once construction has failed.
        unsafe {
            if let Some(device) = self.device.take() {
                device.destroy_device(None);
            }
            self.debug_utils
                .destroy_debug_utils_messenger(self.messenger, None);
            self.instance.destroy_instance(None);
        }
    }
}

/// Picks the physical device and creates the logical device with all supported core features.
fn create_device(
    instance: &ash::Instance,
    requested: Option<&str>,
    partial: &mut Partial<'_>,
) -> Result<DeviceSetup, VkError> {
    let physical_devices = match unsafe { instance.enumerate_physical_devices() } {
        Ok(devices) => devices,
        Err(vk::Result::ERROR_INITIALIZATION_FAILED | vk::Result::ERROR_INCOMPATIBLE_DRIVER) => {
            Vec::new()
        }
        Err(result) => return Err(vk_err("vkEnumeratePhysicalDevices")(result)),
    };
    let properties: Vec<vk::PhysicalDeviceProperties> = physical_devices
        .iter()
        .map(|&pd| unsafe { instance.get_physical_device_properties(pd) })
        .collect();
    let names: Vec<String> = properties
        .iter()
        .map(|p| {
            p.device_name_as_c_str()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        })
        .collect();
    let index = select_device(&names, requested).ok_or_else(|| VkError::NoDevice {
        requested: requested.map(str::to_owned),
        available: names.clone(),
    })?;
    let physical = physical_devices[index];
    let props = properties[index];
    let device_name = names[index].clone();

    let queue_family = unsafe { instance.get_physical_device_queue_family_properties(physical) }
        .iter()
        .position(|q| {
            q.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .ok_or_else(|| VkError::NoQueue(device_name.clone()))? as u32;

    let api = props.api_version;
    let has_dynamic_rendering_ext = api < vk::API_VERSION_1_3
        && unsafe { instance.enumerate_device_extension_properties(physical) }
            .unwrap_or_default()
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(ash::khr::dynamic_rendering::NAME));

    // Query every core feature the device supports and enable exactly those.
    let mut v11 = vk::PhysicalDeviceVulkan11Features::default();
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut dynamic_rendering_ext = vk::PhysicalDeviceDynamicRenderingFeatures::default();
    let mut features = vk::PhysicalDeviceFeatures2::default();
    if api >= vk::API_VERSION_1_2 {
        features = features.push_next(&mut v11).push_next(&mut v12);
    }
    if api >= vk::API_VERSION_1_3 {
        features = features.push_next(&mut v13);
    } else if has_dynamic_rendering_ext {
        features = features.push_next(&mut dynamic_rendering_ext);
    }
    unsafe { instance.get_physical_device_features2(physical, &mut features) };

    let priorities = [1.0f32];
    let queue_infos = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let extensions = if has_dynamic_rendering_ext {
        vec![ash::khr::dynamic_rendering::NAME.as_ptr()]
    } else {
        Vec::new()
    };
    let device_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .enabled_extension_names(&extensions)
        .push_next(&mut features);
    let device = unsafe { instance.create_device(physical, &device_info, None) }
        .map_err(vk_err("vkCreateDevice"))?;
    let dynamic_rendering =
        v13.dynamic_rendering == vk::TRUE || dynamic_rendering_ext.dynamic_rendering == vk::TRUE;
    let queue = unsafe { device.get_device_queue(queue_family, 0) };
    partial.device = Some(device.clone());

    Ok(DeviceSetup {
        device,
        queue,
        queue_family,
        device_name,
        dynamic_rendering,
        memory_properties: unsafe { instance.get_physical_device_memory_properties(physical) },
        max_workgroups_x: props.limits.max_compute_work_group_count[0],
    })
}

/// Converts an entry point name for Vulkan.
fn entry_name(entry: &str) -> Result<CString, VkError> {
    CString::new(entry)
        .map_err(|_| VkError::InvalidArgument(format!("entry point name {entry:?} contains NUL")))
}

/// Puts the operation's messages into a [`VkError::Vulkan`] (other errors are returned as is).
fn with_messages(error: VkError, captured: Vec<String>) -> VkError {
    match error {
        VkError::Vulkan { call, result, .. } => VkError::Vulkan {
            call,
            result,
            messages: captured,
        },
        other => other,
    }
}

/// Result of a pipeline check: success and layer-refused calls both yield the messages.
fn pipeline_outcome(
    result: Result<(), VkError>,
    messages: Vec<String>,
) -> Result<Vec<String>, VkError> {
    match result {
        Ok(()) => Ok(messages),
        Err(VkError::Vulkan {
            result: vk::Result::ERROR_VALIDATION_FAILED_EXT,
            ..
        }) if !messages.is_empty() => Ok(messages),
        Err(e) => Err(with_messages(e, messages)),
    }
}

/// A host-visible, coherent, persistently mapped storage buffer owned by a [`Scratch`].
struct HostBuffer {
    buffer: vk::Buffer,
    /// Bytes bound as the descriptor's range (`VK_WHOLE_SIZE` for an empty request).
    range: vk::DeviceSize,
    ptr: *mut u8,
}

/// Objects created during one [`Validator`] call; all destroyed (in dependency order) on drop.
struct Scratch<'d> {
    device: &'d ash::Device,
    fences: Vec<vk::Fence>,
    command_pools: Vec<vk::CommandPool>,
    descriptor_pools: Vec<vk::DescriptorPool>,
    pipelines: Vec<vk::Pipeline>,
    pipeline_layouts: Vec<vk::PipelineLayout>,
    set_layouts: Vec<vk::DescriptorSetLayout>,
    modules: Vec<vk::ShaderModule>,
    buffers: Vec<vk::Buffer>,
    memories: Vec<vk::DeviceMemory>,
    /// Set when the GPU may still use the objects (fence wait timed out): leak them instead.
    leak: bool,
}

impl Drop for Scratch<'_> {
    fn drop(&mut self) {
        if self.leak {
            return;
        }
        let d = self.device;
        // SAFETY: every submitted command buffer has completed (its fence was waited on), and
        // each handle was created from `d` and is destroyed exactly once.
        unsafe {
            for &f in &self.fences {
                d.destroy_fence(f, None);
            }
            for &p in &self.command_pools {
                d.destroy_command_pool(p, None);
            }
            for &p in &self.descriptor_pools {
                d.destroy_descriptor_pool(p, None);
            }
            for &p in &self.pipelines {
                d.destroy_pipeline(p, None);
            }
            for &l in &self.pipeline_layouts {
                d.destroy_pipeline_layout(l, None);
            }
            for &l in &self.set_layouts {
                d.destroy_descriptor_set_layout(l, None);
            }
            for &m in &self.modules {
                d.destroy_shader_module(m, None);
            }
            for &b in &self.buffers {
                d.destroy_buffer(b, None);
            }
            for &m in &self.memories {
                d.unmap_memory(m);
                d.free_memory(m, None);
            }
        }
    }
}

impl<'d> Scratch<'d> {
    fn new(device: &'d ash::Device) -> Self {
        Scratch {
            device,
            fences: Vec::new(),
            command_pools: Vec::new(),
            descriptor_pools: Vec::new(),
            pipelines: Vec::new(),
            pipeline_layouts: Vec::new(),
            set_layouts: Vec::new(),
            modules: Vec::new(),
            buffers: Vec::new(),
            memories: Vec::new(),
            leak: false,
        }
    }

    fn shader_module(&mut self, spirv: &[u32]) -> Result<vk::ShaderModule, VkError> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        let module = unsafe { self.device.create_shader_module(&info, None) }
            .map_err(vk_err("vkCreateShaderModule"))?;
        self.modules.push(module);
        Ok(module)
    }

    /// One set layout per entry of `sets`, then the pipeline layout over them.
    fn pipeline_layout(
        &mut self,
        sets: &[Vec<DescriptorBinding>],
    ) -> Result<vk::PipelineLayout, VkError> {
        let first = self.set_layouts.len();
        for set in sets {
            let bindings: Vec<vk::DescriptorSetLayoutBinding<'_>> = set
                .iter()
                .map(|b| {
                    vk::DescriptorSetLayoutBinding::default()
                        .binding(b.binding)
                        .descriptor_type(b.kind.to_vk())
                        .descriptor_count(1)
                        .stage_flags(b.stages.to_vk())
                })
                .collect();
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
            let layout = unsafe { self.device.create_descriptor_set_layout(&info, None) }
                .map_err(vk_err("vkCreateDescriptorSetLayout"))?;
            self.set_layouts.push(layout);
        }
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&self.set_layouts[first..]);
        let layout = unsafe { self.device.create_pipeline_layout(&info, None) }
            .map_err(vk_err("vkCreatePipelineLayout"))?;
        self.pipeline_layouts.push(layout);
        Ok(layout)
    }

    fn compute_pipeline(
        &mut self,
        module: vk::ShaderModule,
        entry: &CStr,
        layout: vk::PipelineLayout,
    ) -> Result<vk::Pipeline, VkError> {
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::COMPUTE)
                    .module(module)
                    .name(entry),
            )
            .layout(layout);
        let mut pipeline = vk::Pipeline::null();
        // Called through the raw pointer with a pre-nulled output: when the layer skips the
        // call, ash's wrapper would hand back uninitialised handles.
        let result = unsafe {
            (self.device.fp_v1_0().create_compute_pipelines)(
                self.device.handle(),
                vk::PipelineCache::null(),
                1,
                &info,
                std::ptr::null(),
                &mut pipeline,
            )
        };
        self.finish_pipeline("vkCreateComputePipelines", result, pipeline)
    }

    fn graphics_pipeline(
        &mut self,
        desc: &GraphicsDesc<'_>,
        stages: [(vk::ShaderModule, &CStr); 2],
        layout: vk::PipelineLayout,
    ) -> Result<vk::Pipeline, VkError> {
        let stage_infos = [vk::ShaderStageFlags::VERTEX, vk::ShaderStageFlags::FRAGMENT]
            .into_iter()
            .zip(stages)
            .map(|(stage, (module, name))| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage)
                    .module(module)
                    .name(name)
            })
            .collect::<Vec<_>>();
        let vertex_bindings: Vec<vk::VertexInputBindingDescription> = desc
            .vertex_buffers
            .iter()
            .enumerate()
            .map(|(i, vb)| vk::VertexInputBindingDescription {
                binding: i as u32,
                stride: vb.stride,
                input_rate: if vb.per_instance {
                    vk::VertexInputRate::INSTANCE
                } else {
                    vk::VertexInputRate::VERTEX
                },
            })
            .collect();
        let vertex_attributes: Vec<vk::VertexInputAttributeDescription> = desc
            .vertex_buffers
            .iter()
            .enumerate()
            .flat_map(|(i, vb)| {
                vb.attributes
                    .iter()
                    .map(move |a| vk::VertexInputAttributeDescription {
                        location: a.location,
                        binding: i as u32,
                        format: a.format,
                        offset: a.offset,
                    })
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&vertex_bindings)
            .vertex_attribute_descriptions(&vertex_attributes);
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let mut attachment = vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA);
        if let Some(blend) = desc.blend {
            attachment = attachment
                .blend_enable(true)
                .src_color_blend_factor(blend.color.src_factor)
                .dst_color_blend_factor(blend.color.dst_factor)
                .color_blend_op(blend.color.op)
                .src_alpha_blend_factor(blend.alpha.src_factor)
                .dst_alpha_blend_factor(blend.alpha.dst_factor)
                .alpha_blend_op(blend.alpha.op);
        }
        let attachments = [attachment];
        let color_blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats = [desc.color_format];
        let mut rendering =
            vk::PipelineRenderingCreateInfo::default().color_attachment_formats(&color_formats);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stage_infos)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&rasterization)
            .multisample_state(&multisample)
            .color_blend_state(&color_blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        let mut pipeline = vk::Pipeline::null();
        // See compute_pipeline for why the raw function pointer is used.
        let result = unsafe {
            (self.device.fp_v1_0().create_graphics_pipelines)(
                self.device.handle(),
                vk::PipelineCache::null(),
                1,
                &info,
                std::ptr::null(),
                &mut pipeline,
            )
        };
        self.finish_pipeline("vkCreateGraphicsPipelines", result, pipeline)
    }

    /// Records a created pipeline for destruction and maps the result.
    fn finish_pipeline(
        &mut self,
        call: &'static str,
        result: vk::Result,
        pipeline: vk::Pipeline,
    ) -> Result<vk::Pipeline, VkError> {
        if pipeline != vk::Pipeline::null() {
            self.pipelines.push(pipeline);
        }
        match result {
            vk::Result::SUCCESS if pipeline != vk::Pipeline::null() => Ok(pipeline),
            vk::Result::SUCCESS => Err(vk_err(call)(vk::Result::ERROR_UNKNOWN)),
            other => Err(vk_err(call)(other)),
        }
    }

    /// A zeroed, mapped storage buffer of `len` bytes (at least 4 allocated).
    fn host_buffer(
        &mut self,
        len: usize,
        memory_properties: &vk::PhysicalDeviceMemoryProperties,
    ) -> Result<HostBuffer, VkError> {
        let size = (len.max(4) as vk::DeviceSize).next_multiple_of(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(vk::BufferUsageFlags::STORAGE_BUFFER)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let d = self.device;
        let buffer = unsafe { d.create_buffer(&info, None) }.map_err(vk_err("vkCreateBuffer"))?;
        self.buffers.push(buffer);
        let requirements = unsafe { d.get_buffer_memory_requirements(buffer) };
        let wanted = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let type_index = (0..memory_properties.memory_type_count)
            .find(|&i| {
                requirements.memory_type_bits & (1 << i) != 0
                    && memory_properties.memory_types[i as usize]
                        .property_flags
                        .contains(wanted)
            })
            .ok_or(VkError::NoHostMemory)?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(requirements.size)
            .memory_type_index(type_index);
        let memory =
            unsafe { d.allocate_memory(&alloc, None) }.map_err(vk_err("vkAllocateMemory"))?;
        self.memories.push(memory);
        unsafe { d.bind_buffer_memory(buffer, memory, 0) }.map_err(vk_err("vkBindBufferMemory"))?;
        let ptr = unsafe { d.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
            .map_err(vk_err("vkMapMemory"))? as *mut u8;
        // SAFETY: the mapping covers the whole allocation (>= size bytes).
        unsafe { std::ptr::write_bytes(ptr, 0, size as usize) };
        Ok(HostBuffer {
            buffer,
            range: if len == 0 {
                vk::WHOLE_SIZE
            } else {
                len as vk::DeviceSize
            },
            ptr,
        })
    }

    /// A descriptor set of `layout` with `buffers[i]` as storage buffer at binding `i`.
    fn descriptor_set(
        &mut self,
        layout: vk::DescriptorSetLayout,
        buffers: &[&HostBuffer],
    ) -> Result<vk::DescriptorSet, VkError> {
        let d = self.device;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::STORAGE_BUFFER,
            descriptor_count: buffers.len() as u32,
        }];
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        let pool = unsafe { d.create_descriptor_pool(&pool_info, None) }
            .map_err(vk_err("vkCreateDescriptorPool"))?;
        self.descriptor_pools.push(pool);
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        let set = unsafe { d.allocate_descriptor_sets(&alloc) }
            .map_err(vk_err("vkAllocateDescriptorSets"))?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo {
                    buffer: b.buffer,
                    offset: 0,
                    range: b.range,
                }]
            })
            .collect();
        let writes: Vec<vk::WriteDescriptorSet<'_>> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(i as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        unsafe { d.update_descriptor_sets(&writes, &[]) };
        Ok(set)
    }

    /// A primary command buffer from a new pool of `queue_family`.
    fn command_buffer(&mut self, queue_family: u32) -> Result<vk::CommandBuffer, VkError> {
        let d = self.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .flags(vk::CommandPoolCreateFlags::TRANSIENT)
            .queue_family_index(queue_family);
        let pool = unsafe { d.create_command_pool(&pool_info, None) }
            .map_err(vk_err("vkCreateCommandPool"))?;
        self.command_pools.push(pool);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        Ok(unsafe { d.allocate_command_buffers(&alloc) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?[0])
    }

    /// Submits `command_buffer` to `queue` and waits for it to complete.
    fn submit_and_wait(
        &mut self,
        queue: vk::Queue,
        command_buffer: vk::CommandBuffer,
    ) -> Result<(), VkError> {
        let d = self.device;
        let fence = unsafe { d.create_fence(&vk::FenceCreateInfo::default(), None) }
            .map_err(vk_err("vkCreateFence"))?;
        self.fences.push(fence);
        let command_buffers = [command_buffer];
        let submit = vk::SubmitInfo::default().command_buffers(&command_buffers);
        unsafe { d.queue_submit(queue, &[submit], fence) }.map_err(vk_err("vkQueueSubmit"))?;
        match unsafe { d.wait_for_fences(&[fence], true, FENCE_TIMEOUT_NS) } {
            Ok(()) => Ok(()),
            Err(result) => {
                // The work may still be running: destroying its objects would be invalid.
                self.leak = true;
                Err(vk_err("vkWaitForFences")(result))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_selection() {
        let names = vec![
            "NVIDIA GeForce RTX 4090".to_owned(),
            "llvmpipe (LLVM 15.0.6, 256 bits)".to_owned(),
        ];
        assert_eq!(select_device(&names, None), Some(0));
        assert_eq!(select_device(&names, Some("LLVMpipe")), Some(1));
        assert_eq!(select_device(&names, Some("rtx")), Some(0));
        assert_eq!(select_device(&names, Some("radv")), None);
        assert_eq!(select_device(&[], None), None);
    }

    #[test]
    fn stages_and_kinds_map_to_vulkan() {
        let s = Stages::VERTEX | Stages::FRAGMENT;
        assert_eq!(s, Stages::VERTEX_FRAGMENT);
        assert!(s.contains(Stages::FRAGMENT) && !s.contains(Stages::COMPUTE));
        assert_eq!(
            s.to_vk(),
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT
        );
        assert_eq!(Stages::NONE.to_vk(), vk::ShaderStageFlags::empty());
        assert_eq!(
            DescriptorKind::CombinedImageSampler.to_vk(),
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER
        );
    }

    #[test]
    fn validator_is_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<Validator>();
    }

    #[test]
    fn errors_name_the_install_command() {
        let e = VkError::NoDevice {
            requested: None,
            available: vec![],
        };
        assert!(e.to_string().contains(INSTALL_LAVAPIPE), "{e}");
        assert!(
            VkError::MissingLayer
                .to_string()
                .contains(INSTALL_VALIDATION_LAYER)
        );
    }
}

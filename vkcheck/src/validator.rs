//! The validating instance and device, its message capture and its public checks.

use std::ffi::{CString, c_void};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use ash::vk;

use crate::*;

/// What the debug-utils callback writes into (shared through an `Arc`, passed as `user_data`).
pub(crate) struct MessageSink {
    /// Every WARNING / ERROR message since the last clear, formatted.
    pub(crate) messages: Mutex<Vec<String>>,
    /// Whether ERROR-severity validation messages make the layer skip the call (`VK_TRUE`).
    /// Off during teardown, so that a leak report cannot stop `vkDestroyDevice` itself.
    pub(crate) refuse_errors: AtomicBool,
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
pub(crate) unsafe extern "system" fn debug_callback(
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
pub(crate) fn select_device(names: &[String], requested: Option<&str>) -> Option<usize> {
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
            s.compute_pipeline(module, &entry, layout, vk::PipelineCreateFlags::empty())?;
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
                vk::PipelineCreateFlags::empty(),
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
            let pipeline =
                s.compute_pipeline(module, &entry, layout, vk::PipelineCreateFlags::empty())?;

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
pub(crate) struct DeviceSetup {
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_family: u32,
    pub(crate) device_name: String,
    pub(crate) dynamic_rendering: bool,
    pub(crate) memory_properties: vk::PhysicalDeviceMemoryProperties,
    pub(crate) max_workgroups_x: u32,
}

/// Destroys a half-built Validator's objects when `with_adapter` fails after the instance.
pub(crate) struct Partial<'a> {
    pub(crate) instance: &'a ash::Instance,
    pub(crate) debug_utils: &'a ash::ext::debug_utils::Instance,
    pub(crate) messenger: vk::DebugUtilsMessengerEXT,
    pub(crate) device: Option<ash::Device>,
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
pub(crate) fn create_device(
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
pub(crate) fn entry_name(entry: &str) -> Result<CString, VkError> {
    CString::new(entry)
        .map_err(|_| VkError::InvalidArgument(format!("entry point name {entry:?} contains NUL")))
}

/// Puts the operation's messages into a [`VkError::Vulkan`] (other errors are returned as is).
pub(crate) fn with_messages(error: VkError, captured: Vec<String>) -> VkError {
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
pub(crate) fn pipeline_outcome(
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

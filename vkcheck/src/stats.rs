//! A driver's own compiler statistics: pipelines built with
//! `VK_KHR_pipeline_executable_properties`, returning per executable (one per shader
//! stage the driver compiled) what the driver reports about it — for Mesa's RADV the
//! registers, spills, occupancy, instruction count and ACO's cycle estimates — and,
//! on request, its internal representations (RADV: NIR, ACO IR, disassembly).
//!
//! Unlike [`Validator`](crate::Validator) no layer is enabled: the statistics of a
//! pipeline the layer would refuse are not wanted, and the layer's own checks run
//! elsewhere. Pipelines are described as for the validator.

use std::ffi::{CStr, c_char};
use std::sync::Mutex;

use ash::vk;

use crate::*;

/// One statistic's value, in the format the driver reported it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StatisticValue {
    /// `VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR`.
    Bool(bool),
    /// `VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR`.
    Int(i64),
    /// `VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR`.
    Uint(u64),
    /// `VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR`.
    Float(f64),
}

impl StatisticValue {
    /// The value as a float (a boolean is 0 or 1).
    pub fn as_f64(self) -> f64 {
        match self {
            StatisticValue::Bool(b) => f64::from(u8::from(b)),
            StatisticValue::Int(i) => i as f64,
            StatisticValue::Uint(u) => u as f64,
            StatisticValue::Float(f) => f,
        }
    }
}

/// One statistic of an executable.
#[derive(Clone, Debug, PartialEq)]
pub struct Statistic {
    /// Its name, e.g. RADV's `VGPRs` or `Latency`.
    pub name: String,
    /// The driver's description of it.
    pub description: String,
    /// Its value.
    pub value: StatisticValue,
}

/// One internal representation of an executable (RADV: `NIR Shader(s)`, `ACO IR`,
/// `Assembly`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Representation {
    /// Its name.
    pub name: String,
    /// The driver's description of it.
    pub description: String,
    /// The text, or `None` for a binary representation.
    pub text: Option<String>,
}

/// One executable of a pipeline: a shader (or a merged group of stages) as the
/// driver compiled it.
#[derive(Clone, Debug, PartialEq)]
pub struct Executable {
    /// Its name (RADV: `Compute Shader`, `Vertex Shader`, `Fragment Shader`, ...).
    pub name: String,
    /// The driver's description of it.
    pub description: String,
    /// The stages it runs.
    pub stages: vk::ShaderStageFlags,
    /// Its subgroup (wave) size.
    pub subgroup_size: u32,
    /// Its statistics, in the driver's order.
    pub statistics: Vec<Statistic>,
    /// Its internal representations (empty unless asked for).
    pub representations: Vec<Representation>,
}

impl Executable {
    /// The value of the statistic named `name`.
    pub fn statistic(&self, name: &str) -> Option<StatisticValue> {
        self.statistics
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.value)
    }

    /// The text of the internal representation named `name`.
    pub fn representation(&self, name: &str) -> Option<&str> {
        self.representations
            .iter()
            .find(|r| r.name == name)
            .and_then(|r| r.text.as_deref())
    }
}

/// A device that compiles pipelines and returns their executables' statistics
/// (`VK_KHR_pipeline_executable_properties` with its `pipelineExecutableInfo`
/// feature enabled). Methods take `&self` and are serialised by an internal lock.
pub struct StatsDevice {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    executables: ash::khr::pipeline_executable_properties::Device,
    device_name: String,
    driver: String,
    call_lock: Mutex<()>,
}

impl std::fmt::Debug for StatsDevice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StatsDevice")
            .field("device_name", &self.device_name)
            .finish_non_exhaustive()
    }
}

/// Copies a fixed-size, nul-terminated C string field.
fn fixed_str(chars: &[c_char]) -> String {
    let bytes: Vec<u8> = chars
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

impl StatsDevice {
    /// A device whose name contains `requested` (case-insensitive; `None`: the first
    /// device) that supports `VK_KHR_pipeline_executable_properties`.
    ///
    /// For RADV's null device (no GPU needed) start the process with
    /// `RADV_FORCE_FAMILY=<chip>` and `VK_ICD_FILENAMES` naming RADV's ICD file: the
    /// driver reads both when the instance is created.
    ///
    /// Errors: [`VkError::Loader`] or [`VkError::NoDevice`] with the command that
    /// installs the loader and Mesa's drivers; [`VkError::NoPipelineStatistics`] when
    /// the device lacks the extension or its feature.
    pub fn new(requested: Option<&str>) -> Result<Self, VkError> {
        // SAFETY: loading the system Vulkan loader.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;
        let app_info = vk::ApplicationInfo::default()
            .application_name(c"vkcheck stats")
            .engine_name(c"vkcheck")
            .api_version(vk::API_VERSION_1_3);
        let instance_info = vk::InstanceCreateInfo::default().application_info(&app_info);
        // SAFETY: valid create info without layers or extensions.
        let instance =
            unsafe { entry.create_instance(&instance_info, None) }.map_err(|result| {
                if result == vk::Result::ERROR_INCOMPATIBLE_DRIVER {
                    VkError::NoDevice {
                        requested: requested.map(str::to_owned),
                        available: Vec::new(),
                    }
                } else {
                    vk_err("vkCreateInstance")(result)
                }
            })?;
        match Self::create_device(&instance, requested) {
            Ok((device, device_name, driver)) => {
                let executables =
                    ash::khr::pipeline_executable_properties::Device::new(&instance, &device);
                Ok(StatsDevice {
                    _entry: entry,
                    instance,
                    device,
                    executables,
                    device_name,
                    driver,
                    call_lock: Mutex::new(()),
                })
            }
            Err(e) => {
                // SAFETY: nothing was created from the instance but what failed.
                unsafe { instance.destroy_instance(None) };
                Err(e)
            }
        }
    }

    fn create_device(
        instance: &ash::Instance,
        requested: Option<&str>,
    ) -> Result<(ash::Device, String, String), VkError> {
        let physical_devices = match unsafe { instance.enumerate_physical_devices() } {
            Ok(devices) => devices,
            Err(
                vk::Result::ERROR_INITIALIZATION_FAILED | vk::Result::ERROR_INCOMPATIBLE_DRIVER,
            ) => Vec::new(),
            Err(result) => return Err(vk_err("vkEnumeratePhysicalDevices")(result)),
        };
        let names: Vec<String> = physical_devices
            .iter()
            .map(|&pd| {
                let p = unsafe { instance.get_physical_device_properties(pd) };
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
        let device_name = names[index].clone();
        let mut driver_properties = vk::PhysicalDeviceDriverProperties::default();
        let mut properties =
            vk::PhysicalDeviceProperties2::default().push_next(&mut driver_properties);
        unsafe { instance.get_physical_device_properties2(physical, &mut properties) };
        let driver = format!(
            "{} {}",
            fixed_str(&driver_properties.driver_name),
            fixed_str(&driver_properties.driver_info)
        );
        let extension = ash::khr::pipeline_executable_properties::NAME;
        let has_extension = unsafe { instance.enumerate_device_extension_properties(physical) }
            .unwrap_or_default()
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(extension));
        let supported = has_extension && {
            let mut query = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default();
            let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut query);
            unsafe { instance.get_physical_device_features2(physical, &mut features) };
            query.pipeline_executable_info == vk::TRUE
        };
        if !supported {
            return Err(VkError::NoPipelineStatistics(device_name));
        }
        // Every core feature the device supports (so SPIR-V capabilities are judged
        // against what it can do), and the statistics.
        let mut executable_info =
            vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
                .pipeline_executable_info(true);
        let mut v11 = vk::PhysicalDeviceVulkan11Features::default();
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut v11)
            .push_next(&mut v12)
            .push_next(&mut v13);
        unsafe { instance.get_physical_device_features2(physical, &mut features) };
        let mut features = features.push_next(&mut executable_info);
        let queue_family = unsafe { instance.get_physical_device_queue_family_properties(physical) }
            .iter()
            .position(|q| q.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .ok_or_else(|| VkError::NoQueue(device_name.clone()))?
            as u32;
        let priorities = [1.0f32];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let extensions = [extension.as_ptr()];
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_extension_names(&extensions)
            .push_next(&mut features);
        let device = unsafe { instance.create_device(physical, &device_info, None) }
            .map_err(vk_err("vkCreateDevice"))?;
        Ok((device, device_name, driver))
    }

    /// Name of the chosen device, e.g. `Null hardware (RADV BONAIRE)`.
    pub fn device_name(&self) -> String {
        self.device_name.clone()
    }

    /// The driver's name and version (`VkPhysicalDeviceDriverProperties`), e.g.
    /// `radv Mesa 22.3.6`.
    pub fn driver(&self) -> String {
        self.driver.clone()
    }

    /// Compiles entry point `entry` of `spirv` into a compute pipeline over the
    /// descriptor sets `sets` (as [`Validator::compute_pipeline`](crate::Validator::compute_pipeline))
    /// and returns its executables, with their internal representations when
    /// `representations` is set.
    pub fn compute(
        &self,
        spirv: &[u32],
        entry: &str,
        sets: &[Vec<DescriptorBinding>],
        representations: bool,
    ) -> Result<Vec<Executable>, VkError> {
        let entry = entry_name(entry)?;
        let flags = capture_flags(representations);
        self.with_scratch(|s| {
            let module = s.shader_module(spirv)?;
            let layout = s.pipeline_layout(sets)?;
            let pipeline = s.compute_pipeline(module, &entry, layout, flags)?;
            self.read(pipeline, representations)
        })
    }

    /// Compiles a graphics pipeline (as [`Validator::graphics_pipeline`](crate::Validator::graphics_pipeline)) and returns
    /// its executables (one per stage the driver compiled).
    pub fn graphics(
        &self,
        desc: &GraphicsDesc<'_>,
        representations: bool,
    ) -> Result<Vec<Executable>, VkError> {
        let vertex_entry = entry_name(desc.vertex.entry)?;
        let fragment_entry = entry_name(desc.fragment.entry)?;
        let flags = capture_flags(representations);
        self.with_scratch(|s| {
            let vertex = s.shader_module(desc.vertex.spirv)?;
            let fragment = s.shader_module(desc.fragment.spirv)?;
            let layout = s.pipeline_layout(desc.sets)?;
            let pipeline = s.graphics_pipeline(
                desc,
                [(vertex, &vertex_entry), (fragment, &fragment_entry)],
                layout,
                flags,
            )?;
            self.read(pipeline, representations)
        })
    }

    fn with_scratch<T>(
        &self,
        f: impl FnOnce(&mut Scratch<'_>) -> Result<T, VkError>,
    ) -> Result<T, VkError> {
        let _serialised = lock(&self.call_lock);
        let mut scratch = Scratch::new(&self.device);
        f(&mut scratch)
    }

    /// The executables of `pipeline` with their statistics (and representations).
    fn read(
        &self,
        pipeline: vk::Pipeline,
        representations: bool,
    ) -> Result<Vec<Executable>, VkError> {
        let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
        let properties = unsafe { self.executables.get_pipeline_executable_properties(&info) }
            .map_err(vk_err("vkGetPipelineExecutablePropertiesKHR"))?;
        let mut out = Vec::with_capacity(properties.len());
        for (index, p) in properties.iter().enumerate() {
            let executable_info = vk::PipelineExecutableInfoKHR::default()
                .pipeline(pipeline)
                .executable_index(index as u32);
            let statistics = unsafe {
                self.executables
                    .get_pipeline_executable_statistics(&executable_info)
            }
            .map_err(vk_err("vkGetPipelineExecutableStatisticsKHR"))?
            .iter()
            .map(|s| Statistic {
                name: fixed_str(&s.name),
                description: fixed_str(&s.description),
                // SAFETY: the union member read is the one `format` names.
                value: unsafe {
                    match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => {
                            StatisticValue::Bool(s.value.b32 != 0)
                        }
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => {
                            StatisticValue::Int(s.value.i64)
                        }
                        vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => {
                            StatisticValue::Float(s.value.f64)
                        }
                        _ => StatisticValue::Uint(s.value.u64),
                    }
                },
            })
            .collect();
            let representations = if representations {
                self.representations(&executable_info)?
            } else {
                Vec::new()
            };
            out.push(Executable {
                name: fixed_str(&p.name),
                description: fixed_str(&p.description),
                stages: p.stages,
                subgroup_size: p.subgroup_size,
                statistics,
                representations,
            });
        }
        Ok(out)
    }

    /// The internal representations of one executable, texts included (the two-call
    /// idiom: sizes first, then the data).
    fn representations(
        &self,
        info: &vk::PipelineExecutableInfoKHR<'_>,
    ) -> Result<Vec<Representation>, VkError> {
        let fp = self
            .executables
            .fp()
            .get_pipeline_executable_internal_representations_khr;
        let handle = self.device.handle();
        let call = "vkGetPipelineExecutableInternalRepresentationsKHR";
        let mut count = 0u32;
        unsafe { fp(handle, info, &mut count, std::ptr::null_mut()) }
            .result()
            .map_err(vk_err(call))?;
        let mut sized =
            vec![vk::PipelineExecutableInternalRepresentationKHR::default(); count as usize];
        unsafe { fp(handle, info, &mut count, sized.as_mut_ptr()) }
            .result()
            .map_err(vk_err(call))?;
        sized.truncate(count as usize);
        let mut buffers: Vec<Vec<u8>> = sized.iter().map(|r| vec![0u8; r.data_size]).collect();
        for (r, buffer) in sized.iter_mut().zip(&mut buffers) {
            r.p_data = buffer.as_mut_ptr().cast();
        }
        unsafe { fp(handle, info, &mut count, sized.as_mut_ptr()) }
            .result()
            .map_err(vk_err(call))?;
        Ok(sized
            .iter()
            .zip(buffers)
            .map(|(r, bytes)| Representation {
                name: fixed_str(&r.name),
                description: fixed_str(&r.description),
                text: (r.is_text == vk::TRUE).then(|| {
                    CStr::from_bytes_until_nul(&bytes)
                        .map(|c| c.to_string_lossy().into_owned())
                        .unwrap_or_else(|_| String::from_utf8_lossy(&bytes).into_owned())
                }),
            })
            .collect())
    }
}

/// The pipeline flags that keep statistics (and representations).
fn capture_flags(representations: bool) -> vk::PipelineCreateFlags {
    let mut flags = vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR;
    if representations {
        flags |= vk::PipelineCreateFlags::CAPTURE_INTERNAL_REPRESENTATIONS_KHR;
    }
    flags
}

impl Drop for StatsDevice {
    fn drop(&mut self) {
        // SAFETY: every object created from the device was destroyed by its Scratch,
        // and no work was ever submitted (RADV's null device crashes in
        // vkDeviceWaitIdle once a graphics pipeline exists, so it is not called).
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

//! Short-lived Vulkan objects of one call, destroyed when the call ends.

use std::ffi::CStr;

use ash::vk;

use crate::*;

/// A host-visible, coherent, persistently mapped storage buffer owned by a [`Scratch`].
pub(crate) struct HostBuffer {
    pub(crate) buffer: vk::Buffer,
    /// Bytes bound as the descriptor's range (`VK_WHOLE_SIZE` for an empty request).
    pub(crate) range: vk::DeviceSize,
    pub(crate) ptr: *mut u8,
}

/// Objects created during one [`Validator`] call; all destroyed (in dependency order) on drop.
pub(crate) struct Scratch<'d> {
    pub(crate) device: &'d ash::Device,
    pub(crate) fences: Vec<vk::Fence>,
    pub(crate) command_pools: Vec<vk::CommandPool>,
    pub(crate) descriptor_pools: Vec<vk::DescriptorPool>,
    pub(crate) pipelines: Vec<vk::Pipeline>,
    pub(crate) pipeline_layouts: Vec<vk::PipelineLayout>,
    pub(crate) set_layouts: Vec<vk::DescriptorSetLayout>,
    pub(crate) modules: Vec<vk::ShaderModule>,
    pub(crate) buffers: Vec<vk::Buffer>,
    pub(crate) memories: Vec<vk::DeviceMemory>,
    /// Set when the GPU may still use the objects (fence wait timed out): leak them instead.
    pub(crate) leak: bool,
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
    pub(crate) fn new(device: &'d ash::Device) -> Self {
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

    pub(crate) fn shader_module(&mut self, spirv: &[u32]) -> Result<vk::ShaderModule, VkError> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        let module = unsafe { self.device.create_shader_module(&info, None) }
            .map_err(vk_err("vkCreateShaderModule"))?;
        self.modules.push(module);
        Ok(module)
    }

    /// One set layout per entry of `sets`, then the pipeline layout over them.
    pub(crate) fn pipeline_layout(
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

    pub(crate) fn compute_pipeline(
        &mut self,
        module: vk::ShaderModule,
        entry: &CStr,
        layout: vk::PipelineLayout,
        flags: vk::PipelineCreateFlags,
    ) -> Result<vk::Pipeline, VkError> {
        let info = vk::ComputePipelineCreateInfo::default()
            .flags(flags)
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

    pub(crate) fn graphics_pipeline(
        &mut self,
        desc: &GraphicsDesc<'_>,
        stages: [(vk::ShaderModule, &CStr); 2],
        layout: vk::PipelineLayout,
        flags: vk::PipelineCreateFlags,
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
            .flags(flags)
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
    pub(crate) fn finish_pipeline(
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
    pub(crate) fn host_buffer(
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
    pub(crate) fn descriptor_set(
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
    pub(crate) fn command_buffer(
        &mut self,
        queue_family: u32,
    ) -> Result<vk::CommandBuffer, VkError> {
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
    pub(crate) fn submit_and_wait(
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

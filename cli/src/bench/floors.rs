//! The floors the fog passes are compared with (a plain write and a plain copy of the
//! volume, a fullscreen blit; their shaders are `volfog_cost::floor`'s) and the apply
//! pass cut into its stages.

use super::*;

/// A plain pass over a volume: the floor a fog pass is compared with.
pub(super) struct VolumePass {
    pub(super) label: &'static str,
    pub(super) pipeline: wgpu::ComputePipeline,
    pub(super) group: wgpu::BindGroup,
    pub(super) workgroups: [u32; 3],
}

fn volume_texture(gpu: &Gpu, label: &str, size: wgpu::Extent3d) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: volfog::pipeline::VOLUME_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING,
        view_formats: &[],
    })
}

impl VolumePass {
    fn new(
        gpu: &Gpu,
        label: &'static str,
        source: &'static str,
        path: &'static str,
        views: &[&wgpu::TextureView],
        workgroups: [u32; 3],
    ) -> Result<Self, BenchError> {
        let module = raymarch::shader_module(&gpu.device, source, path, &[])?;
        let pipeline = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: None,
                module: &module,
                entry_point: Some(label),
                compilation_options: Default::default(),
                cache: None,
            });
        let entries: Vec<wgpu::BindGroupEntry> = views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: wgpu::BindingResource::TextureView(v),
            })
            .collect();
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(Self {
            label,
            pipeline,
            group,
            workgroups,
        })
    }

    /// The plain copy of `source` into a volume of its size, with the scan's access
    /// pattern (the scan's bandwidth floor).
    pub(super) fn copy(gpu: &Gpu, source: &wgpu::Texture) -> Result<Self, BenchError> {
        let s = source.size();
        let destination = volume_texture(gpu, "bench copy destination", s);
        Self::new(
            gpu,
            "copy_volume",
            volfog_cost::floor::COPY.source,
            volfog_cost::floor::COPY.path,
            &[
                &source.create_view(&Default::default()),
                &destination.create_view(&Default::default()),
            ],
            [s.width.div_ceil(8), s.height.div_ceil(8), 1],
        )
    }

    /// A constant written to every texel of a volume of `size`, with inject's
    /// dispatch (the inject's floor).
    pub(super) fn write(gpu: &Gpu, size: wgpu::Extent3d) -> Result<Self, BenchError> {
        let destination = volume_texture(gpu, "bench write destination", size);
        Self::new(
            gpu,
            "write_volume",
            volfog_cost::floor::WRITE.source,
            volfog_cost::floor::WRITE.path,
            &[&destination.create_view(&Default::default())],
            [
                size.width.div_ceil(4),
                size.height.div_ceil(4),
                size.depth_or_array_layers.div_ceil(4),
            ],
        )
    }

    pub(super) fn encode(&self, encoder: &mut wgpu::CommandEncoder, timer: &Timer, slot: u32) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: timer.compute(slot),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        let [x, y, z] = self.workgroups;
        pass.dispatch_workgroups(x, y, z);
    }
}

/// The plain fullscreen blit (floor of the apply pass).
pub(super) struct BlitPass {
    pub(super) pipeline: wgpu::RenderPipeline,
    pub(super) group: wgpu::BindGroup,
    pub(super) target: wgpu::TextureView,
}

impl BlitPass {
    pub(super) fn new(
        gpu: &Gpu,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Result<Self, BenchError> {
        let module = raymarch::shader_module(
            &gpu.device,
            volfog_cost::floor::BLIT.source,
            volfog_cost::floor::BLIT.path,
            &[],
        )?;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("bench blit"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                }],
            });
        let pipeline = raymarch::fullscreen_pipeline(
            &gpu.device,
            "bench blit",
            &module,
            ("blit_vs", "blit_fs"),
            &layout,
            wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            },
        );
        let source = texture_2d(
            &gpu.device,
            "bench blit source",
            size,
            format,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let target = texture_2d(
            &gpu.device,
            "bench blit target",
            size,
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench blit"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &source.create_view(&Default::default()),
                ),
            }],
        });
        Ok(Self {
            pipeline,
            group,
            target: target.create_view(&Default::default()),
        })
    }

    pub(super) fn encode(&self, encoder: &mut wgpu::CommandEncoder, timer: &Timer, slot: u32) {
        let mut pass =
            raymarch::fullscreen_pass(encoder, "bench blit", &self.target, timer.render(slot));
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The stages of the apply pass timed apart (`apply_parts.wgsl`): the depth texel
/// alone, with its view position, with the volume look-up (no tail), and the whole
/// apply with its tail behind a branch no pixel takes.
pub(super) struct ApplyParts {
    pub(super) pipelines: [wgpu::RenderPipeline; APPLY_PARTS.len()],
    pub(super) depth_group: wgpu::BindGroup,
}

/// The defines of the apply parts, in series order.
pub(super) const APPLY_PARTS: [&str; 4] = [
    "APPLY_PART_DEPTH",
    "APPLY_PART_UNPROJECT",
    "APPLY_PART_LOOKUP",
    "APPLY_PART_UNTAKEN",
];

impl ApplyParts {
    /// The parts over `screen`'s fog group and depth.
    pub(super) fn new(gpu: &Gpu, screen: &Screen, config: &FogConfig) -> Result<Self, BenchError> {
        let device = &gpu.device;
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bench apply parts depth"),
            entries: &volfog::pipeline::apply::depth_layout_entries(),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("bench apply parts"),
            bind_group_layouts: &[
                Some(screen.fog.fog_bind_group_layout()),
                Some(&depth_layout),
            ],
            immediate_size: 0,
        });
        let filtering: Vec<String> = config.apply_filtering.defines();
        let mut pipelines = Vec::new();
        for part in APPLY_PARTS {
            let mut defs = vec![(part, naga_oil::compose::ShaderDefValue::Bool(true))];
            defs.extend(
                filtering
                    .iter()
                    .map(|d| (d.as_str(), naga_oil::compose::ShaderDefValue::Bool(true))),
            );
            let module = raymarch::shader_module(
                device,
                include_str!("apply_parts.wgsl"),
                "cli/src/bench/apply_parts.wgsl",
                &defs,
            )?;
            pipelines.push(
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(part),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("parts_vs"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("parts_fs"),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: COLOR_FORMAT,
                            blend: Some(volfog::pipeline::apply::FOG_BLEND),
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    primitive: Default::default(),
                    depth_stencil: None,
                    multisample: Default::default(),
                    multiview_mask: None,
                    cache: None,
                }),
            );
        }
        let depth_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench apply parts depth"),
            layout: &depth_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&screen.depth),
            }],
        });
        Ok(Self {
            pipelines: pipelines
                .try_into()
                .unwrap_or_else(|_| unreachable!("one pipeline per part")),
            depth_group,
        })
    }

    /// Records part `part` over `screen`'s colour target, timed in `slot`.
    pub(super) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        screen: &Screen,
        part: usize,
        timer: &Timer,
        slot: u32,
    ) {
        let mut pass = raymarch::fullscreen_pass(
            encoder,
            "bench apply part",
            &screen.color,
            timer.render(slot),
        );
        pass.set_pipeline(&self.pipelines[part]);
        pass.set_bind_group(0, screen.fog.fog_bind_group(), &[]);
        pass.set_bind_group(1, &self.depth_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

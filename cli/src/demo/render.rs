//! The demo's own passes around `VolumetricFog`: cascaded shadow maps, the lit opaque
//! pass and sky, the semi-transparent pass (forward snippet), the tonemap, GPU
//! timestamps of these passes, and readbacks.

use std::borrow::Cow;
use std::collections::HashMap;

use encase::ShaderType;
use glam::{Mat4, Vec3, Vec4};
use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog::pipeline::VolumetricFog;
use volfog::uniforms::{self, FogLight, ShadowCascades};
use volfog_testkit::gpu::texture_2d;
use wgpu::util::DeviceExt;

use super::scene::{Mesh, Scene, Vertex};

/// The HDR colour format (the fog is applied onto it).
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The scene depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The display format.
pub const LDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

const SCENE_WGSL: &str = include_str!("scene.wgsl");
const SHADOW_WGSL: &str = include_str!("shadow.wgsl");
const TONEMAP_WGSL: &str = include_str!("tonemap.wgsl");

/// The `Scene` uniform of `scene.wgsl`.
#[derive(Debug, Clone, Copy, ShaderType)]
pub struct SceneUniform {
    pub clip_from_world: Mat4,
    pub view_from_world: Mat4,
    pub world_from_clip: Mat4,
    pub shadow_texel: Vec4,
    pub camera_position: Vec3,
    pub surface_scale: f32,
    pub sun_direction: Vec3,
    pub light_count: u32,
    pub sun_color: Vec3,
    pub sun_disk: f32,
    pub sky_zenith: Vec3,
    pub sky_horizon: Vec3,
    pub glass_alpha: f32,
    pub ambient_ground: Vec3,
    pub shadow_bias: f32,
    /// The pool's water (`volfog::water`).
    pub water: volfog::uniforms::Water,
    /// The medium as analytic height fog, for what a camera under water sees above
    /// the surface.
    pub air: volfog::uniforms::HeightFog,
    /// The pool's footprint (x, z) from `pool_min` to `pool_max`; `pool_min.w` 1 turns
    /// the water on, 0 renders the pool dry (the probe's reference).
    pub pool_min: Vec4,
    pub pool_max: Vec4,
    /// The sky's atmosphere (`volfog::sky`); the sky texture is solved for it.
    pub atmosphere: volfog::uniforms::SkyAtmosphere,
}

/// The demo's own passes, timed with GPU timestamps when available.
pub const DEMO_PASSES: [&str; 4] = ["shadow maps", "opaque + sky", "transparent", "tonemap"];

struct Geometry {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

impl Geometry {
    fn new(device: &wgpu::Device, label: &str, mesh: &Mesh) -> Self {
        Self {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&mesh.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            count: mesh.indices.len() as u32,
        }
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.count, 0, 0..1);
    }
}

/// Render targets, pipelines and buffers of the demo.
pub struct Renderer {
    pub width: u32,
    pub height: u32,
    pub hdr: wgpu::Texture,
    hdr_view: wgpu::TextureView,
    pub depth: wgpu::Texture,
    depth_view: wgpu::TextureView,
    pub ldr: wgpu::Texture,
    ldr_view: wgpu::TextureView,
    shadow_map: wgpu::Texture,
    shadow_layers: Vec<wgpu::TextureView>,
    opaque: Geometry,
    emissive: Geometry,
    glass: Geometry,
    water_surface: Geometry,
    scene_buffer: wgpu::Buffer,
    cascades_buffer: wgpu::Buffer,
    cascade_matrices: Vec<wgpu::Buffer>,
    exposure_buffer: wgpu::Buffer,
    scene_group: wgpu::BindGroup,
    cascade_groups: Vec<wgpu::BindGroup>,
    tonemap_group: wgpu::BindGroup,
    shadow_pipeline: wgpu::RenderPipeline,
    opaque_pipeline: wgpu::RenderPipeline,
    sky_pipeline: wgpu::RenderPipeline,
    transparent_pipeline: wgpu::RenderPipeline,
    water_pipeline: wgpu::RenderPipeline,
    tonemap_pipeline: wgpu::RenderPipeline,
    timestamps: Option<volfog::pipeline::TimestampPairs>,
}

fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Composes a demo shader with the volfog modules (the fog group at index 1).
fn compose(source: &str, file_path: &str) -> Result<naga::Module, String> {
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).map_err(|e| e.to_string())?;
    let shader_defs = HashMap::from([("VOLFOG_FOG_GROUP".to_string(), ShaderDefValue::UInt(1))]);
    composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path,
            shader_defs,
            ..Default::default()
        })
        .map_err(|e| e.emit_to_string(&composer))
}

impl Renderer {
    /// Creates targets, pipelines and buffers for a scene and a fog pipeline.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        scene: &Scene,
        fog: &VolumetricFog,
        sky: &volfog::pipeline::sky::SkyLight,
        timestamps: bool,
    ) -> Result<Self, String> {
        let config = fog.config();
        let attachment =
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let copy = wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST;
        let hdr = texture_2d(
            device,
            "demo hdr",
            (width, height),
            HDR_FORMAT,
            attachment | copy,
        );
        let depth = texture_2d(
            device,
            "demo depth",
            (width, height),
            DEPTH_FORMAT,
            attachment | wgpu::TextureUsages::COPY_SRC,
        );
        let ldr = texture_2d(
            device,
            "demo ldr",
            (width, height),
            LDR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let shadow_size = config.esm_resolution * 4;
        let shadow_map = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("demo shadow map"),
            size: wgpu::Extent3d {
                width: shadow_size,
                height: shadow_size,
                depth_or_array_layers: config.cascades,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: attachment,
            view_formats: &[],
        });
        let shadow_layers = (0..config.cascades)
            .map(|layer| {
                shadow_map.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("demo shadow layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let shadow_array = shadow_map.create_view(&wgpu::TextureViewDescriptor {
            label: Some("demo shadow array"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });

        let uniform = |label: &str, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let scene_buffer = uniform(
            "demo scene",
            uniforms::to_uniform_bytes(&SceneUniform::zeroed()).len(),
        );
        let cascades_buffer = uniform(
            "demo cascades",
            uniforms::to_uniform_bytes(&ShadowCascades::default()).len(),
        );
        let cascade_matrices: Vec<wgpu::Buffer> = (0..config.cascades)
            .map(|_| uniform("demo cascade matrix", 64))
            .collect();
        let exposure_buffer = uniform("demo exposure", 16);
        let lights_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("demo lights"),
            contents: &uniforms::to_storage_bytes::<FogLight>(&scene.lights),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("demo shadow comparison"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });

        let fragment = wgpu::ShaderStages::FRAGMENT;
        let vertex_fragment = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("demo scene"),
            entries: &[
                uniform_entry(0, vertex_fragment),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: fragment,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                uniform_entry(2, fragment),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: fragment,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: fragment,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("demo scene"),
            layout: &scene_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: scene_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: lights_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: cascades_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&shadow_array),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::TextureView(sky.view()),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::Sampler(sky.sampler()),
                },
            ],
        });
        let cascade_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("demo cascade"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX)],
        });
        let cascade_groups = cascade_matrices
            .iter()
            .map(|b| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("demo cascade"),
                    layout: &cascade_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: b.as_entire_binding(),
                    }],
                })
            })
            .collect();
        let hdr_view = hdr.create_view(&Default::default());
        let tonemap_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("demo tonemap"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                uniform_entry(1, fragment),
            ],
        });
        let tonemap_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("demo tonemap"),
            layout: &tonemap_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&hdr_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: exposure_buffer.as_entire_binding(),
                },
            ],
        });

        let scene_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo scene"),
            source: wgpu::ShaderSource::Naga(Cow::Owned(compose(
                SCENE_WGSL,
                "cli/src/demo/scene.wgsl",
            )?)),
        });
        let shadow_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo shadow"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(SHADOW_WGSL)),
        });
        let tonemap_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo tonemap"),
            source: wgpu::ShaderSource::Naga(Cow::Owned(compose(
                TONEMAP_WGSL,
                "cli/src/demo/tonemap.wgsl",
            )?)),
        });
        let layout = |label: &str, groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> =
                groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let scene_pipeline_layout = layout("demo scene", &[&scene_layout]);
        let transparent_layout = layout(
            "demo transparent",
            &[&scene_layout, fog.fog_bind_group_layout()],
        );
        let depth_state = |write: bool, compare| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            })
        };
        let color = |format, blend| {
            [Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })]
        };
        let back_culled = wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        };
        let vertex_layout = [Some(Vertex::layout())];
        let render_pipeline =
            |label: &str,
             layout: &wgpu::PipelineLayout,
             module: &wgpu::ShaderModule,
             vs: &str,
             buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
             fs: Option<(&str, &[Option<wgpu::ColorTargetState>])>,
             primitive: wgpu::PrimitiveState,
             depth: Option<wgpu::DepthStencilState>| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(layout),
                    vertex: wgpu::VertexState {
                        module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive,
                    depth_stencil: depth,
                    multisample: Default::default(),
                    fragment: fs.map(|(entry, targets)| wgpu::FragmentState {
                        module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        let shadow_pipeline = render_pipeline(
            "demo shadow",
            &layout("demo shadow", &[&cascade_layout]),
            &shadow_module,
            "shadow_vs",
            &vertex_layout,
            None,
            wgpu::PrimitiveState::default(),
            depth_state(true, wgpu::CompareFunction::Less),
        );
        let opaque_pipeline = render_pipeline(
            "demo opaque",
            &scene_pipeline_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("opaque_fs", &color(HDR_FORMAT, None))),
            back_culled,
            depth_state(true, wgpu::CompareFunction::Less),
        );
        let sky_pipeline = render_pipeline(
            "demo sky",
            &scene_pipeline_layout,
            &scene_module,
            "sky_vs",
            &[],
            Some(("sky_fs", &color(HDR_FORMAT, None))),
            wgpu::PrimitiveState::default(),
            depth_state(false, wgpu::CompareFunction::LessEqual),
        );
        // Colour: alpha blending; alpha: the destination's (the probe's sun visibility).
        let glass_blend = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::SrcAlpha,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let transparent_pipeline = render_pipeline(
            "demo transparent",
            &transparent_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("transparent_fs", &color(HDR_FORMAT, Some(glass_blend)))),
            back_culled,
            depth_state(false, wgpu::CompareFunction::Less),
        );
        // The water surface: seen from above and from below (no culling).
        let water_pipeline = render_pipeline(
            "demo water",
            &transparent_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("water_fs", &color(HDR_FORMAT, Some(glass_blend)))),
            wgpu::PrimitiveState::default(),
            depth_state(false, wgpu::CompareFunction::Less),
        );
        let tonemap_pipeline = render_pipeline(
            "demo tonemap",
            &layout("demo tonemap", &[&tonemap_layout]),
            &tonemap_module,
            "tonemap_vs",
            &[],
            Some(("tonemap_fs", &color(LDR_FORMAT, None))),
            wgpu::PrimitiveState::default(),
            None,
        );

        let timestamps = timestamps.then(|| {
            volfog::pipeline::TimestampPairs::new(
                device,
                "demo timestamps",
                DEMO_PASSES.len() as u32,
            )
        });

        Ok(Self {
            width,
            height,
            hdr_view,
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor {
                aspect: wgpu::TextureAspect::DepthOnly,
                ..Default::default()
            }),
            ldr_view: ldr.create_view(&Default::default()),
            hdr,
            depth,
            ldr,
            shadow_map,
            shadow_layers,
            opaque: Geometry::new(device, "demo opaque", &scene.opaque),
            emissive: Geometry::new(device, "demo emissive", &scene.emissive),
            glass: Geometry::new(device, "demo glass", &scene.glass),
            water_surface: Geometry::new(device, "demo water", &scene.water_surface),
            scene_buffer,
            cascades_buffer,
            cascade_matrices,
            exposure_buffer,
            scene_group,
            cascade_groups,
            tonemap_group,
            shadow_pipeline,
            opaque_pipeline,
            sky_pipeline,
            transparent_pipeline,
            water_pipeline,
            tonemap_pipeline,
            timestamps,
        })
    }

    /// The cascaded shadow map (Depth32Float, a layer per cascade), as the fog's ESM
    /// passes read it.
    pub fn shadow_map(&self) -> &wgpu::Texture {
        &self.shadow_map
    }

    /// The HDR colour target (the fog's apply target).
    pub fn hdr_view(&self) -> &wgpu::TextureView {
        &self.hdr_view
    }

    /// The scene depth (depth aspect), as the fog's apply pass reads it.
    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.depth_view
    }

    /// Uploads the per-frame uniforms.
    pub fn upload(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneUniform,
        cascades: &ShadowCascades,
        exposure: f32,
    ) {
        queue.write_buffer(&self.scene_buffer, 0, &uniforms::to_uniform_bytes(scene));
        queue.write_buffer(
            &self.cascades_buffer,
            0,
            &uniforms::to_uniform_bytes(cascades),
        );
        for (buffer, m) in self.cascade_matrices.iter().zip(cascades.light_from_world) {
            queue.write_buffer(buffer, 0, bytemuck::cast_slice(&m.to_cols_array()));
        }
        queue.write_buffer(
            &self.exposure_buffer,
            0,
            bytemuck::cast_slice(&[exposure, 0.0, 0.0, 0.0]),
        );
    }

    fn render_timestamps(
        &self,
        pass: u32,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        if !begin && !end {
            return None;
        }
        self.timestamps.as_ref().map(|t| t.render(pass, begin, end))
    }

    /// Renders every cascade layer of the shadow map (opaque geometry only).
    pub fn encode_shadows(&self, encoder: &mut wgpu::CommandEncoder) {
        let last = self.shadow_layers.len() - 1;
        for (i, view) in self.shadow_layers.iter().enumerate() {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("demo shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.render_timestamps(0, i == 0, i == last),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &self.cascade_groups[i], &[]);
            self.opaque.draw(&mut pass);
        }
    }

    /// The lit opaque pass and the sky: clears colour and depth.
    pub fn encode_opaque(&self, encoder: &mut wgpu::CommandEncoder, timed: bool) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo opaque"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: if timed {
                self.render_timestamps(1, true, true)
            } else {
                None
            },
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.opaque_pipeline);
        pass.set_bind_group(0, &self.scene_group, &[]);
        self.opaque.draw(&mut pass);
        self.emissive.draw(&mut pass);
        pass.set_pipeline(&self.sky_pipeline);
        pass.draw(0..3, 0..1);
    }

    /// The semi-transparent sphere and the pool's water surface, fogged through the
    /// forward snippet, blended over the fogged opaque image.
    pub fn encode_transparent(&self, encoder: &mut wgpu::CommandEncoder, fog: &VolumetricFog) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo transparent"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: self.render_timestamps(2, true, true),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.transparent_pipeline);
        pass.set_bind_group(0, &self.scene_group, &[]);
        pass.set_bind_group(1, fog.fog_bind_group(), &[]);
        self.glass.draw(&mut pass);
        pass.set_pipeline(&self.water_pipeline);
        self.water_surface.draw(&mut pass);
    }

    /// HDR -> sRGB display colour.
    pub fn encode_tonemap(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo tonemap"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.ldr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: self.render_timestamps(3, true, true),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.tonemap_pipeline);
        pass.set_bind_group(0, &self.tonemap_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Copies the HDR target into `dst` (same size and format).
    pub fn copy_hdr(&self, encoder: &mut wgpu::CommandEncoder, dst: &wgpu::Texture) {
        encoder.copy_texture_to_texture(
            self.hdr.as_image_copy(),
            dst.as_image_copy(),
            self.hdr.size(),
        );
    }

    /// A texture like the HDR target, to keep copies of it.
    pub fn hdr_like(&self, device: &wgpu::Device, label: &str) -> wgpu::Texture {
        texture_2d(
            device,
            label,
            (self.width, self.height),
            HDR_FORMAT,
            wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
        )
    }

    /// Resolves this frame's timestamps; call before submitting.
    pub fn resolve_timestamps(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(t) = &self.timestamps {
            t.resolve(encoder);
        }
    }

    /// GPU milliseconds of the demo passes of the last submitted frame (blocks).
    pub fn read_timings(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<[f64; DEMO_PASSES.len()]> {
        let ms = self.timestamps.as_ref()?.read_ms(device, queue).ok()?;
        Some(std::array::from_fn(|i| ms[i]))
    }
}

impl SceneUniform {
    fn zeroed() -> Self {
        Self {
            clip_from_world: Mat4::IDENTITY,
            view_from_world: Mat4::IDENTITY,
            world_from_clip: Mat4::IDENTITY,
            shadow_texel: Vec4::ZERO,
            camera_position: Vec3::ZERO,
            surface_scale: 1.0,
            sun_direction: Vec3::Y,
            light_count: 0,
            sun_color: Vec3::ZERO,
            sun_disk: 0.0,
            sky_zenith: Vec3::ZERO,
            sky_horizon: Vec3::ZERO,
            glass_alpha: 0.0,
            ambient_ground: Vec3::ZERO,
            shadow_bias: 0.0,
            water: volfog::uniforms::Water::default(),
            air: volfog::uniforms::HeightFog::default(),
            pool_min: Vec4::ZERO,
            pool_max: Vec4::ZERO,
            atmosphere: volfog::uniforms::SkyAtmosphere::default(),
        }
    }
}

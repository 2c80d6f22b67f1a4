//! The web demo's frame, in wgpu alone (no windowing, no platform calls): the sun's
//! shadow map, the sky (`SkyLight`: Nishita single scattering solved into its table and
//! drawn per pixel), the lit scene with its depth, `VolumetricFog` (shadowed sun,
//! lights, local volumes, depth culling) and its apply into the lit image. The page runs it on
//! the browser's WebGPU, the browser test natively on lavapipe.

use std::borrow::Cow;

use glam::{Mat4, Vec4};
use volfog::limits::InvalidValue;
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::sky::{SkyError, SkyLight};
use volfog::pipeline::{FogConfig, FogError, VolumetricFog};
use volfog::uniforms::{FogLight, FrustumRays, LocalVolume, SkyAtmosphere};
use wgpu::util::DeviceExt;

use crate::scene::{self, Params, Vertex};

/// Format of the lit and fogged image.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Largest image side (WebGPU's default 2D texture limit).
const MAX_SIDE: u32 = 8192;

/// A frame could not be built or recorded.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A value is out of range (the image size, an input of the frame).
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// The fog refused its configuration, the device or a frame.
    #[error(transparent)]
    Fog(#[from] FogError),
    /// The sky's passes could not be built.
    #[error(transparent)]
    Sky(#[from] SkyError),
}

/// The scene uniform (`Scene` in `scene.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SceneUniform {
    clip_from_world: Mat4,
    light_from_world: Mat4,
    sun_direction: Vec4,
    sun_color: Vec4,
    sky: Vec4,
    ground: Vec4,
    light_positions: [Vec4; 2],
    light_colors: [Vec4; 2],
    spot: Vec4,
}

/// The scene, its fog and the images they draw, for one image size.
pub struct Renderer {
    /// Image size (pixels).
    pub size: (u32, u32),
    /// The fog.
    pub fog: VolumetricFog,
    /// The sky behind the scene.
    pub sky: SkyLight,
    /// The lit image once fogged (`COLOR_FORMAT`, copyable).
    pub color: wgpu::Texture,
    config: FogConfig,
    apply: ApplyPipeline,
    depth_group: wgpu::BindGroup,
    depth_view: wgpu::TextureView,
    shadow_layer: wgpu::TextureView,
    scene_buffer: wgpu::Buffer,
    scene_group: wgpu::BindGroup,
    shadow_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    shadow_pipeline: wgpu::RenderPipeline,
    lit_pipeline: wgpu::RenderPipeline,
    lights: [FogLight; 2],
    volumes: [LocalVolume; 2],
    animated: bool,
    frames: u32,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: size.2,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
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

impl Renderer {
    /// The scene and its fog at `size` pixels (1..=8192 per side); `animated` as in
    /// [`scene::config`].
    pub fn new(
        device: &wgpu::Device,
        size: (u32, u32),
        animated: bool,
    ) -> Result<Self, RenderError> {
        volfog::limits::check(
            (1..=MAX_SIDE).contains(&size.0) && (1..=MAX_SIDE).contains(&size.1),
            "Renderer.size",
            size,
            "1..=8192 pixels per side",
        )?;
        let config = scene::config(animated);
        let mut fog = VolumetricFog::new(device, &config)?;
        let apply = fog.create_apply(device, COLOR_FORMAT)?;
        let sky = SkyLight::new(device, COLOR_FORMAT)?;
        let attachment =
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let shadow_side = config.esm_resolution * 4;
        let shadow_map = texture(
            device,
            "web shadow map",
            (shadow_side, shadow_side, config.cascades),
            DEPTH_FORMAT,
            attachment,
        );
        fog.set_shadow_map(device, &shadow_map)?;
        let depth = texture(
            device,
            "web depth",
            (size.0, size.1, 1),
            DEPTH_FORMAT,
            attachment,
        );
        fog.set_scene_depth(device, &depth, 0)?;
        let color = texture(
            device,
            "web colour",
            (size.0, size.1, 1),
            COLOR_FORMAT,
            attachment | wgpu::TextureUsages::COPY_SRC,
        );
        let depth_view = depth.create_view(&Default::default());
        let depth_group = apply.depth_bind_group(device, &depth_view);
        let shadow_layer = shadow_map.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: 0,
            array_layer_count: Some(1),
            ..Default::default()
        });

        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("web scene"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT)],
        });
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("web shadow lookup"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        let scene_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("web scene"),
            size: std::mem::size_of::<SceneUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("web scene"),
            layout: &scene_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: scene_buffer.as_entire_binding(),
            }],
        });
        let comparison = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("web shadow comparison"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let shadow_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("web shadow lookup"),
            layout: &shadow_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&shadow_map.create_view(
                        &wgpu::TextureViewDescriptor {
                            dimension: Some(wgpu::TextureViewDimension::D2Array),
                            ..Default::default()
                        },
                    )),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&comparison),
                },
            ],
        });

        let mesh = scene::mesh(&scene::blocks());
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("web scene mesh"),
            contents: bytemuck::cast_slice(&mesh),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("web scene"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(include_str!("scene.wgsl"))),
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3];
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attributes,
        };
        let depth_state = wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let primitive = wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        };
        let shadow_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("web shadow"),
            layout: Some(
                &device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("web shadow"),
                    bind_group_layouts: &[Some(&scene_layout)],
                    immediate_size: 0,
                }),
            ),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("shadow_vertex"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout.clone())],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..primitive
            },
            depth_stencil: Some(depth_state.clone()),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let lit_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("web lit"),
            layout: Some(
                &device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("web lit"),
                    bind_group_layouts: &[Some(&scene_layout), Some(&shadow_layout)],
                    immediate_size: 0,
                }),
            ),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("lit_vertex"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout)],
            },
            primitive,
            depth_stencil: Some(depth_state),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("lit_fragment"),
                compilation_options: Default::default(),
                targets: &[Some(COLOR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Ok(Self {
            size,
            fog,
            sky,
            color,
            config,
            apply,
            depth_group,
            depth_view,
            shadow_layer,
            scene_buffer,
            scene_group,
            shadow_group,
            vertices,
            vertex_count: mesh.len() as u32,
            shadow_pipeline,
            lit_pipeline,
            lights: scene::lights(),
            volumes: scene::local_volumes(),
            animated,
            frames: 0,
        })
    }

    /// Records one frame for `params` (clamped to the sliders' ranges): shadow map,
    /// sky, lit image, fog, fog applied to [`Renderer::color`].
    pub fn frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        params: &Params,
    ) -> Result<wgpu::CommandBuffer, RenderError> {
        let params = params.clamped();
        let inputs = scene::frame_inputs(
            &self.config,
            &params,
            self.size,
            &self.lights,
            &self.volumes,
        );
        let sun = inputs.sun;
        let [point, spot] = self.lights;
        let uniform = SceneUniform {
            clip_from_world: inputs.clip_from_view * inputs.view_from_world,
            light_from_world: inputs.cascades.light_from_world[0],
            sun_direction: sun.direction.extend(0.0),
            sun_color: sun.color.extend(0.0),
            sky: scene::SKY.extend(0.0),
            ground: scene::GROUND.extend(0.0),
            light_positions: [
                point.position.extend(point.range),
                spot.position.extend(spot.range),
            ],
            light_colors: [point.color.extend(0.0), spot.color.extend(0.0)],
            spot: spot.direction.extend(spot.cos_outer),
        };
        queue.write_buffer(&self.scene_buffer, 0, bytemuck::bytes_of(&uniform));
        self.fog.prepare(queue, &inputs)?;
        // The sun moves with its slider: the whole sky table in the first frame (and in
        // every frame of a still one), then a band of 8 of its 64 rows per frame.
        self.sky
            .set_atmosphere(SkyAtmosphere::earth(sun.direction)?)?;
        let rays = FrustumRays::new(inputs.view_from_world.inverse(), inputs.clip_from_view)?;
        let rows = if self.animated && self.frames > 0 {
            8
        } else {
            64
        };
        self.sky.prepare(queue, &rays, rows)?;
        self.frames += 1;

        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("web shadow"),
                color_attachments: &[],
                depth_stencil_attachment: Some(depth_attachment(&self.shadow_layer)),
                ..Default::default()
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &self.scene_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.draw(0..self.vertex_count, 0..1);
        }
        let color_view = self.color.create_view(&Default::default());
        // The sky first (its pass has no depth), then the scene over it; the fog's
        // apply adds the tail over the sky.
        self.sky.encode_solve(&mut encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("web sky"),
                color_attachments: &[Some(color_attachment(
                    &color_view,
                    wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                ))],
                ..Default::default()
            });
            self.sky.draw(&mut pass);
        }
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("web lit"),
                color_attachments: &[Some(color_attachment(&color_view, wgpu::LoadOp::Load))],
                depth_stencil_attachment: Some(depth_attachment(&self.depth_view)),
                ..Default::default()
            });
            pass.set_pipeline(&self.lit_pipeline);
            pass.set_bind_group(0, &self.scene_group, &[]);
            pass.set_bind_group(1, &self.shadow_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.draw(0..self.vertex_count, 0..1);
        }
        self.fog.encode(&mut encoder)?;
        self.fog
            .record_apply(&mut encoder, &self.apply, &color_view, &self.depth_group)?;
        Ok(encoder.finish())
    }
}

fn color_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    }
}

fn depth_attachment(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// Draws [`Renderer::color`] into a canvas or window through the tone curve.
pub struct Display {
    pipeline: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
}

impl Display {
    /// A display pass from `renderer`'s image into views of `format`.
    pub fn new(device: &wgpu::Device, renderer: &Renderer, format: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("web display"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(include_str!("display.wgsl"))),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("web display"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("display_vertex"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("display_fragment"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("web display"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &renderer.color.create_view(&Default::default()),
                ),
            }],
        });
        Self { pipeline, group }
    }

    /// Records the display pass into `target`.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("web display"),
            color_attachments: &[Some(color_attachment(
                target,
                wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            ))],
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}

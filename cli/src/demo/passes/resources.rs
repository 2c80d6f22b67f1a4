//! The resources of the demo's passes: render targets (HDR colour, depth, display,
//! the cascaded shadow map, the lamp's cube shadow map), uniform buffers, bind group
//! layouts and bind groups.

use glam::Mat4;
use volfog::pipeline::VolumetricFog;
use volfog::pipeline::sky::SkyLight;
use volfog::uniforms::{self, FogLight, ShadowCascades};
use volfog_testkit::gpu::texture_2d;
use wgpu::util::DeviceExt;

use super::uniform::SceneUniform;
use super::{DEPTH_FORMAT, HDR_FORMAT, LDR_FORMAT};
use crate::demo::scene::Scene;

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

/// Targets, buffers, layouts and bind groups, before the pipelines.
pub(super) struct Resources {
    pub hdr: wgpu::Texture,
    pub depth: wgpu::Texture,
    pub ldr: wgpu::Texture,
    pub shadow_map: wgpu::Texture,
    pub shadow_layers: Vec<wgpu::TextureView>,
    pub lamp_map: wgpu::Texture,
    pub lamp_faces: Vec<wgpu::TextureView>,
    pub lamp_groups: Vec<wgpu::BindGroup>,
    pub hdr_view: wgpu::TextureView,
    pub scene_buffer: wgpu::Buffer,
    pub cascades_buffer: wgpu::Buffer,
    pub cascade_matrices: Vec<wgpu::Buffer>,
    pub exposure_buffer: wgpu::Buffer,
    pub scene_layout: wgpu::BindGroupLayout,
    pub cascade_layout: wgpu::BindGroupLayout,
    pub tonemap_layout: wgpu::BindGroupLayout,
    pub scene_group: wgpu::BindGroup,
    pub cascade_groups: Vec<wgpu::BindGroup>,
    pub tonemap_group: wgpu::BindGroup,
}

impl Resources {
    /// Creates the targets, buffers and bind groups for a scene, a fog pipeline, the
    /// sky texture and the lamp's cube faces (world -> clip of each, `lamp_size`
    /// texels per side).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        scene: &Scene,
        fog: &VolumetricFog,
        sky: &SkyLight,
        lamp_matrices: &[Mat4; 6],
        lamp_size: u32,
    ) -> Self {
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
        // Readable for the probe files.
        let (shadow_map, shadow_layers, shadow_array) = layered_depth(
            device,
            "demo shadow map",
            shadow_size,
            config.cascades,
            attachment | wgpu::TextureUsages::COPY_SRC,
        );
        // The lamp's cube shadow map: six layers, faces +X, -X, +Y, -Y, +Z, -Z.
        let (lamp_map, lamp_faces, lamp_array) =
            layered_depth(device, "demo lamp shadow map", lamp_size, 6, attachment);
        let lamp_face_buffers: Vec<wgpu::Buffer> = lamp_matrices
            .iter()
            .map(|m| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("demo lamp face matrix"),
                    contents: bytemuck::cast_slice(&m.to_cols_array()),
                    usage: wgpu::BufferUsages::UNIFORM,
                })
            })
            .collect();
        let lamp_matrices_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("demo lamp faces"),
            contents: bytemuck::cast_slice(&lamp_matrices.map(|m| m.to_cols_array())),
            usage: wgpu::BufferUsages::UNIFORM,
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
                wgpu::BindGroupLayoutEntry {
                    binding: 7,
                    visibility: fragment,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                uniform_entry(8, fragment),
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
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::TextureView(&lamp_array),
                },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: lamp_matrices_buffer.as_entire_binding(),
                },
            ],
        });
        let cascade_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("demo cascade"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX)],
        });
        let matrix_group = |label: &str, b: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &cascade_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: b.as_entire_binding(),
                }],
            })
        };
        let cascade_groups = cascade_matrices
            .iter()
            .map(|b| matrix_group("demo cascade", b))
            .collect();
        let lamp_groups = lamp_face_buffers
            .iter()
            .map(|b| matrix_group("demo lamp face", b))
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

        Self {
            hdr,
            depth,
            ldr,
            shadow_map,
            shadow_layers,
            lamp_map,
            lamp_faces,
            lamp_groups,
            hdr_view,
            scene_buffer,
            cascades_buffer,
            cascade_matrices,
            exposure_buffer,
            scene_layout,
            cascade_layout,
            tonemap_layout,
            scene_group,
            cascade_groups,
            tonemap_group,
        }
    }
}

/// A depth texture of `layers` square layers: the texture, a view per layer to render
/// into, and the depth aspect of all layers as a 2D array to sample.
fn layered_depth(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
    usage: wgpu::TextureUsages,
) -> (wgpu::Texture, Vec<wgpu::TextureView>, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage,
        view_formats: &[],
    });
    let per_layer = (0..layers)
        .map(|layer| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some(label),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    let array = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(label),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    (texture, per_layer, array)
}

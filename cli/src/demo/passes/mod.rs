//! The demo's own passes around `VolumetricFog`: cascaded shadow maps, the lamp's
//! cube shadow map, the lit opaque pass and sky, the semi-transparent pass (forward snippet), the tonemap, GPU
//! timestamps of these passes, and readbacks; and the fog wired to them.

mod encode;
mod fog;
mod frame;
mod pipelines;
mod resources;
mod uniform;

use glam::Mat4;
use volfog::pipeline::VolumetricFog;
use volfog::uniforms::{self, ShadowCascades};
use volfog_testkit::gpu::texture_2d;
use wgpu::util::DeviceExt;

pub use fog::Demo;
pub(crate) use fog::fog_config;
pub use frame::{FrameSetup, PASS_COUNT, PASS_NAMES};
use pipelines::Pipelines;
use resources::Resources;
pub use uniform::SceneUniform;

use super::scene::{Mesh, Scene};

/// The HDR colour format (the fog is applied onto it).
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The scene depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The display format.
pub const LDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The demo's own passes, timed with GPU timestamps when available.
pub const DEMO_PASSES: [&str; 5] = [
    "shadow maps",
    "lamp shadow map",
    "opaque + sky",
    "transparent",
    "tonemap",
];

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
    lamp_map: wgpu::Texture,
    lamp_faces: Vec<wgpu::TextureView>,
    lamp_groups: Vec<wgpu::BindGroup>,
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

impl Renderer {
    /// Creates targets, pipelines and buffers for a scene, a fog pipeline and the
    /// lamp's cube faces (world -> clip of each, `lamp_size` texels per side).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        scene: &Scene,
        fog: &VolumetricFog,
        sky: &volfog::pipeline::sky::SkyLight,
        lamp_matrices: &[Mat4; 6],
        lamp_size: u32,
        timestamps: bool,
    ) -> Result<Self, String> {
        let Resources {
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
        } = Resources::new(
            device,
            width,
            height,
            scene,
            fog,
            sky,
            lamp_matrices,
            lamp_size,
        );
        let Pipelines {
            shadow_pipeline,
            opaque_pipeline,
            sky_pipeline,
            transparent_pipeline,
            water_pipeline,
            tonemap_pipeline,
        } = Pipelines::new(device, fog, &scene_layout, &cascade_layout, &tonemap_layout)?;

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
            lamp_map,
            lamp_faces,
            lamp_groups,
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

    /// The cascaded shadow map (Depth32Float, a layer per cascade), as the fog's compare
    /// filter (or its ESM passes) read it.
    pub fn shadow_map(&self) -> &wgpu::Texture {
        &self.shadow_map
    }

    /// The lamp's cube shadow map (Depth32Float, six layers +X, -X, +Y, -Y, +Z, -Z),
    /// as the fog's local-light atlas reads it.
    pub fn lamp_shadow_map(&self) -> &wgpu::Texture {
        &self.lamp_map
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

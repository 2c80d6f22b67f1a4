//! The cloud layer's fullscreen passes (`shaders/passes/clouds.wgsl`, `volfog::clouds`):
//! [`CloudPasses`] draws the clouds' shadow on the lit scene, distance clouds and the
//! lit cloud layer, each pixel's position from the depth buffer (`volfog::frustum`).

use wgpu::util::DeviceExt;

use super::apply::FOG_BLEND;
use super::{
    RenderPipelineDesc, bind_group, bind_group_layout, render_pipeline, sampler_entry,
    shader_module, texture_entry, uniform_entry,
};
use crate::limits::{InvalidValue, check};
use crate::shaders::CodegenError;
use crate::uniforms::{CloudLayer, FrustumRays};

/// Which of the cloud passes to draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CloudDraw {
    /// The clouds' shadow multiplied into the lit scene (`cloud_shadow_fs`).
    Shadow,
    /// Distance clouds marched along the view ray (`distance_clouds_fs`).
    Distance,
    /// The layer lit per pixel, soft-clipped at the scene (`cloud_layer_fs`).
    Layer,
}

impl CloudDraw {
    /// Every draw.
    pub const ALL: [CloudDraw; 3] = [Self::Shadow, Self::Distance, Self::Layer];

    /// The fragment entry point.
    pub fn entry(self) -> &'static str {
        match self {
            Self::Shadow => "cloud_shadow_fs",
            Self::Distance => "distance_clouds_fs",
            Self::Layer => "cloud_layer_fs",
        }
    }
}

/// The cloud passes for one colour format, with their uniforms.
///
/// ```no_run
/// # fn f(device: &wgpu::Device, queue: &wgpu::Queue, map: &wgpu::TextureView, depth: &wgpu::TextureView) -> Result<(), Box<dyn std::error::Error>> {
/// use glam::{Mat4, Vec3};
/// use volfog::pipeline::clouds::{CloudDraw, CloudPasses};
/// use volfog::uniforms::{CloudLayer, FrustumRays};
///
/// let clouds = CloudPasses::new(device, wgpu::TextureFormat::Rgba16Float)?;
/// let group = clouds.bind_group(device, map, depth); // per map and depth texture
/// let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.78, 0.1, 500.0);
/// let layer = CloudLayer::new(1500.0, 300.0, 0.01, 6000.0)?;
/// clouds.prepare(queue, &FrustumRays::new(Mat4::IDENTITY, proj)?, &layer)?;
/// // in a render pass that loads the lit scene:
/// // clouds.draw(&mut pass, &group, CloudDraw::Shadow);
/// // clouds.draw(&mut pass, &group, CloudDraw::Distance);
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct CloudPasses {
    layout: wgpu::BindGroupLayout,
    pipelines: [wgpu::RenderPipeline; 3],
    rays: wgpu::Buffer,
    layer: wgpu::Buffer,
    sampler: wgpu::Sampler,
}

impl CloudPasses {
    /// Layout of the `clouds` pass: 0 `FrustumRays`, 1 `CloudLayer`, 2 the density map,
    /// 3 its sampler (linear, repeat), 4 the scene depth (unfilterable float).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 5] {
        let both = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        [
            uniform_entry(0, both),
            uniform_entry(1, wgpu::ShaderStages::FRAGMENT),
            texture_entry(
                2,
                wgpu::ShaderStages::FRAGMENT,
                wgpu::TextureViewDimension::D2,
                true,
            ),
            sampler_entry(3, wgpu::ShaderStages::FRAGMENT, true),
            texture_entry(
                4,
                wgpu::ShaderStages::FRAGMENT,
                wgpu::TextureViewDimension::D2,
                false,
            ),
        ]
    }

    /// The three passes for colour targets of `format`, blended as the fog apply.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Result<Self, CodegenError> {
        let layout = bind_group_layout(device, "volfog clouds", &Self::layout_entries());
        let module = shader_module(device, "clouds", &[])?;
        let pipelines = CloudDraw::ALL.map(|draw| {
            render_pipeline(
                device,
                RenderPipelineDesc {
                    label: draw.entry(),
                    vertex: (&module, "clouds_vs"),
                    fragment: (&module, draw.entry()),
                    bind_group_layouts: &[Some(&layout)],
                    buffers: &[],
                    primitive: wgpu::PrimitiveState::default(),
                    target: wgpu::ColorTargetState {
                        format,
                        blend: Some(FOG_BLEND),
                        write_mask: wgpu::ColorWrites::ALL,
                    },
                    samples: 1,
                },
            )
        });
        let uniform = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        };
        Ok(Self {
            rays: uniform("volfog cloud rays", &FrustumRays::default().to_bytes()),
            layer: uniform("volfog cloud layer", &CloudLayer::default().to_bytes()),
            sampler: cloud_map_sampler(device),
            layout,
            pipelines,
        })
    }

    /// The bind group for a density map (red channel, filterable) and a scene depth
    /// view (depth aspect, the size of the colour target); one per pair.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        map: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog clouds",
            &self.layout,
            &[
                (0, self.rays.as_entire_binding()),
                (1, self.layer.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(map)),
                (3, wgpu::BindingResource::Sampler(&self.sampler)),
                (4, wgpu::BindingResource::TextureView(depth)),
            ],
        )
    }

    /// Uploads this frame's camera rays and cloud layer (checked).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        rays: &FrustumRays,
        layer: &CloudLayer,
    ) -> Result<(), InvalidValue> {
        let layer = layer.validated()?;
        let rays = rays.validated()?;
        queue.write_buffer(&self.rays, 0, &rays.to_bytes());
        queue.write_buffer(&self.layer, 0, &layer.to_bytes());
        Ok(())
    }

    /// Draws one pass into the caller's render pass (it loads the lit scene).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, group: &wgpu::BindGroup, draw: CloudDraw) {
        let index = CloudDraw::ALL
            .iter()
            .position(|d| *d == draw)
            .expect("listed");
        pass.set_pipeline(&self.pipelines[index]);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// GPU memory of the uniforms, bytes (the map and depth are the caller's).
    pub fn memory_bytes(&self) -> u64 {
        self.rays.size() + self.layer.size()
    }
}

/// The sampler the cloud map expects: linear, repeat.
pub fn cloud_map_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog cloud map"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// A cloud density map texture (R16Float, `TEXTURE_BINDING`) of `width` x `height`
/// densities in [0, 1], row-major, for [`CloudPasses::bind_group`] and
/// `VolumetricFog::set_cloud_map`. A float map is filtered in floating point; an 8-bit
/// unorm map may be filtered in 8-bit steps, which dense clouds amplify.
pub fn cloud_map_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (width, height): (u32, u32),
    densities: &[f32],
) -> Result<wgpu::Texture, InvalidValue> {
    check(
        width > 0 && height > 0 && densities.len() == (width * height) as usize,
        "cloud map densities",
        densities.len(),
        format!("width x height = {} values", width as u64 * height as u64),
    )?;
    let halfs: Vec<half::f16> = densities
        .iter()
        .map(|d| {
            half::f16::from_f32(if d.is_finite() {
                d.clamp(0.0, 1.0)
            } else {
                0.0
            })
        })
        .collect();
    Ok(device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("volfog cloud map"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&halfs),
    ))
}

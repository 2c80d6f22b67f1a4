//! Fog hulls (Boyd 2001): the `hull_thickness` pass, which sums the signed face
//! distances of closed meshes per pixel into a float target, and the `hull_composite`
//! pass, which fogs the lit colour with that thickness
//! (`shaders/passes/hull_thickness.wgsl`, `shaders/passes/hull_composite.wgsl`).
//!
//! Per frame: clear a hull-sum texture ([`hull_sum_texture`]) to 0, draw every hull
//! of one medium into it with [`HullThicknessPass::encode`] (one [`FogHull`] uniform
//! per hull, each with its own reference distance), then draw
//! [`HullCompositePass::encode`] onto the lit colour target.
//!
//! [`FogHull`]: crate::uniforms::FogHull

use super::{
    RenderPipelineDesc, bind_group_layout, render_pipeline, shader_module, texture_entry,
    uniform_entry,
};
use crate::pipeline::apply::FOG_BLEND;
use crate::shaders::CodegenError;

/// Bytes per hull vertex: one `Float32x3` world position.
pub const VERTEX_STRIDE: u64 = 12;

/// The vertex attributes of a hull mesh: location 0, world position.
pub const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 1] = [wgpu::VertexAttribute {
    format: wgpu::VertexFormat::Float32x3,
    offset: 0,
    shader_location: 0,
}];

/// The blend state of the thickness pass: every channel adds.
pub const HULL_SUM_BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The float format the hull terms are summed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HullSumFormat {
    /// `Rgba16Float`: blendable everywhere. Terms are stored relative to the hull's
    /// reference distance; the sum errs by about (faces crossed) * extent * 2^-12.
    Half,
    /// `Rgba32Float`: needs the adapter feature `FLOAT32_BLENDABLE`.
    Full,
}

impl HullSumFormat {
    /// `Full` when the device has `FLOAT32_BLENDABLE`, otherwise `Half`.
    pub fn best(features: wgpu::Features) -> Self {
        if features.contains(wgpu::Features::FLOAT32_BLENDABLE) {
            Self::Full
        } else {
            Self::Half
        }
    }

    /// The texture format.
    pub fn texture_format(self) -> wgpu::TextureFormat {
        match self {
            Self::Half => wgpu::TextureFormat::Rgba16Float,
            Self::Full => wgpu::TextureFormat::Rgba32Float,
        }
    }

    /// Bytes per texel.
    pub fn bytes_per_texel(self) -> u32 {
        match self {
            Self::Half => 8,
            Self::Full => 16,
        }
    }
}

/// Errors creating the hull passes.
#[derive(Debug, thiserror::Error)]
pub enum HullError {
    /// `HullSumFormat::Full` was asked for on a device without `FLOAT32_BLENDABLE`.
    #[error(
        "an Rgba32Float hull sum needs the device feature FLOAT32_BLENDABLE; \
         use HullSumFormat::Half (or HullSumFormat::best)"
    )]
    Float32BlendableMissing,
    /// Composing a shader failed.
    #[error(transparent)]
    Shader(#[from] CodegenError),
}

/// A hull-sum texture of `size` pixels (the scene depth buffer's size): render
/// attachment, sampled (unfilterable) and copy source.
pub fn hull_sum_texture(
    device: &wgpu::Device,
    size: [u32; 2],
    format: HullSumFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("volfog hull sum"),
        size: wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: format.texture_format(),
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The two bind group entries both hull passes bind: a uniform and an unfilterable
/// 2D float texture.
fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    hull: &wgpu::Buffer,
    texture: &wgpu::TextureView,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: hull.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(texture),
            },
        ],
    })
}

/// The compiled `hull_thickness` pass.
#[derive(Debug)]
pub struct HullThicknessPass {
    format: HullSumFormat,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl HullThicknessPass {
    /// The bind group layout: 0 `FogHull` uniform (vertex and fragment), 1 scene
    /// depth (2D, unfilterable float view of a depth texture).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            uniform_entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT),
            texture_entry(
                1,
                wgpu::ShaderStages::FRAGMENT,
                wgpu::TextureViewDimension::D2,
                false,
            ),
        ]
    }

    /// The vertex buffer layout of a hull mesh.
    pub fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: VERTEX_STRIDE,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX_ATTRIBUTES,
        }
    }

    /// The primitive state: triangle list, counter-clockwise front faces, no culling.
    pub fn primitive() -> wgpu::PrimitiveState {
        wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: None,
            ..Default::default()
        }
    }

    /// Compiles the pass for a hull-sum format, reading the scene depth buffer.
    pub fn new(device: &wgpu::Device, format: HullSumFormat) -> Result<Self, HullError> {
        Self::with_input(device, format, crate::options::ApplyInput::Depth)
    }

    /// As [`HullThicknessPass::new`], reading `input` at binding 1: the scene depth,
    /// or the resolved MSAA fog layout (`VOLFOG_HULL_RESOLVED`) of a multisampled
    /// scene.
    pub fn with_input(
        device: &wgpu::Device,
        format: HullSumFormat,
        input: crate::options::ApplyInput,
    ) -> Result<Self, HullError> {
        if format == HullSumFormat::Full
            && !device
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE)
        {
            return Err(HullError::Float32BlendableMissing);
        }
        let defines = match input {
            // The far field changes only the apply pass: hulls read the depth.
            crate::options::ApplyInput::Depth | crate::options::ApplyInput::FarField => Vec::new(),
            crate::options::ApplyInput::ResolvedLayout => vec!["VOLFOG_HULL_RESOLVED".to_string()],
        };
        let module = shader_module(device, "hull_thickness", &defines)?;
        let layout = bind_group_layout(device, "volfog hull_thickness", &Self::layout_entries());
        let pipeline = render_pipeline(
            device,
            RenderPipelineDesc {
                label: "volfog hull_thickness",
                vertex: (&module, "hull_thickness_vs"),
                fragment: (&module, "hull_thickness_fs"),
                bind_group_layouts: &[Some(&layout)],
                buffers: &[Some(Self::vertex_layout())],
                primitive: Self::primitive(),
                target: wgpu::ColorTargetState {
                    format: format.texture_format(),
                    blend: Some(HULL_SUM_BLEND),
                    write_mask: wgpu::ColorWrites::ALL,
                },
                samples: 1,
            },
        );
        Ok(Self {
            format,
            layout,
            pipeline,
        })
    }

    /// The hull-sum format the pass draws into.
    pub fn format(&self) -> HullSumFormat {
        self.format
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group: the hull's `FogHull` uniform and the scene depth view (a
    /// depth-aspect view of the depth texture).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        hull: &wgpu::Buffer,
        scene_depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog hull_thickness",
            &self.layout,
            hull,
            scene_depth,
        )
    }

    /// Records one hull (`u32` indices, a triangle list) into a render pass whose
    /// colour attachment is the hull-sum texture (cleared to 0 before the first hull).
    pub fn encode(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind_group: &wgpu::BindGroup,
        vertices: &wgpu::Buffer,
        indices: &wgpu::Buffer,
        index_count: u32,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..index_count, 0, 0..1);
    }
}

/// The compiled `hull_composite` pass.
#[derive(Debug)]
pub struct HullCompositePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl HullCompositePass {
    /// The bind group layout: 0 `FogHull` uniform, 1 hull sum (2D, unfilterable float).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            uniform_entry(0, wgpu::ShaderStages::FRAGMENT),
            texture_entry(
                1,
                wgpu::ShaderStages::FRAGMENT,
                wgpu::TextureViewDimension::D2,
                false,
            ),
        ]
    }

    /// Compiles the pass for a colour target format; it blends with
    /// `apply::FOG_BLEND` (`dst * T + L`).
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, CodegenError> {
        let vs = shader_module(device, "fullscreen", &[])?;
        let fs = shader_module(device, "hull_composite", &[])?;
        let layout = bind_group_layout(device, "volfog hull_composite", &Self::layout_entries());
        let pipeline = render_pipeline(
            device,
            RenderPipelineDesc {
                label: "volfog hull_composite",
                vertex: (&vs, "fullscreen_vs"),
                fragment: (&fs, "hull_composite_fs"),
                bind_group_layouts: &[Some(&layout)],
                buffers: &[],
                primitive: wgpu::PrimitiveState::default(),
                target: wgpu::ColorTargetState {
                    format: color_format,
                    blend: Some(FOG_BLEND),
                    write_mask: wgpu::ColorWrites::ALL,
                },
                samples: 1,
            },
        );
        Ok(Self { layout, pipeline })
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group: the `FogHull` uniform (density and colour) and the hull sum.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        hull: &wgpu::Buffer,
        hull_sum: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog hull_composite",
            &self.layout,
            hull,
            hull_sum,
        )
    }

    /// Records the fullscreen draw into a render pass whose colour attachment is the
    /// lit scene (loaded, not cleared).
    pub fn encode(&self, pass: &mut wgpu::RenderPass<'_>, bind_group: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

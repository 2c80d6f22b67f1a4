//! What callers describe: stages, descriptor bindings, shaders, vertex input, blending.

use std::ops::{BitOr, BitOrAssign};

use ash::vk;

/// Shader stages a descriptor binding is visible to (a small bit set; combine with `|`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Stages(u8);

impl Stages {
    /// No stage.
    pub const NONE: Stages = Stages(0);
    /// The compute stage.
    pub const COMPUTE: Stages = Stages(1);
    /// The vertex stage.
    pub const VERTEX: Stages = Stages(2);
    /// The fragment stage.
    pub const FRAGMENT: Stages = Stages(4);
    /// Vertex and fragment stages.
    pub const VERTEX_FRAGMENT: Stages = Stages(2 | 4);

    /// Both sets of stages.
    pub const fn union(self, other: Stages) -> Stages {
        Stages(self.0 | other.0)
    }

    /// Whether every stage of `other` is in `self`.
    pub const fn contains(self, other: Stages) -> bool {
        self.0 & other.0 == other.0
    }

    /// The equivalent Vulkan stage flags.
    pub fn to_vk(self) -> vk::ShaderStageFlags {
        let mut flags = vk::ShaderStageFlags::empty();
        if self.contains(Stages::COMPUTE) {
            flags |= vk::ShaderStageFlags::COMPUTE;
        }
        if self.contains(Stages::VERTEX) {
            flags |= vk::ShaderStageFlags::VERTEX;
        }
        if self.contains(Stages::FRAGMENT) {
            flags |= vk::ShaderStageFlags::FRAGMENT;
        }
        flags
    }
}

impl BitOr for Stages {
    type Output = Stages;
    fn bitor(self, rhs: Stages) -> Stages {
        self.union(rhs)
    }
}

impl BitOrAssign for Stages {
    fn bitor_assign(&mut self, rhs: Stages) {
        *self = self.union(rhs);
    }
}

/// The type of a descriptor (one array element, `descriptorCount = 1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DescriptorKind {
    /// `VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER` (WGSL `var<uniform>`, GLSL `uniform` block).
    UniformBuffer,
    /// `VK_DESCRIPTOR_TYPE_STORAGE_BUFFER` (WGSL `var<storage>`, GLSL `buffer` block).
    StorageBuffer,
    /// `VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE` (WGSL `texture_*`, GLSL `texture2D`).
    SampledImage,
    /// `VK_DESCRIPTOR_TYPE_STORAGE_IMAGE` (WGSL `texture_storage_*`, GLSL `image2D`).
    StorageImage,
    /// `VK_DESCRIPTOR_TYPE_SAMPLER` (WGSL `sampler`, GLSL `sampler`).
    Sampler,
    /// `VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER` (GLSL `sampler2D`; HLSL/Slang `Sampler2D`).
    CombinedImageSampler,
}

impl DescriptorKind {
    /// The equivalent Vulkan descriptor type.
    pub fn to_vk(self) -> vk::DescriptorType {
        match self {
            DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
            DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
            DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
            DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        }
    }
}

/// One binding of a descriptor set layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DescriptorBinding {
    /// Binding number within its set.
    pub binding: u32,
    /// Descriptor type.
    pub kind: DescriptorKind,
    /// Stages that may access it.
    pub stages: Stages,
}

impl DescriptorBinding {
    /// A binding of `kind` at `binding`, visible to `stages`.
    pub const fn new(binding: u32, kind: DescriptorKind, stages: Stages) -> Self {
        DescriptorBinding {
            binding,
            kind,
            stages,
        }
    }
}

/// A shader stage's code and entry point name.
#[derive(Clone, Copy, Debug)]
pub struct ShaderEntry<'a> {
    /// SPIR-V words.
    pub spirv: &'a [u32],
    /// Entry point name (`OpEntryPoint` name).
    pub entry: &'a str,
}

/// One vertex attribute read from a vertex buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexAttribute {
    /// Shader input location.
    pub location: u32,
    /// Format of the data in the buffer.
    pub format: vk::Format,
    /// Byte offset within one element.
    pub offset: u32,
}

/// One vertex buffer binding (its index in [`GraphicsDesc::vertex_buffers`] is its binding number).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexBuffer {
    /// Bytes between consecutive elements.
    pub stride: u32,
    /// Advance per instance instead of per vertex.
    pub per_instance: bool,
    /// Attributes read from this buffer.
    pub attributes: Vec<VertexAttribute>,
}

/// Blend equation of one channel group: `result = src * src_factor <op> dst * dst_factor`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlendComponent {
    /// Factor applied to the fragment shader's output.
    pub src_factor: vk::BlendFactor,
    /// Factor applied to the attachment's current value.
    pub dst_factor: vk::BlendFactor,
    /// How the two are combined.
    pub op: vk::BlendOp,
}

/// Blending of the colour attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Blend {
    /// RGB channels.
    pub color: BlendComponent,
    /// Alpha channel.
    pub alpha: BlendComponent,
}

impl Blend {
    /// Non-premultiplied "over" (wgpu's `BlendState::ALPHA_BLENDING`).
    pub const ALPHA: Blend = Blend {
        color: BlendComponent {
            src_factor: vk::BlendFactor::SRC_ALPHA,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
        alpha: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
    };
    /// Premultiplied "over" (wgpu's `BlendState::PREMULTIPLIED_ALPHA_BLENDING`).
    pub const PREMULTIPLIED_ALPHA: Blend = Blend {
        color: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
        alpha: BlendComponent {
            src_factor: vk::BlendFactor::ONE,
            dst_factor: vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
            op: vk::BlendOp::ADD,
        },
    };
}

/// Everything [`Validator::graphics_pipeline`](crate::Validator::graphics_pipeline) needs. The topology is a triangle list, there is
/// one colour attachment and no depth/stencil; viewport and scissor are dynamic.
#[derive(Clone, Debug)]
pub struct GraphicsDesc<'a> {
    /// Vertex shader.
    pub vertex: ShaderEntry<'a>,
    /// Fragment shader.
    pub fragment: ShaderEntry<'a>,
    /// Descriptor set layouts used by both stages (index = set number; empty sets allowed).
    pub sets: &'a [Vec<DescriptorBinding>],
    /// Vertex buffers (may be empty, e.g. for a full-screen triangle built from the vertex index).
    pub vertex_buffers: &'a [VertexBuffer],
    /// Format of the single colour attachment.
    pub color_format: vk::Format,
    /// Blending of the colour attachment; `None` writes the output unblended.
    pub blend: Option<Blend>,
}

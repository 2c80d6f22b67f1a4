//! `manifest.json`: everything an engine needs to bind the exported shaders without
//! reading Rust: per variant and entry point its files, workgroup size or draw state,
//! bindings in WebGPU's terms with their slot in every target, and struct layouts.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::manifest::{self, Blend, VertexBuffer};
use crate::reflect::{Binding, HlslSamplerIndexBuffer, HlslSamplers, MslBufferSizes, StructLayout};
use crate::snippets::{Snippet, SnippetLanguage};
use crate::translate::VariantOutput;
use crate::{Stage, Target};

#[derive(Serialize)]
struct Manifest<'a> {
    generator: String,
    conventions: Conventions,
    targets: Vec<TargetInfo>,
    layout_header: &'static str,
    variants: Vec<VariantEntry<'a>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    snippets: Vec<SnippetEntry<'a>>,
}

#[derive(Serialize)]
struct SnippetEntry<'a> {
    name: &'a str,
    files: BTreeMap<&'static str, String>,
    functions: &'a [String],
    structs: Vec<&'a str>,
}

#[derive(Serialize)]
struct Conventions {
    clip_space: &'static str,
    uniforms: &'static str,
    bindings: &'static str,
    glsl: &'static str,
    hlsl_samplers: &'static str,
    hlsl_buffers: &'static str,
    msl: &'static str,
}

#[derive(Serialize)]
struct TargetInfo {
    target: &'static str,
    folder: &'static str,
    extension: &'static str,
    version: &'static str,
    validated_by: &'static str,
}

#[derive(Serialize)]
struct VariantEntry<'a> {
    name: &'a str,
    pass: &'a str,
    defines: &'a [String],
    usage: &'static str,
    entry_points: Vec<EntryEntry<'a>>,
}

#[derive(Serialize)]
struct VertexRef {
    variant: String,
    entry: String,
}

#[derive(Serialize)]
struct ColorTarget {
    location: u32,
    formats: &'static [&'static str],
    blend: Option<Blend>,
}

#[derive(Serialize)]
struct Primitive {
    topology: &'static str,
    front_face: &'static str,
    cull_mode: &'static str,
}

#[derive(Serialize)]
struct EntryEntry<'a> {
    name: &'a str,
    stage: Stage,
    #[serde(skip_serializing_if = "Option::is_none")]
    workgroup_size: Option<[u32; 3]>,
    files: BTreeMap<&'static str, String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vertex: Option<VertexRef>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    color_targets: Vec<ColorTarget>,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    vertex_buffers: &'static [VertexBuffer],
    #[serde(skip_serializing_if = "Option::is_none")]
    primitive: Option<Primitive>,
    bindings: &'a [Binding],
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    hlsl_sampler_index_buffers: &'a [HlslSamplerIndexBuffer],
    #[serde(skip_serializing_if = "Option::is_none")]
    msl_buffer_sizes: Option<&'a MslBufferSizes>,
    structs: &'a [StructLayout],
}

fn target_info(target: Target) -> TargetInfo {
    let (version, validated_by) = match target {
        Target::Wgsl => (
            "WGSL (WebGPU)",
            "naga (all validation flags); Dawn/Tint compiles every module and creates every \
             pipeline with layouts built from this manifest, except the entry points that \
             read @builtin(view_index) (the multiview apply), which Tint takes only under \
             `enable view_instancing;`; runs on wgpu in the tests",
        ),
        Target::Spirv => (
            "SPIR-V 1.3, Vulkan 1.1",
            "naga; spirv-val --target-env vulkan1.1; pipelines created under the Khronos \
             validation layer with descriptor set layouts built from this manifest",
        ),
        Target::Glsl => (
            "GLSL 450 core",
            "naga; compiled and linked per program (vertex + fragment, or compute) by \
             Mesa's OpenGL 4.5 driver, with block and uniform bindings checked against this \
             manifest; fragment shaders that read the view index (the multiview apply) are \
             Vulkan GLSL (GL_EXT_multiview, which OpenGL drivers do not take), compiled by \
             glslang for Vulkan 1.1",
        ),
        Target::Hlsl => (
            "HLSL shader model 6.0 (6.1 for entry points that read the view index, SV_ViewID)",
            "naga; compiled by Slang (HLSL front end, sm_6_0) with warnings as errors",
        ),
        Target::Msl => (
            "Metal Shading Language 2.1 (2.2 for entry points that read the view index, \
             amplification_id)",
            "naga only: no Metal compiler is reachable where volfog is tested",
        ),
    };
    TargetInfo {
        target: target.name(),
        folder: target.name(),
        extension: target.extension(),
        version,
        validated_by,
    }
}

const CLASSIC_SAMPLERS: &str = "Samplers are SamplerState (or SamplerComparisonState) \
    declarations at register(sN, spaceG): G is the bind group, N counts the group's samplers \
    up in binding order (hlsl.register of each sampler binding).";

const HEAP_SAMPLERS: &str = "Samplers are read from naga's sampler heaps: SamplerState \
    nagaSamplerHeap[2048] at s0 space0 and SamplerComparisonState \
    nagaComparisonSamplerHeap[2048] at s0 space1. Each group with samplers has a \
    StructuredBuffer<uint> of heap indices (hlsl_sampler_index_buffers); a sampler's \
    hlsl.sampler_index is its element in that buffer (needs resource binding tier 2).";

fn conventions(hlsl_samplers: HlslSamplers) -> Conventions {
    Conventions {
        clip_space: "WebGPU: NDC x, y in [-1, 1] with y up, depth in [0, 1]; framebuffer and \
                     texture coordinates start at the top-left. Froxel volumes map screen uv \
                     (v down) to x, y.",
        uniforms: "Uniform buffers use the WGSL uniform layout (std140-compatible); struct \
                   member offsets and sizes are listed per entry point and in volfog_layout.h.",
        bindings: "Each binding's resource is a WebGPU GPUBindGroupLayoutEntry: buffer type \
                   (uniform, storage, read-only-storage) with its minimum size, texture \
                   sample_type (float: read through a filtering sampler; unfilterable-float: \
                   loaded or read through a non-filtering sampler, which depth formats also \
                   bind to) and view dimension, storage texture format and access, sampler type \
                   (filtering, non-filtering, comparison). A fragment entry point names the \
                   vertex shader it is drawn with and its colour targets.",
        glsl: "GL-style bindings: layout(binding = N) numbered per namespace (uniform blocks, \
               texture units, image units, shader storage blocks). A uniform or storage block \
               is named glsl.block (the binding's name + _block) in every stage, so a program's \
               stages link. A sampler is merged into the combined sampler of the texture it \
               samples and has no binding of its own. Vertex outputs are adjusted to OpenGL clip \
               space (y flipped, depth remapped to [-1, 1]) so images keep WebGPU's memory \
               layout.",
        hlsl_samplers: match hlsl_samplers {
            HlslSamplers::Classic => CLASSIC_SAMPLERS,
            HlslSamplers::Heap => HEAP_SAMPLERS,
        },
        hlsl_buffers: "hlsl.type is each binding's declaration: cbuffer for uniform buffers, \
                       ByteAddressBuffer / RWByteAddressBuffer for storage buffers (structs are \
                       loaded at the byte offsets listed in structs), Texture* / RWTexture* for \
                       textures.",
        msl: "Argument indices are assigned per entry point: [[buffer(i)]], [[texture(i)]] and \
              [[sampler(i)]] count up separately over all groups in (group, binding) order. An \
              entry point with runtime-sized storage arrays takes msl_buffer_sizes: a struct of \
              uint byte sizes of those bindings at the buffer index after the last bound \
              buffer. No Metal compiler checks these files.",
    }
}

/// Builds the manifest JSON for variant outputs and targets.
pub fn manifest_json(
    variants: &[VariantOutput],
    snippets: &[Snippet],
    targets: &[Target],
    hlsl_samplers: HlslSamplers,
) -> String {
    serde_json::to_string_pretty(&manifest_value(variants, snippets, targets, hlsl_samplers))
        .expect("manifest serialises")
}

/// The manifest as a JSON value: `generator`, `conventions`, `targets`,
/// `layout_header`, `variants` and (when there are any) `snippets`.
pub fn manifest_value(
    variants: &[VariantOutput],
    snippets: &[Snippet],
    targets: &[Target],
    hlsl_samplers: HlslSamplers,
) -> serde_json::Value {
    let manifest = Manifest {
        generator: format!("volfog {}", env!("CARGO_PKG_VERSION")),
        conventions: conventions(hlsl_samplers),
        targets: targets.iter().map(|t| target_info(*t)).collect(),
        layout_header: "volfog_layout.h",
        variants: variants.iter().map(|v| variant_entry(v, targets)).collect(),
        snippets: snippets
            .iter()
            .map(|s| SnippetEntry {
                name: &s.name,
                files: targets
                    .iter()
                    .flat_map(|t| SnippetLanguage::of_target(*t))
                    .map(|l| {
                        (
                            l.name(),
                            format!("{}/include/{}", l.target().name(), s.file_name(l)),
                        )
                    })
                    .collect(),
                functions: &s.functions,
                structs: s.structs.iter().map(|st| st.name.as_str()).collect(),
            })
            .collect(),
    };
    serde_json::to_value(&manifest).expect("manifest serialises")
}

fn variant_entry<'a>(v: &'a VariantOutput, targets: &[Target]) -> VariantEntry<'a> {
    let pass = manifest::pass(&v.pass);
    let render = pass.and_then(|p| p.render);
    VariantEntry {
        name: &v.name,
        pass: &v.pass,
        defines: &v.defines,
        usage: pass.map(|p| p.usage).unwrap_or(""),
        entry_points: v
            .entries
            .iter()
            .map(|e| {
                let fragment = e.stage == Stage::Fragment;
                let vertex = render.filter(|_| fragment).map(|r| match r.vertex {
                    Some((pass, entry)) => VertexRef {
                        variant: manifest::variant_name(pass, &[]),
                        entry: entry.to_string(),
                    },
                    None => VertexRef {
                        variant: v.name.clone(),
                        entry: v
                            .entries
                            .iter()
                            .find(|o| o.stage == Stage::Vertex)
                            .map(|o| o.entry.clone())
                            .unwrap_or_default(),
                    },
                });
                EntryEntry {
                    name: &e.entry,
                    stage: e.stage,
                    workgroup_size: e.reflection.workgroup_size,
                    files: targets
                        .iter()
                        .map(|t| {
                            (
                                t.name(),
                                format!("{}/{}", t.name(), e.file_name(&v.name, *t)),
                            )
                        })
                        .collect(),
                    vertex,
                    color_targets: render
                        .filter(|_| fragment)
                        .map(|r| ColorTarget {
                            location: 0,
                            formats: r.formats,
                            blend: r.blend,
                        })
                        .into_iter()
                        .collect(),
                    vertex_buffers: render
                        .filter(|_| e.stage == Stage::Vertex)
                        .map_or(&[][..], |r| r.vertex_buffers),
                    primitive: render
                        .filter(|_| e.stage != Stage::Compute)
                        .map(|r| Primitive {
                            topology: r.topology,
                            front_face: r.front_face,
                            cull_mode: r.cull_mode,
                        }),
                    bindings: &e.reflection.bindings,
                    hlsl_sampler_index_buffers: &e.reflection.hlsl_sampler_index_buffers,
                    msl_buffer_sizes: e.reflection.msl_buffer_sizes.as_ref(),
                    structs: &e.reflection.structs,
                }
            })
            .collect(),
    }
}

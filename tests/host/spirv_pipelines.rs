//! Every exported SPIR-V entry point as a Vulkan pipeline under the Khronos validation
//! layer (through `vkcheck`, on lavapipe), with descriptor set layouts, vertex input,
//! colour target and blend built from `manifest.json` alone: a compute pipeline per
//! compute entry point, a graphics pipeline per fragment entry point with the vertex
//! shader the manifest names. Any validation message fails.

use std::path::Path;

use serde_json::Value;
use vkcheck::{
    Blend, BlendComponent, DescriptorBinding, DescriptorKind, GraphicsDesc, ShaderEntry, Stages,
    Validator, VertexAttribute, VertexBuffer, vk,
};

use crate::common::{entry_points, exported, manifest, vertex_of};

pub(crate) fn read_spirv(dir: &Path, file: &str) -> Vec<u32> {
    let bytes = std::fs::read(dir.join(file)).unwrap();
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn stages(stage: &str) -> Stages {
    match stage {
        "compute" => Stages::COMPUTE,
        "vertex" => Stages::VERTEX,
        "fragment" => Stages::FRAGMENT,
        other => panic!("stage {other}"),
    }
}

fn kind(resource: &Value) -> DescriptorKind {
    match resource["kind"].as_str().unwrap() {
        "buffer" if resource["type"] == "uniform" => DescriptorKind::UniformBuffer,
        "buffer" => DescriptorKind::StorageBuffer,
        "texture" => DescriptorKind::SampledImage,
        "storage_texture" => DescriptorKind::StorageImage,
        "sampler" => DescriptorKind::Sampler,
        other => panic!("resource kind {other}"),
    }
}

/// Adds an entry point's bindings to the descriptor sets (merging stages).
pub(crate) fn add_bindings(sets: &mut Vec<Vec<DescriptorBinding>>, entry: &Value) {
    let stage = stages(entry["stage"].as_str().unwrap());
    for b in entry["bindings"].as_array().unwrap() {
        let set = b["spirv"]["set"].as_u64().unwrap() as usize;
        let binding = b["spirv"]["binding"].as_u64().unwrap() as u32;
        if sets.len() <= set {
            sets.resize(set + 1, Vec::new());
        }
        match sets[set].iter_mut().find(|d| d.binding == binding) {
            Some(d) => d.stages |= stage,
            None => sets[set].push(DescriptorBinding {
                binding,
                kind: kind(&b["resource"]),
                stages: stage,
            }),
        }
    }
}

fn format(name: &str) -> vk::Format {
    match name {
        "rgba16float" => vk::Format::R16G16B16A16_SFLOAT,
        "rgba32float" => vk::Format::R32G32B32A32_SFLOAT,
        "rgba8unorm" => vk::Format::R8G8B8A8_UNORM,
        "rgba8unorm-srgb" => vk::Format::R8G8B8A8_SRGB,
        "bgra8unorm" => vk::Format::B8G8R8A8_UNORM,
        "bgra8unorm-srgb" => vk::Format::B8G8R8A8_SRGB,
        "rgb10a2unorm" => vk::Format::A2B10G10R10_UNORM_PACK32,
        "float32x3" => vk::Format::R32G32B32_SFLOAT,
        other => panic!("format {other}"),
    }
}

fn factor(name: &str) -> vk::BlendFactor {
    match name {
        "one" => vk::BlendFactor::ONE,
        "zero" => vk::BlendFactor::ZERO,
        "src-alpha" => vk::BlendFactor::SRC_ALPHA,
        "one-minus-src-alpha" => vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
        other => panic!("blend factor {other}"),
    }
}

fn component(c: &Value) -> BlendComponent {
    assert_eq!(c["operation"], "add");
    BlendComponent {
        src_factor: factor(c["src_factor"].as_str().unwrap()),
        dst_factor: factor(c["dst_factor"].as_str().unwrap()),
        op: vk::BlendOp::ADD,
    }
}

#[test]
fn every_spirv_entry_point_makes_a_clean_pipeline_from_the_manifest() {
    let dir = exported();
    let validator = Validator::new().unwrap_or_else(|e| panic!("{e}"));
    let (mut compute, mut graphics, mut vertex_used) = (0, 0, std::collections::BTreeSet::new());
    let mut problems = Vec::new();
    for (variant, e) in entry_points() {
        {
            let name = e["name"].as_str().unwrap();
            let spirv = read_spirv(dir, e["files"]["spirv"].as_str().unwrap());
            let mut sets = Vec::new();
            add_bindings(&mut sets, e);
            let messages = match e["stage"].as_str().unwrap() {
                "compute" => {
                    compute += 1;
                    validator.compute_pipeline(&spirv, name, &sets)
                }
                "fragment" => {
                    graphics += 1;
                    let (vv, vertex) = vertex_of(e);
                    let ve = vertex["name"].as_str().unwrap();
                    vertex_used.insert(format!("{vv}.{ve}"));
                    add_bindings(&mut sets, vertex);
                    let vertex_spirv = read_spirv(dir, vertex["files"]["spirv"].as_str().unwrap());
                    let buffers: Vec<VertexBuffer> = vertex["vertex_buffers"]
                        .as_array()
                        .map(|bs| {
                            bs.iter()
                                .map(|b| VertexBuffer {
                                    stride: b["array_stride"].as_u64().unwrap() as u32,
                                    per_instance: b["step_mode"] == "instance",
                                    attributes: b["attributes"]
                                        .as_array()
                                        .unwrap()
                                        .iter()
                                        .map(|a| VertexAttribute {
                                            location: a["shader_location"].as_u64().unwrap() as u32,
                                            format: format(a["format"].as_str().unwrap()),
                                            offset: a["offset"].as_u64().unwrap() as u32,
                                        })
                                        .collect(),
                                })
                                .collect()
                        })
                        .unwrap_or_default();
                    let target = &e["color_targets"][0];
                    let blend = (!target["blend"].is_null()).then(|| Blend {
                        color: component(&target["blend"]["color"]),
                        alpha: component(&target["blend"]["alpha"]),
                    });
                    validator.graphics_pipeline(&GraphicsDesc {
                        vertex: ShaderEntry {
                            spirv: &vertex_spirv,
                            entry: ve,
                        },
                        fragment: ShaderEntry {
                            spirv: &spirv,
                            entry: name,
                        },
                        sets: &sets,
                        vertex_buffers: &buffers,
                        color_format: format(target["formats"][0].as_str().unwrap()),
                        blend,
                    })
                }
                "vertex" => continue,
                other => panic!("stage {other}"),
            };
            match messages {
                Ok(m) if m.is_empty() => {}
                Ok(m) => problems.push(format!("{variant}.{name}: {}", m.join("\n  "))),
                Err(err) => problems.push(format!("{variant}.{name}: {err}")),
            }
        }
    }
    eprintln!(
        "{compute} compute and {graphics} graphics pipelines ({} vertex shaders) from manifest.json under the Khronos validation layer on {}: {} with messages",
        vertex_used.len(),
        validator.device_name(),
        problems.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // Every vertex entry point was drawn with.
    for (variant, e) in entry_points() {
        if e["stage"] == "vertex" {
            let key = format!("{variant}.{}", e["name"].as_str().unwrap());
            assert!(
                vertex_used.contains(&key),
                "{key} is never paired with a fragment shader"
            );
        }
    }
}

/// The layer is live: a layout built from a wrong manifest entry (a storage buffer
/// declared as a uniform buffer) is reported.
#[test]
fn a_wrong_manifest_layout_is_reported() {
    let dir = exported();
    let inject = manifest()["variants"]
        .as_array()
        .unwrap()
        .iter()
        .find(|v| v["name"] == "inject@default")
        .unwrap();
    let mut entry = inject["entry_points"][0].clone();
    for b in entry["bindings"].as_array_mut().unwrap() {
        if b["name"] == "lights" {
            b["resource"]["type"] = Value::from("uniform");
        }
    }
    let mut sets = Vec::new();
    add_bindings(&mut sets, &entry);
    let spirv = read_spirv(dir, entry["files"]["spirv"].as_str().unwrap());
    let messages = Validator::new()
        .unwrap()
        .compute_pipeline(&spirv, "inject", &sets)
        .unwrap();
    assert!(
        !messages.is_empty(),
        "the validation layer reports the mismatch"
    );
}

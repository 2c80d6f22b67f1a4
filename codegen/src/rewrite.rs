//! Rewrites of the text naga emits, where a backend has no option for what engines
//! need, each tested below on naga's own output shapes:
//!
//! - GLSL: readable resource names; uniform and storage blocks named after their
//!   binding (`<name>_block`) instead of naga's per-stage `<Type>_block_<id><Stage>`,
//!   so a block shared by the vertex and fragment stage links into one program.
//! - HLSL: classic sampler registers instead of naga's sampler heap; stores into
//!   storage textures with fewer than four channels write that many components (naga
//!   stores a `float4` into `RWTexture2DArray<float>`, which Slang rejects and DXC
//!   warns about); the declaration type of every binding, for the manifest.
//! - MSL: the `_mslBufferSizes` argument (which bindings' byte sizes it holds).

use std::collections::HashMap;

use crate::Stage;
use crate::reflect::{EntryReflection, MslBufferSize, MslBufferSizes, Resource};

/// Identifiers that a WGSL binding may legally use but GLSL reserves.
const GLSL_RESERVED: &[&str] = &[
    "active",
    "attribute",
    "buffer",
    "centroid",
    "coherent",
    "common",
    "filter",
    "flat",
    "image",
    "in",
    "inout",
    "input",
    "invariant",
    "layout",
    "main",
    "noperspective",
    "out",
    "output",
    "partition",
    "patch",
    "precision",
    "readonly",
    "resource",
    "restrict",
    "sample",
    "sampler",
    "shared",
    "smooth",
    "struct",
    "subroutine",
    "texture",
    "uniform",
    "varying",
    "volatile",
    "writeonly",
];

fn is_word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Replaces whole-word occurrences of `from` with `to`.
pub(crate) fn replace_word(text: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(pos) = rest.find(from) {
        let before = rest[..pos].chars().next_back();
        let after = rest[pos + from.len()..].chars().next();
        out.push_str(&rest[..pos]);
        if before.is_some_and(is_word_char) || after.is_some_and(is_word_char) {
            out.push_str(from);
        } else {
            out.push_str(to);
        }
        rest = &rest[pos + from.len()..];
    }
    out.push_str(rest);
    out
}

fn contains_word(text: &str, word: &str) -> bool {
    replace_word(text, word, "") != text
}

/// GLSL names: naga names resources `_group_G_binding_B_<stage>`; the WGSL name is used
/// instead wherever it is a safe, unused GLSL identifier. Blocks are named
/// `<identifier>_block`. Both names are recorded in the reflection.
pub(crate) fn glsl(mut text: String, reflection: &mut EntryReflection, stage: Stage) -> String {
    let suffix = match stage {
        Stage::Compute => "cs",
        Stage::Vertex => "vs",
        Stage::Fragment => "fs",
    };
    for b in &mut reflection.bindings {
        let Some(slot) = b.glsl.as_mut() else {
            continue;
        };
        let naga_name = format!("_group_{}_binding_{}_{suffix}", b.group, b.binding);
        let safe = !b.name.starts_with("gl_")
            && !b.name.starts_with('_')
            && !GLSL_RESERVED.contains(&b.name.as_str())
            && !contains_word(&text, &b.name);
        if safe && contains_word(&text, &naga_name) {
            text = replace_word(&text, &naga_name, &b.name);
            slot.name = b.name.clone();
        } else {
            slot.name = naga_name;
        }
    }
    let mut blocks: HashMap<String, String> = HashMap::new();
    let lines: Vec<String> = text
        .lines()
        .map(|line| match glsl_block(line) {
            Some((block, instance)) => {
                let name = format!("{instance}_block");
                blocks.insert(instance.to_string(), name.clone());
                line.replacen(block, &name, 1)
            }
            None => line.to_string(),
        })
        .collect();
    for b in &mut reflection.bindings {
        if let Some(slot) = b.glsl.as_mut() {
            slot.block = blocks.get(&slot.name).cloned();
        }
    }
    lines.join("\n") + "\n"
}

/// For a block declaration line `layout(...) uniform|buffer NAME { T instance; };` (or
/// `T instance[];`), its block name and instance name.
fn glsl_block(line: &str) -> Option<(&str, &str)> {
    if !line.starts_with("layout(") {
        return None;
    }
    let open = line.find(" { ")?;
    let head = &line[..open];
    if !(head.contains(" uniform ") || head.contains(" buffer ")) {
        return None;
    }
    let block = head.rsplit(' ').next()?;
    let body = line[open + 3..].strip_suffix(" };")?.trim_end_matches(';');
    let instance = body.rsplit(' ').next()?.trim_end_matches("[]");
    Some((block, instance))
}

/// HLSL: classic samplers (when `classic`), stores sized to their storage texture, and
/// the declaration type of every binding.
pub(crate) fn hlsl(text: String, reflection: &mut EntryReflection, classic: bool) -> String {
    let mut narrow: HashMap<String, &'static str> = HashMap::new();
    let mut out = Vec::new();
    for line in text.lines() {
        if classic {
            if line.starts_with("SamplerState nagaSamplerHeap[")
                || line.starts_with("SamplerComparisonState nagaComparisonSamplerHeap[")
                || (line.starts_with("StructuredBuffer<uint> nagaGroup")
                    && line.contains("SamplerIndexArray"))
            {
                continue;
            }
            if let Some(rest) = line.strip_prefix("static const ")
                && let Some((ty, name)) = classic_sampler(rest)
            {
                let slot = reflection
                    .bindings
                    .iter()
                    .find(|b| b.name == name && b.resource.is_sampler())
                    .map(|b| (b.hlsl.register.clone(), b.hlsl.space));
                if let Some((register, space)) = slot {
                    out.push(format!("{ty} {name} : register({register}, space{space});"));
                    continue;
                }
            }
        }
        if let Some((name, components)) = storage_texture_components(line)
            && components < 4
        {
            narrow.insert(name.to_string(), [".x", ".xy", ".xyz"][components - 1]);
        }
        out.push(narrow_store(line, &narrow));
    }
    let text = out.join("\n") + "\n";
    for b in &mut reflection.bindings {
        b.hlsl.ty = hlsl_declaration_type(&text, &b.name).unwrap_or_default();
    }
    text
}

/// `SamplerState name = nagaSamplerHeap[...];` -> (`SamplerState`, `name`).
fn classic_sampler(rest: &str) -> Option<(&str, &str)> {
    let (decl, value) = rest.split_once(" = ")?;
    if !(value.starts_with("nagaSamplerHeap[") || value.starts_with("nagaComparisonSamplerHeap[")) {
        return None;
    }
    let (ty, name) = decl.split_once(' ')?;
    Some((ty, name))
}

/// `RWTexture2DArray<float> name : register(...)` -> (`name`, 1).
fn storage_texture_components(line: &str) -> Option<(&str, usize)> {
    let rest = line.strip_prefix("RWTexture")?;
    let open = rest.find('<')?;
    let close = rest.find('>')?;
    let element = &rest[open + 1..close];
    let components = match element.trim_start_matches(|c: char| c.is_ascii_alphabetic()) {
        "" => 1,
        n => n.parse().ok()?,
    };
    let name = rest[close + 1..].split_whitespace().next()?;
    Some((name, components))
}

/// `    name[coord] = value;` -> `    name[coord] = (value).x;` for a narrow texture.
fn narrow_store(line: &str, narrow: &HashMap<String, &'static str>) -> String {
    let trimmed = line.trim_start();
    let indent = &line[..line.len() - trimmed.len()];
    if let Some(bracket) = trimmed.find('[')
        && let Some(swizzle) = narrow.get(&trimmed[..bracket])
        && let Some(eq) = trimmed.find("] = ")
        && let Some(value) = trimmed[eq + 4..].strip_suffix(';')
    {
        return format!("{indent}{} = ({value}){swizzle};", &trimmed[..eq + 1]);
    }
    line.to_string()
}

/// The type of the HLSL declaration of binding `name`: `cbuffer` or the type before the
/// name in `TYPE name : register(...)`.
fn hlsl_declaration_type(text: &str, name: &str) -> Option<String> {
    text.lines().find_map(|line| {
        let (decl, _) = line.split_once(" : register(")?;
        if decl == format!("cbuffer {name}") {
            return Some("cbuffer".to_string());
        }
        let ty = decl.strip_suffix(name)?.strip_suffix(' ')?;
        (!ty.is_empty()).then(|| ty.to_string())
    })
}

/// MSL: the members of `struct _mslBufferSizes` (`uint sizeN;`, N the global's handle
/// index in `globals`) mapped to their bindings, and the buffer index naga puts the
/// struct at.
pub(crate) fn msl_buffer_sizes(
    text: &str,
    reflection: &mut EntryReflection,
    globals: &[(u32, String)],
    index: u32,
) {
    let Some(start) = text.find("struct _mslBufferSizes {") else {
        return;
    };
    let body = &text[start..text[start..].find("};").map_or(text.len(), |e| start + e)];
    let members: Vec<MslBufferSize> = body
        .lines()
        .skip(1)
        .filter_map(|line| {
            let member = line.trim().strip_prefix("uint ")?.strip_suffix(';')?;
            let handle: u32 = member.strip_prefix("size")?.parse().ok()?;
            let name = &globals.iter().find(|(h, _)| *h == handle)?.1;
            let b = reflection.bindings.iter().find(|b| &b.name == name)?;
            Some(MslBufferSize {
                member: member.to_string(),
                binding_name: name.clone(),
                group: b.group,
                binding: b.binding,
            })
        })
        .collect();
    if !members.is_empty() {
        reflection.msl_buffer_sizes = Some(MslBufferSizes { index, members });
    }
}

/// Whether a binding is a runtime-sized storage buffer (MSL passes its size).
pub(crate) fn has_runtime_array(resource: &Resource) -> bool {
    matches!(
        resource,
        Resource::Buffer {
            stride: Some(_),
            ..
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reflect::{Binding, GlslSlot, HlslSlot, MslSlot, SpirvSlot};

    fn binding(name: &str, resource: Resource, register: &str, glsl: Option<&str>) -> Binding {
        Binding {
            name: name.to_string(),
            group: 0,
            binding: 0,
            resource,
            spirv: SpirvSlot { set: 0, binding: 0 },
            hlsl: HlslSlot {
                register: register.to_string(),
                space: 0,
                ty: String::new(),
                sampler_index: None,
            },
            glsl: glsl.map(|ns| GlslSlot {
                name: String::new(),
                block: None,
                binding: 0,
                namespace: ns.to_string(),
            }),
            msl: MslSlot {
                kind: "buffer".to_string(),
                index: 0,
            },
        }
    }

    fn reflection(bindings: Vec<Binding>) -> EntryReflection {
        EntryReflection {
            workgroup_size: None,
            bindings,
            hlsl_sampler_index_buffers: Vec::new(),
            msl_buffer_sizes: None,
            structs: Vec::new(),
        }
    }

    #[test]
    fn glsl_blocks_are_named_after_their_binding_in_every_stage() {
        let uniform = Resource::Buffer {
            ty: "uniform".into(),
            struct_name: "FogHull".into(),
            size: 176,
            stride: None,
        };
        for (stage, naga_block) in [
            (Stage::Vertex, "FogHull_block_0Vertex"),
            (Stage::Fragment, "FogHull_block_0Fragment"),
        ] {
            let mut r = reflection(vec![binding(
                "hull",
                uniform.clone(),
                "b0",
                Some("uniform_block"),
            )]);
            let naga_name = format!(
                "_group_0_binding_0_{}",
                if stage == Stage::Vertex { "vs" } else { "fs" }
            );
            let text = format!(
                "layout(std140, binding = 0) uniform {naga_block} {{ FogHull {naga_name}; }};\nvoid main() {{ float d = {naga_name}.density; }}\n"
            );
            let out = glsl(text, &mut r, stage);
            assert!(
                out.contains("uniform hull_block { FogHull hull; };"),
                "{out}"
            );
            assert!(out.contains("float d = hull.density;"), "{out}");
            assert_eq!(
                r.bindings[0].glsl.as_ref().unwrap().block.as_deref(),
                Some("hull_block")
            );
        }
        let storage = Resource::Buffer {
            ty: "read-only-storage".into(),
            struct_name: "array<FogLight>".into(),
            size: 64,
            stride: Some(64),
        };
        let mut r = reflection(vec![binding(
            "lights",
            storage,
            "t0",
            Some("shader_storage_block"),
        )]);
        let out = glsl(
            "layout(std430, binding = 0) readonly buffer type_12_block_5Compute { FogLight _group_0_binding_0_cs[]; };\n".into(),
            &mut r,
            Stage::Compute,
        );
        assert!(
            out.contains("readonly buffer lights_block { FogLight lights[]; };"),
            "{out}"
        );
    }

    #[test]
    fn hlsl_samplers_become_classic_registers() {
        let sampler = Resource::Sampler {
            ty: "filtering".into(),
        };
        let mut r = reflection(vec![binding("fog_sampler", sampler, "s0", None)]);
        let text = "SamplerState nagaSamplerHeap[2048]: register(s0, space0);\n\
                    SamplerComparisonState nagaComparisonSamplerHeap[2048]: register(s0, space1);\n\
                    StructuredBuffer<uint> nagaGroup0SamplerIndexArray : register(t1, space0);\n\
                    static const SamplerState fog_sampler = nagaSamplerHeap[nagaGroup0SamplerIndexArray[0]];\n"
            .to_string();
        let out = hlsl(text, &mut r, true);
        assert_eq!(out, "SamplerState fog_sampler : register(s0, space0);\n");
        assert_eq!(r.bindings[0].hlsl.ty, "SamplerState");
    }

    #[test]
    fn hlsl_stores_match_the_texture_channels() {
        let texture = Resource::StorageTexture {
            view_dimension: "2d-array".into(),
            format: "r32float".into(),
            access: "write-only".into(),
        };
        let mut r = reflection(vec![binding("filtered", texture, "u0", None)]);
        let text = "RWTexture2DArray<float> filtered : register(u0);\n\
                    RWTexture3D<float4> wide : register(u1);\n\
                    void f() {\n    filtered[int3(coord_1, layer)] = float4(v, 0.0, 0.0, 0.0);\n    wide[id] = texel;\n}\n"
            .to_string();
        let out = hlsl(text, &mut r, true);
        assert!(
            out.contains("    filtered[int3(coord_1, layer)] = (float4(v, 0.0, 0.0, 0.0)).x;"),
            "{out}"
        );
        assert!(out.contains("    wide[id] = texel;"), "{out}");
        assert_eq!(r.bindings[0].hlsl.ty, "RWTexture2DArray<float>");
    }

    #[test]
    fn msl_buffer_sizes_name_their_bindings() {
        let storage = Resource::Buffer {
            ty: "read-only-storage".into(),
            struct_name: "array<FogLight>".into(),
            size: 64,
            stride: Some(64),
        };
        let mut r = reflection(vec![binding("lights", storage, "t0", None)]);
        let text = "struct _mslBufferSizes {\n    uint size3;\n};\n";
        msl_buffer_sizes(text, &mut r, &[(3, "lights".to_string())], 5);
        let sizes = r.msl_buffer_sizes.unwrap();
        assert_eq!(sizes.index, 5);
        assert_eq!(sizes.members[0].member, "size3");
        assert_eq!(sizes.members[0].binding_name, "lights");
    }
}

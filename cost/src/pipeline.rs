//! The pipelines to compile, described so a worker process can build them: SPIR-V,
//! descriptor sets, and for a draw its vertex shader, vertex input and colour target.
//!
//! Two sources: a composed naga module written to SPIR-V as wgpu 30 writes it for
//! RADV (what the runtime hands the driver), and an export folder's `manifest.json`
//! with its SPIR-V files (what a user of the exports hands their driver).

use std::path::Path;

use naga::back::spv;
use serde::{Deserialize, Serialize};
use volfog_codegen::manifest::{self, RenderState};
use volfog_codegen::reflect::{self, HlslSamplers, Resource};

use crate::CostError;

/// SPIR-V and the entry point to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageCode {
    /// The SPIR-V words.
    pub spirv: Vec<u32>,
    /// The entry point.
    pub entry: String,
}

/// The type of a descriptor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DescriptorType {
    /// A uniform buffer.
    UniformBuffer,
    /// A storage buffer.
    StorageBuffer,
    /// A sampled image.
    SampledImage,
    /// A storage image.
    StorageImage,
    /// A sampler.
    Sampler,
}

/// One descriptor binding, visible to the pipeline's stages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BindingDesc {
    /// Its set.
    pub set: u32,
    /// Its binding.
    pub binding: u32,
    /// Its type.
    pub ty: DescriptorType,
}

/// One vertex attribute.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AttributeDesc {
    /// Shader location.
    pub location: u32,
    /// WebGPU vertex format (`float32x3`).
    pub format: String,
    /// Offset in the vertex.
    pub offset: u32,
}

/// One vertex buffer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct VertexBufferDesc {
    /// Bytes per element.
    pub stride: u32,
    /// Per instance instead of per vertex.
    pub per_instance: bool,
    /// Its attributes.
    pub attributes: Vec<AttributeDesc>,
}

/// A blend of the colour target: (source factor, destination factor) per channel
/// group, WebGPU names, operation add.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct BlendDesc {
    /// Colour channels.
    pub color: (String, String),
    /// Alpha.
    pub alpha: (String, String),
}

/// A pipeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PipelineDesc {
    /// A compute pipeline.
    Compute {
        /// Its shader.
        stage: StageCode,
        /// Its bindings.
        bindings: Vec<BindingDesc>,
    },
    /// A graphics pipeline with one colour target.
    Graphics {
        /// The vertex shader.
        vertex: StageCode,
        /// The fragment shader.
        fragment: StageCode,
        /// The bindings of both.
        bindings: Vec<BindingDesc>,
        /// Vertex input.
        vertex_buffers: Vec<VertexBufferDesc>,
        /// The colour target's format (WebGPU name).
        color_format: String,
        /// Its blend.
        blend: Option<BlendDesc>,
    },
}

/// A pipeline to compile, named.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Job {
    /// `variant.entry` (or another name the caller reads back).
    pub label: String,
    /// The pipeline.
    pub pipeline: PipelineDesc,
    /// Also return the count of loops in ACO's IR (captures its internal
    /// representations, which costs compile time).
    pub count_loops: bool,
}

/// Validates a module with every capability.
pub fn validate(module: &naga::Module, what: &str) -> Result<naga::valid::ModuleInfo, CostError> {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .map_err(|e| CostError::Validation {
        what: what.to_string(),
        message: e.emit_to_string(""),
    })
}

/// The runtime checks wgpu 30 writes into a shader module's SPIR-V.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RuntimeChecks {
    /// `Device::create_shader_module` (`ShaderRuntimeChecks::checked()`), as volfog's
    /// runtime creates its modules: index bounds checks, bounded loops, checked
    /// integer division.
    #[default]
    Checked,
    /// `Device::create_shader_module_trusted` with `ShaderRuntimeChecks::unchecked()`,
    /// as Bevy 0.20 creates its own shaders (`RenderDevice::create_shader_module`):
    /// wgpu-hal then writes no bounds check, no loop bound and no division check
    /// (`vulkan/device.rs`, `compile_stage`).
    Unchecked,
}

/// The SPIR-V wgpu 30 writes for entry point `entry` of `module` on a Vulkan 1.3
/// device with robust buffer and image access (RADV): wgpu-hal's options
/// (`vulkan/adapter.rs`): SPIR-V 1.6, index bounds checks `Restrict`, buffer and
/// image loads unchecked (the device's robustness covers them), workgroup memory
/// zeroed natively, every loop bounded (`force_loop_bounding`), integer division
/// checked, varyings labelled and the point size forced.
pub fn runtime_spirv(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    what: &str,
) -> Result<Vec<u32>, CostError> {
    spirv_with_checks(module, info, entry, what, RuntimeChecks::Checked)
}

/// [`runtime_spirv`] with the runtime checks `checks`.
pub fn spirv_with_checks(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    what: &str,
    checks: RuntimeChecks,
) -> Result<Vec<u32>, CostError> {
    let ep = module
        .entry_points
        .iter()
        .find(|e| e.name == entry)
        .ok_or_else(|| CostError::Spirv {
            what: what.to_string(),
            message: format!("no entry point {entry}"),
        })?;
    let checked = checks == RuntimeChecks::Checked;
    let options = spv::Options {
        lang_version: (1, 6),
        flags: spv::WriterFlags::LABEL_VARYINGS | spv::WriterFlags::FORCE_POINT_SIZE,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: if checked {
                naga::proc::BoundsCheckPolicy::Restrict
            } else {
                naga::proc::BoundsCheckPolicy::Unchecked
            },
            buffer: naga::proc::BoundsCheckPolicy::Unchecked,
            image_load: naga::proc::BoundsCheckPolicy::Unchecked,
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        },
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::Native,
        force_loop_bounding: checked,
        emit_int_div_checks: checked,
        ..Default::default()
    };
    let pipeline = spv::PipelineOptions {
        shader_stage: ep.stage,
        entry_point: entry.to_string(),
    };
    let (module, info) =
        naga::back::pipeline_constants::process_overrides(module, info, None, &Default::default())
            .map_err(|e| CostError::Spirv {
                what: what.to_string(),
                message: e.to_string(),
            })?;
    spv::write_vec(&module, &info, &options, Some(&pipeline)).map_err(|e| CostError::Spirv {
        what: format!("{what}.{entry}"),
        message: e.to_string(),
    })
}

/// The descriptor type of a reflected resource.
fn descriptor_type(resource: &Resource) -> DescriptorType {
    match resource {
        Resource::Buffer { ty, .. } if ty == "uniform" => DescriptorType::UniformBuffer,
        Resource::Buffer { .. } => DescriptorType::StorageBuffer,
        Resource::Texture { .. } => DescriptorType::SampledImage,
        Resource::StorageTexture { .. } => DescriptorType::StorageImage,
        Resource::Sampler { .. } => DescriptorType::Sampler,
    }
}

/// The bindings entry point `entry` of a validated module uses.
fn bindings_of(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
) -> Vec<BindingDesc> {
    let Some(index) = module.entry_points.iter().position(|e| e.name == entry) else {
        return Vec::new();
    };
    reflect::reflect_entry(module, info, index, &[], HlslSamplers::Classic)
        .bindings
        .iter()
        .map(|b| BindingDesc {
            set: b.spirv.set,
            binding: b.spirv.binding,
            ty: descriptor_type(&b.resource),
        })
        .collect()
}

/// Adds `more` to `into`, once per (set, binding).
fn merge(into: &mut Vec<BindingDesc>, more: Vec<BindingDesc>) {
    for b in more {
        if !into
            .iter()
            .any(|a| a.set == b.set && a.binding == b.binding)
        {
            into.push(b);
        }
    }
}

fn blend_desc(blend: &manifest::Blend) -> BlendDesc {
    BlendDesc {
        color: (
            blend.color.src_factor.to_string(),
            blend.color.dst_factor.to_string(),
        ),
        alpha: (
            blend.alpha.src_factor.to_string(),
            blend.alpha.dst_factor.to_string(),
        ),
    }
}

fn vertex_buffers(render: &RenderState) -> Vec<VertexBufferDesc> {
    render
        .vertex_buffers
        .iter()
        .map(|b| VertexBufferDesc {
            stride: b.array_stride,
            per_instance: b.step_mode == "instance",
            attributes: b
                .attributes
                .iter()
                .map(|a| AttributeDesc {
                    location: a.shader_location,
                    format: a.format.to_string(),
                    offset: a.offset,
                })
                .collect(),
        })
        .collect()
}

/// The pipeline of entry point `entry` of a composed module, written as wgpu writes
/// it for the runtime; a fragment entry point is drawn with the pipeline state
/// `render` (a pass's manifest entry: [`render_state`]). `count_loops` as in [`Job`].
pub fn runtime_job(
    label: &str,
    module: &naga::Module,
    entry: &str,
    render: Option<&RenderState>,
    count_loops: bool,
) -> Result<Job, CostError> {
    job_with_checks(
        label,
        module,
        entry,
        render,
        count_loops,
        RuntimeChecks::Checked,
    )
}

/// [`runtime_job`] with the runtime checks `checks` (the vertex shader's too).
pub fn job_with_checks(
    label: &str,
    module: &naga::Module,
    entry: &str,
    render: Option<&RenderState>,
    count_loops: bool,
    checks: RuntimeChecks,
) -> Result<Job, CostError> {
    let info = validate(module, label)?;
    let ep = module
        .entry_points
        .iter()
        .find(|e| e.name == entry)
        .ok_or_else(|| CostError::Invalid {
            field: "entry",
            message: format!("{label} has no entry point {entry}"),
        })?;
    let stage = StageCode {
        spirv: spirv_with_checks(module, &info, entry, label, checks)?,
        entry: entry.to_string(),
    };
    let mut bindings = bindings_of(module, &info, entry);
    let pipeline = match ep.stage {
        naga::ShaderStage::Compute => PipelineDesc::Compute { stage, bindings },
        naga::ShaderStage::Fragment => {
            let render = render.ok_or_else(|| CostError::Invalid {
                field: "render",
                message: format!("{label}.{entry} draws, but no render state was given"),
            })?;
            let vertex = match render.vertex {
                Some((vertex_pass, vertex_entry)) => {
                    let vertex_module = volfog::shaders::compose(vertex_pass, &[])?;
                    let vertex_info = validate(&vertex_module, vertex_pass)?;
                    merge(
                        &mut bindings,
                        bindings_of(&vertex_module, &vertex_info, vertex_entry),
                    );
                    StageCode {
                        spirv: spirv_with_checks(
                            &vertex_module,
                            &vertex_info,
                            vertex_entry,
                            vertex_pass,
                            checks,
                        )?,
                        entry: vertex_entry.to_string(),
                    }
                }
                None => {
                    let vertex_entry = module
                        .entry_points
                        .iter()
                        .find(|e| e.stage == naga::ShaderStage::Vertex)
                        .map(|e| e.name.clone())
                        .ok_or_else(|| CostError::Invalid {
                            field: "pass",
                            message: format!("{label} has no vertex entry point"),
                        })?;
                    merge(&mut bindings, bindings_of(module, &info, &vertex_entry));
                    StageCode {
                        spirv: spirv_with_checks(module, &info, &vertex_entry, label, checks)?,
                        entry: vertex_entry,
                    }
                }
            };
            PipelineDesc::Graphics {
                vertex,
                fragment: stage,
                bindings,
                vertex_buffers: vertex_buffers(render),
                color_format: render.formats[0].to_string(),
                blend: render.blend.as_ref().map(blend_desc),
            }
        }
        other => {
            return Err(CostError::Invalid {
                field: "entry",
                message: format!("{label}.{entry} is a {other:?} entry point: not a pipeline"),
            });
        }
    };
    Ok(Job {
        label: label.to_string(),
        pipeline,
        count_loops,
    })
}

/// The draw state the manifest gives pass `pass` (`None` for a compute pass).
pub fn render_state(pass: &str) -> Option<RenderState> {
    manifest::pass(pass).and_then(|p| p.render)
}

/// Every pipeline of an export folder (`volfog export --target spirv`): a compute
/// pipeline per compute entry point and a graphics pipeline per fragment entry point
/// with the vertex shader the manifest names, built from `manifest.json` and the
/// SPIR-V files alone. Labels are `variant.entry`.
pub fn exported_jobs(dir: &Path) -> Result<Vec<Job>, CostError> {
    crate::exported::jobs(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `OpExtInst` instructions of the GLSL.std.450 set's `UMin` (38) in a module (the
    /// clamp that a `Restrict` index bounds check writes).
    fn umins(words: &[u32]) -> usize {
        let mut n = 0;
        let mut i = 5;
        while i < words.len() {
            let (count, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
            if op == 12 && words.get(i + 4) == Some(&38) {
                n += 1;
            }
            i += count.max(1);
        }
        n
    }

    #[test]
    fn unchecked_modules_carry_no_bounds_check_and_no_loop_bound() {
        let module = naga::front::wgsl::parse_str(
            "
            @group(0) @binding(0) var<storage, read_write> data: array<f32, 64>;
            @group(0) @binding(1) var<uniform> n: vec4<u32>;
            @compute @workgroup_size(64)
            fn main(@builtin(local_invocation_index) i: u32) {
                var a = array<f32, 4>(1.0, 2.0, 3.0, 4.0);
                var s = 0.0;
                for (var k = 0u; k < n.x; k++) {
                    s += a[k];
                }
                data[i] = s;
            }",
        )
        .unwrap();
        let info = validate(&module, "checks").unwrap();
        let checked =
            spirv_with_checks(&module, &info, "main", "checks", RuntimeChecks::Checked).unwrap();
        let unchecked =
            spirv_with_checks(&module, &info, "main", "checks", RuntimeChecks::Unchecked).unwrap();
        assert_eq!(
            checked,
            runtime_spirv(&module, &info, "main", "checks").unwrap()
        );
        // The dynamic index into `a` is clamped only when checked, and the loop's bound
        // (a second counter and its compare) adds words.
        assert!(umins(&checked) >= 1);
        assert_eq!(umins(&unchecked), 0);
        assert!(
            unchecked.len() < checked.len(),
            "{} {}",
            unchecked.len(),
            checked.len()
        );
        // Both are pipelines RADV would be handed: the same bindings.
        let job = |c| job_with_checks("checks", &module, "main", None, false, c).unwrap();
        let (a, b) = (job(RuntimeChecks::Checked), job(RuntimeChecks::Unchecked));
        match (&a.pipeline, &b.pipeline) {
            (
                PipelineDesc::Compute { bindings: x, .. },
                PipelineDesc::Compute { bindings: y, .. },
            ) => assert_eq!(x, y),
            _ => panic!("compute pipelines"),
        }
    }
}

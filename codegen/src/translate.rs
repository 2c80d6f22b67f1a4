//! Compaction and translation of a composed module into every target.

use std::collections::BTreeMap;

use naga::back::{glsl, hlsl, msl, spv, wgsl};
use naga::valid::ModuleInfo;

use crate::compose::{Defines, validate, with_shared_composer};
use crate::manifest::{PASSES, PassSource, Variant};
use crate::reflect::{EntryReflection, HlslSamplers, Resource, reflect_entry};
use crate::{CodegenError, Stage, Target, names, rewrite};

/// Choices of a translation.
#[derive(Debug, Clone, Copy, Default)]
pub struct TranslateOptions<'a> {
    /// How HLSL binds samplers.
    pub hlsl_samplers: HlslSamplers,
    /// Samplers of the pass that are bound as non-filtering (by WGSL name).
    pub non_filtering_samplers: &'a [&'a str],
}

/// The module restricted to one entry point and compacted, so that each exported
/// file holds exactly what that entry point uses.
fn single_entry(module: &naga::Module, index: usize) -> naga::Module {
    let mut m = module.clone();
    let ep = m.entry_points.swap_remove(index);
    m.entry_points = vec![ep];
    naga::compact::compact(&mut m, naga::compact::KeepUnused::No);
    m
}

/// Translates every entry point of a composed module.
pub fn translate(
    variant: &str,
    mut module: naga::Module,
    options: &TranslateOptions<'_>,
) -> Result<Vec<EntryOutput>, CodegenError> {
    names::make_readable(&mut module, variant)?;
    let info = validate(&module, variant)?;
    let (module, _) = naga::back::pipeline_constants::process_overrides(
        &module,
        &info,
        None,
        &Default::default(),
    )
    .map_err(|e| CodegenError::Validation(format!("{variant}: overrides: {e}")))?;
    let module = module.into_owned();

    let mut out = Vec::new();
    for index in 0..module.entry_points.len() {
        let m = single_entry(&module, index);
        let ep = &m.entry_points[0];
        let entry = ep.name.clone();
        let stage = Stage::from_naga(ep.stage).ok_or_else(|| CodegenError::Backend {
            target: Target::Wgsl,
            variant: variant.to_string(),
            entry: entry.clone(),
            message: format!("unsupported stage {:?}", ep.stage),
        })?;
        let info = validate(&m, &format!("{variant} entry point {entry}"))?;
        let mut reflection = reflect_entry(
            &m,
            &info,
            0,
            options.non_filtering_samplers,
            options.hlsl_samplers,
        );
        let backend_err = |target: Target, message: String| CodegenError::Backend {
            target,
            variant: variant.to_string(),
            entry: entry.clone(),
            message,
        };
        let wgsl = wgsl::write_string(&m, &info, wgsl::WriterFlags::empty())
            .map_err(|e| backend_err(Target::Wgsl, e.to_string()))?;
        let spirv = write_spirv(&m, &info, &reflection, stage, &entry)
            .map_err(|e| backend_err(Target::Spirv, e))?;
        let glsl = write_glsl(&m, &info, &mut reflection, stage, &entry)
            .map_err(|e| backend_err(Target::Glsl, e))?;
        let hlsl = write_hlsl(&m, &info, &reflection, stage, &entry)
            .map_err(|e| backend_err(Target::Hlsl, e))?;
        let hlsl = rewrite::hlsl(
            hlsl,
            &mut reflection,
            options.hlsl_samplers == HlslSamplers::Classic,
        );
        let msl = write_msl(&m, &info, &mut reflection, stage, &entry)
            .map_err(|e| backend_err(Target::Msl, e))?;
        out.push(EntryOutput {
            entry,
            stage,
            wgsl,
            spirv,
            glsl,
            hlsl,
            msl,
            reflection,
        });
    }
    Ok(out)
}

/// Output of one entry point of one variant in every target.
#[derive(Debug, Clone)]
pub struct EntryOutput {
    /// Entry point name, as in the WGSL source.
    pub entry: String,
    /// Its stage.
    pub stage: Stage,
    /// Flattened WGSL.
    pub wgsl: String,
    /// SPIR-V words.
    pub spirv: Vec<u32>,
    /// GLSL 450.
    pub glsl: String,
    /// HLSL (SM 6.0; SM 6.1 for an entry point that reads the view index).
    pub hlsl: String,
    /// MSL 2.1 (2.2 for an entry point that reads the view index).
    pub msl: String,
    /// Bindings, structs and workgroup size, for the manifest.
    pub reflection: EntryReflection,
}

impl EntryOutput {
    /// The exported file name of this entry point for a target:
    /// `<variant>.<entry>.<stage>.<ext>`.
    pub fn file_name(&self, variant: &str, target: Target) -> String {
        format!(
            "{variant}.{}.{}.{}",
            self.entry,
            self.stage.short(),
            target.extension()
        )
    }

    /// The bytes of the exported file for a target.
    pub fn bytes(&self, target: Target) -> Vec<u8> {
        match target {
            Target::Wgsl => self.wgsl.clone().into_bytes(),
            Target::Spirv => self.spirv.iter().flat_map(|w| w.to_le_bytes()).collect(),
            Target::Glsl => self.glsl.clone().into_bytes(),
            Target::Hlsl => self.hlsl.clone().into_bytes(),
            Target::Msl => self.msl.clone().into_bytes(),
        }
    }
}

/// Output of one variant: a pass composed under one define set.
#[derive(Debug, Clone)]
pub struct VariantOutput {
    /// Variant name, `pass@default` or `pass@A+B`.
    pub name: String,
    /// The pass.
    pub pass: String,
    /// Defines, sorted, as `NAME` or `NAME=VALUE`.
    pub defines: Vec<String>,
    /// One output per entry point.
    pub entries: Vec<EntryOutput>,
}

/// Composes, validates and translates one pass under a define set.
pub fn generate(
    composer: &mut naga_oil::compose::Composer,
    pass: &PassSource,
    defines: &Defines,
    hlsl_samplers: HlslSamplers,
) -> Result<VariantOutput, CodegenError> {
    let name = defines.variant_name(pass.name);
    let module = crate::compose::compose_pass(composer, pass, defines)?;
    let options = TranslateOptions {
        hlsl_samplers,
        non_filtering_samplers: pass.non_filtering_samplers,
    };
    let entries = translate(&name, module, &options)?;
    Ok(VariantOutput {
        name,
        pass: pass.name.to_string(),
        defines: defines.as_strings(),
        entries,
    })
}

/// Composes and translates a variant of the manifest with the shared composer.
pub fn generate_variant(
    variant: &Variant,
    hlsl_samplers: HlslSamplers,
) -> Result<VariantOutput, CodegenError> {
    let defines = Defines::flags(variant.defines.iter().copied());
    with_shared_composer(|composer| generate(composer, variant.pass, &defines, hlsl_samplers))
}

/// Composes a pass under a custom define set (`NAME` or `NAME=VALUE` items) and
/// translates it to every target. Unknown passes or defines, values out of range and
/// exclusive defines set together are errors that list what is valid.
///
/// ```
/// use volfog_codegen::reflect::HlslSamplers;
/// use volfog_codegen::translate::compose_variant;
///
/// let scan = compose_variant("scan", &[], HlslSamplers::Classic).unwrap();
/// assert_eq!(scan.name, "scan@default");
/// assert!(scan.entries[0].hlsl.contains("RWTexture3D"));
/// assert!(compose_variant("scan", &["VOLFOG_NOPE".into()], HlslSamplers::Classic).is_err());
/// ```
pub fn compose_variant(
    pass_name: &str,
    defines: &[String],
    hlsl_samplers: HlslSamplers,
) -> Result<VariantOutput, CodegenError> {
    let pass = crate::manifest::pass(pass_name).ok_or_else(|| {
        CodegenError::Define(format!(
            "unknown pass {pass_name}; passes: {}",
            PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let defines = Defines::parse(pass, defines)?;
    with_shared_composer(|composer| generate(composer, pass, &defines, hlsl_samplers))
}

/// [`compose_variant`] with the users' modules of the pass's hooks
/// ([`crate::custom`]): a hook's define then composes with the user's function (an
/// unused module is not added).
pub fn compose_variant_with(
    pass_name: &str,
    defines: &[String],
    hlsl_samplers: HlslSamplers,
    modules: &[(&crate::manifest::Hook, &crate::custom::CustomModule)],
) -> Result<VariantOutput, CodegenError> {
    let pass = crate::manifest::pass(pass_name).ok_or_else(|| {
        CodegenError::Define(format!(
            "unknown pass {pass_name}; passes: {}",
            PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let defines = Defines::parse(pass, defines)?;
    let used: Vec<_> = modules
        .iter()
        .copied()
        .filter(|(hook, _)| pass.hooks.contains(hook) && defines.contains(hook.define))
        .collect();
    crate::custom::with_custom_modules(&used, |composer| {
        generate(composer, pass, &defines, hlsl_samplers)
    })
}

/// Whether the (single) entry point of `module` reads `@builtin(view_index)`.
pub fn reads_view_index(module: &naga::Module) -> bool {
    let view_index =
        |b: &Option<naga::Binding>| *b == Some(naga::Binding::BuiltIn(naga::BuiltIn::ViewIndex));
    module.entry_points.iter().any(|ep| {
        ep.function.arguments.iter().any(|a| {
            view_index(&a.binding)
                || match &module.types[a.ty].inner {
                    naga::TypeInner::Struct { members, .. } => {
                        members.iter().any(|m| view_index(&m.binding))
                    }
                    _ => false,
                }
        })
    })
}

fn resource_binding(group: u32, binding: u32) -> naga::ResourceBinding {
    naga::ResourceBinding { group, binding }
}

fn write_spirv(
    module: &naga::Module,
    info: &ModuleInfo,
    reflection: &EntryReflection,
    stage: Stage,
    entry: &str,
) -> Result<Vec<u32>, String> {
    let binding_map = reflection
        .bindings
        .iter()
        .map(|b| {
            (
                resource_binding(b.group, b.binding),
                spv::BindingInfo {
                    descriptor_set: b.spirv.set,
                    binding: b.spirv.binding,
                    binding_array_size: None,
                },
            )
        })
        .collect();
    let options = spv::Options {
        lang_version: (1, 3),
        // Debug names make the disassembly readable; the coordinate-space adjustment
        // keeps WebGPU's clip space (y up) as wgpu does on Vulkan.
        flags: spv::WriterFlags::DEBUG
            | spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | spv::WriterFlags::LABEL_VARYINGS
            | spv::WriterFlags::CLAMP_FRAG_DEPTH,
        fake_missing_bindings: false,
        binding_map,
        ..Default::default()
    };
    let pipeline = spv::PipelineOptions {
        shader_stage: stage.to_naga(),
        entry_point: entry.to_string(),
    };
    spv::write_vec(module, info, &options, Some(&pipeline)).map_err(|e| e.to_string())
}

fn write_glsl(
    module: &naga::Module,
    info: &ModuleInfo,
    reflection: &mut EntryReflection,
    stage: Stage,
    entry: &str,
) -> Result<String, String> {
    let mut binding_map = BTreeMap::new();
    for b in &reflection.bindings {
        if let Some(slot) = &b.glsl {
            let index =
                u8::try_from(slot.binding).map_err(|_| "too many GLSL bindings".to_string())?;
            binding_map.insert(resource_binding(b.group, b.binding), index);
        }
    }
    let options = glsl::Options {
        version: glsl::Version::Desktop(450),
        // Keeps WebGPU's clip space: y is flipped and depth mapped to [-1, 1] for OpenGL.
        writer_flags: glsl::WriterFlags::ADJUST_COORDINATE_SPACE,
        binding_map,
        zero_initialize_workgroup_memory: true,
    };
    let pipeline = glsl::PipelineOptions {
        shader_stage: stage.to_naga(),
        entry_point: entry.to_string(),
        multiview: None,
    };
    let mut text = String::new();
    let mut writer = glsl::Writer::new(
        &mut text,
        module,
        info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .map_err(|e| e.to_string())?;
    writer.write().map_err(|e| e.to_string())?;
    Ok(rewrite::glsl(text, reflection, stage))
}

fn hlsl_target(register: &str, space: u32) -> Result<hlsl::BindTarget, String> {
    let index = register[1..]
        .parse::<u32>()
        .map_err(|_| format!("bad register {register}"))?;
    Ok(hlsl::BindTarget {
        space: u8::try_from(space).map_err(|_| "space out of range".to_string())?,
        register: index,
        binding_array_size: None,
        dynamic_storage_buffer_offsets_index: None,
        restrict_indexing: false,
    })
}

fn write_hlsl(
    module: &naga::Module,
    info: &ModuleInfo,
    reflection: &EntryReflection,
    stage: Stage,
    entry: &str,
) -> Result<String, String> {
    let mut binding_map = BTreeMap::new();
    for b in &reflection.bindings {
        let target = match b.hlsl.sampler_index.or_else(|| {
            (b.resource.is_sampler()).then(|| b.hlsl.register[1..].parse().unwrap_or(0))
        }) {
            // naga reads every sampler from its heap through the group's sampler index
            // buffer and takes the sampler's element of that buffer as the register;
            // classic samplers replace these lines afterwards (see `rewrite::hlsl`).
            Some(index) => hlsl::BindTarget {
                space: u8::try_from(b.group).map_err(|_| "space out of range".to_string())?,
                register: index,
                binding_array_size: None,
                dynamic_storage_buffer_offsets_index: None,
                restrict_indexing: false,
            },
            None => hlsl_target(&b.hlsl.register, b.hlsl.space)?,
        };
        binding_map.insert(resource_binding(b.group, b.binding), target);
    }
    let mut sampler_buffer_binding_map = BTreeMap::new();
    for s in &reflection.hlsl_sampler_index_buffers {
        sampler_buffer_binding_map.insert(
            hlsl::SamplerIndexBufferKey { group: s.group },
            hlsl_target(&s.register, s.space)?,
        );
    }
    // With classic samplers the index buffers are removed again: any free slot does.
    for b in reflection
        .bindings
        .iter()
        .filter(|b| b.resource.is_sampler())
    {
        sampler_buffer_binding_map
            .entry(hlsl::SamplerIndexBufferKey { group: b.group })
            .or_insert(hlsl_target("t0", 200 + b.group)?);
    }
    let options = hlsl::Options {
        // SV_ViewID (the multiview apply) needs SM 6.1; everything else stays at 6.0.
        shader_model: if reads_view_index(module) {
            hlsl::ShaderModel::V6_1
        } else {
            hlsl::ShaderModel::V6_0
        },
        binding_map,
        fake_missing_bindings: false,
        sampler_buffer_binding_map,
        zero_initialize_workgroup_memory: true,
        ..Default::default()
    };
    let pipeline = hlsl::PipelineOptions {
        entry_point: Some((stage.to_naga(), entry.to_string())),
    };
    let mut text = String::new();
    let mut writer = hlsl::Writer::new(&mut text, &options, &pipeline);
    writer
        .write(module, info, None)
        .map_err(|e| e.to_string())?;
    Ok(text)
}

fn write_msl(
    module: &naga::Module,
    info: &ModuleInfo,
    reflection: &mut EntryReflection,
    stage: Stage,
    entry: &str,
) -> Result<String, String> {
    let mut resources = BTreeMap::new();
    for b in &reflection.bindings {
        let slot = u8::try_from(b.msl.index).map_err(|_| "MSL index out of range".to_string())?;
        let mut target = msl::BindTarget::default();
        match &b.resource {
            Resource::Buffer { ty, .. } => {
                target.buffer = Some(slot);
                target.mutable = ty == "storage";
            }
            Resource::Texture { .. } => target.texture = Some(slot),
            Resource::StorageTexture { access, .. } => {
                target.texture = Some(slot);
                target.mutable = access != "read-only";
            }
            Resource::Sampler { .. } => {
                target.sampler = Some(msl::BindSamplerTarget::Resource(slot));
            }
        }
        resources.insert(resource_binding(b.group, b.binding), target);
    }
    let buffers = reflection
        .bindings
        .iter()
        .filter(|b| b.msl.kind == "buffer")
        .count();
    let mut per_entry_point_map = BTreeMap::new();
    per_entry_point_map.insert(
        entry.to_string(),
        msl::EntryPointResources {
            resources,
            immediates_buffer: None,
            // Array lengths of runtime-sized storage buffers, after the other buffers.
            sizes_buffer: Some(u8::try_from(buffers).map_err(|_| "too many buffers".to_string())?),
        },
    );
    let options = msl::Options {
        // amplification_id (the multiview apply) needs MSL 2.2; everything else 2.1.
        lang_version: if reads_view_index(module) {
            (2, 2)
        } else {
            (2, 1)
        },
        per_entry_point_map,
        fake_missing_bindings: false,
        zero_initialize_workgroup_memory: true,
        ..Default::default()
    };
    let pipeline = msl::PipelineOptions {
        entry_point: Some((stage.to_naga(), entry.to_string())),
        ..Default::default()
    };
    let text = msl::write_string(module, info, &options, &pipeline)
        .map(|(text, _)| text)
        .map_err(|e| e.to_string())?;
    let runtime_arrays: Vec<(u32, String)> = module
        .global_variables
        .iter()
        .filter(|(_, g)| g.binding.is_some())
        .filter_map(|(h, g)| {
            let name = g.name.clone()?;
            let b = reflection.bindings.iter().find(|b| b.name == name)?;
            rewrite::has_runtime_array(&b.resource).then_some((h.index() as u32, name))
        })
        .collect();
    rewrite::msl_buffer_sizes(&text, reflection, &runtime_arrays, buffers as u32);
    Ok(text)
}

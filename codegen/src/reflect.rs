//! Reflection of an entry point for the binding manifest: its resources with their
//! slot in every target, the layouts of its uniform and storage structs, and its
//! workgroup size.
//!
//! Slot assignment (the binding maps handed to the backends):
//! - SPIR-V: `DescriptorSet` = WGSL group, `Binding` = WGSL binding.
//! - HLSL: `space` = group; per group and register class, registers count up in
//!   binding order: `b` uniform buffers, `t` sampled textures and read-only storage
//!   buffers, `u` storage textures and read-write storage buffers, `s` samplers. With
//!   [`HlslSamplers::Heap`] samplers live in naga's sampler heap instead
//!   (`nagaSamplerHeap`, `s0` in `space0`; comparison samplers
//!   `nagaComparisonSamplerHeap`, `s0` in `space1`) and are found through a per-group
//!   `StructuredBuffer<uint>` of heap indices (`nagaGroup<N>SamplerIndexArray`) at the
//!   next free `t` register of the group's space.
//! - MSL: per entry point, `[[buffer(i)]]`, `[[texture(i)]]` and `[[sampler(i)]]` count
//!   up separately over all groups in (group, binding) order.
//! - GLSL: `layout(binding = i)` counts up separately per OpenGL binding namespace
//!   (uniform blocks, texture units, image units, shader storage blocks) in (group,
//!   binding) order. A sampler is merged into the combined `sampler*` of the texture it
//!   samples and has no binding of its own.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Reflection of one entry point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EntryReflection {
    /// Workgroup size of a compute entry point.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub workgroup_size: Option<[u32; 3]>,
    /// Every resource the entry point uses, in (group, binding) order.
    pub bindings: Vec<Binding>,
    /// HLSL sampler index buffers, one per group that has samplers (only when the
    /// samplers are read from naga's sampler heap).
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub hlsl_sampler_index_buffers: Vec<HlslSamplerIndexBuffer>,
    /// MSL: the buffer naga adds for the byte sizes of runtime-sized storage arrays.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub msl_buffer_sizes: Option<MslBufferSizes>,
    /// Layout of every struct reachable from a uniform or storage buffer.
    pub structs: Vec<StructLayout>,
}

/// One resource binding.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Binding {
    /// The WGSL variable name.
    pub name: String,
    /// WGSL `@group`.
    pub group: u32,
    /// WGSL `@binding`.
    pub binding: u32,
    /// What is bound.
    pub resource: Resource,
    /// SPIR-V `DescriptorSet` / `Binding`.
    pub spirv: SpirvSlot,
    /// HLSL register and space.
    pub hlsl: HlslSlot,
    /// GLSL binding; `None` for samplers, which GLSL merges into combined samplers.
    pub glsl: Option<GlslSlot>,
    /// MSL argument index.
    pub msl: MslSlot,
}

/// What a binding holds, in WebGPU's terms (`GPUBindGroupLayoutEntry`), so a layout
/// can be built from it directly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Resource {
    /// A buffer.
    Buffer {
        /// `uniform`, `storage` or `read-only-storage`.
        #[serde(rename = "type")]
        ty: String,
        /// The WGSL type it holds (a struct name, or `array<T>`).
        #[serde(rename = "struct")]
        struct_name: String,
        /// Minimum binding size in bytes (for a runtime-sized array: its fixed part,
        /// plus `stride` per element).
        size: u32,
        /// Element stride of a runtime-sized array, if any.
        #[serde(skip_serializing_if = "Option::is_none", default)]
        stride: Option<u32>,
    },
    /// A sampled texture.
    Texture {
        /// `1d`, `2d`, `2d-array`, `cube`, `cube-array` or `3d`.
        view_dimension: String,
        /// `float` (read through a filtering sampler), `unfilterable-float` (loaded, or
        /// read through a non-filtering sampler: depth formats bind here too),
        /// `depth`, `sint` or `uint`.
        sample_type: String,
        /// Multisampled.
        multisampled: bool,
    },
    /// A storage texture.
    StorageTexture {
        /// As for textures.
        view_dimension: String,
        /// Texel format in WebGPU spelling, e.g. `rgba16float`.
        format: String,
        /// `write-only`, `read-only` or `read-write`.
        access: String,
    },
    /// A sampler.
    Sampler {
        /// `filtering`, `non-filtering` or `comparison`.
        #[serde(rename = "type")]
        ty: String,
    },
}

impl Resource {
    /// Whether this is a sampler.
    pub fn is_sampler(&self) -> bool {
        matches!(self, Resource::Sampler { .. })
    }
}

/// SPIR-V slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SpirvSlot {
    /// Descriptor set.
    pub set: u32,
    /// Binding.
    pub binding: u32,
}

/// HLSL slot.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct HlslSlot {
    /// Register, e.g. `b0`, `t1`, `u0`, `s0` (with classic samplers); `heap` for
    /// samplers read from naga's sampler heap (see the sampler index buffer).
    pub register: String,
    /// Register space.
    pub space: u32,
    /// The declaration's HLSL type, e.g. `cbuffer`, `Texture3D<float4>`,
    /// `ByteAddressBuffer`, `RWTexture2DArray<float>`, `SamplerState`.
    #[serde(rename = "type", default)]
    pub ty: String,
    /// For samplers read from the heap: the element of the group's sampler index
    /// buffer that holds this sampler's index in the heap.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub sampler_index: Option<u32>,
}

/// HLSL sampler index buffer of one group.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct HlslSamplerIndexBuffer {
    /// The bind group whose samplers it indexes.
    pub group: u32,
    /// Its HLSL name.
    pub name: String,
    /// Register (a `t` register).
    pub register: String,
    /// Register space.
    pub space: u32,
}

/// GLSL slot.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct GlslSlot {
    /// The identifier in the GLSL text: the WGSL name, or naga's
    /// `_group_G_binding_B_<stage>` where the WGSL name is reserved in GLSL.
    #[serde(default)]
    pub name: String,
    /// For uniform and shader storage blocks: the block name, the same in every
    /// stage, as `glGetUniformBlockIndex` / `glGetProgramResourceIndex` look it up.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub block: Option<String>,
    /// `layout(binding = N)`.
    pub binding: u32,
    /// `uniform_block`, `texture_unit`, `image_unit` or `shader_storage_block`.
    pub namespace: String,
}

/// MSL slot.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MslSlot {
    /// `buffer`, `texture` or `sampler`.
    pub kind: String,
    /// Argument index.
    pub index: u32,
}

/// The `_mslBufferSizes` argument of an MSL entry point: a struct of `uint`s, one per
/// binding that holds a runtime-sized array, in this order, each the byte size of the
/// buffer range bound there.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MslBufferSizes {
    /// Its `[[buffer(N)]]` index.
    pub index: u32,
    /// The bindings whose sizes it holds, in member order.
    pub members: Vec<MslBufferSize>,
}

/// One member of [`MslBufferSizes`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MslBufferSize {
    /// The member's name in the MSL struct.
    pub member: String,
    /// The binding's WGSL name.
    pub binding_name: String,
    /// Its group.
    pub group: u32,
    /// Its binding.
    pub binding: u32,
}

/// Memory layout of a struct (WGSL rules, as naga lays it out).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StructLayout {
    /// Struct name.
    pub name: String,
    /// Size in bytes.
    pub size: u32,
    /// Alignment in bytes.
    pub align: u32,
    /// Members in order.
    pub members: Vec<MemberLayout>,
}

/// One struct member.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MemberLayout {
    /// Member name.
    pub name: String,
    /// WGSL type name.
    pub ty: String,
    /// Offset in bytes.
    pub offset: u32,
    /// Size in bytes.
    pub size: u32,
}

/// The WGSL spelling of a type.
pub fn type_name(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    use naga::TypeInner as T;
    let t = &module.types[ty];
    if let Some(name) = &t.name
        && matches!(t.inner, T::Struct { .. })
    {
        return name.clone();
    }
    match &t.inner {
        T::Scalar(s) => scalar_name(*s).to_string(),
        T::Vector { size, scalar } => format!("vec{}<{}>", *size as u8, scalar_name(*scalar)),
        T::Matrix {
            columns,
            rows,
            scalar,
        } => format!(
            "mat{}x{}<{}>",
            *columns as u8,
            *rows as u8,
            scalar_name(*scalar)
        ),
        T::Atomic(s) => format!("atomic<{}>", scalar_name(*s)),
        T::Array { base, size, .. } => match size {
            naga::ArraySize::Constant(n) => format!("array<{}, {}>", type_name(module, *base), n),
            _ => format!("array<{}>", type_name(module, *base)),
        },
        other => format!("{other:?}"),
    }
}

fn scalar_name(s: naga::Scalar) -> &'static str {
    match (s.kind, s.width) {
        (naga::ScalarKind::Float, 4) => "f32",
        (naga::ScalarKind::Float, 2) => "f16",
        (naga::ScalarKind::Float, 8) => "f64",
        (naga::ScalarKind::Sint, 4) => "i32",
        (naga::ScalarKind::Uint, 4) => "u32",
        (naga::ScalarKind::Bool, _) => "bool",
        _ => "unknown",
    }
}

fn dimension_name(dim: naga::ImageDimension, arrayed: bool) -> String {
    let base = match dim {
        naga::ImageDimension::D1 => "1d",
        naga::ImageDimension::D2 => "2d",
        naga::ImageDimension::D3 => "3d",
        naga::ImageDimension::Cube => "cube",
    };
    if arrayed {
        format!("{base}-array")
    } else {
        base.to_string()
    }
}

fn format_name(format: naga::StorageFormat) -> String {
    // naga's Debug spelling is the WebGPU name in CamelCase: Rgba16Float -> rgba16float.
    format!("{format:?}").to_lowercase()
}

fn access_name(access: naga::StorageAccess) -> &'static str {
    let load = access.contains(naga::StorageAccess::LOAD);
    let store = access.contains(naga::StorageAccess::STORE);
    match (load, store) {
        (true, true) => "read-write",
        (false, true) => "write-only",
        _ => "read-only",
    }
}

/// How the pass uses its samplers and the textures they read: from the pass's
/// declaration of its non-filtering samplers and the entry point's (texture, sampler)
/// pairs.
struct Sampling<'a> {
    non_filtering: &'a [&'a str],
    /// Textures read through a filtering sampler.
    filtered: Vec<naga::Handle<naga::GlobalVariable>>,
}

/// Classifies a global variable with a binding; `None` for globals without one.
fn resource_of(
    module: &naga::Module,
    layouter: &naga::proc::Layouter,
    handle: naga::Handle<naga::GlobalVariable>,
    sampling: &Sampling<'_>,
) -> Option<Resource> {
    use naga::TypeInner as T;
    let var = &module.global_variables[handle];
    var.binding.as_ref()?;
    let inner = &module.types[var.ty].inner;
    Some(match (var.space, inner) {
        (naga::AddressSpace::Uniform, _) => Resource::Buffer {
            ty: "uniform".to_string(),
            struct_name: type_name(module, var.ty),
            size: layouter[var.ty].size,
            stride: None,
        },
        (naga::AddressSpace::Storage { access }, _) => {
            let stride = match inner {
                T::Struct { members, .. } => {
                    members
                        .last()
                        .and_then(|m| match &module.types[m.ty].inner {
                            T::Array {
                                size: naga::ArraySize::Dynamic,
                                stride,
                                ..
                            } => Some(*stride),
                            _ => None,
                        })
                }
                T::Array {
                    size: naga::ArraySize::Dynamic,
                    stride,
                    ..
                } => Some(*stride),
                _ => None,
            };
            let read_only = !access.contains(naga::StorageAccess::STORE);
            Resource::Buffer {
                ty: if read_only {
                    "read-only-storage"
                } else {
                    "storage"
                }
                .to_string(),
                struct_name: type_name(module, var.ty),
                size: layouter[var.ty].size,
                stride,
            }
        }
        (
            _,
            T::Image {
                dim,
                arrayed,
                class,
            },
        ) => match class {
            naga::ImageClass::Storage { format, access } => Resource::StorageTexture {
                view_dimension: dimension_name(*dim, *arrayed),
                format: format_name(*format),
                access: access_name(*access).to_string(),
            },
            naga::ImageClass::Sampled { kind, multi } => Resource::Texture {
                view_dimension: dimension_name(*dim, *arrayed),
                sample_type: match kind {
                    naga::ScalarKind::Sint => "sint",
                    naga::ScalarKind::Uint => "uint",
                    _ if sampling.filtered.contains(&handle) => "float",
                    _ => "unfilterable-float",
                }
                .to_string(),
                multisampled: *multi,
            },
            naga::ImageClass::Depth { multi } => Resource::Texture {
                view_dimension: dimension_name(*dim, *arrayed),
                sample_type: "depth".to_string(),
                multisampled: *multi,
            },
            naga::ImageClass::External => Resource::Texture {
                view_dimension: "external".to_string(),
                sample_type: "float".to_string(),
                multisampled: false,
            },
        },
        (_, T::Sampler { comparison }) => Resource::Sampler {
            ty: if *comparison {
                "comparison"
            } else if var
                .name
                .as_deref()
                .is_some_and(|n| sampling.non_filtering.contains(&n))
            {
                "non-filtering"
            } else {
                "filtering"
            }
            .to_string(),
        },
        _ => return None,
    })
}

/// HLSL register class of a resource.
fn hlsl_class(resource: &Resource) -> char {
    match resource {
        Resource::Buffer { ty, .. } if ty == "uniform" => 'b',
        Resource::Buffer { ty, .. } if ty == "read-only-storage" => 't',
        Resource::Buffer { .. } => 'u',
        Resource::Texture { .. } => 't',
        Resource::StorageTexture { .. } => 'u',
        Resource::Sampler { .. } => 's',
    }
}

fn glsl_namespace(resource: &Resource) -> Option<&'static str> {
    match resource {
        Resource::Buffer { ty, .. } if ty == "uniform" => Some("uniform_block"),
        Resource::Buffer { .. } => Some("shader_storage_block"),
        Resource::Texture { .. } => Some("texture_unit"),
        Resource::StorageTexture { .. } => Some("image_unit"),
        Resource::Sampler { .. } => None,
    }
}

fn msl_kind(resource: &Resource) -> &'static str {
    match resource {
        Resource::Buffer { .. } => "buffer",
        Resource::Texture { .. } | Resource::StorageTexture { .. } => "texture",
        Resource::Sampler { .. } => "sampler",
    }
}

fn collect_structs(
    module: &naga::Module,
    layouter: &naga::proc::Layouter,
    ty: naga::Handle<naga::Type>,
    out: &mut Vec<StructLayout>,
) {
    use naga::TypeInner as T;
    match &module.types[ty].inner {
        T::Struct { members, span } => {
            let name = type_name(module, ty);
            if out.iter().any(|s| s.name == name) {
                return;
            }
            for m in members {
                collect_structs(module, layouter, m.ty, out);
            }
            out.push(StructLayout {
                name,
                size: *span,
                align: layouter[ty].alignment.round_up(1),
                members: members
                    .iter()
                    .map(|m| MemberLayout {
                        name: m.name.clone().unwrap_or_default(),
                        ty: type_name(module, m.ty),
                        offset: m.offset,
                        size: layouter[m.ty].size,
                    })
                    .collect(),
            });
        }
        T::Array { base, .. } => collect_structs(module, layouter, *base, out),
        _ => {}
    }
}

/// The layout of every named struct of a module (WGSL rules, as naga lays it out).
pub fn struct_layouts(module: &naga::Module) -> Vec<StructLayout> {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("a validated module has a layout");
    let mut out = Vec::new();
    for (handle, ty) in module.types.iter() {
        if ty.name.is_some() && matches!(ty.inner, naga::TypeInner::Struct { .. }) {
            collect_structs(module, &layouter, handle, &mut out);
        }
    }
    out
}

/// How HLSL exports bind samplers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HlslSamplers {
    /// `SamplerState name : register(sN, spaceG)`, numbered per group in binding order
    /// (Direct3D 11 style; what most engines bind).
    #[default]
    Classic,
    /// naga's sampler heap: samplers are read from `nagaSamplerHeap` through a
    /// per-group `StructuredBuffer<uint>` of heap indices (wgpu's Direct3D 12 layout;
    /// needs resource binding tier 2).
    Heap,
}

/// Reflects the bindings used by entry point `entry_index` of a validated module and
/// assigns their slots in every target. `non_filtering` names the pass's samplers that
/// are bound as non-filtering; `samplers` chooses the HLSL sampler binding.
pub fn reflect_entry(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry_index: usize,
    non_filtering: &[&str],
    samplers: HlslSamplers,
) -> EntryReflection {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("a validated module has a layout");
    let ep = &module.entry_points[entry_index];
    let ep_info = info.get_entry_point(entry_index);
    let filtering_sampler = |h: naga::Handle<naga::GlobalVariable>| {
        let var = &module.global_variables[h];
        let comparison = matches!(
            module.types[var.ty].inner,
            naga::TypeInner::Sampler { comparison: true }
        );
        !comparison
            && !var
                .name
                .as_deref()
                .is_some_and(|n| non_filtering.contains(&n))
    };
    let sampling = Sampling {
        non_filtering,
        filtered: ep_info
            .sampling_set
            .iter()
            .filter(|k| filtering_sampler(k.sampler))
            .map(|k| k.image)
            .collect(),
    };

    let mut used: Vec<(
        naga::ResourceBinding,
        String,
        Resource,
        naga::Handle<naga::GlobalVariable>,
    )> = Vec::new();
    for (handle, var) in module.global_variables.iter() {
        if ep_info[handle].is_empty() {
            continue;
        }
        let (Some(binding), Some(resource)) = (
            var.binding,
            resource_of(module, &layouter, handle, &sampling),
        ) else {
            continue;
        };
        used.push((
            binding,
            var.name.clone().unwrap_or_default(),
            resource,
            handle,
        ));
    }
    used.sort_by_key(|(b, ..)| (b.group, b.binding));

    let mut hlsl_next: BTreeMap<(u32, char), u32> = BTreeMap::new();
    let mut glsl_next: BTreeMap<&str, u32> = BTreeMap::new();
    let mut msl_next: BTreeMap<&str, u32> = BTreeMap::new();
    let mut bindings = Vec::new();
    let mut structs = Vec::new();
    for (rb, name, resource, handle) in used {
        let class = hlsl_class(&resource);
        let n = hlsl_next.entry((rb.group, class)).or_default();
        let hlsl = if class == 's' && samplers == HlslSamplers::Heap {
            HlslSlot {
                register: "heap".to_string(),
                space: rb.group,
                ty: String::new(),
                sampler_index: Some(*n),
            }
        } else {
            HlslSlot {
                register: format!("{class}{n}"),
                space: rb.group,
                ty: String::new(),
                sampler_index: None,
            }
        };
        *n += 1;
        let glsl = glsl_namespace(&resource).map(|ns| {
            let n = glsl_next.entry(ns).or_default();
            let slot = GlslSlot {
                name: String::new(),
                block: None,
                binding: *n,
                namespace: ns.to_string(),
            };
            *n += 1;
            slot
        });
        let kind = msl_kind(&resource);
        let n = msl_next.entry(kind).or_default();
        let msl = MslSlot {
            kind: kind.to_string(),
            index: *n,
        };
        *n += 1;
        if matches!(resource, Resource::Buffer { .. }) {
            collect_structs(
                module,
                &layouter,
                module.global_variables[handle].ty,
                &mut structs,
            );
        }
        bindings.push(Binding {
            name,
            group: rb.group,
            binding: rb.binding,
            resource,
            spirv: SpirvSlot {
                set: rb.group,
                binding: rb.binding,
            },
            hlsl,
            glsl,
            msl,
        });
    }

    let hlsl_sampler_index_buffers = if samplers == HlslSamplers::Heap {
        let mut sampler_groups: Vec<u32> = bindings
            .iter()
            .filter(|b| b.resource.is_sampler())
            .map(|b| b.group)
            .collect();
        sampler_groups.dedup();
        sampler_groups
            .into_iter()
            .map(|group| {
                let n = hlsl_next.entry((group, 't')).or_default();
                let buffer = HlslSamplerIndexBuffer {
                    group,
                    name: format!("nagaGroup{group}SamplerIndexArray"),
                    register: format!("t{n}"),
                    space: group,
                };
                *n += 1;
                buffer
            })
            .collect()
    } else {
        Vec::new()
    };

    EntryReflection {
        workgroup_size: (ep.stage == naga::ShaderStage::Compute).then_some(ep.workgroup_size),
        bindings,
        hlsl_sampler_index_buffers,
        msl_buffer_sizes: None,
        structs,
    }
}

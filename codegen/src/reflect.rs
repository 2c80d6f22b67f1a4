//! Reflection of an entry point for the binding manifest: its resources with their
//! slot in every target, the layouts of its uniform and storage structs, and its
//! workgroup size.
//!
//! Slot assignment (the binding maps handed to the backends):
//! - SPIR-V: `DescriptorSet` = WGSL group, `Binding` = WGSL binding.
//! - HLSL: `space` = group; per group and register class, registers count up in
//!   binding order: `b` uniform buffers, `t` sampled textures and read-only storage
//!   buffers, `u` storage textures and read-write storage buffers. Samplers live in
//!   naga's sampler heap (`nagaSamplerHeap`, `s0` in `space0`; comparison samplers
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
    /// HLSL sampler index buffers, one per group that has samplers.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub hlsl_sampler_index_buffers: Vec<HlslSamplerIndexBuffer>,
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

/// The kind of a bound resource.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Resource {
    /// A uniform buffer holding one value of type `ty`.
    UniformBuffer {
        /// WGSL type name.
        ty: String,
        /// Size in bytes.
        size: u32,
    },
    /// A storage buffer.
    StorageBuffer {
        /// WGSL type name.
        ty: String,
        /// Size in bytes (of the fixed part; arrays of runtime size add `stride` per element).
        size: u32,
        /// Element stride of a runtime-sized array, if any.
        #[serde(skip_serializing_if = "Option::is_none", default)]
        stride: Option<u32>,
        /// `read` or `read_write`.
        access: String,
    },
    /// A sampled texture.
    Texture {
        /// `1d`, `2d`, `2d_array`, `cube`, `cube_array` or `3d`.
        dimension: String,
        /// `float` (filterable), `depth`, `sint` or `uint`.
        sample_type: String,
        /// Multisampled.
        multisampled: bool,
    },
    /// A storage texture.
    StorageTexture {
        /// As for textures.
        dimension: String,
        /// Texel format in WebGPU spelling, e.g. `rgba16float`.
        format: String,
        /// `read`, `write` or `read_write`.
        access: String,
    },
    /// A sampler.
    Sampler {
        /// A comparison sampler.
        comparison: bool,
    },
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
    /// Register, e.g. `b0`, `t1`, `u0`; `heap` for samplers (see the sampler index buffer).
    pub register: String,
    /// Register space.
    pub space: u32,
    /// For samplers: the element of the group's sampler index buffer that holds this
    /// sampler's index in the sampler heap.
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
    if let Some(name) = &t.name {
        if matches!(t.inner, T::Struct { .. }) {
            return name.clone();
        }
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
        format!("{base}_array")
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
        (true, true) => "read_write",
        (false, true) => "write",
        _ => "read",
    }
}

/// Classifies a global variable with a binding; `None` for globals without one.
fn resource_of(
    module: &naga::Module,
    layouter: &naga::proc::Layouter,
    var: &naga::GlobalVariable,
) -> Option<Resource> {
    use naga::TypeInner as T;
    var.binding.as_ref()?;
    let inner = &module.types[var.ty].inner;
    Some(match (var.space, inner) {
        (naga::AddressSpace::Uniform, _) => Resource::UniformBuffer {
            ty: type_name(module, var.ty),
            size: layouter[var.ty].size,
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
            Resource::StorageBuffer {
                ty: type_name(module, var.ty),
                size: layouter[var.ty].size,
                stride,
                access: access_name(access).to_string(),
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
                dimension: dimension_name(*dim, *arrayed),
                format: format_name(*format),
                access: access_name(*access).to_string(),
            },
            naga::ImageClass::Sampled { kind, multi } => Resource::Texture {
                dimension: dimension_name(*dim, *arrayed),
                sample_type: match kind {
                    naga::ScalarKind::Sint => "sint",
                    naga::ScalarKind::Uint => "uint",
                    _ => "float",
                }
                .to_string(),
                multisampled: *multi,
            },
            naga::ImageClass::Depth { multi } => Resource::Texture {
                dimension: dimension_name(*dim, *arrayed),
                sample_type: "depth".to_string(),
                multisampled: *multi,
            },
            naga::ImageClass::External => Resource::Texture {
                dimension: "external".to_string(),
                sample_type: "float".to_string(),
                multisampled: false,
            },
        },
        (_, T::Sampler { comparison }) => Resource::Sampler {
            comparison: *comparison,
        },
        _ => return None,
    })
}

/// HLSL register class of a resource.
fn hlsl_class(resource: &Resource) -> Option<char> {
    match resource {
        Resource::UniformBuffer { .. } => Some('b'),
        Resource::StorageBuffer { access, .. } if access == "read" => Some('t'),
        Resource::StorageBuffer { .. } => Some('u'),
        Resource::Texture { .. } => Some('t'),
        Resource::StorageTexture { .. } => Some('u'),
        Resource::Sampler { .. } => None,
    }
}

fn glsl_namespace(resource: &Resource) -> Option<&'static str> {
    match resource {
        Resource::UniformBuffer { .. } => Some("uniform_block"),
        Resource::StorageBuffer { .. } => Some("shader_storage_block"),
        Resource::Texture { .. } => Some("texture_unit"),
        Resource::StorageTexture { .. } => Some("image_unit"),
        Resource::Sampler { .. } => None,
    }
}

fn msl_kind(resource: &Resource) -> &'static str {
    match resource {
        Resource::UniformBuffer { .. } | Resource::StorageBuffer { .. } => "buffer",
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

/// Reflects the bindings used by entry point `entry_index` of a validated module and
/// assigns their slots in every target.
pub fn reflect_entry(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry_index: usize,
) -> EntryReflection {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("a validated module has a layout");
    let ep = &module.entry_points[entry_index];
    let ep_info = info.get_entry_point(entry_index);

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
        let (Some(binding), Some(resource)) = (var.binding, resource_of(module, &layouter, var))
        else {
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
        let hlsl = match hlsl_class(&resource) {
            Some(class) => {
                let n = hlsl_next.entry((rb.group, class)).or_default();
                let slot = HlslSlot {
                    register: format!("{class}{n}"),
                    space: rb.group,
                    sampler_index: None,
                };
                *n += 1;
                slot
            }
            None => {
                let n = hlsl_next.entry((rb.group, 's')).or_default();
                let slot = HlslSlot {
                    register: "heap".to_string(),
                    space: rb.group,
                    sampler_index: Some(*n),
                };
                *n += 1;
                slot
            }
        };
        let glsl = glsl_namespace(&resource).map(|ns| {
            let n = glsl_next.entry(ns).or_default();
            let slot = GlslSlot {
                name: String::new(),
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
        if matches!(
            resource,
            Resource::UniformBuffer { .. } | Resource::StorageBuffer { .. }
        ) {
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

    let mut sampler_groups: Vec<u32> = bindings
        .iter()
        .filter(|b| matches!(b.resource, Resource::Sampler { .. }))
        .map(|b| b.group)
        .collect();
    sampler_groups.dedup();
    let hlsl_sampler_index_buffers = sampler_groups
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
        .collect();

    EntryReflection {
        workgroup_size: (ep.stage == naga::ShaderStage::Compute).then_some(ep.workgroup_size),
        bindings,
        hlsl_sampler_index_buffers,
        structs,
    }
}

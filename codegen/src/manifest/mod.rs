//! The shader manifest: every importable module in dependency order, and every
//! pass with the define axes it is built under.
//!
//! `build.rs` of the library composes and validates every variant listed here, the
//! wgpu runtime composes the ones it needs, and the exports and tests walk the same
//! list, so they can never disagree about what exists.

/// One importable WGSL module, `#define_import_path volfog::<stem>`.
#[derive(Debug, Clone, Copy)]
pub struct ModuleSource {
    /// The import path, `volfog::<file stem>`.
    pub import_path: &'static str,
    /// Path of the file relative to the crate root (for error messages).
    pub file: &'static str,
    /// The WGSL text.
    pub source: &'static str,
}

/// One axis along which a pass is specialised.
#[derive(Debug, Clone, Copy)]
pub enum Axis {
    /// A boolean define: the variant either has it or not.
    Flag(&'static str),
    /// Mutually exclusive defines: the variant has none or exactly one of them.
    OneOf(&'static [&'static str]),
    /// Defines prebuilt together: the variant has none or all of them (each may still
    /// be set alone in a custom composition).
    Together(&'static [&'static str]),
    /// Sets of defines, each prebuilt together: the variant has none of them or every
    /// define of exactly one set (the sets may share defines; each define may still be
    /// set alone in a custom composition).
    Sets(&'static [&'static [&'static str]]),
}

impl Axis {
    /// Every define this axis can set, each once.
    pub fn defines(&self) -> Vec<&'static str> {
        match self {
            Axis::Flag(name) => vec![*name],
            Axis::OneOf(names) | Axis::Together(names) => names.to_vec(),
            Axis::Sets(sets) => {
                let mut all: Vec<&'static str> = Vec::new();
                for name in sets.iter().flat_map(|s| s.iter()) {
                    if !all.contains(name) {
                        all.push(name);
                    }
                }
                all
            }
        }
    }

    /// The define sets this axis adds to a variant besides none: one per define, or,
    /// for [`Axis::Together`], all of them at once, or, for [`Axis::Sets`], each set.
    pub fn choices(&self) -> Vec<Vec<&'static str>> {
        match self {
            Axis::Together(names) => vec![names.to_vec()],
            Axis::Sets(sets) => sets.iter().map(|s| s.to_vec()).collect(),
            _ => self.defines().into_iter().map(|d| vec![d]).collect(),
        }
    }
}

/// A define that carries an unsigned value (`NAME=VALUE`), accepted by
/// custom compositions with the given inclusive range.
#[derive(Debug, Clone, Copy)]
pub struct ValueDefine {
    /// Define name, e.g. `VOLFOG_NOISE_OCTAVES`.
    pub name: &'static str,
    /// Smallest accepted value.
    pub min: u32,
    /// Largest accepted value.
    pub max: u32,
    /// Value used when the define is absent.
    pub default: u32,
}

/// One blend component in WebGPU's terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct BlendComponent {
    /// `one`, `zero`, `src-alpha`, ...
    pub src_factor: &'static str,
    /// As `src_factor`.
    pub dst_factor: &'static str,
    /// `add`, ...
    pub operation: &'static str,
}

/// A colour target's blend state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Blend {
    /// Colour channels.
    pub color: BlendComponent,
    /// Alpha channel.
    pub alpha: BlendComponent,
}

/// `dst * T + L` from a fragment output (L, T): the blend of every fog composite.
pub const FOG_BLEND: Blend = Blend {
    color: BlendComponent {
        src_factor: "one",
        dst_factor: "src-alpha",
        operation: "add",
    },
    alpha: BlendComponent {
        src_factor: "zero",
        dst_factor: "one",
        operation: "add",
    },
};

/// One vertex attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct VertexAttribute {
    /// `@location`.
    pub shader_location: u32,
    /// WebGPU vertex format, e.g. `float32x3`.
    pub format: &'static str,
    /// Byte offset in the vertex.
    pub offset: u32,
}

/// One vertex buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct VertexBuffer {
    /// Bytes per vertex.
    pub array_stride: u32,
    /// `vertex` or `instance`.
    pub step_mode: &'static str,
    /// Its attributes.
    pub attributes: &'static [VertexAttribute],
}

/// The render pipeline state of a pass that draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderState {
    /// The vertex shader of the pass's fragment entry points, (pass, entry point), when
    /// it comes from another pass; `None` when the pass has its own vertex entry point.
    pub vertex: Option<(&'static str, &'static str)>,
    /// Colour target formats the pass draws into (WebGPU names); the first is the
    /// default.
    pub formats: &'static [&'static str],
    /// The colour target's blend.
    pub blend: Option<Blend>,
    /// Vertex buffers of the pass's own vertex entry point.
    pub vertex_buffers: &'static [VertexBuffer],
    /// `triangle-list`, ...
    pub topology: &'static str,
    /// `ccw` or `cw`.
    pub front_face: &'static str,
    /// `none`, `front` or `back`.
    pub cull_mode: &'static str,
}

/// Colour formats WebGPU can blend into without optional features.
pub const BLENDABLE_FORMATS: &[&str] = &[
    "rgba16float",
    "rgba8unorm",
    "rgba8unorm-srgb",
    "bgra8unorm",
    "bgra8unorm-srgb",
    "rgb10a2unorm",
];

/// A fullscreen fog composite: the fullscreen vertex shader, any blendable colour
/// target, [`FOG_BLEND`].
const FULLSCREEN_COMPOSITE: RenderState = RenderState {
    vertex: Some(("fullscreen", "fullscreen_vs")),
    formats: BLENDABLE_FORMATS,
    blend: Some(FOG_BLEND),
    vertex_buffers: &[],
    topology: "triangle-list",
    front_face: "ccw",
    cull_mode: "none",
};

/// A function a pass takes from the user: a define turns it on, and the pass then
/// imports the function from a module the user writes (added to the composer at
/// `import_path` by [`crate::custom`]), never from volfog. No prebuilt variant sets the
/// define; the runtime and the export compose it with the user's module.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Hook {
    /// The define, e.g. `VOLFOG_INJECT_CUSTOM_DENSITY`.
    pub define: &'static str,
    /// Where the user's module is added, e.g. `volfog::custom_density`.
    pub import_path: &'static str,
    /// The function the module must define.
    pub function: &'static str,
    /// Its required signature, as WGSL.
    pub signature: &'static str,
    /// What the module may import from volfog for it (`#import` lines).
    pub imports: &'static str,
    /// A shader that calls the function as the pass does: it composes only when the
    /// signature is right.
    pub probe: &'static str,
}

/// The custom density of inject: the user's medium, added at each froxel.
pub const CUSTOM_DENSITY: Hook = Hook {
    define: "VOLFOG_INJECT_CUSTOM_DENSITY",
    import_path: "volfog::custom_density",
    function: "volfog_custom_density",
    signature: "fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) \
                -> FogSample",
    imports: "#import volfog::types::{FogSample, FogCustomParams}",
    probe: "#import volfog::types::{FogSample, FogCustomParams}\n\
            #import volfog::custom_density::volfog_custom_density\n\
            @group(0) @binding(0) var<uniform> volfog_probe_params: FogCustomParams;\n\
            @compute @workgroup_size(1)\n\
            fn volfog_probe() {\n\
            \x20   let sample: FogSample = volfog_custom_density(vec3<f32>(0.0), 0.0, volfog_probe_params);\n\
            }\n",
};

/// A pass: one WGSL file of entry points plus its bindings.
#[derive(Debug, Clone, Copy)]
pub struct PassSource {
    /// Pass name, also the file stem under `shaders/passes/`.
    pub name: &'static str,
    /// Path of the file relative to the crate root.
    pub file: &'static str,
    /// The WGSL text.
    pub source: &'static str,
    /// Boolean / exclusive define axes; the prebuilt variants are their product.
    pub axes: &'static [Axis],
    /// Valued defines accepted by custom compositions (not expanded at build time).
    pub values: &'static [ValueDefine],
    /// How to run the pass (dispatch or draw, pipeline state), for the binding manifest.
    pub usage: &'static str,
    /// Samplers (by WGSL name) the pass binds as non-filtering; every other sampler is
    /// filtering.
    pub non_filtering_samplers: &'static [&'static str],
    /// The draw's pipeline state for a pass with vertex or fragment entry points.
    pub render: Option<RenderState>,
    /// Functions the pass takes from the user, each under its define (composed with the
    /// user's module only: [`crate::custom`]).
    pub hooks: &'static [Hook],
}

macro_rules! module {
    ($stem:literal) => {
        ModuleSource {
            import_path: concat!("volfog::", $stem),
            file: concat!("shaders/volfog/", $stem, ".wgsl"),
            source: include_str!(concat!("../../shaders/volfog/", $stem, ".wgsl")),
        }
    };
}

macro_rules! pass {
    ($stem:literal, axes: $axes:expr, values: $values:expr, usage: $usage:expr $(, non_filtering: $nf:expr)? $(, render: $render:expr)? $(, hooks: $hooks:expr)?) => {
        PassSource {
            name: $stem,
            file: concat!("shaders/passes/", $stem, ".wgsl"),
            source: include_str!(concat!("../../shaders/passes/", $stem, ".wgsl")),
            axes: $axes,
            values: $values,
            usage: $usage,
            non_filtering_samplers: pass!(@or $($nf)?; &[]),
            render: pass!(@or $(Some($render))?; None),
            hooks: pass!(@or $($hooks)?; &[]),
        }
    };
    (@or $value:expr; $default:expr) => { $value };
    (@or ; $default:expr) => { $default };
}

/// Radius of the ESM box blur in texels (taps = 2 radius + 1).
pub const ESM_BLUR_RADIUS: ValueDefine = ValueDefine {
    name: "VOLFOG_ESM_BLUR_RADIUS",
    min: 1,
    max: 16,
    default: 5,
};

/// Octaves of the fbm noise that modulates the froxel density.
pub const INJECT_NOISE_OCTAVES: ValueDefine = ValueDefine {
    name: "VOLFOG_INJECT_NOISE_OCTAVES",
    min: 1,
    max: 8,
    default: 1,
};

/// Importable modules, each after the modules it imports.
pub const MODULES: &[ModuleSource] = &[
    module!("types"),
    module!("fullscreen"),
    module!("froxel"),
    module!("temporal"),
    module!("stereo"),
    module!("noise"),
    module!("phase"),
    module!("height_fog"),
    module!("scan"),
    module!("apply"),
    module!("hull"),
    module!("bindings"),
    module!("stereo_apply"),
    module!("stereo_bindings"),
    module!("density"),
    module!("lights"),
    module!("area_lights"),
    module!("particles"),
    module!("medium_shadow"),
    module!("esm"),
    module!("fog_volume"),
    module!("water"),
    module!("lightning"),
    module!("soft_particles"),
    module!("fog_lit"),
    module!("sky"),
    module!("frustum"),
    module!("shadow"),
    module!("local_shadow"),
    module!("clouds"),
    module!("epipolar"),
];

mod passes;
pub use passes::PASSES;

/// Looks a pass up by name.
pub fn pass(name: &str) -> Option<&'static PassSource> {
    PASSES.iter().find(|p| p.name == name)
}

/// The variant name for a pass and a set of boolean defines:
/// `pass@default` without defines, otherwise `pass@A+B` with the `VOLFOG_`
/// prefix dropped and the defines sorted.
pub fn variant_name(pass: &str, defines: &[&str]) -> String {
    if defines.is_empty() {
        return format!("{pass}@default");
    }
    let mut short: Vec<&str> = defines
        .iter()
        .map(|d| d.strip_prefix("VOLFOG_").unwrap_or(d))
        .collect();
    short.sort_unstable();
    format!("{pass}@{}", short.join("+"))
}

/// Every combination of a pass's axes, each as a sorted list of defines.
pub fn expand_axes(axes: &[Axis]) -> Vec<Vec<&'static str>> {
    let mut combos: Vec<Vec<&'static str>> = vec![Vec::new()];
    for axis in axes {
        let mut next = Vec::new();
        for combo in &combos {
            next.push(combo.clone());
            for choice in axis.choices() {
                let mut with = combo.clone();
                with.extend(choice);
                next.push(with);
            }
        }
        combos = next;
    }
    for combo in &mut combos {
        combo.sort_unstable();
    }
    combos
}

/// One variant of the manifest: a pass under one combination of its axes' defines.
#[derive(Debug, Clone)]
pub struct Variant {
    /// `pass@default` or `pass@A+B` (see [`variant_name`]).
    pub name: String,
    /// The pass.
    pub pass: &'static PassSource,
    /// Its boolean defines, sorted.
    pub defines: Vec<&'static str>,
}

/// Every variant of every pass: the product of each pass's axes, in manifest order.
pub fn variants() -> Vec<Variant> {
    PASSES
        .iter()
        .flat_map(|pass| {
            expand_axes(pass.axes)
                .into_iter()
                .map(move |defines| Variant {
                    name: variant_name(pass.name, &defines),
                    pass,
                    defines,
                })
        })
        .collect()
}

/// A variant of the manifest by name.
pub fn variant(name: &str) -> Option<Variant> {
    variants().into_iter().find(|v| v.name == name)
}

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
            source: include_str!(concat!("../shaders/volfog/", $stem, ".wgsl")),
        }
    };
}

macro_rules! pass {
    ($stem:literal, axes: $axes:expr, values: $values:expr, usage: $usage:expr $(, non_filtering: $nf:expr)? $(, render: $render:expr)? $(, hooks: $hooks:expr)?) => {
        PassSource {
            name: $stem,
            file: concat!("shaders/passes/", $stem, ".wgsl"),
            source: include_str!(concat!("../shaders/passes/", $stem, ".wgsl")),
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
    module!("noise"),
    module!("phase"),
    module!("height_fog"),
    module!("scan"),
    module!("apply"),
    module!("hull"),
    module!("bindings"),
    module!("density"),
    module!("lights"),
    module!("area_lights"),
    module!("esm"),
    module!("fog_volume"),
    module!("water"),
    module!("lightning"),
    module!("soft_particles"),
    module!("sky"),
    module!("frustum"),
    module!("shadow"),
    module!("local_shadow"),
    module!("clouds"),
    module!("epipolar"),
];

/// Passes (entry-point files) and their define axes.
pub const PASSES: &[PassSource] = &[
    pass!(
        "scan",
        axes: &[Axis::Flag("VOLFOG_SCAN_WRONSKI_STEP"), Axis::Flag("VOLFOG_FROXEL_CULL"),
            Axis::Flag("VOLFOG_SCAN_TRANSIENT_LIGHTS")],
        values: &[],
        usage: "Dispatch ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups after the \
                scattering volume is written; the integrated volume is then read by apply. \
                Under VOLFOG_FROXEL_CULL binding 3 is this frame's live-slice texture \
                (froxel_cull), bound as uint. VOLFOG_SCAN_TRANSIENT_LIGHTS (frames with \
                transient lights; binding 1 the stabilised volume): bindings 4, 5, 6 are \
                FogMedium, TransientLighting and the transient FogLight buffer (>= 1)."
    ),
    pass!(
        "froxel_cull",
        axes: &[],
        values: &[],
        usage: "Dispatch size.x x size.y x 1 workgroups (one per froxel column) before \
                inject, after the scene depth is laid out. Binding 1 is the scene depth \
                (or a farthest-depth level of a hierarchical depth buffer), bound as \
                unfilterable float; binding 2 an r32uint size.x x size.y storage texture \
                that inject, temporal and scan read under VOLFOG_FROXEL_CULL. With \
                temporal reprojection keep two and swap them by frame parity like the \
                history volumes: temporal binding 9 is the one the history was written with."
    ),
    pass!(
        "fullscreen",
        axes: &[],
        values: &[],
        usage: "The vertex shader of the fullscreen passes (apply, hull_composite): draw 3 \
                vertices without vertex buffers; it writes only the position.",
        render: RenderState { vertex: None, formats: &[], blend: None, ..FULLSCREEN_COMPOSITE }
    ),
    pass!(
        "apply",
        axes: &[
            Axis::Flag("VOLFOG_BINDINGS_NO_SAMPLER"),
            Axis::Flag("VOLFOG_APPLY_RESOLVED"),
            Axis::OneOf(&["VOLFOG_APPLY_EPIPOLAR", "VOLFOG_APPLY_NO_TAIL"]),
        ],
        values: &[],
        usage: "Draw 3 vertices with fullscreen_vs (pass fullscreen), no vertex buffers, onto \
                the lit colour target (load, no depth attachment). Blend colour: src * One + \
                dst * SrcAlpha (add); alpha: src * Zero + dst * One (add). Group 0 is the fog \
                group; its sampler (binding 2, absent in BINDINGS_NO_SAMPLER) is linear with \
                clamp-to-edge addressing. Group 1 binding 0 is the scene depth buffer, bound \
                as unfilterable float; under VOLFOG_APPLY_RESOLVED it is the resolved \
                two-channel MSAA fog layout (rg16float: r the view depth in m, g the fog \
                amount 1 - T, averaged by the resolve of a multisampled target the depth \
                pre-pass wrote with fog_layout), bound as unfilterable float. Under \
                VOLFOG_APPLY_EPIPOLAR group 1 binding 1 is the epipolar shaft texture \
                (rgba16float, rgb the lit fraction), bound as unfilterable float. \
                VOLFOG_APPLY_NO_TAIL leaves out the analytic tail beyond the far plane: use \
                it for frames whose tail has density 0, where it draws the same image for \
                less work per pixel. It declares no group 0 binding 3 (the tail), so the fog \
                group of the other variants fits it as it is.",
        render: FULLSCREEN_COMPOSITE
    ),
    pass!(
        "esm_downsample",
        axes: &[Axis::Flag("VOLFOG_ESM_LOG_SPACE"), Axis::Flag("VOLFOG_ESM_REVERSED_Z")],
        values: &[],
        usage: "Dispatch ceil(esm_width / 8) x ceil(esm_height / 8) x cascades workgroups; \
                the shadow map is 4x the ESM size, one array layer per cascade. The sampler \
                (binding 2) is non-filtering with clamp-to-edge addressing.",
        non_filtering: &["gather_sampler"]
    ),
    pass!(
        "esm_blur",
        axes: &[Axis::Flag("VOLFOG_ESM_LOG_SPACE")],
        values: &[ESM_BLUR_RADIUS],
        usage: "Run esm_blur_x from the ESM into a temporary array, then esm_blur_y back. \
                esm_blur_x: dispatch ceil(width / 64) x height x cascades; esm_blur_y: \
                ceil(height / 64) x width x cascades."
    ),
    pass!(
        "inject",
        axes: &[
            // Log space only changes how the ESM is read; the compare filter reads none.
            Axis::OneOf(&["VOLFOG_ESM_LOG_SPACE", "VOLFOG_INJECT_SHADOW_COMPARE"]),
            Axis::Flag("VOLFOG_INJECT_JITTER"),
            Axis::Flag("VOLFOG_INJECT_TWO_COLOR_PHASE"),
            Axis::Flag("VOLFOG_INJECT_DENSITY_TEXTURE"),
            Axis::Flag("VOLFOG_INJECT_CLOUD_SHADOW"),
            Axis::Flag("VOLFOG_INJECT_LOCAL_SHADOWS"),
            Axis::Sets(&[
                &[
                    "VOLFOG_FROXEL_CULL",
                    "VOLFOG_INJECT_CHECKERBOARD",
                    "VOLFOG_INJECT_NOISE_TEXTURE",
                ],
                &[
                    "VOLFOG_FROXEL_CULL",
                    "VOLFOG_INJECT_CHECKERBOARD",
                    "VOLFOG_INJECT_NOISE_TEXTURE",
                    "VOLFOG_INJECT_TEMPORAL",
                ],
                // The area lights (binding 33), prebuilt alone; the runtime composes
                // them with the other defines it needs.
                &["VOLFOG_INJECT_AREA_LIGHTS"],
            ]),
        ],
        values: &[INJECT_NOISE_OCTAVES],
        usage: "Dispatch ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 8) workgroups \
                (one per block of 4 x 4 x 8 froxels) after the ESM passes. The light buffer holds light_count FogLight elements \
                (64-byte stride), the local volume buffer local_volume_count LocalVolume \
                elements (112-byte stride); bind at least one element each. The density \
                sampler (binding 10) and the noise sampler (binding 13) are linear with \
                repeat addressing; binding 12 is the texture noise_bake wrote. Under \
                VOLFOG_FROXEL_CULL binding 11 is this frame's live-slice texture \
                (froxel_cull), bound as uint, binding 14 the live blocks, and the dispatch \
                is indirect from froxel_cull's arguments. VOLFOG_INJECT_CHECKERBOARD \
                needs FogFrame.checkerboard = 1 (temporal reads it), and the other \
                variants 0. Under VOLFOG_INJECT_TEMPORAL inject also does what the \
                temporal pass does (which then does not run): binding 8 is the \
                stabilised volume of this frame's parity, binding 22 the history (the \
                other parity's volume), bound as filterable float, binding 23 its \
                sampler, linear with clamp-to-edge addressing, bindings 24 and 25 the \
                history's and the stabilised volume's HistoryState (as temporal's 6 \
                and 7), and with VOLFOG_FROXEL_CULL binding 26 the live-slice texture \
                the history was written with (uint). Under VOLFOG_INJECT_LOCAL_SHADOWS binding 18 is the \
                local-light ESM atlas (r32float 2D array, after local_shadow_downsample \
                and esm_blur), bound as unfilterable float; binding 19 the \
                LightProjection buffer (112-byte stride, at least one element) that \
                FogLight.projection indexes (0xffffffff: none); binding 20 the cookie \
                array (a filterable float 2D array, at least one layer) and binding 21 \
                its sampler, linear with clamp-to-edge addressing. Under \
                VOLFOG_INJECT_SHADOW_COMPARE (the compare filter) no ESM pass runs: \
                binding 5 is the sun's cascaded shadow map itself (a depth texture of any \
                size, one layer per cascade, bound as unfilterable float), binding 27 the \
                ShadowTaps uniform (the tap offsets of this frame, their counts with and \
                without history, whether the sun's map holds reversed depth) and binding \
                28 a non-filtering sampler (nearest, clamp to edge) for the maps' \
                gathers; with VOLFOG_INJECT_LOCAL_SHADOWS binding 18 is absent and \
                bindings 29 and 30 are the spot lights' shadow maps and the point lights' \
                cube maps (six layers a cube), 2D arrays of depth bound as unfilterable \
                float (bind a 1 x 1 array where there is none), which \
                LightProjection.layer indexes directly; with VOLFOG_FROXEL_CULL binding 32 \
                is the scene depth froxel_cull reads, bound as unfilterable float (where \
                ShadowTaps.use_scene_depth is 1 the taps are moved in front of its surface; \
                bind a 1 x 1 texture where there is none). Under \
                VOLFOG_INJECT_CUSTOM_DENSITY (composed with the user's module, never \
                prebuilt) binding 31 is the FogCustomParams uniform (128 bytes: eight \
                vec4 the user's function reads).",
        non_filtering: &["gather_sampler"],
        hooks: &[CUSTOM_DENSITY]
    ),
    pass!(
        "local_shadow_downsample",
        axes: &[Axis::Flag("VOLFOG_ESM_LOG_SPACE")],
        values: &[],
        usage: "Dispatch ceil(atlas_size / 8) x ceil(atlas_size / 8) x n workgroups for n \
                LocalShadowSource elements (48-byte stride) at binding 0, after the \
                lights' shadow maps are rendered and before inject. Bindings 1 and 2 are \
                the spot lights' shadow maps and the point lights' cube maps (six layers \
                a cube) as 2D arrays of depth, bound as unfilterable float, each the \
                atlas size times a whole factor (bind a 1 x 1 array where there is none); \
                binding 3 the atlas (r32float 2D array storage, write); binding 4 a \
                non-filtering sampler (nearest, clamp to edge) for the maps' gathers. Then run \
                esm_blur_x from the atlas into a temporary array and esm_blur_y back over \
                the n written layers (the layers are written from 0 up).",
        non_filtering: &["gather_sampler"]
    ),
    pass!(
        "noise_bake",
        axes: &[],
        values: &[],
        usage: "Dispatch ceil(NOISE_TEXTURE_SIZE / 4) workgroups on each axis, once, into a \
                NOISE_TEXTURE_SIZE^3 rgba16float 3D texture (storage and texture binding \
                usage); inject@INJECT_NOISE_TEXTURE then samples it with a linear, repeat \
                sampler."
    ),
    pass!(
        "temporal",
        axes: &[Axis::Flag("VOLFOG_FROXEL_CULL")],
        values: &[],
        usage: "Dispatch ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 8) workgroups \
                (one per block of 4 x 4 x 8 froxels) after inject. Ping-pong two volumes and their HistoryState buffers (80 bytes, \
                zero-initialised) by frame parity: frame n reads volume and state (n + 1) % 2 \
                at bindings 3 and 6 and writes volume and state n % 2 at bindings 5 and 7. \
                The sampler (binding 4) is linear with clamp-to-edge addressing. Under \
                VOLFOG_FROXEL_CULL bindings 8 and 9 are the live-slice textures of this \
                frame and of the history (uint), binding 10 the live blocks, and the \
                dispatch is indirect from froxel_cull's arguments."
    ),
    pass!(
        "hull_thickness",
        axes: &[Axis::Flag("VOLFOG_HULL_RESOLVED")],
        values: &[],
        usage: "Draw each hull's triangle list (every face) into a float target cleared to 0, \
                the size of the scene depth buffer. Vertex buffer 0: stride 12, location 0 \
                = world position (Float32x3, offset 0; HLSL semantic LOC0; MSL [[attribute(0)]] \
                from a vertex-descriptor buffer index other than 0, which holds the uniform); \
                faces wound counter-clockwise seen from outside. Primitive: TriangleList, front face Ccw, cull mode none; no \
                depth-stencil attachment (depth test off). Target format Rgba16Float (with \
                FogHull.reference and quantum set from the hull's bounds) or Rgba32Float \
                where FLOAT32_BLENDABLE is available (quantum 0). Blend colour and alpha: \
                src * One + dst * One (add). Binding 1 is the scene depth buffer, bound as \
                unfilterable float; under VOLFOG_HULL_RESOLVED the resolved two-channel MSAA \
                fog layout (rg16float, r the view depth in m; see apply).",
        render: RenderState {
            vertex: None,
            formats: &["rgba16float", "rgba32float"],
            blend: Some(Blend {
                color: BlendComponent { src_factor: "one", dst_factor: "one", operation: "add" },
                alpha: BlendComponent { src_factor: "one", dst_factor: "one", operation: "add" },
            }),
            vertex_buffers: &[VertexBuffer {
                array_stride: 12,
                step_mode: "vertex",
                attributes: &[VertexAttribute { shader_location: 0, format: "float32x3", offset: 0 }],
            }],
            topology: "triangle-list",
            front_face: "ccw",
            cull_mode: "none",
        }
    ),
    pass!(
        "sky_solve",
        axes: &[],
        values: &[],
        usage: "Dispatch ceil(SKY_TEXTURE_WIDTH / 8) x ceil(rows / 8) x 1 workgroups to fill \
                rows [first_row, first_row + rows) of the sky texture (SkyAtmosphere.first_row): \
                all 64 rows at once, or a band per frame. Binding 1 is a 128 x 64 rgba16float \
                2D array of 2 layers (0 Rayleigh, 1 Mie) with storage and texture binding \
                usage; sky_draw and volfog::sky::sky_sample read it with a linear sampler, \
                repeat in u, clamp-to-edge in v."
    ),
    pass!(
        "sky_horizon",
        axes: &[],
        values: &[],
        usage: "Dispatch 1 workgroup whenever the sun moves. Binding 1 is a 32-byte storage \
                buffer: the Rayleigh (bytes 0-11) and Mie (bytes 16-27) scattering of the sky \
                averaged along the horizon, the colour of fog that matches the sky there \
                (volfog::sky::sky_radiance with the view's phase)."
    ),
    pass!(
        "sky_draw",
        axes: &[],
        values: &[],
        usage: "Draw 3 vertices with sky_draw_vs, no vertex buffers, onto the colour target \
                before the opaque geometry (no blending, no depth attachment). Binding 2 is \
                the sky texture sky_solve wrote; the sampler (binding 3) is linear, repeat in \
                u and clamp-to-edge in v.",
        render: RenderState { vertex: None, blend: None, ..FULLSCREEN_COMPOSITE }
    ),
    pass!(
        "clouds",
        axes: &[],
        values: &[],
        usage: "Draw 3 vertices with clouds_vs, no vertex buffers, onto the lit colour \
                target (load, no depth attachment), with cloud_shadow_fs (the clouds' shadow \
                on the lit scene), distance_clouds_fs or cloud_layer_fs. Blend colour: src * \
                One + dst * SrcAlpha (add); alpha: src * Zero + dst * One (add). Binding 2 is \
                the cloud density map (red channel) with a linear, repeat sampler (binding \
                3); binding 4 the scene depth buffer, bound as unfilterable float.",
        render: RenderState { vertex: None, ..FULLSCREEN_COMPOSITE }
    ),
    pass!(
        "hull_composite",
        axes: &[],
        values: &[],
        usage: "After hull_thickness, draw 3 vertices with fullscreen_vs (pass fullscreen), \
                no vertex buffers, onto the lit colour target (load, no depth attachment). Blend colour: src * One + dst * \
                SrcAlpha (add); alpha: src * Zero + dst * One (add). Binding 1 is the \
                hull_thickness target, bound as unfilterable float.",
        render: FULLSCREEN_COMPOSITE
    ),
    pass!(
        "epipolar_coords",
        axes: &[],
        values: &[],
        usage: "First pass of epipolar sun shafts (EpipolarShafts runs them all). Dispatch \
                ceil(samples / 64) x slices workgroups. Binding 1 is the scene depth buffer, \
                bound as unfilterable float; binding 2 the coordinate texture, rgba32float, \
                samples x slices, storage and texture binding usage."
    ),
    pass!(
        "epipolar_refine",
        axes: &[],
        values: &[],
        usage: "Dispatch samples / 128 x slices workgroups after epipolar_coords. Binding 1 is \
                the coordinate texture (unfilterable float); binding 2 the interpolation \
                sources, r32uint (two u16 indices), samples x slices, storage and texture \
                binding usage."
    ),
    pass!(
        "epipolar_tree",
        axes: &[],
        values: &[],
        usage: "Dispatch epipolar_tree_init ceil(shadow_size / 128) x slices with the tree \
                texture at binding 3 (rgba32float, shadow_size x slices, storage, texture \
                binding and copy-destination usage) and the scratch texture at binding 2 \
                (rgba32float, shadow_size / 4 x slices, storage, texture binding and copy \
                source usage). Then for l = 1 .. log2(shadow_size): epipolar_tree_level \
                ceil(max(shadow_size >> l, 2) / 128) x slices with the tree texture at \
                binding 2 and the scratch texture at binding 3, then copy the scratch \
                texels [0, max(shadow_size >> l, 2) / 2) of every row to the tree texture \
                at texel (2 shadow_size - (2 shadow_size >> l)) / 2. Binding 4 is a 16-byte \
                uniform whose first u32 is l (0 for init). Binding 1 is the shadow map, a \
                2D array bound as unfilterable float (one layer per cascade, as the ESM \
                passes read it)."
    ),
    pass!(
        "epipolar_march",
        axes: &[
            Axis::Flag("VOLFOG_EPIPOLAR_BRUTE_FORCE"),
            Axis::Flag("VOLFOG_EPIPOLAR_COLORED"),
        ],
        values: &[],
        usage: "Dispatch ceil(samples / 64) x slices workgroups after epipolar_refine and \
                epipolar_tree. Binding 4 is the tree texture (unfilterable float); under \
                VOLFOG_EPIPOLAR_BRUTE_FORCE the shadow map (2D array, unfilterable float). \
                Binding 5: rgba32float, samples x slices, storage and texture binding \
                usage. Under VOLFOG_EPIPOLAR_COLORED binding 6 is the light-space colour \
                texture (rgb, texel-aligned with the cascade), bound as unfilterable float."
    ),
    pass!(
        "epipolar_interpolate",
        axes: &[],
        values: &[],
        usage: "Dispatch ceil(samples / 64) x slices workgroups after epipolar_march. Binding 3: \
                rgba32float, samples x slices, storage and texture binding usage."
    ),
    pass!(
        "epipolar_resolve",
        axes: &[Axis::Flag("VOLFOG_EPIPOLAR_COLORED")],
        values: &[],
        usage: "Dispatch ceil(width / downscale / 8) x ceil(height / downscale / 8) workgroups \
                after epipolar_interpolate. Binding 6: rgba16float, ceil(width / downscale) x \
                ceil(height / downscale), storage and texture binding usage; binding 7 a \
                storage buffer of at least 2 u32 counters (zero them each frame). Under \
                VOLFOG_EPIPOLAR_COLORED binding 8 is the light-space colour texture, bound \
                as unfilterable float."
    ),
    pass!(
        "epipolar_upscale",
        axes: &[Axis::Flag("VOLFOG_EPIPOLAR_COLORED")],
        values: &[],
        usage: "Only when downscale > 1: dispatch ceil(width / 8) x ceil(height / 8) workgroups \
                after epipolar_resolve. Binding 5, the shaft texture: rgba16float, width x \
                height, storage and texture binding usage; binding 6 the resolve's counters. \
                Under VOLFOG_EPIPOLAR_COLORED binding 7 is the light-space colour texture, \
                bound as unfilterable float."
    ),
    pass!(
        "epipolar_reference",
        axes: &[Axis::Flag("VOLFOG_EPIPOLAR_COLORED")],
        values: &[],
        usage: "The brute-force reference: dispatch ceil(width / 8) x ceil(height / 8) \
                workgroups; binding 4 is the shaft texture (rgba16float, width x height). \
                Under VOLFOG_EPIPOLAR_COLORED binding 5 is the light-space colour texture, \
                bound as unfilterable float."
    ),
    pass!(
        "epipolar_apply",
        axes: &[],
        values: &[],
        usage: "Draw 3 vertices with fullscreen_vs (pass fullscreen), no vertex buffers, onto \
                the lit colour target (load, no depth attachment). Blend colour: src * One + \
                dst * SrcAlpha (add); alpha: src * Zero + dst * One (add). Bindings 2 (scene \
                depth) and 3 (shaft texture) are bound as unfilterable float.",
        render: FULLSCREEN_COMPOSITE
    ),
];

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

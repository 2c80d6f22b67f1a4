//! Every pass (entry-point file) of the manifest with its define axes, value defines,
//! usage text, render state and hooks.

use super::*;

/// Passes (entry-point files) and their define axes.
pub const PASSES: &[PassSource] = &[
    pass!(
        "scan",
        axes: &[Axis::Flag("VOLFOG_SCAN_WRONSKI_STEP"), Axis::Flag("VOLFOG_FROXEL_CULL"),
            Axis::OneOf(&["VOLFOG_SCAN_TRANSIENT_LIGHTS", "VOLFOG_SCAN_RESAMPLE"])],
        values: &[],
        usage: "Dispatch ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups (under \
                VOLFOG_SCAN_RESAMPLE ceil(size.x / 8) x ceil(size.y / 4) x 1) after the \
                scattering volume is written; the integrated volume is then read by apply. \
                Under VOLFOG_FROXEL_CULL binding 3 is this frame's live-slice texture \
                (froxel_cull), bound as uint. VOLFOG_SCAN_TRANSIENT_LIGHTS (frames with \
                transient lights; binding 1 the stabilised volume): bindings 4, 5, 6 are \
                FogMedium, TransientLighting and the transient FogLight buffer (>= 1). \
                VOLFOG_SCAN_RESAMPLE (stereo: both eyes' scans of the volume shared by \
                both eyes, in one dispatch): bindings 0, 2, 3 are the left eye's Froxels, \
                integrated volume and live slices, 1 the shared stabilised volume bound as \
                filterable float, 5 the left eye's TransientLighting (its rays), 7 a \
                filtering clamp-to-edge sampler, 8 the shared volume's FogFrame and 9 its \
                Froxels, 10, 11, 12 the right eye's Froxels, integrated volume and \
                TransientLighting, 13 its live slices (VOLFOG_FROXEL_CULL); not with \
                VOLFOG_SCAN_TRANSIENT_LIGHTS."
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
            // The resolved MSAA layout, the far field and the variant without the tail
            // combine as before; the multiview variant (stereo fog) reads depth, with
            // the tail or without it.
            Axis::Sets(&[
                &["VOLFOG_APPLY_RESOLVED"],
                &["VOLFOG_APPLY_EPIPOLAR"],
                &["VOLFOG_APPLY_NO_TAIL"],
                &["VOLFOG_APPLY_EPIPOLAR", "VOLFOG_APPLY_RESOLVED"],
                &["VOLFOG_APPLY_NO_TAIL", "VOLFOG_APPLY_RESOLVED"],
                &["VOLFOG_APPLY_MULTIVIEW"],
                &["VOLFOG_APPLY_MULTIVIEW", "VOLFOG_APPLY_NO_TAIL"],
            ]),
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
                group of the other variants fits it as it is. VOLFOG_APPLY_MULTIVIEW (stereo \
                fog, both eyes in one draw): a multiview render pass and pipeline with view \
                mask 0b11 onto a two-layer colour target (layer 0 the left eye); group 0 is \
                the stereo fog group (volfog::stereo_bindings: the left eye at the fog group's \
                bindings 0 to 4, the right eye's Froxels, volume, tail and FogView at 5, 6, 8, \
                9, one sampler at 2); group 1 binding 0 is a two-layer texture_2d_array of \
                the eyes' scene depths, bound as unfilterable float. Its fragment reads the \
                view index: HLSL needs SM 6.1 (SV_ViewID), MSL 2.2 (amplification_id), GLSL \
                GL_EXT_multiview (Vulkan GLSL, for glslang and shaderc: OpenGL drivers do not \
                take it), SPIR-V the MultiView capability; Dawn/Tint take \
                @builtin(view_index) only under `enable view_instancing;`, which the WGSL \
                file (as naga and wgpu write and read it) does not declare.",
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
                // The particles (binding 34), prebuilt alone; the runtime composes
                // them with the other defines it needs.
                &["VOLFOG_INJECT_PARTICLES"],
                // The medium's shadows (bindings 35 to 37), likewise.
                &["VOLFOG_INJECT_MEDIUM_SHADOW"],
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
                vec4 the user's function reads). Under VOLFOG_INJECT_MEDIUM_SHADOW \
                binding 35 is the volume the medium_shadow pass wrote this frame \
                (rgba16float 3D, bound as filterable float), binding 36 its sampler, \
                linear with clamp-to-edge addressing, binding 37 the MediumShadow \
                uniform medium_shadow read.",
        non_filtering: &["gather_sampler"],
        hooks: &[CUSTOM_DENSITY]
    ),
    pass!(
        "medium_shadow",
        axes: &[
            Axis::Flag("VOLFOG_INJECT_NOISE_TEXTURE"),
            Axis::Sets(&[&["VOLFOG_INJECT_DENSITY_TEXTURE"], &["VOLFOG_INJECT_PARTICLES"]]),
        ],
        values: &[INJECT_NOISE_OCTAVES],
        usage: "Entry point medium_shadow_fill. Dispatch size.x x size.y x 1 workgroups (one \
                per column of the MediumShadow volume, 64 invocations along it) each \
                frame before inject@INJECT_MEDIUM_SHADOW, with the defines of the medium \
                that inject variant has (noise texture, octaves, density texture, custom \
                density, particles) and the same FogFrame, FogMedium, local volumes, density \
                texture, noise texture, FogCustomParams and particles at the same binding \
                numbers. \
                Binding 35 is an rgba16float 3D storage texture of MediumShadow.size \
                texels (write), which inject then reads at its binding 35; binding 37 \
                the MediumShadow uniform (160 bytes): a box aligned with the sun, around \
                the view frustum up to the covered distance and reaching further towards \
                the sun, its origin snapped to whole texels.",
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

//! The pipelines the runtime creates for a [`FogConfig`], as the constructors of
//! `volfog::pipeline` compose them (`VolumetricFog::new`, `create_apply`, the
//! shadowed inject it compiles once shadow maps are set), and the passes one frame
//! runs, with their dispatch sizes and the trip counts of their loops.

use serde::Serialize;
use volfog::options::{InjectOptions, cull_defines};
use volfog::pipeline::FogConfig;
use volfog::pipeline::apply::NO_TAIL_DEFINE;
use volfog::pipeline::esm::BLUR_GROUP;
use volfog::pipeline::local_shadow::LocalShadowPass;

use crate::workload::Workload;

/// One shader variant the runtime builds pipelines from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RuntimeVariant {
    /// The pass.
    pub pass: &'static str,
    /// Its defines (`NAME` or `NAME=VALUE`), as the runtime passes them.
    pub defines: Vec<String>,
    /// When the runtime builds it.
    pub when: &'static str,
}

impl RuntimeVariant {
    /// A variant of `pass` (or another shader's name) with `defines`, built `when`.
    pub fn new(pass: &'static str, defines: Vec<String>, when: &'static str) -> Self {
        Self {
            pass,
            defines,
            when,
        }
    }

    /// The variant's name, `pass@default` or `pass@A+B` (as the exports name it).
    pub fn name(&self) -> String {
        let defines: Vec<&str> = self.defines.iter().map(String::as_str).collect();
        volfog_codegen::manifest::variant_name(self.pass, &defines)
    }
}

/// Every variant the runtime builds pipelines from for `config`: each of its compute
/// entry points is a compute pipeline, each fragment entry point a draw.
pub fn runtime_variants(config: &FogConfig) -> Vec<RuntimeVariant> {
    let esm = config.esm_options();
    let plain_inject = InjectOptions {
        local_shadows: false,
        ..config.inject_options()
    }
    .defines();
    // With the compare filter the ESM passes are built but do not run.
    let (esm_when, atlas_when) = if plain_inject.iter().any(|d| d == SHADOW_COMPARE_DEFINE) {
        (
            "built, not run: the compare filter reads the shadow map in inject",
            "built, not run: the compare filter reads the lights' maps in inject",
        )
    } else {
        (
            "every frame",
            "frames whose shadowed lights have new depth maps",
        )
    };
    let mut v = vec![
        RuntimeVariant::new("esm_downsample", esm.downsample_defines(), esm_when),
        RuntimeVariant::new("esm_blur", esm.blur_defines(), esm_when),
        RuntimeVariant::new("inject", plain_inject, "every frame"),
    ];
    if config.local_shadows.is_some() {
        v.push(RuntimeVariant::new(
            "inject",
            config.inject_options().defines(),
            "frames with shadowed point or spot lights",
        ));
        v.push(RuntimeVariant::new(
            "local_shadow_downsample",
            LocalShadowPass::defines(config.esm_log_space),
            atlas_when,
        ));
    }
    if config.depth_cull {
        v.push(RuntimeVariant::new(
            "froxel_cull",
            Vec::new(),
            "frames with a scene depth",
        ));
    }
    if config.temporal && !config.fused_temporal() {
        v.push(RuntimeVariant::new(
            "temporal",
            cull_defines(config.depth_cull),
            "every frame",
        ));
    }
    let mut scan = config.scan_step.defines();
    scan.extend(cull_defines(config.depth_cull));
    v.push(RuntimeVariant::new("scan", scan, "every frame"));
    v.extend(crate::transient::transient_variant(config));
    v.extend(crate::medium_shadow::medium_shadow_variant(config));
    if config.noise_texture {
        v.push(RuntimeVariant::new("noise_bake", Vec::new(), "once"));
    }
    let apply = config.apply_filtering.defines();
    let mut no_tail = apply.clone();
    no_tail.push(NO_TAIL_DEFINE.to_string());
    v.push(RuntimeVariant::new(
        "apply",
        apply,
        "frames whose pixels beyond the volume need the far-plane tail (create_apply)",
    ));
    v.push(RuntimeVariant::new(
        "apply",
        no_tail,
        "frames without a far-plane tail (create_apply)",
    ));
    v
}

/// Assassin's Creed IV's fog on the Xbox One, per pass (Wronski 2014, "Volumetric
/// fog: unified compute shader-based solution to atmospheric scattering", SIGGRAPH
/// 2014 Advances in Real-Time Rendering, the slide of timings): ms.
pub const AC4_MS: [(&str, f64); 5] = [
    ("ESM downsample", 0.163),
    ("ESM blur", 0.177),
    ("inject", 0.43),
    ("scan", 0.116),
    ("apply", 0.247),
];
/// AC4's whole fog on the Xbox One (ms).
pub const AC4_TOTAL_MS: f64 = 1.1;

/// The define that makes inject test shadows by depth compares instead of the ESM.
const SHADOW_COMPARE_DEFINE: &str = "VOLFOG_INJECT_SHADOW_COMPARE";

/// One dispatch or draw of a frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FramePass {
    /// The row's name (`inject`, `ESM blur x`, ...).
    pub name: String,
    /// The AC4 figure it counts towards ([`AC4_MS`]), if any.
    pub ac4: Option<&'static str>,
    /// Its shader variant.
    pub variant: RuntimeVariant,
    /// Its entry point.
    pub entry: String,
    /// Invocations dispatched (threads, or pixels).
    pub invocations: f64,
    /// Whether it runs over the live blocks only (its volume traffic scales by the
    /// live share).
    pub culled: bool,
    /// The colour target's bytes read by blending and written (a draw).
    pub target: (u64, u64),
    /// Bytes of bindings the pass sizes itself (where [`crate::floor::Sizes`] does not
    /// know them, or knows another texture by the same name).
    pub binding_bytes: Vec<(String, u64)>,
    /// Trip counts per wave of its loops, by the start of their labels
    /// ([`crate::loops::LoopInfo::label`]).
    pub trips: Vec<(String, f64)>,
}

/// Invocations of a 2D dispatch of `size` over workgroups of `group` x `group`.
fn grid2(size: (u32, u32), group: u32) -> f64 {
    f64::from(size.0.div_ceil(group) * group) * f64::from(size.1.div_ceil(group) * group)
}

fn trips(list: &[(&str, f64)]) -> Vec<(String, f64)> {
    list.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// The passes of one frame of `config` over `work` (the frame's scene, without
/// shadowed lights whose maps change: the local-light atlas does not run), in the
/// order the runtime records them, then the fullscreen apply.
pub fn frame_passes(config: &FogConfig, work: &Workload) -> Vec<FramePass> {
    let variants = runtime_variants(config);
    let variant = |pass: &str, when_contains: &str| -> RuntimeVariant {
        variants
            .iter()
            .find(|v| v.pass == pass && v.when.contains(when_contains))
            .cloned()
            .expect("runtime_variants lists every pass of a frame")
    };
    let [x, y, _] = work.grid;
    let mut passes = Vec::new();
    // Inject reads the medium-shadow volume, which Sizes does not know.
    let medium_shadow_bytes = config.medium_shadows.map_or(0, |m| m.memory_bytes());
    let mut add = |name: &str,
                   ac4,
                   variant: RuntimeVariant,
                   entry: &str,
                   invocations,
                   culled,
                   t: &[(&str, f64)]| {
        passes.push(FramePass {
            name: name.to_string(),
            ac4,
            variant,
            entry: entry.to_string(),
            invocations,
            culled,
            target: (0, 0),
            binding_bytes: if name == "inject" && medium_shadow_bytes > 0 {
                vec![(
                    crate::medium_shadow::MEDIUM_SHADOW_BINDING.to_string(),
                    medium_shadow_bytes,
                )]
            } else {
                Vec::new()
            },
            trips: trips(t),
        })
    };
    let inject = variant("inject", "every frame");
    let compares = inject.defines.iter().any(|d| d == SHADOW_COMPARE_DEFINE);
    if !compares {
        let res = config.esm_resolution;
        let layers = f64::from(config.cascades);
        add(
            "ESM downsample",
            Some("ESM downsample"),
            variant("esm_downsample", ""),
            "esm_downsample",
            grid2((res, res), 8) * layers,
            false,
            &[],
        );
        // The blur's workgroup loads its segment and the radius on either side.
        let fill = f64::from((BLUR_GROUP + 2 * config.esm_blur_radius).div_ceil(BLUR_GROUP));
        for axis in ["x", "y"] {
            add(
                &format!("ESM blur {axis}"),
                Some("ESM blur"),
                variant("esm_blur", ""),
                &format!("esm_blur_{axis}"),
                f64::from(res.div_ceil(BLUR_GROUP) * BLUR_GROUP) * f64::from(res) * layers,
                false,
                &[("blur: i < ", fill)],
            );
        }
    }
    if config.depth_cull {
        let cull = variant("froxel_cull", "");
        let (rows, cols) = work.cell_texels;
        add(
            "cull: cells",
            None,
            cull.clone(),
            "froxel_cull_cells",
            grid2((2 * x, 2 * y), 8),
            false,
            &[
                ("froxel_cull_cells: y <=", rows),
                ("froxel_cull_cells: x <=", cols),
            ],
        );
        add(
            "cull: columns",
            None,
            cull.clone(),
            "froxel_cull",
            grid2((x, y), 8),
            false,
            &[("froxel_cull: y <=", 4.0), ("froxel_cull: x <=", 4.0)],
        );
        add(
            "cull: blocks",
            None,
            cull,
            "froxel_cull_compact",
            grid2((x.div_ceil(4), y.div_ceil(4)), 8),
            false,
            &[
                ("froxel_cull_compact: y <=", 4.0),
                ("froxel_cull_compact: x <=", 4.0),
                ("froxel_cull_compact: z < count", work.compact_blocks),
            ],
        );
    }
    let group = if config.amortize { 64.0 } else { 128.0 };
    let blocks = if config.depth_cull {
        work.blocks.0
    } else {
        work.blocks.1
    };
    let taps = work.extra_shadow_taps;
    add(
        "inject",
        Some("inject"),
        inject,
        "inject",
        blocks as f64 * group,
        config.depth_cull,
        &[
            ("inject: i < light_count", work.light_gather),
            ("inject: i < volume_count", work.volume_gather),
            ("inject: other < tile_gathered", work.volume_sort),
            (
                "froxel_scattering: i < volume_count",
                work.volumes_per_block,
            ),
            (
                "froxel_scattering: i < tile_light_count",
                work.lights_per_block,
            ),
            (
                "froxel_scattering: i < shadowed_count",
                work.shadowed_per_block,
            ),
            ("esm_cascade:", work.cascade_steps),
            ("sun_visibility: t < taps", taps),
            ("local_visibility: t < taps", taps),
            (
                "medium_shadow_segment: i < steps",
                f64::from(config.medium_shadows.map_or(0, |m| m.march_steps)),
            ),
        ],
    );
    if config.temporal && !config.fused_temporal() {
        add(
            "temporal",
            None,
            variant("temporal", ""),
            "temporal",
            blocks as f64 * 128.0,
            config.depth_cull,
            &[],
        );
    }
    let scan_trips = [
        ("scan: k < live", work.scan_live),
        ("scan: k < slices", work.scan_rest),
    ];
    add(
        "scan",
        Some("scan"),
        variant("scan", ""),
        "scan",
        grid2((x, y), 8),
        config.depth_cull,
        &scan_trips,
    );
    passes.push(FramePass {
        name: "apply".to_string(),
        ac4: Some("apply"),
        variant: variant(
            "apply",
            if work.far_tail {
                "need the far-plane tail"
            } else {
                "without a far-plane tail"
            },
        ),
        entry: "apply_fs".to_string(),
        invocations: f64::from(work.screen.0) * f64::from(work.screen.1),
        culled: false,
        target: {
            let bytes = u64::from(work.screen.0) * u64::from(work.screen.1) * 8;
            (bytes, bytes)
        },
        binding_bytes: Vec::new(),
        trips: Vec::new(),
    });
    // The medium's shadows run just before inject.
    if let Some(pass) = crate::medium_shadow::medium_shadow_pass(config, work) {
        let at = passes
            .iter()
            .position(|p| p.name == "inject")
            .expect("every frame injects");
        passes.insert(at, pass);
    }
    passes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_configuration_builds_what_its_options_ask_for() {
        let config = FogConfig::default();
        let names: Vec<String> = runtime_variants(&config).iter().map(|v| v.name()).collect();
        assert!(names.contains(&"froxel_cull@default".to_string()));
        assert!(
            !names.iter().any(|n| n.starts_with("temporal@")),
            "{names:?}"
        );
        let apart = FogConfig {
            fuse_temporal: false,
            depth_cull: false,
            local_shadows: None,
            ..FogConfig::default()
        };
        let names: Vec<String> = runtime_variants(&apart).iter().map(|v| v.name()).collect();
        assert!(names.contains(&"temporal@default".to_string()), "{names:?}");
        assert!(!names.iter().any(|n| n.starts_with("froxel_cull")));
        assert_eq!(names.iter().filter(|n| n.starts_with("inject@")).count(), 1);
    }

    #[test]
    fn a_frame_runs_the_esm_passes_only_with_the_esm_filter() {
        let work = Workload {
            grid: [160, 90, 64],
            screen: (1920, 1080),
            far_tail: false,
            blocks: (100, 200),
            live_fraction: 0.5,
            lights: 8,
            local_volumes: 1,
            light_gather: 0.5,
            volume_gather: 0.5,
            lights_per_block: 1.0,
            shadowed_per_block: 0.0,
            volumes_per_block: 0.25,
            volume_sort: 0.125,
            cascade_steps: 1.0,
            extra_shadow_taps: 0.0,
            scan_live: 40.0,
            scan_rest: 24.0,
            compact_blocks: 5.0,
            cell_texels: (7.0, 7.0),
        };
        let names = |p: &[FramePass]| p.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        let compare = frame_passes(&FogConfig::default(), &work);
        assert_eq!(
            names(&compare),
            [
                "cull: cells",
                "cull: columns",
                "cull: blocks",
                "inject",
                "scan",
                "apply"
            ]
        );
        let inject = &compare[3];
        // The live blocks, 128 invocations each; the volume traffic is the live share.
        assert_eq!(inject.invocations, 100.0 * 128.0);
        assert!(inject.culled);
        assert!(
            inject
                .trips
                .iter()
                .any(|(k, n)| k == "froxel_scattering: i < tile_light_count" && *n == 1.0)
        );
        let apply = &compare[5];
        assert!(apply.variant.defines.iter().any(|d| d == NO_TAIL_DEFINE));
        assert_eq!(apply.invocations, 1920.0 * 1080.0);
        let esm = FogConfig {
            shadow_filter: volfog::options::ShadowFilter::Esm,
            ..FogConfig::default()
        };
        let with_esm = frame_passes(&esm, &work);
        assert_eq!(
            names(&with_esm)[..3],
            ["ESM downsample", "ESM blur x", "ESM blur y"]
        );
        // One invocation per ESM texel of each cascade; the blur loads its segment and
        // 5 texels either side in two rounds of 64.
        assert_eq!(with_esm[0].invocations, 256.0 * 256.0 * 4.0);
        assert_eq!(with_esm[1].trips, [("blur: i < ".to_string(), 2.0)]);
    }
}

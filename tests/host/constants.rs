//! Every WGSL constant that has a Rust twin, read from the composed naga modules, against
//! that twin; and every compute pass's workgroup size against the constant the runtime
//! dispatches with.

use naga_oil::compose::{Composer, NagaModuleDescriptor};
use volfog::cpu;
use volfog::limits;
use volfog_codegen::names::undecorate;

/// A scalar constant of a naga module by its (undecorated) name, as f64.
fn constant(module: &naga::Module, name: &str) -> Option<f64> {
    module.constants.iter().find_map(|(_, c)| {
        let n = c.name.as_deref()?;
        let plain = undecorate(n).map_or(n.to_string(), |(item, _)| item);
        if plain != name {
            return None;
        }
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => Some(f64::from(v)),
            naga::Expression::Literal(naga::Literal::U32(v)) => Some(f64::from(v)),
            naga::Expression::Literal(naga::Literal::I32(v)) => Some(f64::from(v)),
            ref other => panic!("{name}: not a scalar literal: {other:?}"),
        }
    })
}

/// A module that imports `names` from the volfog module `path` and uses each of them.
fn import(path: &str, names: &[&str]) -> naga::Module {
    let uses: Vec<String> = names.iter().map(|n| format!("f32({n})")).collect();
    let source = format!(
        "#import {path}::{{{}}}\n@compute @workgroup_size(1) fn main() {{ let sink = {}; }}\n",
        names.join(", "),
        uses.join(" + ")
    );
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).unwrap();
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: &source,
            file_path: "constants.wgsl",
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)))
}

#[test]
fn module_constants_match_their_rust_twins() {
    let twins: &[(&str, &[(&str, f64)])] = &[
        (
            "volfog::phase",
            &[
                ("PI", cpu::phase::PI as f64),
                ("INV_4PI", cpu::phase::INV_4PI as f64),
                ("SH_Y0", cpu::phase::SH_Y0 as f64),
                ("SH_Y1", cpu::phase::SH_Y1 as f64),
            ],
        ),
        (
            "volfog::froxel",
            &[
                ("CURVE_LINEAR_LIMIT", cpu::froxel::CURVE_LINEAR_LIMIT as f64),
                ("FROXEL_BLOCK_X", volfog::pipeline::cull::BLOCK[0] as f64),
                ("FROXEL_BLOCK_Y", volfog::pipeline::cull::BLOCK[1] as f64),
                ("FROXEL_BLOCK_Z", volfog::pipeline::cull::BLOCK[2] as f64),
            ],
        ),
        (
            "volfog::height_fog",
            &[
                ("FOG_SERIES_LIMIT", cpu::height_fog::FOG_SERIES_LIMIT as f64),
                (
                    "FOG_EXPONENT_LIMIT",
                    cpu::height_fog::FOG_EXPONENT_LIMIT as f64,
                ),
                ("FOG_DENSITY_LIMIT", limits::FOG_DENSITY_LIMIT as f64),
                ("FOG_FALLOFF_LIMIT", limits::FOG_FALLOFF_LIMIT as f64),
                ("FOG_POSITION_LIMIT", limits::FOG_POSITION_LIMIT as f64),
                ("FOG_PEAK_LIMIT", cpu::height_fog::FOG_PEAK_LIMIT as f64),
            ],
        ),
        (
            "volfog::density",
            &[
                (
                    "DENSITY_MAX_EXPONENT",
                    cpu::density::DENSITY_MAX_EXPONENT as f64,
                ),
                ("LOCAL_VOLUME_ADD", cpu::density::LOCAL_VOLUME_ADD as f64),
                (
                    "LOCAL_VOLUME_SUBTRACT",
                    cpu::density::LOCAL_VOLUME_SUBTRACT as f64,
                ),
                (
                    "LOCAL_VOLUME_MULTIPLY",
                    cpu::density::LOCAL_VOLUME_MULTIPLY as f64,
                ),
                ("LOCAL_VOLUME_MIN", cpu::density::LOCAL_VOLUME_MIN as f64),
                ("LOCAL_VOLUME_MAX", cpu::density::LOCAL_VOLUME_MAX as f64),
                (
                    "LOCAL_VOLUME_OVERWRITE",
                    cpu::density::LOCAL_VOLUME_OVERWRITE as f64,
                ),
                (
                    "LOCAL_VOLUME_ADD",
                    volfog::uniforms::BlendMode::Add as u32 as f64,
                ),
                (
                    "LOCAL_VOLUME_SUBTRACT",
                    volfog::uniforms::BlendMode::Subtract as u32 as f64,
                ),
                (
                    "LOCAL_VOLUME_MULTIPLY",
                    volfog::uniforms::BlendMode::Multiply as u32 as f64,
                ),
                (
                    "LOCAL_VOLUME_MIN",
                    volfog::uniforms::BlendMode::Min as u32 as f64,
                ),
                (
                    "LOCAL_VOLUME_MAX",
                    volfog::uniforms::BlendMode::Max as u32 as f64,
                ),
                (
                    "LOCAL_VOLUME_OVERWRITE",
                    volfog::uniforms::BlendMode::Overwrite as u32 as f64,
                ),
                (
                    "FOG_SAMPLE_MAX_EXTINCTION",
                    cpu::density::FOG_SAMPLE_MAX_EXTINCTION as f64,
                ),
                (
                    "FOG_SAMPLE_MAX_EXTINCTION",
                    limits::LOCAL_VOLUME_DENSITY.max as f64,
                ),
                (
                    "FOG_SAMPLE_MAX_EMISSION",
                    cpu::density::FOG_SAMPLE_MAX_EMISSION as f64,
                ),
                ("FOG_SAMPLE_MAX_EMISSION", limits::EMISSION.max as f64),
            ],
        ),
        (
            "volfog::noise",
            &[
                ("NOISE_MAX_OCTAVES", cpu::noise::NOISE_MAX_OCTAVES as f64),
                ("NOISE_MAX_OCTAVES", limits::NOISE_OCTAVES.max as f64),
                (
                    "NOISE_TEXTURE_PERIOD",
                    cpu::noise::NOISE_TEXTURE_PERIOD as f64,
                ),
                (
                    "NOISE_TEXTURE_TEXELS_PER_UNIT",
                    cpu::noise::NOISE_TEXTURE_TEXELS_PER_UNIT as f64,
                ),
                ("NOISE_TEXTURE_SIZE", cpu::noise::NOISE_TEXTURE_SIZE as f64),
            ],
        ),
        (
            "volfog::scan",
            &[("SCAN_SERIES_LIMIT", cpu::scan::SCAN_SERIES_LIMIT as f64)],
        ),
        (
            "volfog::soft_particles",
            &[
                (
                    "SOFT_PARTICLE_MIN_THICKNESS",
                    cpu::soft_particles::SOFT_PARTICLE_MIN_THICKNESS as f64,
                ),
                (
                    "SOFT_PARTICLE_DEPTH_LIMIT",
                    cpu::soft_particles::SOFT_PARTICLE_DEPTH_LIMIT as f64,
                ),
            ],
        ),
        (
            "volfog::fog_volume",
            &[
                (
                    "FOG_VOLUME_BOX",
                    volfog::uniforms::VolumeShape::Box as u32 as f64,
                ),
                (
                    "FOG_VOLUME_ELLIPSOID",
                    volfog::uniforms::VolumeShape::Ellipsoid as u32 as f64,
                ),
                ("FOG_VOLUME_BOX", cpu::fog_volume::FOG_VOLUME_BOX as f64),
                (
                    "FOG_VOLUME_ELLIPSOID",
                    cpu::fog_volume::FOG_VOLUME_ELLIPSOID as f64,
                ),
                (
                    "FOG_VOLUME_MIN_DIRECTION",
                    cpu::fog_volume::FOG_VOLUME_MIN_DIRECTION as f64,
                ),
                ("FOG_VOLUME_PLANE", cpu::fog_volume::FOG_VOLUME_PLANE as f64),
            ],
        ),
        (
            "volfog::apply",
            &[(
                "FOG_RESOLVED_MIN_AMOUNT",
                cpu::apply::FOG_RESOLVED_MIN_AMOUNT as f64,
            )],
        ),
        (
            "volfog::sky",
            &[
                ("SKY_TEXTURE_WIDTH", cpu::sky::SKY_TEXTURE_WIDTH as f64),
                ("SKY_TEXTURE_HEIGHT", cpu::sky::SKY_TEXTURE_HEIGHT as f64),
                ("SKY_PI", cpu::sky::SKY_PI as f64),
                ("SKY_OPAQUE", cpu::sky::SKY_OPAQUE as f64),
            ],
        ),
        (
            "volfog::clouds",
            &[
                (
                    "CLOUD_MIN_SUN_HEIGHT",
                    cpu::clouds::CLOUD_MIN_SUN_HEIGHT as f64,
                ),
                ("CLOUD_MAX_DISTANCE", cpu::clouds::CLOUD_MAX_DISTANCE as f64),
            ],
        ),
        (
            "volfog::epipolar",
            &[
                ("EPIPOLAR_INVALID", cpu::epipolar::INVALID as f64),
                (
                    "EPIPOLAR_INVALID_DEPTH",
                    cpu::epipolar::INVALID_DEPTH as f64,
                ),
                ("EPIPOLAR_GROUP", cpu::epipolar::GROUP as f64),
                ("EPIPOLAR_LIT_DEPTH", cpu::epipolar::LIT_DEPTH as f64),
                ("EPIPOLAR_BORDER", cpu::epipolar::BORDER as f64),
            ],
        ),
        (
            "volfog::water",
            &[(
                "WATER_MIN_SHORE_FADE",
                cpu::water::WATER_MIN_SHORE_FADE as f64,
            )],
        ),
        (
            "volfog::lightning",
            &[
                (
                    "LIGHTNING_POSITION_LIMIT",
                    cpu::lightning::LIGHTNING_POSITION_LIMIT as f64,
                ),
                (
                    "LIGHTNING_ATTENUATION_LIMIT",
                    cpu::lightning::LIGHTNING_ATTENUATION_LIMIT as f64,
                ),
                (
                    "LIGHTNING_INTENSITY_LIMIT",
                    cpu::lightning::LIGHTNING_INTENSITY_LIMIT as f64,
                ),
                (
                    "LIGHTNING_SERIES_LIMIT",
                    cpu::lightning::LIGHTNING_SERIES_LIMIT as f64,
                ),
                ("LIGHTNING_PI", cpu::phase::PI as f64),
            ],
        ),
        (
            "volfog::hull",
            &[("HULL_MIN_W", cpu::hull::HULL_MIN_W as f64)],
        ),
    ];
    let mut checked = 0;
    for (path, pairs) in twins {
        let names: Vec<&str> = pairs
            .iter()
            .map(|(n, _)| *n)
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let module = import(path, &names);
        for (name, rust) in *pairs {
            let wgsl =
                constant(&module, name).unwrap_or_else(|| panic!("{path}::{name} not found"));
            // f32 twins: equal after rounding to f32.
            assert_eq!(
                wgsl as f32, *rust as f32,
                "{path}::{name}: WGSL {wgsl} vs Rust {rust}"
            );
            checked += 1;
        }
    }
    eprintln!("{checked} WGSL constants equal their Rust twins");
}

#[test]
fn pass_constants_and_workgroups_match_the_runtime() {
    use volfog::pipeline::{cull, esm, inject, noise, scan, temporal};
    let pass = |name: &str, defines: &[&str]| {
        let defines: Vec<String> = defines.iter().map(|d| d.to_string()).collect();
        volfog::shaders::compose(name, &defines).unwrap()
    };
    let inject_module = pass("inject", &[]);
    assert_eq!(
        constant(&inject_module, "TILE_LIGHTS"),
        Some(limits::MAX_LIGHTS as f64)
    );
    assert_eq!(
        constant(&inject_module, "HALF_MAX"),
        Some(cpu::inject::HALF_MAX as f64)
    );
    assert_eq!(
        constant(
            &pass("temporal", &["VOLFOG_FROXEL_CULL"]),
            "TEMPORAL_HISTORY_REACH"
        ),
        Some(cpu::temporal::HISTORY_REACH as f64)
    );
    let blur = pass("esm_blur", &[]);
    assert_eq!(constant(&blur, "GROUP"), Some(esm::BLUR_GROUP as f64));
    let workgroup = |m: &naga::Module, entry: &str| {
        m.entry_points
            .iter()
            .find(|e| e.name == entry)
            .unwrap()
            .workgroup_size
    };
    assert_eq!(workgroup(&inject_module, "inject"), inject::WORKGROUP);
    assert_eq!(
        workgroup(&pass("inject", &["VOLFOG_INJECT_CHECKERBOARD"]), "inject"),
        inject::WORKGROUP_CHECKERBOARD
    );
    let cull_module = pass("froxel_cull", &[]);
    let w = cull::WORKGROUP;
    assert_eq!(workgroup(&cull_module, "froxel_cull_cells"), [w, w, 1]);
    assert_eq!(workgroup(&cull_module, "froxel_cull"), [w, w, 1]);
    let w = cull::COMPACT_WORKGROUP;
    assert_eq!(workgroup(&cull_module, "froxel_cull_compact"), [w, w, 1]);
    let w = noise::WORKGROUP;
    assert_eq!(workgroup(&pass("noise_bake", &[]), "noise_bake"), [w, w, w]);
    assert_eq!(
        workgroup(&pass("temporal", &[]), "temporal"),
        temporal::WORKGROUP
    );
    assert_eq!(
        workgroup(&pass("scan", &[]), "scan"),
        [scan::WORKGROUP, scan::WORKGROUP, 1]
    );
    let w = esm::DOWNSAMPLE_WORKGROUP;
    assert_eq!(
        workgroup(&pass("esm_downsample", &[]), "esm_downsample"),
        [w, w, 1]
    );
    for entry in ["esm_blur_x", "esm_blur_y"] {
        assert_eq!(workgroup(&blur, entry), [esm::BLUR_GROUP, 1, 1], "{entry}");
    }
}

//! Every bind group layout the wgpu runtime builds against the reflection of the
//! shader it binds (the manifest's bindings): the same bindings, and for each the same
//! buffer type, texture sample type and dimension, storage format and access, sampler
//! type, and a visibility that includes every stage that uses it.

use volfog::options::{ApplyInput, CULL_DEFINE, Filtering, InjectOptions};
use volfog::pipeline::{
    apply, clouds, cull, esm, hull, inject, local_shadow, noise, scan, sky, temporal,
};
use volfog_codegen::Stage;
use volfog_codegen::reflect::Resource;
use volfog_codegen::translate::VariantOutput;

fn variant(name: &str) -> &'static VariantOutput {
    crate::common::variants()
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("variant {name}"))
}

fn stage_flag(stage: Stage) -> wgpu::ShaderStages {
    match stage {
        Stage::Compute => wgpu::ShaderStages::COMPUTE,
        Stage::Vertex => wgpu::ShaderStages::VERTEX,
        Stage::Fragment => wgpu::ShaderStages::FRAGMENT,
    }
}

fn dimension(d: wgpu::TextureViewDimension) -> &'static str {
    match d {
        wgpu::TextureViewDimension::D1 => "1d",
        wgpu::TextureViewDimension::D2 => "2d",
        wgpu::TextureViewDimension::D2Array => "2d-array",
        wgpu::TextureViewDimension::Cube => "cube",
        wgpu::TextureViewDimension::CubeArray => "cube-array",
        wgpu::TextureViewDimension::D3 => "3d",
    }
}

/// The reflection's description of what a layout entry must be.
fn matches(entry: &wgpu::BindGroupLayoutEntry, resource: &Resource) -> Result<(), String> {
    use wgpu::BindingType as B;
    let ok = match (&entry.ty, resource) {
        (B::Buffer { ty, .. }, Resource::Buffer { ty: want, .. }) => {
            let got = match ty {
                wgpu::BufferBindingType::Uniform => "uniform",
                wgpu::BufferBindingType::Storage { read_only: true } => "read-only-storage",
                wgpu::BufferBindingType::Storage { read_only: false } => "storage",
            };
            got == want
        }
        (
            B::Texture {
                sample_type,
                view_dimension,
                multisampled,
            },
            Resource::Texture {
                view_dimension: want_dim,
                sample_type: want_type,
                multisampled: want_ms,
            },
        ) => {
            let got = match sample_type {
                wgpu::TextureSampleType::Float { filterable: true } => "float",
                wgpu::TextureSampleType::Float { filterable: false } => "unfilterable-float",
                wgpu::TextureSampleType::Depth => "depth",
                wgpu::TextureSampleType::Sint => "sint",
                wgpu::TextureSampleType::Uint => "uint",
            };
            got == want_type && dimension(*view_dimension) == want_dim && multisampled == want_ms
        }
        (
            B::StorageTexture {
                access,
                format,
                view_dimension,
            },
            Resource::StorageTexture {
                view_dimension: want_dim,
                format: want_format,
                access: want_access,
            },
        ) => {
            let got_access = match access {
                wgpu::StorageTextureAccess::WriteOnly => "write-only",
                wgpu::StorageTextureAccess::ReadOnly => "read-only",
                wgpu::StorageTextureAccess::ReadWrite => "read-write",
                wgpu::StorageTextureAccess::Atomic => "atomic",
            };
            got_access == want_access
                && format!("{format:?}").to_lowercase() == *want_format
                && dimension(*view_dimension) == want_dim
        }
        (B::Sampler(kind), Resource::Sampler { ty }) => {
            let got = match kind {
                wgpu::SamplerBindingType::Filtering => "filtering",
                wgpu::SamplerBindingType::NonFiltering => "non-filtering",
                wgpu::SamplerBindingType::Comparison => "comparison",
            };
            got == ty
        }
        _ => false,
    };
    if ok {
        Ok(())
    } else {
        Err(format!("layout {:?} vs shader {resource:?}", entry.ty))
    }
}

/// Checks the layouts of `groups` (group index, entries) against every entry point of
/// the variant: each reflected binding has its entry, and every entry of the groups in
/// `complete` is used.
fn check(variant_name: &str, groups: &[(u32, Vec<wgpu::BindGroupLayoutEntry>)]) -> usize {
    check_entries(
        &variant(variant_name).entries,
        variant_name,
        groups,
        &[0, 1],
    )
}

fn check_entries(
    entries: &[volfog_codegen::translate::EntryOutput],
    variant_name: &str,
    groups: &[(u32, Vec<wgpu::BindGroupLayoutEntry>)],
    complete: &[u32],
) -> usize {
    let v = VariantOutput {
        name: variant_name.to_string(),
        pass: String::new(),
        defines: Vec::new(),
        entries: entries.to_vec(),
    };
    let mut problems = Vec::new();
    let mut used = std::collections::BTreeSet::new();
    for e in &v.entries {
        for b in &e.reflection.bindings {
            let entry = groups
                .iter()
                .find(|(g, _)| *g == b.group)
                .and_then(|(_, entries)| entries.iter().find(|l| l.binding == b.binding));
            let Some(entry) = entry else {
                problems.push(format!("{} {}: no layout entry", e.entry, b.name));
                continue;
            };
            used.insert((b.group, b.binding));
            if let Err(p) = matches(entry, &b.resource) {
                problems.push(format!("{} {}: {p}", e.entry, b.name));
            }
            if !entry.visibility.contains(stage_flag(e.stage)) {
                problems.push(format!(
                    "{} {}: not visible to {:?}",
                    e.entry, b.name, e.stage
                ));
            }
        }
    }
    for (g, entries) in groups.iter().filter(|(g, _)| complete.contains(g)) {
        for l in entries {
            if !used.contains(&(*g, l.binding)) {
                problems.push(format!(
                    "group {g} binding {}: in the layout, unused",
                    l.binding
                ));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "{variant_name}:\n{}",
        problems.join("\n")
    );
    used.len()
}

#[test]
fn runtime_layouts_match_the_shaders() {
    let mut checked = 0;
    for v in volfog_codegen::manifest::variants()
        .into_iter()
        .filter(|v| v.pass.name == "scan")
    {
        let cull = v.defines.contains(&CULL_DEFINE);
        let transient = v.defines.contains(&scan::TRANSIENT_LIGHTS_DEFINE);
        let entries = if v.defines.contains(&scan::RESAMPLE_DEFINE) {
            scan::ScanPass::resample_layout_entries(cull)
        } else {
            scan::ScanPass::layout_entries(cull, transient)
        };
        checked += check(&v.name, &[(0, entries)]);
    }
    for (name, cull) in [("temporal@default", false), ("temporal@FROXEL_CULL", true)] {
        checked += check(name, &[(0, temporal::TemporalPass::layout_entries(cull))]);
    }
    checked += check(
        "froxel_cull@default",
        &[(0, cull::FroxelCullPass::layout_entries().to_vec())],
    );
    checked += check(
        "noise_bake@default",
        &[(0, noise::NoiseBake::layout_entries().to_vec())],
    );
    for name in ["esm_downsample@default", "esm_downsample@ESM_LOG_SPACE"] {
        checked += check(name, &[(0, esm::EsmPasses::downsample_entries().to_vec())]);
    }
    for name in ["esm_blur@default", "esm_blur@ESM_LOG_SPACE"] {
        checked += check(name, &[(0, esm::EsmPasses::blur_entries().to_vec())]);
    }
    for name in [
        "local_shadow_downsample@default",
        "local_shadow_downsample@ESM_LOG_SPACE",
    ] {
        checked += check(
            name,
            &[(0, local_shadow::LocalShadowPass::layout_entries().to_vec())],
        );
    }
    for v in volfog_codegen::manifest::variants()
        .into_iter()
        .filter(|v| v.pass.name == "inject")
    {
        let options = InjectOptions {
            density_texture: v.defines.contains(&"VOLFOG_INJECT_DENSITY_TEXTURE"),
            noise_texture: v.defines.contains(&"VOLFOG_INJECT_NOISE_TEXTURE"),
            depth_cull: v.defines.contains(&CULL_DEFINE),
            checkerboard: v.defines.contains(&"VOLFOG_INJECT_CHECKERBOARD"),
            cloud_shadow: v.defines.contains(&"VOLFOG_INJECT_CLOUD_SHADOW"),
            local_shadows: v.defines.contains(&"VOLFOG_INJECT_LOCAL_SHADOWS"),
            temporal: v.defines.contains(&"VOLFOG_INJECT_TEMPORAL"),
            shadow_compare: v.defines.contains(&"VOLFOG_INJECT_SHADOW_COMPARE"),
            area_lights: v.defines.contains(&"VOLFOG_INJECT_AREA_LIGHTS"),
            particles: v.defines.contains(&"VOLFOG_INJECT_PARTICLES"),
            medium_shadow: v.defines.contains(&"VOLFOG_INJECT_MEDIUM_SHADOW"),
            ..InjectOptions::default()
        };
        checked += check(
            &v.name,
            &[(0, inject::InjectPass::layout_entries(&options))],
        );
    }
    for v in volfog_codegen::manifest::variants()
        .into_iter()
        .filter(|v| v.pass.name == "medium_shadow")
    {
        let options = InjectOptions {
            density_texture: v.defines.contains(&"VOLFOG_INJECT_DENSITY_TEXTURE"),
            noise_texture: v.defines.contains(&"VOLFOG_INJECT_NOISE_TEXTURE"),
            particles: v.defines.contains(&"VOLFOG_INJECT_PARTICLES"),
            ..InjectOptions::default()
        };
        checked += check(
            &v.name,
            &[(
                0,
                volfog::pipeline::medium_shadow::MediumShadowPass::layout_entries(&options),
            )],
        );
    }
    // The custom-density variant (composed with a user's module, never prebuilt), alone
    // and with the runtime's default defines.
    let swirl = volfog_codegen::custom::CustomModule::new(
        "examples/portal_swirl.wgsl",
        include_str!("../../examples/portal_swirl.wgsl"),
    );
    let hook = volfog_codegen::manifest::CUSTOM_DENSITY;
    for options in [
        InjectOptions {
            jitter: false,
            noise_texture: false,
            custom_density: true,
            ..InjectOptions::default()
        },
        InjectOptions {
            custom_density: true,
            local_shadows: false,
            ..volfog::pipeline::FogConfig::default().inject_options()
        },
    ] {
        let out = volfog_codegen::translate::compose_variant_with(
            "inject",
            &options.defines(),
            volfog_codegen::reflect::HlslSamplers::Classic,
            &[(&hook, &swirl)],
        )
        .unwrap_or_else(|e| panic!("{e}"));
        checked += check_entries(
            &out.entries,
            &out.name,
            &[(0, inject::InjectPass::layout_entries(&options))],
            &[0, 1],
        );
    }
    for v in volfog_codegen::manifest::variants()
        .into_iter()
        .filter(|v| v.pass.name == "apply")
    {
        let name = v.name.as_str();
        let filtering = if v.defines.contains(&"VOLFOG_BINDINGS_NO_SAMPLER") {
            Filtering::Manual
        } else {
            Filtering::Sampler
        };
        let input = if v.defines.contains(&"VOLFOG_APPLY_EPIPOLAR") {
            ApplyInput::FarField
        } else {
            ApplyInput::Depth
        };
        // The multiview apply reads the stereo fog group and the eyes' depth array.
        let groups = if v.defines.contains(&apply::MULTIVIEW_DEFINE) {
            [
                (
                    0,
                    apply::stereo_fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT),
                ),
                (1, apply::depth_array_layout_entries().to_vec()),
            ]
        } else {
            [
                (
                    0,
                    apply::fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT),
                ),
                (1, apply::input_layout_entries(input)),
            ]
        };
        // The apply pass reads the fog group but not its FogView (binding 4; the stereo
        // group's 4 and 9).
        checked += check_entries(&variant(name).entries, name, &groups, &[1]);
    }
    for name in ["hull_thickness@default", "hull_thickness@HULL_RESOLVED"] {
        checked += check(
            name,
            &[(0, hull::HullThicknessPass::layout_entries().to_vec())],
        );
    }
    checked += check(
        "hull_composite@default",
        &[(0, hull::HullCompositePass::layout_entries().to_vec())],
    );
    {
        use volfog::pipeline::epipolar::EpipolarShafts as E;
        for (name, entries) in [
            ("epipolar_coords@default", E::coords_entries()),
            ("epipolar_refine@default", E::refine_entries()),
            ("epipolar_tree@default", E::tree_entries()),
            ("epipolar_interpolate@default", E::interpolate_entries()),
            ("epipolar_apply@default", E::apply_entries()),
        ] {
            checked += check(name, &[(0, entries)]);
        }
        for v in volfog_codegen::manifest::variants() {
            let colored = v.defines.contains(&"VOLFOG_EPIPOLAR_COLORED");
            let entries = match v.pass.name {
                "epipolar_march" => {
                    E::march_entries(v.defines.contains(&"VOLFOG_EPIPOLAR_BRUTE_FORCE"), colored)
                }
                "epipolar_resolve" => E::resolve_entries(colored),
                "epipolar_upscale" => E::upscale_entries(colored),
                "epipolar_reference" => E::reference_entries(colored),
                _ => continue,
            };
            checked += check(&v.name, &[(0, entries)]);
        }
    }
    checked += check(
        "sky_solve@default",
        &[(0, sky::SkyLight::solve_layout_entries().to_vec())],
    );
    checked += check(
        "sky_horizon@default",
        &[(0, sky::SkyLight::horizon_layout_entries().to_vec())],
    );
    checked += check(
        "sky_draw@default",
        &[(0, sky::SkyLight::draw_layout_entries().to_vec())],
    );
    checked += check(
        "clouds@default",
        &[(0, clouds::CloudPasses::layout_entries().to_vec())],
    );
    eprintln!("{checked} runtime layout entries match their shaders' bindings");
}

/// The layout check fails on a mismatch: a filterable texture where the shader only
/// loads, and a missing binding.
#[test]
fn a_wrong_layout_is_caught() {
    let mut wrong = scan::ScanPass::layout_entries(false, false);
    if let wgpu::BindingType::Texture { sample_type, .. } = &mut wrong[1].ty {
        *sample_type = wgpu::TextureSampleType::Float { filterable: true };
    }
    let caught = std::panic::catch_unwind(|| check("scan@default", &[(0, wrong.clone())]));
    assert!(caught.is_err());
    wrong.remove(0);
    let caught = std::panic::catch_unwind(|| check("scan@default", &[(0, wrong)]));
    assert!(caught.is_err());
}

/// The fog group's layout against a shader that reads every binding of
/// `volfog::bindings` (as a forward shader may).
#[test]
fn fog_group_layout_matches_volfog_bindings() {
    for (filtering, defs) in [
        (Filtering::Sampler, vec![]),
        (
            Filtering::Manual,
            vec![(
                "VOLFOG_BINDINGS_NO_SAMPLER",
                naga_oil::compose::ShaderDefValue::Bool(true),
            )],
        ),
    ] {
        let source = format!(
            "#import volfog::bindings\n\
             #import volfog::apply::{{fog_coord_from_world, {}, fog_tail}}\n\
             @fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {{\n\
                 let view = bindings::fog_view.view_from_world;\n\
                 let coord = fog_coord_from_world(p.xyz, view, bindings::fog_froxels);\n\
                 let fog = {};\n\
                 return fog + fog_tail(bindings::fog_froxels, bindings::fog_far_tail, p.xyz);\n\
             }}\n",
            if filtering == Filtering::Sampler {
                "fog_sample"
            } else {
                "fog_load"
            },
            if filtering == Filtering::Sampler {
                "fog_sample(bindings::fog_integrated, bindings::fog_sampler, coord)"
            } else {
                "fog_load(bindings::fog_integrated, coord)"
            }
        );
        let module = volfog_testkit::kernel::compose(&source, &defs);
        let entries =
            volfog_codegen::translate::translate("fog group", module, &Default::default()).unwrap();
        let groups = [(
            0,
            apply::fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT),
        )];
        let n = check_entries(&entries, "fog group", &groups, &[0]);
        assert_eq!(
            n,
            if filtering == Filtering::Sampler {
                5
            } else {
                4
            }
        );
    }
}

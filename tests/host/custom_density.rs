//! The export of inject with a custom density (`volfog export --custom-density FILE`,
//! `ExportRequest::custom_density`): the example module `examples/portal_swirl.wgsl`
//! composed into the bare custom-density variant and into the runtime's default inject
//! variant, every file of both through the same independent compilers as every other
//! export (spirv-val, the Khronos validation layer with the manifest's layouts, Slang,
//! Mesa's OpenGL driver with the manifest's bindings, Dawn/Tint), and the manifest
//! describing binding 31 and `FogCustomParams`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;
use volfog_codegen::Target;
use volfog_codegen::custom::CustomModule;
use volfog_codegen::export::{ExportRequest, export};
use volfog_codegen::manifest::CUSTOM_DENSITY;
use volfog_codegen::reflect::HlslSamplers;

use crate::common::scratch;
use crate::compilers::{dawn, gl_resources, manifest_resources, slang};
use crate::exports::tool;
use crate::spirv_pipelines::{add_bindings, read_spirv};
use crate::tools::{gl_link, output, text};

/// The example module, as a user hands it over.
fn swirl() -> CustomModule {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/portal_swirl.wgsl");
    CustomModule::new(
        "examples/portal_swirl.wgsl",
        std::fs::read_to_string(path).unwrap(),
    )
}

/// The inject pass exported with `defines` and the example module, in every target.
fn export_with(name: &str, defines: &[&str]) -> (PathBuf, Value) {
    let out = scratch(name);
    export(&ExportRequest {
        out: out.clone(),
        targets: Target::ALL.to_vec(),
        variants: vec!["inject".to_string()],
        defines: defines.iter().map(|d| d.to_string()).collect(),
        hlsl_samplers: HlslSamplers::Classic,
        snippets: None,
        custom_density: Some(swirl()),
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    (out, serde_json::from_str(&manifest).unwrap())
}

#[test]
fn inject_with_a_custom_density_exports_through_every_compiler() {
    let runtime_default = [
        CUSTOM_DENSITY.define,
        "VOLFOG_FROXEL_CULL",
        "VOLFOG_INJECT_JITTER",
        "VOLFOG_INJECT_NOISE_TEXTURE",
        "VOLFOG_INJECT_SHADOW_COMPARE",
        "VOLFOG_INJECT_TEMPORAL",
    ];
    let validator = vkcheck::Validator::new().unwrap_or_else(|e| panic!("{e}"));
    for (name, defines) in [
        ("custom-density-bare", &[CUSTOM_DENSITY.define][..]),
        ("custom-density-default", &runtime_default[..]),
    ] {
        let (dir, manifest) = export_with(name, defines);
        let variants = manifest["variants"].as_array().unwrap();
        assert_eq!(variants.len(), 1, "{name}: one variant");
        let variant = &variants[0];
        let vname = variant["name"].as_str().unwrap();
        assert!(vname.contains("INJECT_CUSTOM_DENSITY"), "{vname}");
        let entry = &variant["entry_points"][0];
        assert_eq!(entry["name"], "inject");

        // The manifest: binding 31 is the FogCustomParams uniform (128 bytes).
        let params = entry["bindings"]
            .as_array()
            .unwrap()
            .iter()
            .find(|b| b["binding"] == 31)
            .unwrap_or_else(|| panic!("{vname}: no binding 31"));
        assert_eq!(params["resource"]["type"], "uniform", "{params}");
        assert_eq!(params["resource"]["size"], 128, "{params}");
        assert_eq!(params["resource"]["struct"], "FogCustomParams", "{params}");
        let structs = entry["structs"].as_array().unwrap();
        assert!(
            structs.iter().any(|s| s["name"] == "FogCustomParams"),
            "{vname}: FogCustomParams is among the layouts"
        );

        // The user's function under its own name in the WGSL.
        let wgsl =
            std::fs::read_to_string(dir.join(entry["files"]["wgsl"].as_str().unwrap())).unwrap();
        assert!(wgsl.contains("fn volfog_custom_density("), "{vname}");

        // spirv-val.
        let spv = dir.join(entry["files"]["spirv"].as_str().unwrap());
        let o = tool("spirv-val")
            .args(["--target-env", "vulkan1.1"])
            .arg(&spv)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{vname}: {}",
            String::from_utf8_lossy(&o.stderr)
        );

        // The Khronos validation layer, with the layout from the manifest alone.
        let spirv = read_spirv(&dir, entry["files"]["spirv"].as_str().unwrap());
        let mut sets = Vec::new();
        add_bindings(&mut sets, entry);
        let messages = validator
            .compute_pipeline(&spirv, "inject", &sets)
            .unwrap_or_else(|e| panic!("{vname}: {e}"));
        assert!(messages.is_empty(), "{vname}: {messages:?}");

        // Slang (HLSL front end, warnings as errors).
        let hlsl = dir.join(entry["files"]["hlsl"].as_str().unwrap());
        slang(&hlsl, "compute", "inject").unwrap_or_else(|e| panic!("{vname}: {e}"));

        // Mesa's OpenGL driver: compiled, linked, every block and image at its
        // manifest binding and size.
        let glsl = entry["files"]["glsl"].as_str().unwrap();
        let o = output(
            gl_link()
                .current_dir(&dir)
                .arg("--json")
                .arg(format!("comp:{glsl}")),
        );
        assert!(o.status.success(), "{vname}: {}", text(&o));
        let report: Value = serde_json::from_slice(&o.stdout).unwrap();
        let mut expected = BTreeMap::new();
        manifest_resources(entry, &mut expected);
        assert_eq!(gl_resources(&report), expected, "{vname}");

        // Dawn/Tint: the module and its pipeline from the manifest, on the null and the
        // OpenGL backend.
        for backend in ["null", "opengl"] {
            let failed = dawn(&dir.join("manifest.json"), backend, 1);
            assert!(failed.is_empty(), "{vname} on {backend}: {failed:?}");
        }
        eprintln!(
            "{vname} with examples/portal_swirl.wgsl: spirv-val, the validation layer, \
             Slang, Mesa GL and Dawn (null, OpenGL) pass; binding 31 is FogCustomParams"
        );
    }

    // Without the define the module has nothing to go into: a typed error.
    let err = export(&ExportRequest {
        out: scratch("custom-density-no-define"),
        targets: vec![Target::Wgsl],
        variants: vec!["inject".to_string()],
        defines: vec![],
        hlsl_samplers: HlslSamplers::Classic,
        snippets: None,
        custom_density: Some(swirl()),
    })
    .unwrap_err();
    assert!(err.to_string().contains(CUSTOM_DENSITY.define), "{err}");
}

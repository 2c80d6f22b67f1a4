//! The export folder (`volfog_codegen::export`): every SPIR-V file passes `spirv-val`,
//! every GLSL file passes `glslangValidator`, the manifest describes every file,
//! custom defines compose at run time, a re-export replaces the previous one, and
//! bindings keep their WGSL names in every target.

use std::path::{Path, PathBuf};
use std::process::Command;

use volfog_codegen::Target;
use volfog_codegen::export::{ExportRequest, export};
use volfog_codegen::reflect::HlslSamplers;

use crate::common::{exported, scratch, variants};

const TOOLS_HINT: &str = "apt-get update && apt-get install -y spirv-tools glslang-tools";

pub(crate) fn tool(name: &str) -> Command {
    let probe = Command::new(name).arg("--version").output();
    if probe.is_err() {
        panic!("{name} is not installed; install it with: {TOOLS_HINT}");
    }
    Command::new(name)
}

fn files_with_ext(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    files
}

#[test]
fn every_spirv_export_passes_spirv_val() {
    let out = exported();
    let files = files_with_ext(&out.join("spirv"), "spv");
    assert_eq!(
        files.len(),
        variants().iter().map(|v| v.entries.len()).sum::<usize>()
    );
    for f in &files {
        let o = tool("spirv-val")
            .args(["--target-env", "vulkan1.1"])
            .arg(f)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            f.display(),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    // The validator is live: a truncated module is rejected.
    let broken = scratch("broken-spirv").with_extension("spv");
    let bytes = std::fs::read(&files[0]).unwrap();
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    let o = tool("spirv-val")
        .args(["--target-env", "vulkan1.1"])
        .arg(&broken)
        .output()
        .unwrap();
    assert!(!o.status.success(), "spirv-val accepted a truncated module");
}

#[test]
fn every_glsl_export_passes_glslang() {
    let out = exported();
    let files = files_with_ext(&out.join("glsl"), "glsl");
    assert!(!files.is_empty());
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let stage = name.rsplit('.').nth(1).unwrap();
        assert!(["comp", "vert", "frag"].contains(&stage), "{name}");
        let o = tool("glslangValidator")
            .args(["-S", stage])
            .arg(f)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        let text = std::fs::read_to_string(f).unwrap();
        assert!(text.starts_with("#version 450"), "{name}");
        assert!(!text.contains("naga_oil"), "{name} has a decorated name");
    }
    let broken = scratch("broken-glsl").with_extension("comp");
    std::fs::write(&broken, "#version 450\nvoid main() { undefined_call(); }\n").unwrap();
    let o = tool("glslangValidator").arg(&broken).output().unwrap();
    assert!(!o.status.success(), "glslangValidator accepted broken GLSL");
}

#[test]
fn manifest_lists_every_file_with_explicit_slots() {
    let out = exported();
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let variants = manifest["variants"].as_array().unwrap();
    assert_eq!(variants.len(), crate::common::variants().len());
    let mut listed = 0;
    for v in variants {
        for e in v["entry_points"].as_array().unwrap() {
            for (target, file) in e["files"].as_object().unwrap() {
                let path = out.join(file.as_str().unwrap());
                assert!(path.is_file(), "{target}: {} missing", path.display());
                listed += 1;
            }
            for b in e["bindings"].as_array().unwrap() {
                assert!(b["hlsl"]["register"].is_string(), "{b}");
                assert!(b["msl"]["index"].is_u64(), "{b}");
                assert!(b["spirv"]["set"].is_u64(), "{b}");
                if b["resource"]["kind"] != "sampler" {
                    assert!(b["glsl"]["binding"].is_u64(), "{b}");
                }
            }
            if e["stage"] == "compute" {
                assert!(e["workgroup_size"].is_array());
            }
        }
    }
    for s in manifest["snippets"].as_array().unwrap() {
        for (target, file) in s["files"].as_object().unwrap() {
            let path = out.join(file.as_str().unwrap());
            assert!(path.is_file(), "{target}: {} missing", path.display());
            listed += 1;
        }
    }
    let files_in = |dir: &Path| {
        std::fs::read_dir(dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().path().is_file())
            .count()
    };
    let on_disk: usize = ["wgsl", "spirv", "glsl", "hlsl", "msl"]
        .iter()
        .map(|t| {
            let include = out.join(t).join("include");
            files_in(&out.join(t))
                + if include.is_dir() {
                    files_in(&include)
                } else {
                    0
                }
        })
        .sum();
    assert_eq!(listed, on_disk, "every file is listed in the manifest");
    assert!(
        out.join(manifest["layout_header"].as_str().unwrap())
            .is_file()
    );
    // No target falls back to naga's invented slots.
    for t in ["msl", "hlsl"] {
        for f in std::fs::read_dir(out.join(t)).unwrap() {
            let path = f.unwrap().path();
            if path.is_file() {
                let text = std::fs::read_to_string(path).unwrap();
                assert!(!text.contains("fake"), "{t} output uses a fake binding");
            }
        }
    }
}

#[test]
fn custom_defines_compose_at_run_time() {
    let out = scratch("export-custom");
    export(&ExportRequest {
        out: out.clone(),
        targets: vec![Target::Wgsl, Target::Hlsl],
        variants: vec![],
        defines: vec!["VOLFOG_SCAN_WRONSKI_STEP".to_string()],
        hlsl_samplers: HlslSamplers::Classic,
        snippets: None,
        custom_density: None,
    })
    .unwrap();
    let wgsl =
        std::fs::read_to_string(out.join("wgsl/scan@SCAN_WRONSKI_STEP.scan.comp.wgsl")).unwrap();
    let listed = variants()
        .iter()
        .find(|v| v.name == "scan@SCAN_WRONSKI_STEP")
        .unwrap();
    assert_eq!(
        wgsl, listed.entries[0].wgsl,
        "a composition from defines equals the manifest's variant"
    );
    assert!(
        out.join("hlsl/scan@SCAN_WRONSKI_STEP.scan.comp.hlsl")
            .is_file()
    );
    assert!(!out.join("spirv").exists());
}

#[test]
fn re_export_replaces_the_previous_export_whole() {
    let out = scratch("export-replace");
    let request = |targets: Vec<Target>, variants: Vec<String>| ExportRequest {
        out: out.clone(),
        targets,
        variants,
        defines: vec![],
        hlsl_samplers: HlslSamplers::Classic,
        snippets: None,
        custom_density: None,
    };
    export(&request(Target::ALL.to_vec(), vec![])).unwrap();
    std::fs::write(out.join("hlsl/stale.hlsl"), "old").unwrap();
    std::fs::write(out.join("notes.txt"), "user file").unwrap();
    export(&request(vec![Target::Hlsl], vec!["scan".to_string()])).unwrap();
    assert!(!out.join("hlsl/stale.hlsl").exists());
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "user file"
    );
    assert!(
        !out.join("glsl").exists(),
        "targets the manifest no longer lists are removed"
    );
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    assert!(
        !manifest.contains("apply@"),
        "the manifest lists only the new export"
    );
}

#[test]
fn bindings_keep_their_wgsl_names_in_every_target() {
    let mut problems = Vec::new();
    for v in variants() {
        for e in &v.entries {
            for b in &e.reflection.bindings {
                let n = &b.name;
                let hlsl_ok = e.hlsl.contains(&format!("{n} : register("))
                    || e.hlsl.contains(&format!("cbuffer {n} : register("))
                    || e.hlsl.contains(&format!("static const SamplerState {n} ="));
                let msl_ok = e.msl.contains(&format!(" {n} [["));
                let glsl_ok = b.glsl.as_ref().is_none_or(|g| &g.name == n);
                let wgsl_ok =
                    e.wgsl.contains(&format!("var {n}:")) || e.wgsl.contains(&format!("> {n}:"));
                for (target, ok) in [
                    ("hlsl", hlsl_ok),
                    ("msl", msl_ok),
                    ("glsl", glsl_ok),
                    ("wgsl", wgsl_ok),
                ] {
                    if !ok {
                        problems.push(format!(
                            "{} {}: binding {n} renamed in {target}",
                            v.name, e.entry
                        ));
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// `volfog_layout.h` compiles as C11 and C++17 with every warning an error, including
/// after `near` and `far` were defined as empty macros (as windows.h does), and
/// declares every struct of the manifest with its size.
#[test]
fn layout_header_compiles_in_c_and_cpp() {
    let out = exported();
    let header = std::fs::read_to_string(out.join("volfog_layout.h")).unwrap();
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let mut structs = std::collections::BTreeMap::new();
    for v in manifest["variants"].as_array().unwrap() {
        for e in v["entry_points"].as_array().unwrap() {
            for s in e["structs"].as_array().unwrap() {
                structs.insert(
                    s["name"].as_str().unwrap().to_string(),
                    s["size"].as_u64().unwrap(),
                );
            }
        }
    }
    for (name, size) in &structs {
        assert!(
            header.contains(&format!("sizeof(volfog_{name}) == {size},")),
            "{name} ({size} bytes) is not in the header"
        );
    }
    let dir = scratch("layout-header");
    std::fs::create_dir_all(&dir).unwrap();
    let source = "#define near\n#define far\n#include \"volfog_layout.h\"\n\
                  int volfog_check(void) { volfog_Froxels f; f.curve = 1.0f; return (int)sizeof f + (int)f.curve; }\n";
    for (compiler, std, file) in [
        ("gcc", "-std=c11", "check.c"),
        ("g++", "-std=c++17", "check.cpp"),
    ] {
        let path = dir.join(file);
        std::fs::write(&path, source).unwrap();
        let o = Command::new(compiler)
            .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic", "-c", "-o"])
            .arg(dir.join(format!("{file}.o")))
            .arg("-I")
            .arg(out)
            .arg(&path)
            .output()
            .unwrap_or_else(|e| panic!("{compiler}: {e}"));
        assert!(
            o.status.success(),
            "{compiler}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    eprintln!(
        "volfog_layout.h: {} structs, compiled by gcc (C11) and g++ (C++17)",
        structs.len()
    );
    // The assertions are live: a header with one offset changed does not compile.
    let broken = header.replacen(
        "== 140, \"volfog_Froxels.near",
        "== 144, \"volfog_Froxels.near",
        1,
    );
    assert_ne!(broken, header);
    std::fs::write(dir.join("volfog_layout.h"), broken).unwrap();
    std::fs::write(dir.join("broken.c"), "#include \"volfog_layout.h\"\n").unwrap();
    let o = Command::new("gcc")
        .args(["-std=c11", "-c", "-o"])
        .arg(dir.join("broken.o"))
        .arg("-I")
        .arg(&dir)
        .arg(dir.join("broken.c"))
        .output()
        .unwrap();
    assert!(!o.status.success(), "a wrong offset must fail to compile");
}

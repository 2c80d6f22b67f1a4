//! Exports through the `volfog` binary: every SPIR-V file passes `spirv-val`, every
//! GLSL file passes `glslangValidator`, the manifest describes every file, and bad
//! requests exit with code 2 leaving nothing behind.

use std::path::{Path, PathBuf};
use std::process::Command;

const TOOLS_HINT: &str = "apt-get update && apt-get install -y spirv-tools glslang-tools";

fn volfog() -> Command {
    Command::new(env!("CARGO_BIN_EXE_volfog"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn tool(name: &str) -> Command {
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

fn export_all(name: &str) -> PathBuf {
    let out = scratch(name);
    let status = volfog()
        .args(["export", "--target", "all", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    out
}

#[test]
fn every_spirv_export_passes_spirv_val() {
    let out = export_all("export-spirv");
    let files = files_with_ext(&out.join("spirv"), "spv");
    assert_eq!(
        files.len(),
        volfog::shaders::variants()
            .iter()
            .map(|v| v.entries.len())
            .sum::<usize>()
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
    let broken = out.join("broken.spv");
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
    let out = export_all("export-glsl");
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
    let broken = out.join("broken.comp");
    std::fs::write(&broken, "#version 450\nvoid main() { undefined_call(); }\n").unwrap();
    let o = tool("glslangValidator").arg(&broken).output().unwrap();
    assert!(!o.status.success(), "glslangValidator accepted broken GLSL");
}

#[test]
fn manifest_lists_every_file_with_explicit_slots() {
    let out = export_all("export-manifest");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let variants = manifest["variants"].as_array().unwrap();
    assert_eq!(variants.len(), volfog::shaders::variants().len());
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
    let on_disk: usize = ["wgsl", "spirv", "glsl", "hlsl", "msl"]
        .iter()
        .map(|t| std::fs::read_dir(out.join(t)).unwrap().count())
        .sum();
    assert_eq!(listed, on_disk);
    // No target falls back to naga's invented slots.
    for t in ["msl", "hlsl"] {
        for f in std::fs::read_dir(out.join(t)).unwrap() {
            let text = std::fs::read_to_string(f.unwrap().path()).unwrap();
            assert!(!text.contains("fake"), "{t} output uses a fake binding");
        }
    }
}

#[test]
fn custom_defines_compose_at_run_time() {
    let out = scratch("export-custom");
    let o = volfog()
        .args([
            "export",
            "--target",
            "wgsl,hlsl",
            "--define",
            "VOLFOG_SCAN_WRONSKI_STEP",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let wgsl =
        std::fs::read_to_string(out.join("wgsl/scan@SCAN_WRONSKI_STEP.scan.comp.wgsl")).unwrap();
    let prebuilt = volfog::shaders::variant("scan@SCAN_WRONSKI_STEP")
        .unwrap()
        .entries[0]
        .wgsl;
    assert_eq!(
        wgsl, prebuilt,
        "a runtime composition equals the prebuilt one"
    );
    assert!(out
        .join("hlsl/scan@SCAN_WRONSKI_STEP.scan.comp.hlsl")
        .is_file());
    assert!(!out.join("spirv").exists());
}

#[test]
fn bad_requests_exit_2_and_write_nothing() {
    let cases: [&[&str]; 4] = [
        &["export", "--target", "dxil"],
        &["export", "--target", "all", "--variant", "scan@NOPE"],
        &[
            "export",
            "--target",
            "all",
            "--define",
            "VOLFOG_NOT_A_DEFINE",
        ],
        &[
            "export",
            "--target",
            "all",
            "--variant",
            "apply",
            "--define",
            "VOLFOG_SCAN_WRONSKI_STEP",
        ],
    ];
    for (i, args) in cases.iter().enumerate() {
        let out = scratch(&format!("export-bad-{i}"));
        let o = volfog()
            .args(*args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("valid") || stderr.contains("possible values"),
            "{args:?} lists the valid choices: {stderr}"
        );
        assert!(!out.exists(), "{args:?} left {}", out.display());
        let parent = out.parent().unwrap();
        let leftovers: Vec<_> = std::fs::read_dir(parent)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains("volfog-staging"))
            .collect();
        assert!(leftovers.is_empty(), "staging folders left behind");
    }
}

#[test]
fn re_export_replaces_the_previous_export_whole() {
    let out = export_all("export-replace");
    std::fs::write(out.join("hlsl/stale.hlsl"), "old").unwrap();
    std::fs::write(out.join("notes.txt"), "user file").unwrap();
    let status = volfog()
        .args(["export", "--target", "hlsl", "--variant", "scan", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
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
    for v in volfog::shaders::variants() {
        for e in v.entries {
            let reflection = e.reflection();
            for b in &reflection.bindings {
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

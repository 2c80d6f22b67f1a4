//! `volfog export` and `volfog list` through the binary: a complete export, and bad
//! requests that exit with code 2, list the valid choices and leave nothing behind.

use std::path::{Path, PathBuf};
use std::process::Command;

fn volfog() -> Command {
    Command::new(env!("CARGO_BIN_EXE_volfog"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn export_writes_every_variant_and_the_manifest() {
    let out = scratch("cli-export");
    let o = volfog()
        .args(["export", "--target", "spirv,hlsl", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let variants = volfog_codegen::manifest::variants().len();
    assert!(
        stdout.contains(&format!("exported {variants} variants")),
        "{stdout}"
    );
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["variants"].as_array().unwrap().len(), variants);
    assert!(out.join("spirv").is_dir() && out.join("hlsl").is_dir());
    assert!(!out.join("glsl").exists());
}

#[test]
fn export_writes_the_named_snippets_and_lists_them() {
    let out = scratch("cli-export-snippets");
    let o = volfog()
        .args([
            "export",
            "--target",
            "glsl,hlsl",
            "--snippets",
            "phase,lightning",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let names: Vec<&str> = manifest["snippets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["phase", "lightning"]);
    for file in [
        "glsl/include/volfog_phase.glsl",
        "hlsl/include/volfog_lightning.hlsli",
        "volfog_layout.h",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    assert!(!out.join("glsl/include/volfog_apply.glsl").exists());
}

#[test]
fn list_names_every_variant() {
    let o = volfog().arg("list").output().unwrap();
    assert!(o.status.success());
    let stdout = String::from_utf8_lossy(&o.stdout);
    for v in volfog_codegen::manifest::variants() {
        assert!(stdout.contains(&v.name), "{} missing", v.name);
    }
}

#[test]
fn bad_requests_exit_2_and_write_nothing() {
    let cases: [&[&str]; 5] = [
        &["export", "--target", "dxil"],
        &[
            "export",
            "--target",
            "hlsl",
            "--snippets",
            "apply,fog_light",
        ],
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
        // A parent of its own: other tests export beside their own folders meanwhile.
        let out = scratch(&format!("cli-export-bad-{i}")).join("out");
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
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
        let leftovers: Vec<_> = std::fs::read_dir(out.parent().unwrap())
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains("volfog-staging"))
            .collect();
        assert!(leftovers.is_empty(), "staging folders left behind");
    }
}

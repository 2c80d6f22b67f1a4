//! Every exported file through a compiler that is not naga, with the manifest as the
//! only description: HLSL through Slang's HLSL front end (warnings as errors), GLSL
//! compiled and linked per program by Mesa's OpenGL 4.5 driver (uniform blocks, samplers
//! and images at the manifest's bindings), WGSL modules and pipelines in Dawn/Tint (its
//! null backend, and its OpenGL backend, where Tint's output is compiled by Mesa). Each
//! tool also rejects a broken input, so a pass means something.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::common::{entry_points, exported, manifest, scratch, vertex_of};
use crate::tools::{
    dawn_check, dawn_results, each_in_parallel, gl_link, glslang, output, slang_check, text,
};

pub(crate) fn slang(file: &Path, stage: &str, entry: &str) -> Result<(), String> {
    let o = output(
        slang_check()
            .args([
                "--werror", "--target", "hlsl", "--stage", stage, "--entry", entry,
            ])
            .arg(file),
    );
    if o.status.success() {
        Ok(())
    } else {
        Err(text(&o))
    }
}

#[test]
fn every_hlsl_export_compiles_in_slang() {
    let dir = exported();
    let entries = entry_points();
    let failed: Vec<String> = each_in_parallel(&entries, |(variant, e)| {
        let file = dir.join(e["files"]["hlsl"].as_str().unwrap());
        let (stage, name) = (e["stage"].as_str().unwrap(), e["name"].as_str().unwrap());
        slang(&file, stage, name)
            .err()
            .map(|message| format!("{variant}.{name}: {message}"))
    })
    .into_iter()
    .flatten()
    .collect();
    eprintln!(
        "hlsl x Slang (HLSL front end, sm_6_0, warnings as errors): {} passed, {} failed",
        entries.len() - failed.len(),
        failed.len()
    );
    assert!(failed.is_empty(), "{}", failed.join("\n"));

    // Slang is live: a float4 stored into a one-channel storage texture is rejected.
    let bad = scratch("slang-negative").with_extension("hlsl");
    std::fs::write(
        &bad,
        "RWTexture2DArray<float> filtered : register(u0);\n\
         [numthreads(8, 8, 1)] void main(uint3 id : SV_DispatchThreadID) {\n\
         filtered[int3(id)] = float4(1.0, 0.0, 0.0, 0.0);\n}\n",
    )
    .unwrap();
    assert!(slang(&bad, "compute", "main").is_err());
}

/// What GL reports of a linked program, keyed by (kind, name): binding and, for blocks,
/// data size.
pub(crate) fn gl_resources(report: &Value) -> BTreeMap<(String, String), (u64, Option<u64>)> {
    let mut out = BTreeMap::new();
    for (key, kind) in [
        ("uniform_blocks", "uniform_block"),
        ("shader_storage_blocks", "shader_storage_block"),
    ] {
        for b in report[key].as_array().unwrap() {
            out.insert(
                (kind.to_string(), b["name"].as_str().unwrap().to_string()),
                (b["binding"].as_u64().unwrap(), b["data_size"].as_u64()),
            );
        }
    }
    for u in report["opaque_uniforms"].as_array().unwrap() {
        let ty = u["type"].as_str().unwrap();
        let kind = if ty.starts_with("image") || ty.starts_with("uimage") {
            "image_unit"
        } else {
            "texture_unit"
        };
        out.insert(
            (kind.to_string(), u["name"].as_str().unwrap().to_string()),
            (u["binding"].as_u64().unwrap(), None),
        );
    }
    out
}

/// What the manifest says GL will report for an entry point's bindings.
pub(crate) fn manifest_resources(
    entry: &Value,
    into: &mut BTreeMap<(String, String), (u64, Option<u64>)>,
) {
    for b in entry["bindings"].as_array().unwrap() {
        let glsl = &b["glsl"];
        if glsl.is_null() {
            // A sampler: merged into the combined sampler of its texture.
            assert_eq!(b["resource"]["kind"], "sampler", "{b}");
            continue;
        }
        let namespace = glsl["namespace"].as_str().unwrap();
        let size = b["resource"]["size"].as_u64();
        let (name, size) = match namespace {
            "uniform_block" => (glsl["block"].as_str().unwrap(), size),
            // Mesa reports a storage block's data size rounded up to 16 bytes (a block
            // of one u32 array element, or of three u32, reads 16).
            "shader_storage_block" => (
                glsl["block"].as_str().unwrap(),
                size.map(|s| s.div_ceil(16) * 16),
            ),
            _ => (glsl["name"].as_str().unwrap(), None),
        };
        into.insert(
            (namespace.to_string(), name.to_string()),
            (glsl["binding"].as_u64().unwrap(), size),
        );
    }
}

#[test]
fn every_glsl_program_links_in_mesa_with_the_manifest_bindings() {
    let dir = exported();
    let (mut programs, mut files) = (0, std::collections::BTreeSet::new());
    let (mut vulkan_glsl, mut failed) = (0, Vec::new());
    for (variant, e) in entry_points() {
        let name = e["name"].as_str().unwrap();
        let file = |e: &Value| e["files"]["glsl"].as_str().unwrap().to_string();
        // An entry point that reads the view index (the multiview apply) is Vulkan GLSL
        // (GL_EXT_multiview), which OpenGL drivers do not take: glslang compiles it for
        // Vulkan. Its vertex shader (OpenGL GLSL, gl_VertexID) links in Mesa with the
        // other fragment shaders that name it.
        let source = std::fs::read_to_string(dir.join(file(e))).unwrap();
        if source.contains("#extension GL_EXT_multiview") {
            assert_eq!(e["stage"], "fragment", "{variant}.{name}");
            let o = output(
                glslang()
                    .current_dir(dir)
                    .args(["-V", "--target-env", "vulkan1.1", "-S", "frag", "-o"])
                    .arg(scratch("vulkan-glsl.spv"))
                    .arg(file(e)),
            );
            if !o.status.success() {
                failed.push(format!("{variant}.{name} (glslang, Vulkan): {}", text(&o)));
            }
            files.insert(file(e));
            vulkan_glsl += 1;
            continue;
        }
        let mut expected = BTreeMap::new();
        let mut cmd = gl_link();
        cmd.current_dir(dir).arg("--json");
        match e["stage"].as_str().unwrap() {
            "compute" => {
                cmd.arg(format!("comp:{}", file(e)));
                files.insert(file(e));
            }
            "fragment" => {
                let (_, vertex) = vertex_of(e);
                cmd.arg(format!("vert:{}", file(vertex)));
                cmd.arg(format!("frag:{}", file(e)));
                files.insert(file(vertex));
                files.insert(file(e));
                manifest_resources(vertex, &mut expected);
            }
            // Linked with the fragment shaders that name it.
            _ => continue,
        }
        manifest_resources(e, &mut expected);
        programs += 1;
        let o = output(&mut cmd);
        if !o.status.success() {
            failed.push(format!("{variant}.{name}: {}", text(&o)));
            continue;
        }
        let report: Value = serde_json::from_slice(&o.stdout).unwrap();
        let got = gl_resources(&report);
        if got != expected {
            failed.push(format!(
                "{variant}.{name}: GL reports {got:?}, the manifest says {expected:?}"
            ));
        }
    }
    let glsl_files = entry_points().len();
    eprintln!(
        "glsl x Mesa OpenGL 4.5 (llvmpipe, EGL surfaceless): {programs} programs from {} files, \
         {} failed; every block, sampler and image at its manifest binding and size; \
         {vulkan_glsl} Vulkan GLSL (GL_EXT_multiview) programs compiled by glslang for Vulkan",
        files.len(),
        failed.len()
    );
    assert!(
        vulkan_glsl > 0,
        "the multiview apply's programs were compiled"
    );
    assert_eq!(files.len(), glsl_files, "every GLSL file is in a program");
    assert!(failed.is_empty(), "{}", failed.join("\n"));

    // Mesa is live: a program whose stages name a block differently does not link.
    let scratch = scratch("gl-negative");
    std::fs::create_dir_all(&scratch).unwrap();
    let block = |stage_name: &str| {
        format!(
            "#version 450 core\nlayout(std140, binding = 0) uniform Hull_{stage_name} {{ vec4 hull; }};\n"
        )
    };
    let vs = scratch.join("a.vert");
    let fs = scratch.join("a.frag");
    std::fs::write(&vs, block("v") + "void main() { gl_Position = hull; }\n").unwrap();
    std::fs::write(
        &fs,
        block("f") + "layout(location = 0) out vec4 o;\nvoid main() { o = hull; }\n",
    )
    .unwrap();
    let o = output(
        gl_link()
            .arg(format!("vert:{}", vs.display()))
            .arg(format!("frag:{}", fs.display())),
    );
    assert!(!o.status.success(), "Mesa linked mismatched blocks");
}

/// Runs `dawn_check` on a manifest and returns its failures; checks the summary
/// counts the whole manifest.
pub fn dawn(manifest_path: &Path, backend: &str, expected_entries: usize) -> Vec<String> {
    let mut cmd = dawn_check();
    cmd.arg("--manifest")
        .arg(manifest_path)
        .args(["--backend", backend])
        .env("EGL_PLATFORM", "surfaceless");
    let o = output(&mut cmd);
    let (results, passed, failed) = dawn_results(&o);
    assert_eq!(
        (passed + failed) as usize,
        expected_entries,
        "dawn_check saw every entry point:\n{}",
        text(&o)
    );
    assert_eq!(results.len(), expected_entries, "{}", text(&o));
    let failures: Vec<String> = results
        .into_iter()
        .filter_map(|r| {
            r.outcome
                .err()
                .map(|err| format!("{}.{}: {err}", r.variant, r.entry))
        })
        .collect();
    assert_eq!(failures.len() as u64, failed);
    assert_eq!(
        o.status.success(),
        failures.is_empty(),
        "exit status agrees with the results:\n{}",
        text(&o)
    );
    failures
}

#[test]
fn every_wgsl_export_makes_dawn_pipelines_from_the_manifest() {
    let path = exported().join("manifest.json");
    let entries = entry_points().len();
    for (backend, what) in [
        ("null", "null backend: Tint and WebGPU validation"),
        (
            "opengl",
            "OpenGL backend: Tint's GLSL compiled by Mesa 4.5, compatibility mode",
        ),
    ] {
        // Tint takes @builtin(view_index) only under `enable view_instancing;`, which
        // naga's WGSL does not declare (wgpu takes the file as it is): the multiview
        // apply's entry points fail with exactly that, every other entry point passes.
        let (view_instancing, failed): (Vec<String>, Vec<String>) = dawn(&path, backend, entries)
            .into_iter()
            .partition(|f| f.contains("requires enabling extension 'view_instancing'"));
        let multiview = entry_points()
            .iter()
            .filter(|(v, _)| v.contains("APPLY_MULTIVIEW"))
            .count();
        eprintln!(
            "wgsl x Dawn/Tint ({what}): {} passed, {} failed; {} multiview entry points \
             rejected for the view_instancing extension naga does not declare",
            entries - failed.len() - view_instancing.len(),
            failed.len(),
            view_instancing.len()
        );
        assert!(failed.is_empty(), "{backend}:\n{}", failed.join("\n"));
        assert_eq!(
            view_instancing.len(),
            multiview,
            "{backend}: only the multiview entry points:\n{}",
            view_instancing.join("\n")
        );
    }

    // Dawn is live: a layout from a wrong manifest entry (a storage buffer declared as
    // a uniform buffer) fails pipeline creation.
    let mut wrong = manifest().clone();
    let variants = wrong["variants"].as_array_mut().unwrap();
    variants.retain(|v| v["name"] == "inject@default");
    for b in variants[0]["entry_points"][0]["bindings"]
        .as_array_mut()
        .unwrap()
    {
        if b["name"] == "lights" {
            b["resource"]["type"] = Value::from("uniform");
        }
    }
    let wrong_path = exported().join("manifest-wrong-lights.json");
    std::fs::write(&wrong_path, serde_json::to_string(&wrong).unwrap()).unwrap();
    let failed = dawn(&wrong_path, "null", 1);
    std::fs::remove_file(&wrong_path).unwrap();
    assert_eq!(failed.len(), 1, "Dawn accepted a wrong layout");
}

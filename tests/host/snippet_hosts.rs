//! Every include snippet through the compilers an engine would use, inside small host
//! shaders: one host per snippet that only includes it (a snippet stands alone), one
//! that includes every snippet and then each again (the guards keep one definition),
//! and two hand-written hosts in `hosts/`: a forward fragment shader that calls every
//! function taking resources or structs, and the compute shader of the number checks.
//! HLSL through Slang (warnings as errors), GLSL through glslang (with
//! GL_GOOGLE_include_directive) and Mesa's OpenGL 4.5 driver (includes pasted in), GLSL
//! ES 3.00 through glslang and Mesa as fragment shaders (includes pasted in; WebGL2
//! itself compiles them in the browser test of `volfog-web`), WGSL through Dawn/Tint
//! (null and OpenGL backends). MSL has no compiler here.

use std::path::{Path, PathBuf};

use serde_json::json;
use volfog_codegen::snippets::{ALL_SNIPPETS, SNIPPET_MODULES};

use crate::common::{exported, scratch};
use crate::compilers::dawn;
use crate::tools::{gl_link, glslang, output, slang_check, text};

fn hosts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/host/hosts")
}

/// Every snippet name, `all` last.
fn names() -> Vec<&'static str> {
    SNIPPET_MODULES
        .iter()
        .copied()
        .chain([ALL_SNIPPETS])
        .collect()
}

/// `#include` lines for every snippet, `all` included, then every one again.
fn include_everything(ext: &str) -> String {
    let once: String = names()
        .iter()
        .map(|n| format!("#include \"volfog_{n}.{ext}\"\n"))
        .collect();
    once.clone() + &once
}

/// A host shader: its file name, stage and entry point.
struct Host {
    file: PathBuf,
    stage: &'static str,
    entry: &'static str,
}

/// The generated hosts of a language, written to `dir`, and the hand-written ones.
fn host_shaders(dir: &Path, ext: &str, body: impl Fn(&str) -> String) -> Vec<Host> {
    std::fs::create_dir_all(dir).unwrap();
    let mut hosts_out = Vec::new();
    let mut write = |name: &str, includes: String| {
        let file = dir.join(name);
        std::fs::write(&file, body(&includes)).unwrap();
        hosts_out.push(Host {
            file,
            stage: "compute",
            entry: "main",
        });
    };
    for n in names() {
        write(
            &format!("include_{n}.{}", host_ext(ext)),
            format!("#include \"volfog_{n}.{ext}\"\n"),
        );
    }
    write(
        &format!("include_everything_twice.{}", host_ext(ext)),
        include_everything(ext),
    );
    hosts_out
}

fn host_ext(include_ext: &str) -> &'static str {
    match include_ext {
        "hlsli" => "hlsl",
        "glsl" => "comp",
        "es.glsl" => "frag",
        other => panic!("{other}"),
    }
}

#[test]
fn every_hlsl_snippet_compiles_in_slang() {
    let include = exported().join("hlsl/include");
    let mut all = host_shaders(&scratch("snippet-hosts-hlsl"), "hlsli", |includes| {
        format!("{includes}\n[numthreads(1, 1, 1)]\nvoid main() {{}}\n")
    });
    all.push(Host {
        file: hosts().join("forward.hlsl"),
        stage: "fragment",
        entry: "main",
    });
    all.push(Host {
        file: hosts().join("numbers.hlsl"),
        stage: "compute",
        entry: "main",
    });
    let mut failed = Vec::new();
    for h in &all {
        let o = output(
            slang_check()
                .args(["--werror", "--target", "hlsl", "--stage", h.stage])
                .args(["--entry", h.entry])
                .arg("-I")
                .arg(&include)
                .arg(&h.file),
        );
        if !o.status.success() {
            failed.push(format!("{}: {}", h.file.display(), text(&o)));
        }
    }
    eprintln!(
        "hlsl snippets x Slang: {} snippet files in {} host shaders, {} failed",
        names().len(),
        all.len(),
        failed.len()
    );
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

fn file_name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

/// Pastes `#include "X"` files from `dir` in (OpenGL compiles no includes).
pub(crate) fn paste_includes(text: &str, dir: &Path) -> String {
    text.lines()
        .filter(|l| !l.contains("GL_GOOGLE_include_directive"))
        .map(|l| match l.strip_prefix("#include \"") {
            Some(rest) => {
                let name = rest.trim_end().trim_end_matches('"');
                std::fs::read_to_string(dir.join(name)).unwrap()
            }
            None => format!("{l}\n"),
        })
        .collect()
}

#[test]
fn every_glsl_es_snippet_compiles_as_a_webgl2_fragment_shader() {
    let include = exported().join("glsl/include");
    let dir = scratch("snippet-hosts-glsl-es");
    let header = "#version 300 es\nprecision highp float;\nprecision highp int;\n";
    let hosts = host_shaders(&dir, "es.glsl", |includes| {
        let body = format!(
            "{includes}\nlayout(location = 0) out vec4 volfog_out;\nvoid main() {{ volfog_out = vec4(0.0); }}\n"
        );
        format!("{header}{}", paste_includes(&body, &include))
    });
    let mut failed = Vec::new();
    for h in &hosts {
        let o = output(glslang().args(["-S", "frag"]).arg(&h.file));
        if !o.status.success() {
            failed.push(format!("glslang {}: {}", h.file.display(), text(&o)));
        }
        let o = output(gl_link().arg(format!("frag:{}", h.file.display())));
        if !o.status.success() {
            failed.push(format!("Mesa {}: {}", h.file.display(), text(&o)));
        }
    }
    eprintln!(
        "glsl es snippets x glslang and x Mesa (GLSL ES 3.00): {} snippet files in {} host shaders, {} failed",
        names().len(),
        hosts.len(),
        failed.len()
    );
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn every_glsl_snippet_compiles_in_glslang_and_links_in_mesa() {
    let include = exported().join("glsl/include");
    let dir = scratch("snippet-hosts-glsl");
    let header = "#version 450 core\n#extension GL_GOOGLE_include_directive : require\n";
    let mut all = host_shaders(&dir, "glsl", |includes| {
        format!("{header}{includes}\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n")
    });
    all.push(Host {
        file: hosts().join("forward.frag"),
        stage: "fragment",
        entry: "main",
    });
    all.push(Host {
        file: hosts().join("numbers.comp"),
        stage: "compute",
        entry: "main",
    });
    let mut failed = Vec::new();
    for h in &all {
        let stage = if h.stage == "compute" { "comp" } else { "frag" };
        // glslang: the include mechanism engines with a GLSL-to-SPIR-V path use.
        let o = output(
            glslang()
                .args(["-V", "--target-env", "vulkan1.1", "-S", stage])
                .arg(format!("-I{}", include.display()))
                .arg("-o")
                .arg(dir.join(format!("{}.spv", file_name(&h.file))))
                .arg(&h.file),
        );
        if !o.status.success() {
            failed.push(format!("glslang {}: {}", h.file.display(), text(&o)));
        }
        // Mesa: compile and link as an OpenGL program, includes pasted in.
        let source = std::fs::read_to_string(&h.file).unwrap();
        let pasted = dir.join(format!("gl_{}", file_name(&h.file)));
        std::fs::write(&pasted, paste_includes(&source, &include)).unwrap();
        let o = output(gl_link().arg(format!("{stage}:{}", pasted.display())));
        if !o.status.success() {
            failed.push(format!("Mesa {}: {}", pasted.display(), text(&o)));
        }
    }
    eprintln!(
        "glsl snippets x glslang and x Mesa OpenGL 4.5: {} snippet files in {} host shaders, {} failed",
        names().len(),
        all.len(),
        failed.len()
    );
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn every_wgsl_snippet_makes_a_dawn_pipeline() {
    let include = exported().join("wgsl/include");
    let dir = scratch("snippet-hosts-wgsl");
    std::fs::create_dir_all(&dir).unwrap();
    let mut variants = Vec::new();
    for n in names() {
        let file = format!("include_{n}.wgsl");
        let snippet = std::fs::read_to_string(include.join(format!("volfog_{n}.wgsl"))).unwrap();
        std::fs::write(
            dir.join(&file),
            snippet + "\n@compute @workgroup_size(1)\nfn main() {}\n",
        )
        .unwrap();
        variants.push(json!({
            "name": format!("include_{n}"),
            "entry_points": [{ "name": "main", "stage": "compute", "files": { "wgsl": file }, "bindings": [] }],
        }));
    }
    // The forward host: volfog_all.wgsl pasted in front.
    let forward = std::fs::read_to_string(include.join("volfog_all.wgsl")).unwrap()
        + "\n"
        + &std::fs::read_to_string(hosts().join("forward.wgsl")).unwrap();
    std::fs::write(dir.join("forward.wgsl"), forward).unwrap();
    let texture = |binding: u32, name: &str, sample_type: &str| {
        json!({ "group": 0, "binding": binding, "name": name,
                "resource": { "kind": "texture", "sample_type": sample_type,
                              "view_dimension": if name == "scene_depth" { "2d" } else { "3d" },
                              "multisampled": false } })
    };
    let bindings = vec![
        json!({ "group": 0, "binding": 0, "name": "params",
                "resource": { "kind": "buffer", "type": "uniform" } }),
        texture(1, "fog_integrated", "float"),
        json!({ "group": 0, "binding": 2, "name": "fog_sampler",
                "resource": { "kind": "sampler", "type": "filtering" } }),
        texture(3, "scene_depth", "unfilterable-float"),
    ];
    variants.push(json!({
        "name": "forward",
        "entry_points": [
            { "name": "vs_main", "stage": "vertex", "files": { "wgsl": "forward.wgsl" }, "bindings": [],
              "vertex_buffers": [{ "array_stride": 12, "step_mode": "vertex",
                  "attributes": [{ "format": "float32x3", "offset": 0, "shader_location": 0 }] }] },
            { "name": "fs_main", "stage": "fragment", "files": { "wgsl": "forward.wgsl" }, "bindings": bindings,
              "vertex": { "variant": "forward", "entry": "vs_main" },
              "color_targets": [{ "location": 0, "formats": ["rgba16float"],
                  "blend": { "color": { "operation": "add", "src_factor": "src-alpha", "dst_factor": "one-minus-src-alpha" },
                             "alpha": { "operation": "add", "src_factor": "one", "dst_factor": "one-minus-src-alpha" } } }] },
        ],
    }));
    let count = variants.len() + 1;
    let manifest = dir.join("manifest.json");
    std::fs::write(
        &manifest,
        serde_json::to_string_pretty(&json!({ "variants": variants })).unwrap(),
    )
    .unwrap();
    for backend in ["null", "opengl"] {
        let failed = dawn(&manifest, backend, count);
        eprintln!(
            "wgsl snippets x Dawn/Tint ({backend}): {} snippet files in {count} entry points, {} failed",
            names().len(),
            failed.len()
        );
        assert!(failed.is_empty(), "{backend}:\n{}", failed.join("\n"));
    }
}

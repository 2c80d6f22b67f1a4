//! The README and the guides under `docs/`: every fenced code block is checked by its
//! kind, and any other kind fails. `rust` blocks appear line for line in a compiled
//! example ([`COMPILED`]); `wgsl` blocks compose with volfog's modules through naga_oil
//! and validate with naga; `hlsl` blocks compile in Slang, `glsl` blocks in glslang and
//! Mesa's OpenGL driver; `metal` blocks (no Metal compiler runs on Linux) include
//! snippets that exist and use only `volfog_` names those define; `sh` lines are
//! `volfog-cli` commands the built `volfog` binary parses, `cargo xtask` jobs, or the
//! reviewed `cargo insta` lines; `text` blocks are not code. Relative links and images
//! resolve, anchors included.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use naga_oil::compose::{Composer, NagaModuleDescriptor};
use volfog_codegen::snippets::SnippetLanguage;

use crate::common::{exported, scratch, snippets};
use crate::snippet_hosts::paste_includes;
use crate::tools::{gl_link, glslang, output, slang_check, text};

/// The files that hold every `rust` block of the guides, compiled: the root crate's
/// example (built by `cargo test`, run by `cargo run --example wgpu_fog`), the Bevy
/// workspace's (built by its `cargo test` and `cargo check --examples`) and the web
/// page's wasm module (built by `cargo xtask web`, which `cargo xtask test` runs).
const COMPILED: [&str; 5] = [
    "examples/wgpu_fog.rs",
    "examples/stereo_fog.rs",
    "bevy/examples/quick_start.rs",
    "web/src/page.rs",
    "web/src/readback.rs",
];

/// The kinds of fenced block the guides may hold, each checked here.
const KINDS: [&str; 7] = ["rust", "wgsl", "hlsl", "glsl", "metal", "sh", "text"];

/// The `cargo insta` lines of the guides. cargo-insta is not among the test tools, so
/// these are pinned: a new or changed one fails until it is reviewed and added here.
const INSTA_LINES: [&str; 2] = [
    "cargo insta test --review",
    "cargo insta test --check --unreferenced=reject",
];

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// README.md and every `docs/*.md`, as (path relative to the repository, text).
fn guides() -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    names.sort();
    names.insert(0, "README.md".to_string());
    names
        .into_iter()
        .map(|n| {
            let text = read(&repo().join(&n));
            (n, text)
        })
        .collect()
}

/// A fenced code block: where it starts, its kind (the fence's info string) and text.
struct Block {
    at: String,
    kind: String,
    text: String,
}

/// Every fenced block of `text` (from `file`); panics on a fence left open.
fn fenced(file: &str, text: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        match (&mut open, fence) {
            (None, Some(info)) => {
                open = Some(Block {
                    at: format!("{file}:{}", i + 1),
                    kind: info.trim().to_string(),
                    text: String::new(),
                })
            }
            (Some(_), Some("")) => blocks.push(open.take().unwrap()),
            (Some(block), _) => {
                block.text.push_str(line);
                block.text.push('\n');
            }
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "{file}: a code fence is left open");
    blocks
}

/// Every block of the README and the guides.
fn all_blocks() -> Vec<Block> {
    guides()
        .iter()
        .flat_map(|(file, text)| fenced(file, text))
        .collect()
}

/// The blocks of one kind.
fn blocks(kind: &str) -> Vec<Block> {
    all_blocks()
        .into_iter()
        .filter(|b| b.kind == kind)
        .collect()
}

#[test]
fn every_guide_block_is_of_a_checked_kind() {
    let all = all_blocks();
    let unchecked: Vec<String> = all
        .iter()
        .filter(|b| !KINDS.contains(&b.kind.as_str()))
        .map(|b| format!("{}: ```{}", b.at, b.kind))
        .collect();
    assert!(
        unchecked.is_empty(),
        "code blocks of a kind no test checks (give each fence one of {KINDS:?}, \
         or teach tests/host/guides.rs the new kind):\n{}",
        unchecked.join("\n")
    );
    for kind in KINDS {
        eprintln!(
            "guides: {} ```{kind} blocks",
            all.iter().filter(|b| b.kind == kind).count()
        );
    }
}

/// The lines of `text` without their common indentation (blank lines empty).
fn dedent(text: &str) -> Vec<String> {
    let indent = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    text.lines()
        .map(|l| {
            if l.trim().is_empty() {
                String::new()
            } else {
                l[indent..].trim_end().to_string()
            }
        })
        .collect()
}

/// Whether `block` (dedented lines) appears in `file` as consecutive lines under one
/// indentation of spaces.
fn contains_lines(file: &[&str], block: &[String]) -> bool {
    let Some(first) = block.iter().position(|l| !l.is_empty()) else {
        return true;
    };
    (0..=file.len().saturating_sub(block.len())).any(|start| {
        let Some(indent) = file[start + first]
            .trim_end()
            .strip_suffix(block[first].as_str())
        else {
            return false;
        };
        indent.chars().all(|c| c == ' ')
            && block.iter().enumerate().all(|(i, line)| {
                let f = file[start + i].trim_end();
                if line.is_empty() {
                    f.is_empty()
                } else {
                    f.strip_prefix(indent) == Some(line.as_str())
                }
            })
    })
}

/// Every `rust` block is in a compiled example line for line, so a guide edited without
/// its example (or an example edited without its guide) fails here.
#[test]
fn every_guide_rust_block_is_in_a_compiled_example() {
    let compiled: Vec<(&str, String)> = COMPILED
        .iter()
        .map(|p| (*p, read(&repo().join(p))))
        .collect();
    let rust = blocks("rust");
    assert!(!rust.is_empty(), "the guides show Rust");
    let mut missing = Vec::new();
    for b in &rust {
        let lines = dedent(&b.text);
        let home = compiled.iter().find(|(_, text)| {
            let file: Vec<&str> = text.lines().collect();
            contains_lines(&file, &lines)
        });
        match home {
            Some((path, _)) => eprintln!("{}: in {path}", b.at),
            None => missing.push(b.at.clone()),
        }
    }
    assert!(
        missing.is_empty(),
        "rust blocks not found line for line in any of {COMPILED:?} (change the example \
         with the guide):\n{}",
        missing.join("\n")
    );
}

/// Stand-ins for what the guides' WGSL leaves to the engine's own shader, added where
/// a block does not define them: (the name a block would define, its stand-in).
const WGSL_STANDINS: [(&str, &str); 2] = [
    (
        "struct VertexOut",
        "struct VertexOut {\n    @builtin(position) position: vec4<f32>,\n    \
         @location(0) view_pos: vec3<f32>,\n    @location(1) alpha: f32,\n}\n",
    ),
    (
        "fn shade(",
        "fn shade(in: VertexOut) -> vec3<f32> {\n    return vec3<f32>(in.alpha);\n}\n",
    ),
];

/// Every `wgsl` block composes with volfog's modules (`volfog::shaders::add_to_composer`)
/// and validates in naga, with stand-ins for the engine's own helpers; a block that
/// defines a custom density (`volfog_custom_density`) composes into the inject pass as
/// its module.
#[test]
fn every_guide_wgsl_block_composes_and_validates() {
    let wgsl = blocks("wgsl");
    assert!(!wgsl.is_empty(), "the guides show WGSL");
    for b in &wgsl {
        let hook = volfog::shaders::CUSTOM_DENSITY;
        if b.text.contains(&format!("fn {}(", hook.function)) {
            let module = volfog::shaders::CustomModule::new(b.at.clone(), b.text.clone());
            volfog::shaders::compose_with_custom(
                "inject",
                &[hook.define.to_string()],
                Some(&module),
            )
            .unwrap_or_else(|e| panic!("{}: {e}", b.at));
            eprintln!("{}: composed into inject as its custom density", b.at);
            continue;
        }
        let mut source = b.text.clone();
        for (defined, standin) in WGSL_STANDINS {
            if !b.text.contains(defined) {
                source.push('\n');
                source.push_str(standin);
            }
        }
        // Multiview shaders (`@builtin(view_index)`, the stereo section) validate with
        // the capability a device with wgpu::Features::MULTIVIEW grants.
        let capabilities =
            naga::valid::Capabilities::default() | naga::valid::Capabilities::MULTIVIEW;
        let mut composer = Composer::default().with_capabilities(capabilities);
        volfog::shaders::add_to_composer(&mut composer).unwrap();
        let module = composer
            .make_naga_module(NagaModuleDescriptor {
                source: &source,
                file_path: &b.at,
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{}: {}", b.at, e.emit_to_string(&composer)));
        assert!(
            !module.entry_points.is_empty(),
            "{}: no entry point to compose",
            b.at
        );
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {}", b.at, e.emit_to_string(&source)));
        eprintln!("{}: composed and validated", b.at);
    }
}

/// The guides' HLSL and GLSL snippet examples compile as written (with an empty entry
/// point added): HLSL in Slang, GLSL in glslang and, includes pasted in, Mesa.
#[test]
fn the_guides_hlsl_and_glsl_examples_compile() {
    let dir = scratch("guide-examples");
    std::fs::create_dir_all(&dir).unwrap();
    let hlsl = blocks("hlsl");
    let glsl = blocks("glsl");
    assert!(!hlsl.is_empty() && !glsl.is_empty(), "the guides show both");
    for (i, b) in hlsl.iter().enumerate() {
        let file = dir.join(format!("guide_{i}.hlsl"));
        std::fs::write(
            &file,
            format!("{}\n[numthreads(1, 1, 1)]\nvoid main() {{}}\n", b.text),
        )
        .unwrap();
        let o = output(
            slang_check()
                .args([
                    "--werror", "--target", "hlsl", "--stage", "compute", "--entry", "main",
                ])
                .arg("-I")
                .arg(exported().join("hlsl/include"))
                .arg(&file),
        );
        assert!(o.status.success(), "{} (HLSL):\n{}", b.at, text(&o));
    }
    for (i, b) in glsl.iter().enumerate() {
        let file = dir.join(format!("guide_{i}.frag"));
        std::fs::write(&file, format!("{}\nvoid main() {{}}\n", b.text)).unwrap();
        let include = exported().join("glsl/include");
        let o = output(
            glslang()
                .args(["-V", "--target-env", "vulkan1.1", "-S", "frag"])
                .arg(format!("-I{}", include.display()))
                .arg("-o")
                .arg(dir.join(format!("guide_{i}.spv")))
                .arg(&file),
        );
        assert!(
            o.status.success(),
            "{} (GLSL, glslang):\n{}",
            b.at,
            text(&o)
        );
        let pasted = dir.join(format!("gl_guide_{i}.frag"));
        std::fs::write(&pasted, paste_includes(&read(&file), &include)).unwrap();
        let o = output(gl_link().arg(format!("frag:{}", pasted.display())));
        assert!(o.status.success(), "{} (GLSL, Mesa):\n{}", b.at, text(&o));
    }
    eprintln!(
        "guide examples: {} HLSL through Slang, {} GLSL through glslang and Mesa",
        hlsl.len(),
        glsl.len()
    );
}

/// The `volfog_`-prefixed words of a text.
fn volfog_names(text: &str) -> BTreeSet<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with("volfog_"))
        .map(str::to_string)
        .collect()
}

/// No Metal compiler runs on Linux: every `metal` block includes snippets that exist
/// (`#include "volfog_<name>.h"`), and every `volfog_` name it uses is a function or a
/// struct of those snippets.
#[test]
fn every_guide_metal_block_uses_what_its_snippets_define() {
    let metal = blocks("metal");
    assert!(!metal.is_empty(), "the guides show MSL");
    for b in &metal {
        let mut defined = BTreeSet::new();
        let mut includes = BTreeSet::new();
        for line in b.text.lines() {
            let Some(file) = line.trim().strip_prefix("#include \"") else {
                continue;
            };
            let file = file.trim_end_matches('"');
            let snippet = snippets()
                .iter()
                .find(|s| s.file_name(SnippetLanguage::Msl) == file)
                .unwrap_or_else(|| panic!("{}: no MSL snippet {file}", b.at));
            defined.extend(snippet.functions.iter().cloned());
            defined.extend(snippet.structs.iter().map(|s| s.name.clone()));
            includes.insert(file.to_string());
        }
        assert!(!includes.is_empty(), "{}: includes no snippet", b.at);
        let undefined: Vec<String> = volfog_names(&b.text)
            .into_iter()
            .filter(|n| !defined.contains(n) && !includes.contains(&format!("{n}.h")))
            .collect();
        assert!(
            undefined.is_empty(),
            "{}: names that {includes:?} do not define: {undefined:?}",
            b.at
        );
        eprintln!(
            "{}: {} volfog names, all defined by {includes:?} (not compiled: no Metal compiler on Linux)",
            b.at,
            volfog_names(&b.text).len()
        );
    }
}

/// The commands of an `sh` block: continuation lines joined, comments dropped.
fn commands(block: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for line in block.lines() {
        let line = match line.find(" #") {
            Some(i) => &line[..i],
            None if line.trim_start().starts_with('#') => "",
            None => line,
        };
        match line.trim_end().strip_suffix('\\') {
            Some(part) => current.push_str(part),
            None => {
                current.push_str(line);
                let command = current.split_whitespace().collect::<Vec<_>>().join(" ");
                if !command.is_empty() {
                    out.push(command);
                }
                current.clear();
            }
        }
    }
    assert!(current.trim().is_empty(), "a continued line ends the block");
    out
}

/// The jobs of `cargo xtask` (its `main` matches on them).
fn xtask_jobs() -> BTreeSet<String> {
    read(&repo().join("xtask/src/main.rs"))
        .lines()
        .filter_map(|l| {
            let job = l.trim().strip_prefix('"')?.split_once("\" =>")?.0;
            Some(job.to_string())
        })
        .collect()
}

/// The newest modification time of the files under `dir`.
fn newest(dir: &Path) -> std::time::SystemTime {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                newest(&e.path())
            } else {
                e.metadata().unwrap().modified().unwrap()
            }
        })
        .max()
        .unwrap_or(std::time::UNIX_EPOCH)
}

/// The `volfog` binary of this build (`cargo test --workspace` builds it for the CLI's
/// tests); fails when it is missing or older than the CLI's sources.
fn volfog_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile = exe.parent().and_then(Path::parent).unwrap();
    let binary = profile.join(format!("volfog{}", std::env::consts::EXE_SUFFIX));
    let build =
        "build it with `cargo build -p volfog-cli` (or run the suite with `cargo xtask test`)";
    let built = std::fs::metadata(&binary)
        .unwrap_or_else(|_| panic!("{} is missing; {build}", binary.display()))
        .modified()
        .unwrap();
    assert!(
        built >= newest(&repo().join("cli/src")),
        "{} is older than cli/src; {build}",
        binary.display()
    );
    binary
}

/// Every command of an `sh` block is checked: `cargo run -p volfog-cli -- ARGS` parses
/// with the CLI (the built binary given `ARGS --help`, which parses every argument
/// before it and then prints the subcommand's help), `cargo xtask JOB` names a job of
/// xtask, and `cargo insta` lines are the reviewed ones of a crate that uses insta.
#[test]
fn every_guide_shell_command_parses() {
    let jobs = xtask_jobs();
    assert!(jobs.contains("test"), "xtask's jobs are read: {jobs:?}");
    let sh = blocks("sh");
    assert!(!sh.is_empty(), "the guides show commands");
    let mut binary = None;
    let mut count = 0;
    for b in &sh {
        for command in commands(&b.text) {
            count += 1;
            let words: Vec<&str> = command.split(' ').collect();
            match words.as_slice() {
                ["cargo", "xtask", job, ..] => assert!(
                    jobs.contains(*job),
                    "{}: `{command}`: xtask has no job {job} (it has {jobs:?})",
                    b.at
                ),
                ["cargo", "run", "-p", "volfog-cli", "--", sub, args @ ..] => {
                    let volfog = binary.get_or_insert_with(volfog_binary);
                    let o = output(Command::new(&*volfog).arg(sub).args(args).arg("--help"));
                    assert!(
                        o.status.success()
                            && String::from_utf8_lossy(&o.stdout)
                                .contains(&format!("Usage: volfog {sub}")),
                        "{}: `{command}` does not parse:\n{}",
                        b.at,
                        text(&o)
                    );
                }
                ["cargo", "insta", ..] => {
                    assert!(
                        INSTA_LINES.contains(&command.as_str()),
                        "{}: `{command}` is not one of the reviewed cargo insta lines {INSTA_LINES:?}",
                        b.at
                    );
                    assert!(
                        read(&repo().join("Cargo.toml")).contains("\ninsta = "),
                        "the root crate has no insta dev-dependency"
                    );
                }
                _ => panic!(
                    "{}: `{command}`: no check for this command (tests/host/guides.rs)",
                    b.at
                ),
            }
        }
    }
    eprintln!("guides: {count} shell commands checked");
}

/// A heading's anchor as GitHub makes it.
fn anchor(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c.to_ascii_lowercase()),
            _ => None,
        })
        .collect()
}

/// The anchors of a markdown text's headings (outside code blocks).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut in_code = false;
    let mut out = BTreeSet::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        } else if !in_code && line.starts_with('#') {
            out.insert(anchor(line.trim_start_matches('#').trim()));
        }
    }
    out
}

/// The targets of the links and images of a markdown text (outside code blocks).
fn link_targets(text: &str) -> Vec<String> {
    let mut in_code = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let end = after.find(')').unwrap_or(after.len());
            out.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    out
}

/// Every relative link and image of the README and the guides names a file that
/// exists, and an anchor a heading of its markdown file.
#[test]
fn every_guide_link_resolves() {
    let mut broken = Vec::new();
    let mut count = 0;
    for (file, text) in guides() {
        let dir = repo().join(&file).parent().unwrap().to_path_buf();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            count += 1;
            let (path, fragment) = target.split_once('#').unwrap_or((&target, ""));
            let linked = if path.is_empty() {
                repo().join(&file)
            } else {
                dir.join(path)
            };
            if !linked.exists() {
                broken.push(format!("{file}: {target}: no such file"));
            } else if !fragment.is_empty() && !anchors(&read(&linked)).contains(fragment) {
                broken.push(format!("{file}: {target}: no such heading"));
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
    eprintln!("guides: {count} relative links and images resolve");
}

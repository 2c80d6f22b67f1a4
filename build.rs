//! Prebuilds every shader variant: compose (naga_oil) -> validate (naga, all flags) ->
//! compact -> translate to WGSL, SPIR-V, GLSL, HLSL and MSL, writing only into OUT_DIR
//! together with `shader_index.rs`, which the library includes.
//!
//! A shader error fails the build with the file, line, column and source line.

#[allow(dead_code)]
#[path = "src/manifest.rs"]
mod manifest;

#[allow(dead_code)]
#[path = "src/codegen/mod.rs"]
mod codegen;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use codegen::{compose, Target};

fn main() {
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/manifest.rs");
    println!("cargo:rerun-if-changed=src/codegen");
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    if let Err(message) = run(&out_dir) {
        eprintln!("\nvolfog shader codegen failed:\n\n{message}\n");
        std::process::exit(1);
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("writing {}: {e}", path.display()))
}

fn run(out_dir: &Path) -> Result<(), String> {
    let started = Instant::now();
    let root = out_dir.join("shaders");
    for target in Target::ALL {
        std::fs::create_dir_all(root.join(target.name())).map_err(|e| e.to_string())?;
    }
    std::fs::create_dir_all(root.join("reflect")).map_err(|e| e.to_string())?;

    let mut composer = compose::composer().map_err(|e| e.to_string())?;
    let mut index = String::from("&[\n");
    let mut count = 0usize;
    for pass in manifest::PASSES {
        for combo in manifest::expand_axes(pass.axes) {
            let defines = compose::Defines::flags(combo.iter().copied());
            let variant =
                codegen::generate(&mut composer, pass, &defines).map_err(|e| e.to_string())?;
            writeln!(
                index,
                "    PrebuiltVariant {{ name: {:?}, pass: {:?}, defines: &{:?}, entries: &[",
                variant.name, variant.pass, variant.defines
            )
            .unwrap();
            for entry in &variant.entries {
                let mut files = Vec::new();
                for target in Target::ALL {
                    let rel = format!(
                        "{}/{}",
                        target.name(),
                        entry.file_name(&variant.name, target)
                    );
                    write(&root.join(&rel), &entry.bytes(target))?;
                    files.push(rel);
                }
                let reflection =
                    serde_json::to_string_pretty(&entry.reflection).map_err(|e| e.to_string())?;
                let rel = format!("reflect/{}.{}.json", variant.name, entry.entry);
                write(&root.join(&rel), reflection.as_bytes())?;
                files.push(rel);
                let inc = |i: usize, mac: &str| {
                    format!(
                        "{mac}!(concat!(env!(\"OUT_DIR\"), \"/shaders/{}\"))",
                        files[i]
                    )
                };
                writeln!(
                    index,
                    "        PrebuiltEntry {{ entry: {:?}, stage: Stage::{:?}, wgsl: {}, spirv: {}, glsl: {}, hlsl: {}, msl: {}, reflection: {} }},",
                    entry.entry,
                    entry.stage,
                    inc(0, "include_str"),
                    inc(1, "include_bytes"),
                    inc(2, "include_str"),
                    inc(3, "include_str"),
                    inc(4, "include_str"),
                    inc(5, "include_str"),
                )
                .unwrap();
            }
            index.push_str("    ] },\n");
            count += 1;
        }
    }
    index.push_str("]\n");
    write(&out_dir.join("shader_index.rs"), index.as_bytes())?;
    write(
        &out_dir.join("codegen_stats.txt"),
        format!(
            "variants {count}\nmilliseconds {}\n",
            started.elapsed().as_millis()
        )
        .as_bytes(),
    )?;
    Ok(())
}

//! The wgpu guide's example runs: `examples/wgpu_fog.rs` holds every Rust block of
//! `docs/wgpu.md` (the host test `guides::every_guide_rust_block_is_in_a_compiled_example`
//! checks that), and each of its functions checks what its block promises. `cargo test`
//! builds the example; this runs it on the test adapter, so a guide whose code stops
//! working fails the suite rather than the reader.

use std::path::PathBuf;
use std::process::Command;

/// The example binary `cargo test` built beside this test (`target/<profile>/examples`).
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let profile = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>/deps");
    profile
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX))
}

#[test]
fn the_wgpu_guides_example_runs() {
    let binary = example("wgpu_fog");
    assert!(
        binary.exists(),
        "{} is missing: `cargo test -p volfog` builds it (or `cargo build --example wgpu_fog`)",
        binary.display()
    );
    let output = Command::new(&binary)
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .output()
        .expect("the example starts");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("{stdout}");
    assert!(
        output.status.success(),
        "examples/wgpu_fog.rs failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    // Every guide section it holds ran to its end.
    let ran = stdout.lines().filter(|l| l.ends_with(": ran")).count();
    assert!(ran >= 8, "only {ran} guide sections ran:\n{stdout}");
}

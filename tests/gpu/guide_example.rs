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

/// The guide's stereo section (`examples/stereo_fog.rs`) runs and writes the two eyes
/// side by side; the example itself checks that the eyes differ and that their mean
/// brightness agrees within 5 %.
#[test]
fn the_stereo_example_writes_both_eyes_side_by_side() {
    let binary = example("stereo_fog");
    assert!(binary.exists(), "{} is missing", binary.display());
    let out = std::env::temp_dir().join(format!("volfog-stereo-{}.ppm", std::process::id()));
    let output = Command::new(&binary)
        .arg(&out)
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .output()
        .expect("the example starts");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "examples/stereo_fog.rs failed ({}):\n{stdout}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    eprintln!("{stdout}");
    let image = std::fs::read(&out).expect("the image was written");
    let _ = std::fs::remove_file(&out);
    let header = b"P6\n960 480\n255\n";
    assert!(image.starts_with(header));
    assert_eq!(image.len(), header.len() + 960 * 480 * 3);
}

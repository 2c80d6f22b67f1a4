//! The independent compilers the tests run, built under `target/tools`: Slang's HLSL
//! front end (`slang_check`, over the compiler library of the `slangpy` wheel in a
//! private venv), Mesa's OpenGL 4.5 driver (`gl_link`) and Dawn/Tint (the npm package
//! `webgpu`, installed next to `tools/dawn/dawn_check.mjs` and next to the JavaScript
//! host example in `examples/webgpu-node`); and the path tracer the fog is held
//! against, Mitsuba 3 in the same venv (`tools/mitsuba/render.py`), with the libLLVM
//! its CPU back end needs.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{root, run};

/// The pinned slangpy wheel (Slang 2026.12).
const SLANGPY: &str = "slangpy==0.43.1";
/// Mitsuba 3 and the Dr.Jit it was built against, the whole dependency closure of
/// `mitsuba==3.9.1` (tools/mitsuba/render.py needs nothing else).
const MITSUBA: [&str; 2] = ["mitsuba==3.9.1", "drjit==1.5.0"];
/// The pinned Dawn node package (see tools/dawn/package-lock.json).
const WEBGPU_VERSION: &str = "\"version\": \"0.6.2\"";

/// The folder the tests read the tools from (`VOLFOG_TOOLS_DIR`).
pub fn dir() -> PathBuf {
    root().join("target").join("tools")
}

fn newer_than(output: &Path, inputs: &[PathBuf]) -> bool {
    let Ok(built) = output.metadata().and_then(|m| m.modified()) else {
        return false;
    };
    inputs.iter().all(|input| {
        input
            .metadata()
            .and_then(|m| m.modified())
            .map(|t| t <= built)
            .unwrap_or(false)
    })
}

fn slang(dir: &Path) {
    let venv = dir.join("venv");
    let python = venv.join("bin").join("python3");
    if !python.exists() {
        run(Command::new("python3").arg("-m").arg("venv").arg(&venv));
    }
    let found = Command::new(&python)
        .args([
            "-c",
            "import importlib.util; assert importlib.util.find_spec('slangpy')",
        ])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !found {
        // Only the compiler library inside the wheel is used: no Python dependencies.
        run(Command::new(&python).args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--no-deps",
            SLANGPY,
        ]));
    }
    let source = root().join("tools/slang");
    let binary = dir.join("bin/slang_check");
    if !newer_than(
        &binary,
        &[source.join("slang_check.cpp"), source.join("build.sh")],
    ) {
        run(Command::new(source.join("build.sh"))
            .arg(dir.join("bin"))
            .env("PYTHON", &python)
            .env("SLANGPY_SPEC", SLANGPY));
    }
}

/// Whether the venv holds exactly the pinned distributions (`name==version` each).
fn pinned_installed(python: &Path, pins: &[&str]) -> bool {
    let checks: Vec<String> = pins
        .iter()
        .filter_map(|pin| pin.split_once("=="))
        .map(|(name, version)| format!("m.version({name:?}) == {version:?}"))
        .collect();
    let script = format!(
        "import importlib.metadata as m, sys; sys.exit(0 if {} else 1)",
        checks.join(" and ")
    );
    Command::new(python)
        .args(["-c", &script])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Mitsuba 3 into the tools' venv (pinned, no dependency resolution); the libLLVM 19
/// its CPU back end loads is a system package (`system::ensure`).
fn mitsuba(dir: &Path) {
    let python = dir.join("venv").join("bin").join("python3");
    if !pinned_installed(&python, &MITSUBA) {
        run(Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "--no-deps",
            ])
            .args(MITSUBA));
    }
}

fn gl(dir: &Path) {
    let source = root().join("tools/gl");
    let binary = dir.join("bin/gl_link");
    if !newer_than(
        &binary,
        &[source.join("gl_link.c"), source.join("build.sh")],
    ) {
        run(Command::new(source.join("build.sh")).arg(dir.join("bin")));
    }
}

/// Dawn for `tools/dawn/dawn_check.mjs` and for the JavaScript host example, each
/// from its own lock file (npm's cache downloads the package once).
fn dawn() {
    for folder in ["tools/dawn", "examples/webgpu-node"] {
        let dir = root().join(folder);
        let installed = std::fs::read_to_string(dir.join("node_modules/webgpu/package.json"))
            .map(|s| s.contains(WEBGPU_VERSION))
            .unwrap_or(false);
        if !installed {
            run(Command::new("npm")
                .args(["ci", "--ignore-scripts", "--no-audit", "--no-fund"])
                .current_dir(&dir));
        }
    }
}

/// Builds whatever is missing or stale and returns the tools folder.
pub fn ensure() -> PathBuf {
    let dir = dir();
    std::fs::create_dir_all(dir.join("bin")).expect("create target/tools");
    slang(&dir);
    mitsuba(&dir);
    gl(&dir);
    dawn();
    dir
}

//! `cargo xtask web`: the browser demo built into `target/web` (the wasm module and its
//! wasm-bindgen glue in `pkg/`, the page from `web/www`, the GLSL ES snippet the
//! WebGL2 tier includes in `shaders/`) and, with `--serve`, served from 127.0.0.1.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{cargo, root, run};

/// The wasm-bindgen CLI must be the version of the `wasm-bindgen` crate in Cargo.lock.
const WASM_BINDGEN: &str = "0.2.130";
const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// The folder the page is built into (`VOLFOG_WEB_DIR` for the tests).
pub fn dir() -> PathBuf {
    root().join("target").join("web")
}

fn wasm_target() {
    let installed = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .any(|l| l.trim() == WASM_TARGET)
        })
        .unwrap_or(false);
    if !installed {
        run(Command::new("rustup").args(["target", "add", WASM_TARGET]));
    }
}

fn wasm_bindgen() -> PathBuf {
    let tools = crate::tools::dir().join("wasm-bindgen");
    let bin = tools.join("bin").join("wasm-bindgen");
    let version = Command::new(&bin)
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    if !version.contains(WASM_BINDGEN) {
        // Optimised at level 1, not 3: it compiles in about 70 % of the time, writes the
        // same glue and wasm byte for byte, and takes 0.65 s rather than 0.58 s on the
        // page's module.
        run(cargo()
            .args(["install", "wasm-bindgen-cli", "--force", "--version"])
            .arg(format!("={WASM_BINDGEN}"))
            .arg("--root")
            .arg(&tools)
            .env("CARGO_PROFILE_RELEASE_OPT_LEVEL", "1"));
    }
    bin
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
    for entry in std::fs::read_dir(from).unwrap_or_else(|e| panic!("{}: {e}", from.display())) {
        let entry = entry.expect("a directory entry");
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target)
                .unwrap_or_else(|e| panic!("{}: {e}", target.display()));
        }
    }
}

/// Builds the page into [`dir`] (into a temporary folder first, renamed when whole).
pub fn build() -> PathBuf {
    wasm_target();
    let bindgen = wasm_bindgen();
    run(cargo().args([
        "build",
        "--release",
        "-p",
        "volfog-web",
        "--lib",
        "--target",
        WASM_TARGET,
    ]));
    let out = dir();
    let staging = out.with_extension("partial");
    let _ = std::fs::remove_dir_all(&staging);
    let wasm = root()
        .join("target")
        .join(WASM_TARGET)
        .join("release")
        .join("volfog_web.wasm");
    run(Command::new(bindgen)
        .args(["--target", "web", "--no-typescript", "--out-dir"])
        .arg(staging.join("pkg"))
        .arg(wasm));
    copy_dir(&root().join("web").join("www"), &staging);
    // The GLSL ES snippet the WebGL2 tier includes (and the apply pass beside it).
    run(cargo()
        .args(["run", "--bin", "volfog", "--", "export", "--target", "glsl"])
        .args(["--variant", "apply", "--snippets", "all", "--out"])
        .arg(staging.join("shaders")));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::rename(&staging, &out).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
    let size = std::fs::metadata(out.join("pkg").join("volfog_web_bg.wasm"))
        .map(|m| m.len())
        .unwrap_or(0);
    eprintln!(
        "web page in {} (wasm {:.1} MiB)",
        out.display(),
        size as f64 / (1024.0 * 1024.0)
    );
    out
}

/// Serves [`dir`] on 127.0.0.1:`port` until stopped (the page's own server in
/// `volfog-web`, which prints what the page posts to `/report/...`).
pub fn serve(port: u16) {
    run(cargo()
        .args(["run", "-p", "volfog-web", "--bin", "volfog-web-serve", "--"])
        .arg(dir())
        .arg(port.to_string()));
}

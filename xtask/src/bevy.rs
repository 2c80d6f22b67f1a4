//! The Bevy plugin (`bevy/`): a workspace of its own, built with the Rust toolchain its
//! `rust-toolchain.toml` names (Bevy 0.20 needs a newer rustc than the rest of
//! volfog). rustup installs that toolchain when it is missing; it goes to the user's
//! rustup home, so no root is needed.

use std::process::{Command, exit};

use crate::root;

/// The toolchain channel of `bevy/rust-toolchain.toml`.
pub fn channel() -> String {
    let path = root().join("bevy").join("rust-toolchain.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("cannot read {}: {e}", path.display());
        exit(1);
    });
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("channel"))
        .filter_map(|rest| rest.trim().strip_prefix('='))
        .map(|v| v.trim().trim_matches('"').to_string())
        .next()
        .unwrap_or_else(|| {
            eprintln!("{} names no channel", path.display());
            exit(1);
        })
}

/// Installs the plugin's toolchain with rustup unless it is there.
pub fn ensure_toolchain(channel: &str) {
    let listed = Command::new("rustup")
        .args(["toolchain", "list"])
        .output()
        .unwrap_or_else(|e| {
            eprintln!(
                "the Bevy plugin builds with Rust {channel} (bevy/rust-toolchain.toml), which rustup installs; rustup is not available: {e}"
            );
            exit(1);
        });
    let installed = String::from_utf8_lossy(&listed.stdout).lines().any(|l| {
        l.starts_with(&format!("{channel}-")) || l.split_whitespace().next() == Some(channel)
    });
    if !installed {
        crate::run(Command::new("rustup").args([
            "toolchain",
            "install",
            channel,
            "--profile",
            "minimal",
            "--component",
            "clippy,rustfmt",
        ]));
    }
}

/// `cargo ARGS` in `bevy/` with its toolchain.
pub fn cargo(channel: &str, args: &[&str]) -> Command {
    let mut cmd = Command::new("rustup");
    cmd.args(["run", channel, "cargo"])
        .args(args)
        .current_dir(root().join("bevy"));
    // The outer cargo's toolchain must not leak into the inner one.
    for var in [
        "RUSTUP_TOOLCHAIN",
        "CARGO",
        "RUSTC",
        "RUSTDOC",
        "RUSTC_WRAPPER",
    ] {
        cmd.env_remove(var);
    }
    cmd
}

/// The `fog_scene` example in a window on a virtual X display (Xvfb): 12 frames, then
/// a screenshot of the window that the example checks is drawn (not flat) and writes
/// to `target/tmp/fog_scene_window.png`.
pub fn window(channel: &str) -> Command {
    let screenshot = root()
        .join("target")
        .join("tmp")
        .join("fog_scene_window.png");
    let _ = std::fs::create_dir_all(screenshot.parent().expect("a folder"));
    let inner = cargo(channel, &[]);
    let mut cmd = Command::new("xvfb-run");
    cmd.args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(inner.get_program())
        .args(inner.get_args())
        .args(["run", "--example", "fog_scene", "--"])
        .args(["--width", "640", "--height", "360", "--exit-after", "12"])
        .arg("--screenshot")
        .arg(screenshot)
        .current_dir(root().join("bevy"));
    for (key, value) in inner.get_envs() {
        match value {
            Some(v) => cmd.env(key, v),
            None => cmd.env_remove(key),
        };
    }
    cmd
}

/// What only the root suite uses: its dev build, its test scratch space, the web page's
/// wasm build (and the host side of that release build) and the Dawn packages (all
/// rebuilt by the next `cargo xtask test`). The tools' venv stays: the Bevy suite's
/// path-tracer test reads Mitsuba's renders through it.
const ROOT_ONLY: [&str; 6] = [
    "target/debug",
    "target/tmp",
    "target/release",
    "target/wasm32-unknown-unknown",
    "tools/dawn/node_modules",
    "examples/webgpu-node/node_modules",
];

/// Removes what only the root suite uses once that suite has passed, so that a
/// disk-tight machine holds one workspace's build at a time: the Bevy workspace builds
/// into `target/bevy` with its own toolchain and reads none of it.
pub fn drop_root_outputs() {
    for rel in ROOT_ONLY {
        let dir = root().join(rel);
        let bytes = dir_size(&dir);
        match std::fs::remove_dir_all(&dir) {
            Ok(()) => eprintln!(
                "VOLFOG_FREE_DISK=1: removed {rel} ({} MB) before the Bevy build",
                bytes / 1_000_000
            ),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => eprintln!("VOLFOG_FREE_DISK=1: could not remove {rel}: {e}; going on"),
        }
    }
}

fn dir_size(dir: &std::path::Path) -> u64 {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    entries
        .flatten()
        .map(|e| match e.file_type() {
            Ok(t) if t.is_dir() => dir_size(&e.path()),
            Ok(t) if t.is_file() => e.metadata().map(|m| m.len()).unwrap_or(0),
            _ => 0,
        })
        .sum()
}

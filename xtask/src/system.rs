//! Debian packages the jobs need: found, installed with apt-get when running as root, or
//! named in the exact command to run.

use std::path::Path;
use std::process::{Command, exit};

use crate::run;

/// What a job needs from the system.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Needs {
    /// The Vulkan loader and lavapipe (demo, self-check).
    Gpu,
    /// Everything the test suite runs: the GPU, the validators and the independent
    /// compilers' prerequisites.
    Tests,
}

fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|p| p.join(tool).is_file()))
        .unwrap_or(false)
}

fn vulkan_loader_present() -> bool {
    match Command::new("ldconfig").arg("-p").output() {
        Ok(o) => String::from_utf8_lossy(&o.stdout).contains("libvulkan.so.1"),
        Err(_) => [
            "/usr/lib/x86_64-linux-gnu",
            "/usr/lib/aarch64-linux-gnu",
            "/usr/lib",
            "/usr/lib64",
        ]
        .iter()
        .any(|d| Path::new(d).join("libvulkan.so.1").exists()),
    }
}

/// Whether a Vulkan manifest whose file name starts with `prefix` sits in `kind`
/// (`icd.d` or `explicit_layer.d`) under the loader's system folders.
fn vulkan_manifest_present(kind: &str, prefix: &str) -> bool {
    [
        "/usr/share/vulkan",
        "/etc/vulkan",
        "/usr/local/share/vulkan",
    ]
    .iter()
    .any(|dir| {
        std::fs::read_dir(Path::new(dir).join(kind))
            .map(|entries| {
                entries
                    .filter_map(|e| e.ok())
                    .any(|e| e.file_name().to_string_lossy().starts_with(prefix))
            })
            .unwrap_or(false)
    })
}

/// Whether dpkg lists the package as installed (true where there is no dpkg: the
/// build then reports what it misses itself).
fn dpkg_installed(package: &str) -> bool {
    match Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", package])
        .output()
    {
        Ok(o) => String::from_utf8_lossy(&o.stdout).contains("install ok installed"),
        Err(_) => true,
    }
}

fn python_venv_works() -> bool {
    Command::new("python3")
        .args(["-c", "import ensurepip, venv"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// The Debian packages `needs` lacks on this machine.
fn missing(needs: Needs) -> Vec<&'static str> {
    let mut missing = Vec::new();
    if !vulkan_loader_present() || !vulkan_manifest_present("icd.d", "lvp_icd") {
        missing.extend(["mesa-vulkan-drivers", "libvulkan1"]);
    }
    if needs == Needs::Gpu {
        return missing;
    }
    if !vulkan_manifest_present("explicit_layer.d", "VkLayer_khronos_validation") {
        missing.push("vulkan-validationlayers");
    }
    for (tool, package) in [
        ("spirv-val", "spirv-tools"),
        ("glslangValidator", "glslang-tools"),
        ("gcc", "gcc"),
        ("g++", "g++"),
        ("node", "nodejs"),
        ("npm", "npm"),
    ] {
        if !on_path(tool) {
            missing.push(package);
        }
    }
    if !on_path("python3") {
        missing.extend(["python3", "python3-venv"]);
    } else if !python_venv_works() {
        missing.push("python3-venv");
    }
    // Mesa's OpenGL driver through EGL without a display, and the headers to build
    // against it.
    for package in [
        "libegl-dev",
        "libopengl-dev",
        "libgl-dev",
        "libegl-mesa0",
        "libgl1-mesa-dri",
        // The libLLVM Mitsuba 3's CPU back end (Dr.Jit 1.5) loads: Mesa's libLLVM 15
        // cannot compile its kernels.
        "libllvm19",
        // The browser the web page is tested in (WebGPU on its bundled SwiftShader).
        "chromium",
        // A virtual X display for the Bevy example's window.
        "xvfb",
        "xauth",
    ] {
        if !dpkg_installed(package) {
            missing.push(package);
        }
    }
    missing
}

/// Installs the missing Debian packages (as root) or stops with the command to run.
pub fn ensure(needs: Needs) {
    let missing = missing(needs);
    if missing.is_empty() {
        return;
    }
    let list = missing.join(" ");
    if !is_root() {
        eprintln!("volfog needs these Debian packages: {list}");
        eprintln!(
            "install them with:\n\n    sudo apt-get update && sudo apt-get install -y --no-install-recommends {list}\n"
        );
        exit(1);
    }
    eprintln!("installing missing packages: {list}");
    run(Command::new("apt-get").arg("update"));
    run(Command::new("apt-get")
        .args(["install", "-y", "--no-install-recommends"])
        .args(&missing)
        .env("DEBIAN_FRONTEND", "noninteractive"));
}

//! `cargo xtask demo` and `cargo xtask test`: make sure the system tools exist
//! (Mesa's lavapipe Vulkan driver and loader, spirv-tools, glslang-tools), installing
//! them with apt-get when running as root, then run the job.

use std::path::{Path, PathBuf};
use std::process::{Command, exit};

const PACKAGES_GPU: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];
const PACKAGES_TOOLS: &[&str] = &["spirv-tools", "glslang-tools"];

fn usage() -> ! {
    eprintln!(
        "usage: cargo xtask demo [--out DIR]   export every shader target, run the GPU self-check, render the demo to DIR/demo"
    );
    eprintln!(
        "       cargo xtask test [ARGS...]      run the whole test suite (ARGS go to cargo test)"
    );
    exit(2);
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|p| p.join(tool).is_file()))
        .unwrap_or(false)
}

fn vulkan_loader_present() -> bool {
    let output = Command::new("ldconfig").arg("-p").output();
    match output {
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

fn lavapipe_present() -> bool {
    ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"]
        .iter()
        .any(|dir| {
            std::fs::read_dir(dir)
                .map(|entries| {
                    entries
                        .filter_map(|e| e.ok())
                        .any(|e| e.file_name().to_string_lossy().starts_with("lvp_icd"))
                })
                .unwrap_or(false)
        })
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

fn run(cmd: &mut Command) {
    eprintln!("+ {cmd:?}");
    match cmd.status() {
        Ok(s) if s.success() => {}
        Ok(s) => exit(s.code().unwrap_or(1)),
        Err(e) => {
            eprintln!("cannot run {cmd:?}: {e}");
            exit(1);
        }
    }
}

/// Installs the missing Debian packages (as root) or stops with the command to run.
fn ensure_system(with_tools: bool) {
    let mut missing: Vec<&str> = Vec::new();
    if !vulkan_loader_present() || !lavapipe_present() {
        missing.extend(PACKAGES_GPU);
    }
    if with_tools {
        for (tool, package) in [
            ("spirv-val", PACKAGES_TOOLS[0]),
            ("glslangValidator", PACKAGES_TOOLS[1]),
        ] {
            if !on_path(tool) {
                missing.push(package);
            }
        }
    }
    if missing.is_empty() {
        return;
    }
    let list = missing.join(" ");
    if !is_root() {
        eprintln!("volfog needs these Debian packages: {list}");
        eprintln!(
            "install them with:\n\n    sudo apt-get update && sudo apt-get install -y {list}\n"
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

/// Environment for GPU runs on lavapipe: no shader cache, a valid runtime dir.
fn gpu_env(cmd: &mut Command) -> &mut Command {
    let runtime = root().join("target").join("xdg-runtime");
    let _ = std::fs::create_dir_all(&runtime);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700));
    }
    cmd.env("MESA_SHADER_CACHE_DISABLE", "true");
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        cmd.env("XDG_RUNTIME_DIR", runtime);
    }
    cmd
}

fn cargo() -> Command {
    let mut cmd = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    cmd.current_dir(root());
    cmd
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((job, rest)) = args.split_first() else {
        usage()
    };
    match job.as_str() {
        "demo" => {
            let out = match rest {
                [] => "out".to_string(),
                [flag, dir] if flag == "--out" => dir.clone(),
                _ => usage(),
            };
            ensure_system(false);
            run(gpu_env(cargo().args([
                "run", "--bin", "volfog", "--", "export", "--target", "all", "--out",
            ]))
            .arg(Path::new(&out).join("shaders")));
            run(gpu_env(cargo().args([
                "run",
                "--bin",
                "volfog",
                "--",
                "selfcheck",
            ])));
            run(
                gpu_env(cargo().args(["run", "--bin", "volfog", "--", "demo", "--out"]))
                    .arg(Path::new(&out).join("demo")),
            );
        }
        "test" => {
            ensure_system(true);
            run(gpu_env(cargo().args(["test", "--workspace"]).args(rest))
                .env("INSTA_UPDATE", "no")
                .env("CI", "true"));
        }
        _ => usage(),
    }
}

//! `cargo xtask demo`, `cargo xtask test`, `cargo xtask tools` and `cargo xtask web`:
//! make sure the system packages exist (installing them with apt-get when running as
//! root), build the independent compilers and the browser page the tests use, then run
//! the job.

mod bevy;
mod system;
mod tools;
mod web;

use std::path::{Path, PathBuf};
use std::process::{Command, exit};

use system::Needs;

fn usage() -> ! {
    eprintln!(
        "usage: cargo xtask demo [--out DIR]   export every shader target, run the GPU self-check, render the demo to DIR/demo"
    );
    eprintln!(
        "       cargo xtask test [ARGS...]      run the whole test suite, the Bevy plugin's included (ARGS go to cargo test)"
    );
    eprintln!(
        "       cargo xtask tools               install and build only what the test suite needs (target/tools)"
    );
    eprintln!(
        "       cargo xtask web [--serve PORT]  build the browser demo into target/web (wasm), and serve it on 127.0.0.1"
    );
    exit(2);
}

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

pub fn run(cmd: &mut Command) {
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

fn volfog(args: &[&str]) -> Command {
    let mut cmd = cargo();
    cmd.args(["run", "--bin", "volfog", "--"]).args(args);
    gpu_env(&mut cmd);
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
            system::ensure(Needs::Gpu);
            let out = Path::new(&out);
            run(volfog(&["export", "--target", "all", "--out"]).arg(out.join("shaders")));
            run(&mut volfog(&["selfcheck"]));
            run(volfog(&["demo", "--out"]).arg(out.join("demo")));
        }
        "web" => {
            let port = match rest {
                [] => None,
                [flag, port] if flag == "--serve" => Some(port.parse().unwrap_or_else(|_| usage())),
                _ => usage(),
            };
            web::build();
            if let Some(port) = port {
                web::serve(port);
            }
        }
        "tools" => {
            system::ensure(Needs::Tests);
            println!("{}", tools::ensure().display());
        }
        "test" => {
            system::ensure(Needs::Tests);
            let tools = tools::ensure();
            let page = web::build();
            run(gpu_env(cargo().args(["test", "--workspace"]).args(rest))
                .env("VOLFOG_TOOLS_DIR", tools)
                .env("VOLFOG_WEB_DIR", page)
                .env("INSTA_UPDATE", "no")
                .env("CI", "true"));
            if std::env::var_os("VOLFOG_FREE_DISK").is_some_and(|v| v == "1") {
                bevy::drop_root_outputs();
            }
            // The Bevy plugin, its WESL package and its example scene.
            let channel = bevy::channel();
            bevy::ensure_toolchain(&channel);
            let args: Vec<&str> = rest.iter().map(String::as_str).collect();
            run(gpu_env(&mut bevy::cargo(
                &channel,
                &[&["test"], args.as_slice()].concat(),
            ))
            .env("CI", "true"));
            // Its example in a window, as a Bevy user runs it.
            run(gpu_env(&mut bevy::window(&channel)));
        }
        _ => usage(),
    }
}

//! The independent compilers the host tests run, built by `cargo xtask tools` (and by
//! `cargo xtask test`) under `target/tools` or the folder `VOLFOG_TOOLS_DIR` names. A
//! missing tool fails the test with the command that builds it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BUILD: &str = "cargo xtask tools";

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn dir() -> PathBuf {
    std::env::var_os("VOLFOG_TOOLS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo().join("target/tools"))
}

fn binary(name: &str) -> Command {
    let path = dir().join("bin").join(name);
    assert!(
        path.is_file(),
        "{} is missing; build the test tools with `{BUILD}` (or run the suite with `cargo xtask test`)",
        path.display()
    );
    Command::new(path)
}

/// `slang_check`: one entry point of an HLSL file through Slang's HLSL front end.
pub fn slang_check() -> Command {
    binary("slang_check")
}

/// `gl_link`: GLSL files compiled and linked as one program by Mesa's OpenGL 4.5 driver.
pub fn gl_link() -> Command {
    binary("gl_link")
}

/// `node tools/dawn/dawn_check.mjs`: modules and pipelines of a manifest in Dawn/Tint.
pub fn dawn_check() -> Command {
    let script = repo().join("tools/dawn/dawn_check.mjs");
    assert!(
        repo().join("tools/dawn/node_modules/webgpu").is_dir(),
        "Dawn (npm package webgpu) is not installed in tools/dawn; install it with `{BUILD}`"
    );
    let mut cmd = Command::new("node");
    cmd.arg(script);
    cmd
}

/// `glslangValidator` (Debian package glslang-tools).
pub fn glslang() -> Command {
    Command::new("glslangValidator")
}

/// Runs a command and returns its output, failing with the command line when it cannot
/// start.
pub fn output(cmd: &mut Command) -> Output {
    cmd.output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}; install the tools with `{BUILD}`"))
}

/// stdout and stderr of a run, for failure messages.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// One entry point's outcome in a `dawn_check` run: `Err` holds Dawn's message.
pub struct DawnResult {
    pub variant: String,
    pub entry: String,
    pub outcome: Result<(), String>,
}

/// The per-entry results of a `dawn_check` run and its summary counts (passed, failed).
pub fn dawn_results(o: &Output) -> (Vec<DawnResult>, u64, u64) {
    let stdout = String::from_utf8_lossy(&o.stdout);
    let mut results = Vec::new();
    for line in stdout.lines() {
        let Some((head, outcome)) = line.split_once("): ") else {
            continue;
        };
        let mut words = head.split(' ');
        let (Some(variant), Some(entry), Some(stage)) = (words.next(), words.next(), words.next())
        else {
            continue;
        };
        if !["(compute", "(vertex", "(fragment"].contains(&stage) {
            continue;
        }
        results.push(DawnResult {
            variant: variant.to_string(),
            entry: entry.to_string(),
            outcome: if outcome == "ok" {
                Ok(())
            } else {
                Err(outcome.to_string())
            },
        });
    }
    let summary: serde_json::Value = stdout
        .lines()
        .rev()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("dawn_check printed no summary:\n{}", text(o)));
    (
        results,
        summary["passed"].as_u64().unwrap(),
        summary["failed"].as_u64().unwrap(),
    )
}

/// `f` of every item, in the items' order, run by as many threads as the machine has
/// cores: the compilers run one process per file, and a suite whose other tests have
/// finished would otherwise leave all but one core idle.
pub(crate) fn each_in_parallel<T: Sync, R: Send>(
    items: &[T],
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut results: Vec<(usize, R)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else {
                            return done;
                        };
                        done.push((i, f(item)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a worker panicked"))
            .collect()
    });
    results.sort_by_key(|(i, _)| *i);
    results.into_iter().map(|(_, r)| r).collect()
}

//! Where Mitsuba's renders are kept, each under the key of what was rendered
//! ([`super::mitsuba`]: a SHA-256 of the scene's JSON, the samples per pixel, the seed,
//! the mode, the bytes of render.py and the installed Mitsuba and Dr.Jit versions),
//! as `<key>.bin` (little-endian f32 rgb, row-major):
//!
//! - the references committed with the repository ([`REFERENCES`]): the renders of
//!   every scene the truth suites compare with (`scenes::all` and
//!   `scenes::area_lights` at the suites' samples per pixel), read first, so that a
//!   clean checkout compares without rendering them again. A changed scene, script or
//!   Mitsuba version changes the key: the render is made anew and the committed file no
//!   longer matches, which the testkit's `committed_references_are_the_suites_renders`
//!   reports, naming the command that writes the new ones ([`WRITE_REFERENCES`]);
//! - the machine's cache, `target/truth-cache/`, which keeps every other render.
//!
//! `VOLFOG_TRUTH_CACHE=off` reads neither and renders everything.

use std::path::{Path, PathBuf};

/// The committed references' folder, relative to the workspace.
pub const REFERENCES: &str = "tests/truth-references";

/// The environment variable that, set to `write`, also writes each render (made or
/// read from the cache) into [`REFERENCES`].
pub const WRITE_REFERENCES: &str = "VOLFOG_TRUTH_REFERENCES";

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The committed references' folder.
pub fn references_dir() -> PathBuf {
    workspace().join(REFERENCES)
}

fn stores_enabled() -> bool {
    !matches!(
        std::env::var("VOLFOG_TRUTH_CACHE").as_deref(),
        Ok("off" | "0")
    )
}

fn cache_dir() -> PathBuf {
    workspace().join("target/truth-cache")
}

/// The bytes kept under `key`, the committed reference first, then the cache; `None`
/// when neither holds it (or the stores are off). `valid` rejects a file of the wrong
/// size, which is then rendered again.
pub fn load(key: &str, valid: impl Fn(&[u8]) -> bool) -> Option<Vec<u8>> {
    if !stores_enabled() {
        return None;
    }
    let name = format!("{key}.bin");
    let found = [references_dir(), cache_dir()]
        .into_iter()
        .filter_map(|dir| std::fs::read(dir.join(&name)).ok())
        .find(|bytes| valid(bytes));
    if let Some(bytes) = &found {
        keep_reference(key, bytes);
    }
    found
}

/// Keeps a new render in the cache (and in the references under
/// [`WRITE_REFERENCES`]`=write`). A failed write only costs a later render.
pub fn keep(key: &str, bytes: &[u8]) {
    if !stores_enabled() {
        return;
    }
    write_whole(&cache_dir(), key, bytes);
    keep_reference(key, bytes);
}

fn keep_reference(key: &str, bytes: &[u8]) {
    if std::env::var(WRITE_REFERENCES).as_deref() == Ok("write") {
        write_whole(&references_dir(), key, bytes);
    }
}

/// Writes `<dir>/<key>.bin` through a temporary file renamed when whole.
fn write_whole(dir: &Path, key: &str, bytes: &[u8]) {
    let path = dir.join(format!("{key}.bin"));
    if std::fs::read(&path).is_ok_and(|b| b == bytes) {
        return;
    }
    let partial = dir.join(format!("{key}.{}.partial", std::process::id()));
    if std::fs::create_dir_all(dir).is_ok() && std::fs::write(&partial, bytes).is_ok() {
        let _ = std::fs::rename(&partial, &path);
    }
    let _ = std::fs::remove_file(&partial);
}

/// The keys of the committed references (their file stems), sorted.
pub fn committed_keys() -> Vec<String> {
    let mut keys: Vec<String> = std::fs::read_dir(references_dir())
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.strip_suffix(".bin").map(str::to_string)
        })
        .collect();
    keys.sort();
    keys
}

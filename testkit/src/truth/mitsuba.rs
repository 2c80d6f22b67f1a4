//! Mitsuba 3 (`volpath`, single scattering) as the reference renderer of a
//! [`TruthScene`]: `tools/mitsuba/render.py` run by the Python of the test tools'
//! venv (`$VOLFOG_TOOLS_DIR/venv`, else `target/tools/venv`, where `cargo xtask tools`
//! installs Mitsuba), once for the radiance and once for the transmittance. The
//! scene mapping is documented at the top of render.py.
//!
//! Renders are kept under a key, a SHA-256 of the scene's JSON, the samples per pixel,
//! the seed, the mode, the bytes of render.py and the installed Mitsuba and Dr.Jit
//! versions: those of the scenes the truth suites compare with are committed with the
//! repository, every other is cached under `target/truth-cache/`
//! ([`super::stored`]), so that neither a clean checkout nor a rerun renders them
//! again. `VOLFOG_TRUTH_CACHE=off` reads neither.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;
use sha2::{Digest, Sha256};

use super::scene::{TruthImage, TruthScene};
use super::stored;

/// The command that installs Mitsuba into the test tools' venv.
pub const INSTALL_COMMAND: &str = "cargo xtask tools";

/// Samples per pixel recommended for the radiance of the scenes in
/// [`super::scenes`]: the image mean of each then carries 0.04 to 0.4 % of Mitsuba's
/// own noise, a single pixel 4 to 28 % ([`RadiancePair::noise`];
/// tools/mitsuba/README.md has the figures): compare block means, not pixels.
pub const RECOMMENDED_SPP: u32 = 1024;

/// Samples per pixel of every transmittance render (8 x 8 strata). The transmittance
/// integrator of render.py is deterministic along a ray; the samples only spread the
/// rays over the pixel (box filter).
pub const TRANSMITTANCE_SPP: u32 = 64;

/// How Mitsuba renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MitsubaOptions {
    /// Samples per pixel of the radiance (>= 1); the noise of a pixel falls as
    /// 1 / sqrt(spp).
    pub spp: u32,
    /// Seed of Mitsuba's `independent` sampler: renders with different seeds carry
    /// independent noise.
    pub seed: u32,
}

impl Default for MitsubaOptions {
    /// [`RECOMMENDED_SPP`] samples per pixel, seed 1.
    fn default() -> Self {
        Self {
            spp: RECOMMENDED_SPP,
            seed: 1,
        }
    }
}

/// Why a Mitsuba render failed.
#[derive(Debug, thiserror::Error)]
pub enum MitsubaError {
    /// The venv's Python or Mitsuba in it is missing.
    #[error("Mitsuba 3 is not installed ({detail}); install it with `{INSTALL_COMMAND}`")]
    ToolMissing {
        /// What was missing.
        detail: String,
    },
    /// render.py exited with an error.
    #[error("render.py --mode {mode} for scene {scene} failed ({status}):\n{stderr}")]
    Process {
        /// The scene's name.
        scene: String,
        /// `radiance` or `transmittance`.
        mode: &'static str,
        /// The exit status.
        status: String,
        /// What render.py printed on stderr.
        stderr: String,
    },
    /// render.py wrote a file of the wrong size.
    #[error("render.py wrote {bytes} bytes for scene {scene}, expected {expected}")]
    BadOutput {
        /// The scene's name.
        scene: String,
        /// The file's size.
        bytes: usize,
        /// width * height * 3 * 4.
        expected: usize,
    },
    /// The options or the scene cannot be rendered.
    #[error("cannot render scene {scene}: {reason}")]
    Invalid {
        /// The scene's name.
        scene: String,
        /// Why.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("{context}: {source}")]
    Io {
        /// The file and what was done with it.
        context: String,
        /// The error.
        #[source]
        source: std::io::Error,
    },
}

/// Two radiance renders of one scene that differ only in the seed, to measure
/// Mitsuba's own noise.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RadiancePair {
    /// Width (pixels).
    pub width: u32,
    /// Height (pixels).
    pub height: u32,
    /// The radiance with the options' seed (row-major, top row first).
    pub first: Vec<Vec3>,
    /// The radiance with the next seed.
    pub second: Vec<Vec3>,
}

/// Mitsuba's noise in one render, estimated from two seeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseEstimate {
    /// Relative standard deviation of one pixel of one render: the standard deviation
    /// of (a - b) / ((a + b) / 2) over the pixels counted, divided by sqrt(2).
    pub per_pixel: f32,
    /// Relative standard deviation of the sum of the pixels counted in one render:
    /// sqrt(sum (a - b)^2 / 2) / sum (a + b) / 2.
    pub image_mean: f32,
    /// The pixels counted: those whose mean radiance (over channels and both renders)
    /// exceeds 5 % of the image mean.
    pub pixels: usize,
}

impl RadiancePair {
    /// Mitsuba's noise, on the channel mean of each pixel.
    pub fn noise(&self) -> NoiseEstimate {
        let mean = |v: Vec3| (v.x + v.y + v.z) / 3.0;
        let pairs: Vec<(f64, f64)> = self
            .first
            .iter()
            .zip(&self.second)
            .map(|(&a, &b)| (mean(a) as f64, mean(b) as f64))
            .collect();
        let image = pairs.iter().map(|(a, b)| a + b).sum::<f64>() / (2 * pairs.len().max(1)) as f64;
        let counted: Vec<(f64, f64)> = pairs
            .into_iter()
            .filter(|(a, b)| (a + b) * 0.5 > 0.05 * image)
            .collect();
        let n = counted.len().max(1) as f64;
        let rel: Vec<f64> = counted
            .iter()
            .map(|(a, b)| (a - b) / ((a + b) * 0.5))
            .collect();
        let rel_mean = rel.iter().sum::<f64>() / n;
        let rel_var = rel.iter().map(|r| (r - rel_mean).powi(2)).sum::<f64>() / n;
        let diff2 = counted
            .iter()
            .map(|(a, b)| (a - b).powi(2) * 0.5)
            .sum::<f64>();
        let sum = counted.iter().map(|(a, b)| (a + b) * 0.5).sum::<f64>();
        NoiseEstimate {
            per_pixel: (rel_var * 0.5).sqrt() as f32,
            image_mean: if sum > 0.0 {
                (diff2.sqrt() / sum) as f32
            } else {
                0.0
            },
            pixels: counted.len(),
        }
    }
}

/// Renders the scene's radiance (`options.spp`, `options.seed`) and transmittance
/// ([`TRANSMITTANCE_SPP`]).
pub fn render(scene: &TruthScene, options: &MitsubaOptions) -> Result<TruthImage, MitsubaError> {
    let radiance = run(scene, Mode::Radiance, options.spp, options.seed)?;
    let transmittance = run(scene, Mode::Transmittance, TRANSMITTANCE_SPP, options.seed)?;
    Ok(TruthImage {
        width: scene.resolution[0],
        height: scene.resolution[1],
        radiance,
        transmittance,
    })
}

/// Renders only the scene's transmittance ([`TRANSMITTANCE_SPP`], `seed`).
pub fn render_transmittance(scene: &TruthScene, seed: u32) -> Result<Vec<Vec3>, MitsubaError> {
    run(scene, Mode::Transmittance, TRANSMITTANCE_SPP, seed)
}

/// Renders the scene's radiance with `options.seed` and with the next seed, for an
/// estimate of Mitsuba's own noise ([`RadiancePair::noise`]); the first equals the
/// radiance of [`render`] with the same options.
pub fn render_noise(
    scene: &TruthScene,
    options: &MitsubaOptions,
) -> Result<RadiancePair, MitsubaError> {
    let first = run(scene, Mode::Radiance, options.spp, options.seed)?;
    let second = run(
        scene,
        Mode::Radiance,
        options.spp,
        options.seed.wrapping_add(1),
    )?;
    Ok(RadiancePair {
        width: scene.resolution[0],
        height: scene.resolution[1],
        first,
        second,
    })
}

#[derive(Debug, Clone, Copy)]
enum Mode {
    Radiance,
    Transmittance,
}

impl Mode {
    fn name(self) -> &'static str {
        match self {
            Mode::Radiance => "radiance",
            Mode::Transmittance => "transmittance",
        }
    }
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn script() -> PathBuf {
    workspace().join("tools/mitsuba/render.py")
}

fn tools_dir() -> PathBuf {
    std::env::var_os("VOLFOG_TOOLS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("target/tools"))
}

fn io(context: impl Into<String>) -> impl FnOnce(std::io::Error) -> MitsubaError {
    let context = context.into();
    move |source| MitsubaError::Io { context, source }
}

/// The names of the venv's Mitsuba and Dr.Jit distributions (`mitsuba-3.9.1.dist-info`
/// and the like), which carry their versions.
fn installed_versions(venv: &Path) -> Result<Vec<String>, MitsubaError> {
    let lib = venv.join("lib");
    let mut found = Vec::new();
    let pythons = std::fs::read_dir(&lib).map_err(|e| MitsubaError::ToolMissing {
        detail: format!("{}: {e}", lib.display()),
    })?;
    for python in pythons.flatten() {
        let Ok(packages) = std::fs::read_dir(python.path().join("site-packages")) else {
            continue;
        };
        for entry in packages.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let ours = name.starts_with("mitsuba-") || name.starts_with("drjit-");
            if ours && name.ends_with(".dist-info") {
                found.push(name);
            }
        }
    }
    found.sort();
    if !found.iter().any(|n| n.starts_with("mitsuba-")) {
        return Err(MitsubaError::ToolMissing {
            detail: format!("no mitsuba package in {}", venv.display()),
        });
    }
    Ok(found)
}

/// One render at a time in this process: Mitsuba already uses every core.
static RENDERING: Mutex<()> = Mutex::new(());
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

fn decode(scene: &TruthScene, bytes: &[u8]) -> Result<Vec<Vec3>, MitsubaError> {
    let expected = scene.resolution[0] as usize * scene.resolution[1] as usize * 12;
    if bytes.len() != expected {
        return Err(MitsubaError::BadOutput {
            scene: scene.name.clone(),
            bytes: bytes.len(),
            expected,
        });
    }
    Ok(bytes
        .chunks_exact(12)
        .map(|c| {
            let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
            Vec3::new(f(0), f(4), f(8))
        })
        .collect())
}

/// The keys of the three renders [`super::report::Reference::render`] asks for with
/// `options`: the radiance with `options.seed`, with the next seed, and the
/// transmittance ([`super::stored`] keeps each under its key).
pub fn reference_keys(
    scene: &TruthScene,
    options: &MitsubaOptions,
) -> Result<[String; 3], MitsubaError> {
    Ok([
        key(scene, Mode::Radiance, options.spp, options.seed)?,
        key(
            scene,
            Mode::Radiance,
            options.spp,
            options.seed.wrapping_add(1),
        )?,
        key(scene, Mode::Transmittance, TRANSMITTANCE_SPP, options.seed)?,
    ])
}

/// The venv's Python, after checking the request.
fn python(scene: &TruthScene, spp: u32) -> Result<PathBuf, MitsubaError> {
    let invalid = |reason: &str| MitsubaError::Invalid {
        scene: scene.name.clone(),
        reason: reason.to_string(),
    };
    if spp == 0 {
        return Err(invalid("spp must be at least 1"));
    }
    if scene.resolution[0] == 0 || scene.resolution[1] == 0 {
        return Err(invalid("empty resolution"));
    }
    let python = tools_dir().join("venv").join("bin/python3");
    if !python.is_file() {
        return Err(MitsubaError::ToolMissing {
            detail: format!("{} is missing", python.display()),
        });
    }
    Ok(python)
}

/// The key a render is kept under: a SHA-256 of everything that decides its pixels.
fn key(scene: &TruthScene, mode: Mode, spp: u32, seed: u32) -> Result<String, MitsubaError> {
    let versions = installed_versions(&tools_dir().join("venv"))?;
    let script = script();
    let script_bytes =
        std::fs::read(&script).map_err(io(format!("reading {}", script.display())))?;
    let json = scene_json(scene)?;
    let mut hasher = Sha256::new();
    for part in [
        b"volfog-truth-1".as_slice(),
        json.as_bytes(),
        &spp.to_le_bytes(),
        &seed.to_le_bytes(),
        mode.name().as_bytes(),
        &script_bytes,
        versions.join(",").as_bytes(),
    ] {
        hasher.update((part.len() as u64).to_le_bytes());
        hasher.update(part);
    }
    let mut key = String::with_capacity(64);
    for b in hasher.finalize() {
        let _ = write!(key, "{b:02x}");
    }
    Ok(key)
}

fn scene_json(scene: &TruthScene) -> Result<String, MitsubaError> {
    serde_json::to_string(scene).map_err(|e| MitsubaError::Invalid {
        scene: scene.name.clone(),
        reason: e.to_string(),
    })
}

fn run(scene: &TruthScene, mode: Mode, spp: u32, seed: u32) -> Result<Vec<Vec3>, MitsubaError> {
    let python = python(scene, spp)?;
    let key = key(scene, mode, spp, seed)?;
    if let Some(bytes) = stored::load(&key, |b| decode(scene, b).is_ok()) {
        return decode(scene, &bytes);
    }
    let script = script();
    let json = scene_json(scene)?;

    let _guard = RENDERING.lock().unwrap_or_else(|e| e.into_inner());
    let stem = format!(
        "volfog-truth-{}-{}",
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    );
    let tmp = std::env::temp_dir();
    let json_path = tmp.join(format!("{stem}.json"));
    let out_path = tmp.join(format!("{stem}.bin"));
    std::fs::write(&json_path, &json).map_err(io(format!("writing {}", json_path.display())))?;
    let output = Command::new(&python)
        .arg(&script)
        .arg(&json_path)
        .arg(&out_path)
        .args(["--spp", &spp.to_string(), "--seed", &seed.to_string()])
        .args(["--mode", mode.name()])
        .output();
    let _ = std::fs::remove_file(&json_path);
    let output = output.map_err(io(format!("running {}", python.display())))?;
    if !output.status.success() {
        let _ = std::fs::remove_file(&out_path);
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        if stderr.contains("No module named 'mitsuba'")
            || stderr.contains("No module named 'drjit'")
        {
            return Err(MitsubaError::ToolMissing {
                detail: format!("{} cannot import it", python.display()),
            });
        }
        return Err(MitsubaError::Process {
            scene: scene.name.clone(),
            mode: mode.name(),
            status: output.status.to_string(),
            stderr,
        });
    }
    let bytes = std::fs::read(&out_path).map_err(io(format!("reading {}", out_path.display())))?;
    let _ = std::fs::remove_file(&out_path);
    let values = decode(scene, &bytes)?;
    stored::keep(&key, &bytes);
    Ok(values)
}

//! Bevy 0.20's own `VolumetricFog` beside volfog's froxel fog on the same GPU models,
//! read from the report of the Bevy plugin's `fog_gpu_cost` example
//! (`cargo run -p volfog-bevy --example fog_gpu_cost` in `bevy/`, a workspace of its own:
//! Bevy needs a newer rustc than this crate). That example captures both fogs from
//! Bevy apps of `fog_bench`'s scene, compiles each pipeline with RADV on its null device
//! and models it with `volfog_cost`, as this report models the bench scene.

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::GpuCostError;
use super::table::ms;

/// Bevy's fog and volfog's frame in `fog_bench`'s scene on one GPU model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BevyRow {
    /// The GPU model's name (`RX 7900 XTX`).
    pub gpu: String,
    /// Its chip, by `RADV_FORCE_FAMILY` name.
    pub chip: String,
    /// VGPRs of Bevy's fog shader (its fragment stage).
    pub vgprs: u32,
    /// Its waves of 64 per SIMD.
    pub waves_per_simd: u32,
    /// Its instructions.
    pub instructions: u32,
    /// What bounds Bevy's pass on the model: `memory`, `latency` or `issue`.
    pub bound: String,
    /// Bevy's pass (ms), every light of a step's cluster counted as a full iteration.
    pub bevy_ms: f64,
    /// The same with only the volumetric lights' iterations counted (ms): the lower of
    /// the model's two figures for Bevy.
    pub bevy_lower_ms: f64,
    /// volfog's froxel pipeline in the same scene (ms).
    pub volfog_ms: f64,
}

impl BevyRow {
    /// Bevy's time over volfog's: (lower, upper).
    pub fn ratios(&self) -> (f64, f64) {
        (
            self.bevy_lower_ms / self.volfog_ms,
            self.bevy_ms / self.volfog_ms,
        )
    }
}

/// Bevy's fog on the GPU models, as `fog_gpu_cost` reported it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BevyPeer {
    /// The screen (pixels).
    pub screen: [u32; 2],
    /// Bevy's `VolumetricFog::step_count`.
    pub step_count: u32,
    /// volfog's grid.
    pub grid: [u32; 3],
    /// One row per GPU model.
    pub rows: Vec<BevyRow>,
}

// The parts of `fog_gpu_cost.json` read here (serde skips the rest).
#[derive(Deserialize)]
struct File {
    screen: [u32; 2],
    bevy: FileBevy,
    volfog: FileVolfog,
    models: Vec<FileModel>,
}

#[derive(Deserialize)]
struct FileBevy {
    step_count: u32,
}

#[derive(Deserialize)]
struct FileVolfog {
    grid: [u32; 3],
}

#[derive(Deserialize)]
struct FileModel {
    gpu: FileGpu,
    bevy: FilePass,
    bevy_lower: FilePass,
    volfog_ms: f64,
}

#[derive(Deserialize)]
struct FileGpu {
    name: String,
    chip: String,
}

#[derive(Deserialize)]
struct FilePass {
    stats: FileStats,
    estimate: FileEstimate,
}

#[derive(Deserialize)]
struct FileStats {
    vgprs: u32,
    waves_per_simd: u32,
    instructions: u32,
}

#[derive(Deserialize)]
struct FileEstimate {
    ms: f64,
    memory_bound: bool,
    latency_bound: bool,
}

/// Parses a `fog_gpu_cost.json` report; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<BevyPeer, GpuCostError> {
    let fail = |message: String| GpuCostError::Bevy {
        path: path.to_path_buf(),
        message,
    };
    let file: File = serde_json::from_str(text).map_err(|e| fail(e.to_string()))?;
    if file.models.is_empty() {
        return Err(fail("it has no GPU model".to_string()));
    }
    let rows = file
        .models
        .into_iter()
        .map(|m| {
            let times = [m.bevy.estimate.ms, m.bevy_lower.estimate.ms, m.volfog_ms];
            if times.iter().any(|t| !t.is_finite() || *t <= 0.0) {
                return Err(fail(format!(
                    "{}: times must be finite and positive, not {times:?}",
                    m.gpu.name
                )));
            }
            let e = &m.bevy.estimate;
            let bound = if e.memory_bound {
                "memory"
            } else if e.latency_bound {
                "latency"
            } else {
                "issue"
            };
            Ok(BevyRow {
                gpu: m.gpu.name,
                chip: m.gpu.chip,
                vgprs: m.bevy.stats.vgprs,
                waves_per_simd: m.bevy.stats.waves_per_simd,
                instructions: m.bevy.stats.instructions,
                bound: bound.to_string(),
                bevy_ms: m.bevy.estimate.ms,
                bevy_lower_ms: m.bevy_lower.estimate.ms,
                volfog_ms: m.volfog_ms,
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(BevyPeer {
        screen: file.screen,
        step_count: file.bevy.step_count,
        grid: file.volfog.grid,
        rows,
    })
}

/// Reads the `fog_gpu_cost.json` report at `path`.
pub fn read(path: &Path) -> Result<BevyPeer, GpuCostError> {
    let text = std::fs::read_to_string(path).map_err(|e| GpuCostError::Bevy {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    parse(&text, path)
}

/// Bevy's section of the report: its fog pass and volfog's frame per GPU model, with
/// the two ratios.
pub fn table(out: &mut String, peer: &BevyPeer) {
    let _ = writeln!(
        out,
        "\n## Bevy 0.20's VolumetricFog ({} steps per pixel) beside volfog ({}x{}x{}) in fog_bench's scene at {}x{} (ms; from fog_gpu_cost)\n\n\
         | GPU model | Bevy: VGPRs | waves/SIMD | instructions | bound | Bevy | Bevy, only volumetric lights' iterations | volfog | Bevy / volfog |\n\
         | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |",
        peer.step_count, peer.grid[0], peer.grid[1], peer.grid[2], peer.screen[0], peer.screen[1]
    );
    for r in &peer.rows {
        let (lower, upper) = r.ratios();
        let _ = writeln!(
            out,
            "| {} ({}) | {} | {} | {} | {} | {} | {} | {} | {lower:.1}x to {upper:.1}x |",
            r.gpu,
            r.chip,
            r.vgprs,
            r.waves_per_simd,
            r.instructions,
            r.bound,
            ms(r.bevy_ms),
            ms(r.bevy_lower_ms),
            ms(r.volfog_ms)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(ms: f64, latency_bound: bool) -> String {
        format!(
            r#"{{"stats": {{"vgprs": 48, "waves_per_simd": 5, "instructions": 822, "sgprs": 64}},
                "estimate": {{"ms": {ms}, "memory_bound": false, "latency_bound": {latency_bound}}}}}"#
        )
    }

    fn file(bevy_ms: f64) -> String {
        format!(
            r#"{{"screen": [1920, 1080], "bevy": {{"step_count": 64, "shader": "x"}},
                "volfog": {{"grid": [160, 90, 128]}},
                "models": [{{"gpu": {{"name": "Xbox One", "chip": "bonaire"}},
                             "bevy": {}, "bevy_lower": {}, "volfog_ms": 2.5, "ratio": 1.0}}]}}"#,
            pass(bevy_ms, true),
            pass(12.5, true)
        )
    }

    #[test]
    fn reads_the_rows_and_their_ratios() {
        let peer = parse(&file(30.0), Path::new("f.json")).unwrap();
        assert_eq!(
            (peer.screen, peer.step_count, peer.grid),
            ([1920, 1080], 64, [160, 90, 128])
        );
        let row = &peer.rows[0];
        assert_eq!(
            (row.gpu.as_str(), row.chip.as_str()),
            ("Xbox One", "bonaire")
        );
        assert_eq!(
            (row.vgprs, row.waves_per_simd, row.bound.as_str()),
            (48, 5, "latency")
        );
        assert_eq!(row.ratios(), (5.0, 12.0));
        let mut text = String::new();
        table(&mut text, &peer);
        assert!(text.contains("| Xbox One (bonaire) | 48 | 5 | 822 | latency | 30.00 | 12.50 | 2.50 | 5.0x to 12.0x |"), "{text}");
    }

    #[test]
    fn bad_reports_are_errors() {
        for text in [
            file(f64::NAN).replace("NaN", "null"),
            file(0.0),
            file(-1.0),
            "{}".to_string(),
            "not json".to_string(),
            file(30.0).replace(r#""models": ["#, r#""models": [], "x": ["#),
        ] {
            let e = parse(&text, Path::new("f.json")).unwrap_err();
            assert!(
                e.to_string()
                    .starts_with("reading Bevy's fog report f.json"),
                "{e}"
            );
        }
    }
}

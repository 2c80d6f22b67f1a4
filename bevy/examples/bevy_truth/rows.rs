//! Rows of the path-tracer table for Bevy's fog (and volfog's beside them): the
//! errors of one renderer's image of one scene against Mitsuba, as
//! `volfog_testkit::truth::report` computes them for volfog (per 4 x 4 block, the same
//! masks and floor), printed as Markdown and written as JSON.

use std::fmt::Write as _;
use std::path::Path;

use volfog_testkit::truth::compare::ErrorStats;
use volfog_testkit::truth::report::{Reference, SceneErrors};

/// One renderer's errors on one scene.
#[derive(Debug, Clone)]
pub struct TruthRow {
    /// The scene's name.
    pub scene: String,
    /// The renderer and its settings, e.g. "Bevy VolumetricFog, 64 steps".
    pub renderer: String,
    /// The errors against Mitsuba.
    pub errors: SceneErrors,
}

/// Mitsuba's noise of a scene: relative, of one pixel and of one 4 x 4 block.
#[derive(Debug, Clone, PartialEq)]
pub struct Noise {
    /// The scene's name.
    pub scene: String,
    /// One pixel's relative noise.
    pub pixel: f32,
    /// One block's.
    pub block: f32,
}

impl Noise {
    /// The noise measured with `reference`.
    pub fn of(reference: &Reference) -> Self {
        Self {
            scene: reference.scene.name.clone(),
            pixel: reference.noise.per_pixel,
            block: reference.block_noise,
        }
    }
}

fn pct(v: f32) -> String {
    format!("{:.1}", v * 100.0)
}

fn pair(s: &ErrorStats) -> String {
    format!("{} / {}", pct(s.mean), pct(s.p95))
}

/// The rows as a Markdown table: per scene and renderer, the mean / 95th percentile
/// relative error (per block) of the in-scattered radiance and of the transmittance,
/// the ratio of the renderer's mean radiance to Mitsuba's over the compared blocks,
/// and Mitsuba's own noise.
pub fn markdown(rows: &[TruthRow], noise: &[Noise]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| scene | renderer | radiance: mean / p95 % | transmittance: mean / p95 % | radiance / Mitsuba's | Mitsuba noise (pixel / block) % |"
    );
    let _ = writeln!(out, "| --- | --- | ---: | ---: | ---: | ---: |");
    for r in rows {
        let n = noise
            .iter()
            .find(|n| n.scene == r.scene)
            .map(|n| format!("{} / {}", pct(n.pixel), pct(n.block)))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.3} | {} |",
            r.scene,
            r.renderer,
            pair(&r.errors.radiance),
            pair(&r.errors.transmittance),
            r.errors.radiance_ratio,
            n
        );
    }
    out
}

/// The rows as JSON: `{ "adapters": [...], "spp": ..., "noise": [{scene, pixel,
/// block}], "rows": [{scene, renderer, errors}] }`, `errors` as
/// `volfog_testkit::truth::report::SceneErrors` serializes it (the shape of volfog's
/// rows in `volfog truth --out`).
pub fn json(adapters: &[String], spp: u32, rows: &[TruthRow], noise: &[Noise]) -> String {
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "scene": r.scene,
                "renderer": r.renderer,
                "errors": serde_json::to_value(r.errors).expect("the errors serialize"),
            })
        })
        .collect();
    let noise: Vec<serde_json::Value> = noise
        .iter()
        .map(|n| serde_json::json!({ "scene": n.scene, "pixel": n.pixel, "block": n.block }))
        .collect();
    let doc = serde_json::json!({
        "adapters": adapters,
        "spp": spp,
        "noise": noise,
        "rows": rows,
    });
    serde_json::to_string_pretty(&doc).expect("the report serializes")
}

/// Writes `text` to `path` through a file beside it renamed into place (never a
/// half-written file), creating the folder.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let partial = path.with_extension("partial");
    std::fs::write(&partial, text)?;
    std::fs::rename(&partial, path)
}

//! volfog against Mitsuba 3, scene by scene: the reference (two radiance renders with
//! different seeds, for Mitsuba's own noise, and the transmittance), volfog's images at
//! a chosen grid (the first frame's and the converged last frame's of a still camera,
//! [`volfog::render`]), the grid floor ([`floor`]) and the errors between them.
//!
//! Errors are relative, per block of [`BLOCK`] x [`BLOCK`] pixels, of the channel mean
//! (see [`compare::relative_error`]), over the blocks whose pixels are all away from
//! occluder silhouettes ([`compare::edge_mask`]) and reach [`FLOOR_FRACTION`] of the
//! image's mean radiance in the reference. Blocks, not pixels: a path tracer's noise
//! falls as the square root of the samples, and at [`SPP`] samples one pixel of these
//! scenes still carries a few percent of it, a block a quarter of that (the fog itself
//! varies little across 4 x 4 pixels; silhouettes are masked out). In scenes with a sun
//! and occluders the blocks whose rays cross a boundary of the sun's shadow
//! ([`compare::penumbra_mask`], [`PENUMBRA_WIDTH`]) are also reported apart from the
//! others.

use glam::{UVec3, Vec3};
use serde::Serialize;

use super::compare::{self, ErrorStats, channel_mean};
use super::floor;
use super::mitsuba::{self, MitsubaError, MitsubaOptions, NoiseEstimate};
use super::scene::{TruthImage, TruthScene};
use super::volfog::{self, TruthError, VolfogOptions};
use crate::Gpu;

/// Mitsuba's samples per pixel for the comparisons.
pub const SPP: u32 = 4096;

/// Pixels per side of the blocks compared.
pub const BLOCK: u32 = 4;

/// Reference pixels fainter than this fraction of the image's mean radiance are not
/// compared (their relative error says nothing; they also set the error's floor).
pub const FLOOR_FRACTION: f32 = 0.02;

/// A ray whose points lie within this distance (m) of a shadow boundary, across the
/// sun's direction, is in the penumbra.
pub const PENUMBRA_WIDTH: f32 = 0.75;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Mitsuba failed or is missing.
    #[error(transparent)]
    Mitsuba(#[from] MitsubaError),
    /// volfog's side failed.
    #[error(transparent)]
    Volfog(#[from] TruthError),
}

/// Mitsuba's rendering of a scene.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The scene.
    pub scene: TruthScene,
    /// Radiance (first seed) and transmittance.
    pub image: TruthImage,
    /// Mitsuba's own noise per pixel, from a second seed.
    pub noise: NoiseEstimate,
    /// Mitsuba's own noise per block ([`block_noise`]).
    pub block_noise: f32,
    /// Hit distance of each pixel's ray (infinity for none).
    pub depths: Vec<f32>,
    /// The pixels compared.
    pub mask: Vec<bool>,
    /// The pixels in the sun's penumbra (all false without a sun or occluders).
    pub penumbra: Vec<bool>,
    /// The error floor: [`FLOOR_FRACTION`] of the image's mean radiance.
    pub floor: f32,
}

impl Reference {
    /// Renders the scene in Mitsuba (`options.spp`, seeds `options.seed` and the next).
    pub fn render(scene: &TruthScene, options: &MitsubaOptions) -> Result<Self, ReportError> {
        let pair = mitsuba::render_noise(scene, options)?;
        let transmittance = mitsuba::render_transmittance(scene, options.seed)?;
        let noise = pair.noise();
        let block_noise = block_noise(&pair.first, &pair.second, pair.width, pair.height);
        let image = TruthImage {
            width: pair.width,
            height: pair.height,
            radiance: pair.first,
            transmittance,
        };
        let depths = volfog::pixel_depths(scene);
        let mean = image.radiance.iter().map(|v| channel_mean(*v)).sum::<f32>()
            / image.radiance.len().max(1) as f32;
        let floor = (FLOOR_FRACTION * mean).max(1e-12);
        let mask = compare::comparison_mask(scene, &depths, &image.radiance, floor);
        let penumbra = compare::penumbra_mask(scene, &depths, PENUMBRA_WIDTH);
        Ok(Self {
            scene: scene.clone(),
            image,
            noise,
            block_noise,
            depths,
            mask,
            penumbra,
            floor,
        })
    }

    /// Compares an image of the same scene with this reference, block by block.
    pub fn compare(&self, image: &TruthImage) -> SceneErrors {
        let (w, h) = (self.image.width, self.image.height);
        let test = blocks(&image.radiance, w, h);
        let reference = blocks(&self.image.radiance, w, h);
        let mask = block_mask(&self.mask, w, h);
        let penumbra = block_mask(&self.penumbra.iter().map(|p| !p).collect::<Vec<_>>(), w, h)
            .into_iter()
            .map(|clear| !clear)
            .collect::<Vec<_>>();
        let radiance = |keep: &dyn Fn(usize) -> bool| {
            let m: Vec<bool> = (0..mask.len()).map(|i| mask[i] && keep(i)).collect();
            compare::relative_error(&test, &reference, &m, self.floor)
        };
        let shadowed = penumbra.iter().any(|p| *p);
        let edges = block_mask(&compare::edge_mask(&self.scene, &self.depths), w, h);
        SceneErrors {
            radiance: radiance(&|_| true),
            outside_penumbra: shadowed.then(|| radiance(&|i| !penumbra[i])),
            inside_penumbra: shadowed.then(|| radiance(&|i| penumbra[i])),
            transmittance: compare::relative_error(
                &blocks(&image.transmittance, w, h),
                &blocks(&self.image.transmittance, w, h),
                &edges,
                1e-3,
            ),
            radiance_ratio: mean_ratio(&test, &reference, &mask),
        }
    }
}

/// The image averaged over blocks of [`BLOCK`] x [`BLOCK`] pixels (partial blocks at
/// the right and bottom edges dropped), row-major.
pub fn blocks(values: &[Vec3], width: u32, height: u32) -> Vec<Vec3> {
    let (bw, bh) = (width / BLOCK, height / BLOCK);
    let mut out = Vec::with_capacity((bw * bh) as usize);
    for by in 0..bh {
        for bx in 0..bw {
            let mut sum = Vec3::ZERO;
            for y in 0..BLOCK {
                for x in 0..BLOCK {
                    sum += values[((by * BLOCK + y) * width + bx * BLOCK + x) as usize];
                }
            }
            out.push(sum / (BLOCK * BLOCK) as f32);
        }
    }
    out
}

/// A per-pixel mask over blocks: a block is kept when all its pixels are.
pub fn block_mask(mask: &[bool], width: u32, height: u32) -> Vec<bool> {
    let (bw, bh) = (width / BLOCK, height / BLOCK);
    (0..bw * bh)
        .map(|b| {
            let (bx, by) = (b % bw, b / bw);
            (0..BLOCK * BLOCK).all(|k| {
                let (x, y) = (bx * BLOCK + k % BLOCK, by * BLOCK + k / BLOCK);
                mask[(y * width + x) as usize]
            })
        })
        .collect()
}

/// Mitsuba's noise in one block of one render: the standard deviation of the relative
/// difference of two seeds' blocks, over sqrt(2), over the blocks brighter than 5 % of
/// the image's mean.
pub fn block_noise(first: &[Vec3], second: &[Vec3], width: u32, height: u32) -> f32 {
    let a = blocks(first, width, height);
    let b = blocks(second, width, height);
    let mean = a.iter().map(|v| f64::from(channel_mean(*v))).sum::<f64>() / a.len().max(1) as f64;
    let rel: Vec<f64> = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (f64::from(channel_mean(*x)), f64::from(channel_mean(*y))))
        .filter(|(x, y)| (x + y) * 0.5 > 0.05 * mean)
        .map(|(x, y)| (x - y) / ((x + y) * 0.5))
        .collect();
    let n = rel.len().max(1) as f64;
    let m = rel.iter().sum::<f64>() / n;
    let var = rel.iter().map(|r| (r - m).powi(2)).sum::<f64>() / n;
    (var * 0.5).sqrt() as f32
}

/// The ratio of the mean radiance of `test` to that of `reference` over the mask: 1
/// when no light is missing or added overall.
fn mean_ratio(test: &[Vec3], reference: &[Vec3], mask: &[bool]) -> f32 {
    let sum = |img: &[Vec3]| -> f64 {
        img.iter()
            .zip(mask)
            .filter(|(_, m)| **m)
            .map(|(v, _)| f64::from(channel_mean(*v)))
            .sum()
    };
    let r = sum(reference);
    if r > 0.0 { (sum(test) / r) as f32 } else { 1.0 }
}

/// The errors of one image against its reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SceneErrors {
    /// In-scattered radiance over the compared pixels.
    #[serde(serialize_with = "stats_json")]
    pub radiance: ErrorStats,
    /// The same outside the sun's penumbra (scenes with a shadowed sun only).
    #[serde(serialize_with = "option_stats_json")]
    pub outside_penumbra: Option<ErrorStats>,
    /// The same inside the sun's penumbra (scenes with a shadowed sun only).
    #[serde(serialize_with = "option_stats_json")]
    pub inside_penumbra: Option<ErrorStats>,
    /// Transmittance from the eye to the first occluder, away from silhouettes.
    #[serde(serialize_with = "stats_json")]
    pub transmittance: ErrorStats,
    /// Mean radiance of volfog's image / the reference's over the compared pixels.
    pub radiance_ratio: f32,
}

fn stats_json<S: serde::Serializer>(s: &ErrorStats, ser: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = ser.serialize_struct("ErrorStats", 4)?;
    st.serialize_field("mean", &s.mean)?;
    st.serialize_field("p95", &s.p95)?;
    st.serialize_field("max", &s.max)?;
    st.serialize_field("pixels", &s.pixels)?;
    st.end()
}

fn option_stats_json<S: serde::Serializer>(
    s: &Option<ErrorStats>,
    ser: S,
) -> Result<S::Ok, S::Error> {
    match s {
        Some(s) => stats_json(s, ser),
        None => ser.serialize_none(),
    }
}

/// One row of the report: a scene at one grid under one configuration.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// The scene's name.
    pub scene: String,
    /// What the configuration is called in the table (e.g. "default").
    pub label: String,
    /// Froxels (x, y, slices).
    pub volume: [u32; 3],
    /// `FogConfig::light_transmittance`.
    pub light_transmittance: bool,
    /// Frames rendered.
    pub frames: u32,
    /// The errors of the last frame's image.
    pub converged: SceneErrors,
    /// The errors of the first frame's image.
    pub first: SceneErrors,
    /// The change of the radiance over the last jitter cycle: the relative difference,
    /// per compared block, between the last image and the one
    /// [`JITTER_CYCLE`](super::volfog::JITTER_CYCLE) frames before it (`None` with
    /// fewer frames).
    #[serde(serialize_with = "option_stats_json")]
    pub last_cycle: Option<ErrorStats>,
    /// The errors of the grid floor ([`super::floor`]), when computed.
    pub floor: Option<SceneErrors>,
}

/// Renders the scene with volfog under `options` and compares the first and the last
/// frame's images with the reference; `label` names the configuration. The grid floor
/// is left out ([`floor_errors`]).
pub fn row(
    gpu: &Gpu,
    reference: &Reference,
    label: &str,
    options: &VolfogOptions,
) -> Result<Row, ReportError> {
    let render = volfog::render(gpu, &reference.scene, options)?;
    let last_cycle = render.cycle_before.as_ref().map(|before| {
        let (w, h) = (reference.image.width, reference.image.height);
        let mask = block_mask(&reference.mask, w, h);
        compare::relative_error(
            &blocks(&render.converged.radiance, w, h),
            &blocks(&before.radiance, w, h),
            &mask,
            reference.floor,
        )
    });
    Ok(Row {
        scene: reference.scene.name.clone(),
        label: label.to_string(),
        volume: options.config.volume_size.to_array(),
        light_transmittance: options.config.light_transmittance,
        frames: render.frames,
        converged: reference.compare(&render.converged),
        first: reference.compare(&render.first),
        last_cycle,
        floor: None,
    })
}

/// The grid floor of the scene at `options`' grid ([`floor::grid_floor`]) compared
/// with the reference like volfog's images.
pub fn floor_errors(
    reference: &Reference,
    options: &VolfogOptions,
) -> Result<SceneErrors, ReportError> {
    let floor = floor::grid_floor(&reference.scene, options)?;
    Ok(reference.compare(&floor.image))
}

/// The grids of the report: the default's 128 slices, half and twice as many.
pub fn grids() -> [UVec3; 3] {
    let d = VolfogOptions::default().config.volume_size;
    [
        UVec3::new(d.x, d.y, d.z / 2),
        d,
        UVec3::new(d.x, d.y, d.z * 2),
    ]
}

/// The whole report: every scene at each grid under each named configuration, with
/// the grid floor, and Mitsuba's noise per scene.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The adapter volfog ran on.
    pub adapter: String,
    /// Mitsuba's samples per pixel.
    pub spp: u32,
    /// Mitsuba's noise per scene: (scene, relative noise of one pixel, of one block).
    pub noise: Vec<(String, f32, f32)>,
    /// Every comparison.
    pub rows: Vec<Row>,
}

/// Runs the report over `scenes`: at each grid of `grids`, each configuration of
/// `configurations` (a label and the options, whose grid is replaced) and the grid
/// floor (computed once per grid, with the first configuration's light transmittance
/// and scan step).
pub fn report(
    gpu: &Gpu,
    scenes: &[TruthScene],
    options: &MitsubaOptions,
    grids: &[UVec3],
    configurations: &[(String, VolfogOptions)],
) -> Result<Report, ReportError> {
    let mut rows = Vec::new();
    let mut noise = Vec::new();
    for scene in scenes {
        let reference = Reference::render(scene, options)?;
        noise.push((
            scene.name.clone(),
            reference.noise.per_pixel,
            reference.block_noise,
        ));
        for &volume_size in grids {
            let mut floor = None;
            for (label, base) in configurations {
                let o = base.clone().with_config(|c| c.volume_size = volume_size);
                if floor.is_none() {
                    floor = Some(floor_errors(&reference, &o)?);
                }
                rows.push(Row {
                    floor,
                    ..row(gpu, &reference, label, &o)?
                });
            }
        }
    }
    Ok(Report {
        adapter: gpu.describe(),
        spp: options.spp,
        noise,
        rows,
    })
}

/// The report as a Markdown table: per scene, grid and configuration the mean /
/// 95th-percentile relative error (per block) of the in-scattered radiance converged
/// (the last frame), after the first frame and of the grid floor, of the
/// transmittance, the change over the last jitter cycle, and Mitsuba's own noise.
pub fn markdown(report: &Report) -> String {
    use std::fmt::Write;
    let pct = |v: f32| format!("{:.1}", v * 100.0);
    let pair = |s: &ErrorStats| format!("{} / {}", pct(s.mean), pct(s.p95));
    let labels = report.rows.iter().any(|r| r.label != report.rows[0].label);
    let mut out = String::new();
    let filter = if labels { " filter |" } else { "" };
    let _ = writeln!(
        out,
        "| scene | slices |{filter} converged: mean / p95 % | first frame: mean / p95 % | grid floor: mean / p95 % | transmittance: mean / p95 % | last cycle's change: mean % | Mitsuba noise (pixel / block) % |"
    );
    let rule = if labels { " --- |" } else { "" };
    let _ = writeln!(
        out,
        "| --- | ---: |{rule} ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for r in &report.rows {
        let noise = report.noise.iter().find(|n| n.0 == r.scene);
        let label = if labels {
            format!(" {} |", r.label)
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "| {} | {} |{label} {} | {} | {} | {} | {} | {} |",
            r.scene,
            r.volume[2],
            pair(&r.converged.radiance),
            pair(&r.first.radiance),
            r.floor.map(|f| pair(&f.radiance)).unwrap_or_default(),
            pair(&r.converged.transmittance),
            r.last_cycle
                .map(|c| format!("{:.2}", c.mean * 100.0))
                .unwrap_or_default(),
            noise
                .map(|n| format!("{} / {}", pct(n.1), pct(n.2)))
                .unwrap_or_default(),
        );
    }
    out
}

//! The memory floor of the timed passes, so a reader sees how far each pass is from
//! it on any GPU: the bench's series sized by `volfog_cost::floor` (the textures each
//! pass's shader reads and writes, found in its composed naga module, and the bytes
//! they hold in the bench's configuration and dispatch, the live share of the volume
//! where the pass culls), and the time moving those bytes once takes at a stated
//! bandwidth, next to the measured median.
//!
//! It is a floor, not a prediction: each texture's bytes count once per direction, as
//! if the caches caught every re-read of a texel; storage and uniform buffers and
//! arithmetic are left out. A pass far above its floor on a GPU is bound by its
//! arithmetic or its latency, not by memory.

use naga::Module;
use serde::Serialize;
use volfog::options::cull_defines;
pub use volfog_cost::floor::{Sizes, TextureTraffic, TextureUse, texture_uses};

use super::*;

/// The bandwidths (TB/s) the floors are given at: a mid-range GPU and a large
/// data-centre GPU.
pub const BANDWIDTHS_TB_S: [f64; 2] = [0.9, 4.8];

/// The memory floor of one timed pass.
#[derive(Debug, Clone, Serialize)]
pub struct PassCost {
    /// The bench series it explains.
    pub series: &'static str,
    /// The shader variant and its entry points.
    pub shader: String,
    /// The textures it reads and writes.
    pub textures: Vec<TextureTraffic>,
    /// The render target's bytes read by blending (render passes).
    pub target_read_bytes: u64,
    /// The render target's bytes written (render passes).
    pub target_written_bytes: u64,
    /// Bytes read, each texture once.
    pub bytes_read: u64,
    /// Bytes written, each texture once.
    pub bytes_written: u64,
    /// The time moving them takes at each of [`BANDWIDTHS_TB_S`] (ms).
    pub floor_ms: Vec<f64>,
    /// The measured median (ms, the report's clock).
    pub measured_ms: f64,
    /// Measured / floor at each bandwidth.
    pub measured_vs_floor: Vec<f64>,
}

/// The floors of every pass the model covers, at [`BANDWIDTHS_TB_S`].
#[derive(Debug, Clone, Serialize)]
pub struct CostModel {
    /// The bandwidths (TB/s).
    pub bandwidths_tb_s: [f64; 2],
    /// One entry per timed pass.
    pub passes: Vec<PassCost>,
}

/// What the bench's passes read and write: its configuration behind the 1080p screen,
/// the culling passes covering `live_fraction` of the volume. The light cookies and
/// the local-light shadow atlas, which the bench's main scene leaves unused (its
/// shadowed lights are timed apart), count nothing.
pub fn sizes(config: &FogConfig, live_fraction: f64) -> Sizes {
    Sizes::new(config, SCREEN, live_fraction)
}

/// One pass the model covers: its series, its shader and how to size it.
struct Modelled {
    series: &'static str,
    label: String,
    module: Module,
    entries: &'static [&'static str],
    culled: bool,
    /// The render target's bytes read by blending and written.
    target: (u64, u64),
}

/// The floors of the bench's main passes, with their measured medians.
pub fn model(
    config: &FogConfig,
    sizes: &Sizes,
    medians: &dyn Fn(&str) -> f64,
) -> Result<CostModel, BenchError> {
    let compose = |pass: &str, defines: Vec<String>| -> Result<(String, Module), BenchError> {
        let name = volfog_codegen::manifest::variant_name(
            pass,
            &defines.iter().map(String::as_str).collect::<Vec<_>>(),
        );
        Ok((name, volfog::shaders::compose(pass, &defines)?))
    };
    let parse = |floor: volfog_cost::floor::FloorShader| -> Result<(String, Module), BenchError> {
        Ok((
            floor.path.to_string(),
            super::raymarch::compose(floor.source, floor.path, &[])?,
        ))
    };
    let [_, _, _, fast, separate] = variant_configs(config);
    let mut modelled = Vec::new();
    let mut add = |series, (label, module): (String, Module), entries, culled, target| {
        modelled.push(Modelled {
            series,
            label,
            module,
            entries,
            culled,
            target,
        })
    };
    add(
        "inject",
        compose("inject", config.inject_options().defines())?,
        &["inject"],
        false,
        (0, 0),
    );
    add(
        "inject_fast",
        compose("inject", fast.inject_options().defines())?,
        &["inject"],
        true,
        (0, 0),
    );
    add(
        "inject_fast_separate",
        compose("inject", separate.inject_options().defines())?,
        &["inject"],
        true,
        (0, 0),
    );
    add(
        "temporal",
        compose("temporal", cull_defines(false))?,
        &["temporal"],
        false,
        (0, 0),
    );
    add(
        "temporal_fast",
        compose("temporal", cull_defines(true))?,
        &["temporal"],
        true,
        (0, 0),
    );
    let scan = |cull: bool| {
        let mut defines = config.scan_step.defines();
        defines.extend(cull_defines(cull));
        compose("scan", defines)
    };
    add("scan", scan(false)?, &["scan"], false, (0, 0));
    add("scan_fast", scan(true)?, &["scan"], true, (0, 0));
    add(
        "cull",
        compose("froxel_cull", Vec::new())?,
        &["froxel_cull_cells", "froxel_cull", "froxel_cull_compact"],
        false,
        (0, 0),
    );
    add(
        "apply_1080p",
        compose("apply", config.apply_filtering.defines())?,
        &["apply_fs"],
        false,
        // The fog blends onto the colour target: read and written.
        (sizes.screen, sizes.screen),
    );
    add(
        "write",
        parse(volfog_cost::floor::WRITE)?,
        &["write_volume"],
        false,
        (0, 0),
    );
    add(
        "copy",
        parse(volfog_cost::floor::COPY)?,
        &["copy_volume"],
        false,
        (0, 0),
    );
    add(
        "blit_1080p",
        parse(volfog_cost::floor::BLIT)?,
        &["blit_fs"],
        false,
        (0, sizes.screen),
    );

    let passes = modelled
        .into_iter()
        .map(|m| {
            // The blit's source is a 1080p target.
            let blit = m.series == "blit_1080p";
            let bytes_of = |name: &str| {
                if blit && name == "source" {
                    sizes.screen
                } else {
                    sizes.of(name, m.culled)
                }
            };
            let t = volfog_cost::floor::traffic(&m.module, m.entries, &bytes_of, m.target);
            let floor_ms: Vec<f64> = BANDWIDTHS_TB_S
                .iter()
                .map(|tb| t.floor_ms(tb * 1e12))
                .collect();
            let measured_ms = medians(m.series);
            PassCost {
                series: m.series,
                shader: format!("{} ({})", m.label, m.entries.join(", ")),
                textures: t.textures,
                target_read_bytes: t.target_read_bytes,
                target_written_bytes: t.target_written_bytes,
                bytes_read: t.bytes_read,
                bytes_written: t.bytes_written,
                measured_vs_floor: floor_ms.iter().map(|f| measured_ms / f).collect(),
                floor_ms,
                measured_ms,
            }
        })
        .collect();
    Ok(CostModel {
        bandwidths_tb_s: BANDWIDTHS_TB_S,
        passes,
    })
}

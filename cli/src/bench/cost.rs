//! The memory floor of the timed passes, so a reader sees how far each pass is from
//! it on any GPU: the textures each pass's shader reads and writes, found in its
//! composed naga module (from the entry points through every function they call, a
//! texture passed as an argument followed back to its binding), the bytes those
//! textures hold in the bench's configuration and dispatch (the live share of the
//! volume where the pass culls), and the time moving those bytes once takes at a
//! stated bandwidth, next to the measured median.
//!
//! It is a floor, not a prediction: each texture's bytes count once per direction, as
//! if the caches caught every re-read of a texel (a trilinear sample's eight texels,
//! the scan's neighbouring slices); storage and uniform buffers (lights, local
//! volumes, uniforms: kilobytes) are left out, and so is arithmetic. A pass far above
//! its floor on a GPU is bound by its arithmetic or its latency, not by memory.

use std::collections::BTreeMap;

use naga::{Block, Expression, Function, GlobalVariable, Handle, Module, Statement};
use serde::Serialize;
use volfog::options::cull_defines;

use super::*;

/// The bandwidths (TB/s) the floors are given at: a mid-range GPU and a large
/// data-centre GPU.
pub const BANDWIDTHS_TB_S: [f64; 2] = [0.9, 4.8];

/// How a shader touches one texture binding: the places in the code that read it
/// (loads and samples) and write it (stores), each call of a function counting its
/// places again, a loop's body once.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct TextureUse {
    /// The binding's name in the WGSL.
    pub name: String,
    /// Places that load or sample it.
    pub read_sites: u32,
    /// Places that store to it.
    pub write_sites: u32,
}

/// The textures entry point `entry` of `module` reads or writes, by binding name.
pub fn texture_uses(module: &Module, entry: &str) -> Vec<TextureUse> {
    let mut uses: BTreeMap<Handle<GlobalVariable>, (u32, u32)> = BTreeMap::new();
    for e in module.entry_points.iter().filter(|e| e.name == entry) {
        walk(module, &e.function, &[], &mut uses);
    }
    uses.into_iter()
        .map(|(g, (read_sites, write_sites))| {
            let name = module.global_variables[g].name.clone().unwrap_or_default();
            let name = volfog_codegen::names::undecorate(&name).map_or(name, |(item, _)| item);
            TextureUse {
                name,
                read_sites,
                write_sites,
            }
        })
        .collect()
}

/// Adds the texture accesses of `function` (its texture arguments bound to `args`)
/// and of every function it calls.
fn walk(
    module: &Module,
    function: &Function,
    args: &[Option<Handle<GlobalVariable>>],
    uses: &mut BTreeMap<Handle<GlobalVariable>, (u32, u32)>,
) {
    let resolve = |e: Handle<Expression>| match function.expressions[e] {
        Expression::GlobalVariable(g) => Some(g),
        Expression::FunctionArgument(i) => args.get(i as usize).copied().flatten(),
        _ => None,
    };
    for (_, expression) in function.expressions.iter() {
        if let Expression::ImageLoad { image, .. } | Expression::ImageSample { image, .. } =
            expression
            && let Some(g) = resolve(*image)
        {
            uses.entry(g).or_default().0 += 1;
        }
    }
    let mut calls = Vec::new();
    statements(&function.body, &mut |s| match s {
        Statement::ImageStore { image, .. } => {
            if let Some(g) = resolve(*image) {
                uses.entry(g).or_default().1 += 1;
            }
        }
        Statement::Call {
            function: callee,
            arguments,
            ..
        } => calls.push((
            *callee,
            arguments.iter().map(|a| resolve(*a)).collect::<Vec<_>>(),
        )),
        _ => {}
    });
    for (callee, bound) in calls {
        walk(module, &module.functions[callee], &bound, uses);
    }
}

/// Visits every statement of a block and of the blocks nested in it.
fn statements(block: &Block, visit: &mut dyn FnMut(&Statement)) {
    for s in block.iter() {
        visit(s);
        match s {
            Statement::Block(b) => statements(b, visit),
            Statement::If { accept, reject, .. } => {
                statements(accept, visit);
                statements(reject, visit);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                statements(body, visit);
                statements(continuing, visit);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    statements(&c.body, visit);
                }
            }
            _ => {}
        }
    }
}

/// One texture's traffic in a pass.
#[derive(Debug, Clone, Serialize)]
pub struct TextureTraffic {
    /// How the shader touches it.
    #[serde(flatten)]
    pub uses: TextureUse,
    /// The bytes it holds that the dispatch covers (read once if read, written once
    /// if written).
    pub bytes: u64,
}

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

/// What the bench's passes read and write, sized for its configuration. The light
/// cookies and the local-light shadow atlas, which the bench's main scene leaves
/// unused (its shadowed lights are timed apart), count nothing.
pub struct Sizes {
    /// One volume of the bench (rgba16float), bytes.
    volume: u64,
    /// The share of the volume the culling passes cover.
    live_fraction: f64,
    /// The live-slice texture (r32uint per column).
    live: u64,
    /// The filtered ESM (r32float, one layer per cascade).
    esm: u64,
    /// The baked noise texture.
    noise: u64,
    /// The 1080p depth buffer (Depth32Float).
    depth: u64,
    /// A 1080p rgba16float target.
    screen: u64,
}

impl Sizes {
    /// The sizes for the bench configuration `config`, whose culling passes cover
    /// `live_fraction` of the volume.
    pub fn new(config: &FogConfig, live_fraction: f64) -> Self {
        let v = config.volume_size;
        let pixels = u64::from(SCREEN.0) * u64::from(SCREEN.1);
        Self {
            volume: u64::from(v.x) * u64::from(v.y) * u64::from(v.z) * 8,
            live_fraction,
            live: u64::from(v.x) * u64::from(v.y) * 4,
            esm: u64::from(config.esm_resolution).pow(2) * u64::from(config.cascades) * 4,
            noise: u64::from(volfog::cpu::noise::NOISE_TEXTURE_SIZE).pow(3) * 8,
            depth: pixels * 4,
            screen: pixels * 8,
        }
    }

    /// The bytes of binding `name` the pass's dispatch covers (`culled`: it runs over
    /// the live blocks only).
    fn of(&self, name: &str, culled: bool) -> u64 {
        let share = |bytes: u64| {
            if culled {
                (bytes as f64 * self.live_fraction).round() as u64
            } else {
                bytes
            }
        };
        match name {
            "scattering" | "integrated" | "current" | "history" | "stabilised" | "destination"
            | "fog_integrated" => share(self.volume),
            "source" if !culled => self.volume,
            "live_slices" | "history_live_slices" => self.live,
            "esm_array" => self.esm,
            "noise_texture" => self.noise,
            "scene_depth" => self.depth,
            _ => 0,
        }
    }
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
    let parse = |file: &'static str, source: &str| -> Result<(String, Module), BenchError> {
        Ok((
            file.to_string(),
            super::raymarch::compose(source, file, &[])?,
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
        parse("write.wgsl", include_str!("write.wgsl"))?,
        &["write_volume"],
        false,
        (0, 0),
    );
    add(
        "copy",
        parse("copy.wgsl", include_str!("copy.wgsl"))?,
        &["copy_volume"],
        false,
        (0, 0),
    );
    add(
        "blit_1080p",
        parse("blit.wgsl", include_str!("blit.wgsl"))?,
        &["blit_fs"],
        false,
        (0, sizes.screen),
    );

    let passes = modelled
        .into_iter()
        .map(|m| {
            let mut merged: BTreeMap<String, TextureUse> = BTreeMap::new();
            for entry in m.entries {
                for u in texture_uses(&m.module, entry) {
                    let slot = merged.entry(u.name.clone()).or_insert_with(|| TextureUse {
                        name: u.name.clone(),
                        ..TextureUse::default()
                    });
                    slot.read_sites += u.read_sites;
                    slot.write_sites += u.write_sites;
                }
            }
            let textures: Vec<TextureTraffic> = merged
                .into_values()
                .map(|uses| {
                    // The blit's source is a 1080p target.
                    let bytes = if m.series == "blit_1080p" && uses.name == "source" {
                        sizes.screen
                    } else {
                        sizes.of(&uses.name, m.culled)
                    };
                    TextureTraffic { uses, bytes }
                })
                .collect();
            let sum = |pick: &dyn Fn(&TextureUse) -> bool| -> u64 {
                textures
                    .iter()
                    .filter(|t| pick(&t.uses))
                    .map(|t| t.bytes)
                    .sum()
            };
            let bytes_read = sum(&|u| u.read_sites > 0) + m.target.0;
            let bytes_written = sum(&|u| u.write_sites > 0) + m.target.1;
            let total = (bytes_read + bytes_written) as f64;
            let floor_ms: Vec<f64> = BANDWIDTHS_TB_S
                .iter()
                .map(|tb| total / (tb * 1e12) * 1e3)
                .collect();
            let measured_ms = medians(m.series);
            PassCost {
                series: m.series,
                shader: format!("{} ({})", m.label, m.entries.join(", ")),
                textures,
                target_read_bytes: m.target.0,
                target_written_bytes: m.target.1,
                bytes_read,
                bytes_written,
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

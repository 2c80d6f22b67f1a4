//! Both fogs of `fog_bench`'s scene on volfog's GPU model (`volfog_cost`, the model of
//! `volfog gpu-cost`): each pipeline compiled by Mesa's RADV (ACO) on its null device
//! for bonaire (GCN2), navi21 (RDNA2) and gfx1100 (RDNA3), its loops counted by their
//! trip counts in the scene, against its memory floor, on the Xbox One, RX 6800 XT
//! and RX 7900 XTX models.
//!
//! - Bevy's `VolumetricFog`: one draw of the fog shader over the screen (the camera is
//!   inside the fog volume, so Bevy draws its plane hull: every pixel), with the
//!   trips of [`crate::trips`]; its floor is the depth buffer, the sun's shadow
//!   texture array and the colour target it blends onto (read and written).
//! - volfog: the passes of one frame of the plugin's `FogConfig` for the scene
//!   (`volfog_cost::frame::frame_passes`), over the workload of the scene's froxels,
//!   lights, volumes and depth (`volfog_cost::workload`), as `volfog gpu-cost` models
//!   its bench scene.

use std::fmt::Write as _;

use serde::Serialize;
use volfog::cpu::froxel::live_slices_from_depth;
use volfog::options::ShadowFilter;
use volfog::pipeline::FogConfig;
use volfog::uniforms::Froxels;
use volfog_bevy::ExtractedFroxelFog;
use volfog_codegen::manifest::{Blend, BlendComponent, RenderState, VertexAttribute, VertexBuffer};
use volfog_cost::floor::{Sizes, texture_uses};
use volfog_cost::frame::{FramePass, RuntimeVariant, frame_passes};
use volfog_cost::measure::{PassModel, Shader, measure_with_checks, model_pass};
use volfog_cost::pipeline::{RuntimeChecks, job_with_checks};
use volfog_cost::worker::Worker;
use volfog_cost::workload::{SceneFrame, Workload};
use volfog_cost::{Chip, CostError, GpuModel, MODELS, ShaderStats};

use crate::capture::BevyFog;
use crate::trips::{BevyTrips, Depth};

/// The name of Bevy's fog shader in the report.
pub const BEVY_FOG: &str = "bevy_pbr::volumetric_fog";

const HULL_ATTRIBUTES: [VertexAttribute; 1] = [VertexAttribute {
    shader_location: 0,
    format: "float32x3",
    offset: 0,
}];
const HULL_BUFFERS: [VertexBuffer; 1] = [VertexBuffer {
    array_stride: 32,
    step_mode: "vertex",
    attributes: &HULL_ATTRIBUTES,
}];

/// The draw state of Bevy 0.20.1's fog pipeline
/// (`bevy_pbr-0.20.1/src/volumetric_fog/render.rs`, `specialize`): the shader's own
/// vertex entry point over the hull mesh's positions (Bevy's plane and cube meshes:
/// position, normal and uv, 32 bytes a vertex), back faces culled, the `Hdr` camera's
/// colour target, premultiplied "over" blending of the colour, the alpha kept.
/// [`check_state`] holds the captured pipeline to it.
pub const BEVY_FOG_STATE: RenderState = RenderState {
    vertex: None,
    formats: &["rgba16float"],
    blend: Some(Blend {
        color: BlendComponent {
            src_factor: "one",
            dst_factor: "one-minus-src-alpha",
            operation: "add",
        },
        alpha: BlendComponent {
            src_factor: "zero",
            dst_factor: "one",
            operation: "add",
        },
    }),
    vertex_buffers: &HULL_BUFFERS,
    topology: "triangle-list",
    front_face: "ccw",
    cull_mode: "back",
};

type Error = Box<dyn std::error::Error>;

/// Checks that the captured pipeline draws as [`BEVY_FOG_STATE`] says.
pub fn check_state(fog: &BevyFog) -> Result<(), Error> {
    let s = BEVY_FOG_STATE;
    let blend = s.blend.expect("the state blends");
    let pair = |c: BlendComponent| (c.src_factor.to_string(), c.dst_factor.to_string());
    let expected = (
        u64::from(s.vertex_buffers[0].array_stride),
        (0, s.vertex_buffers[0].attributes[0].format.to_string()),
        s.formats[0].to_string(),
        (pair(blend.color), pair(blend.alpha)),
    );
    let got = (
        fog.vertex_stride,
        fog.vertex_attribute.clone(),
        fog.target_format.clone(),
        fog.blend.clone(),
    );
    if got != expected {
        return Err(
            format!("Bevy's fog pipeline draws as {got:?}, the model as {expected:?}").into(),
        );
    }
    Ok(())
}

/// What the model compiles and counts.
pub struct Plan {
    /// Bevy's pass and shader.
    pub bevy: (FramePass, Shader),
    /// The same pass with the loop over a cluster's point and spot lights counted at
    /// the volumetric lights only. The loop runs every light of the cluster, but skips
    /// the others once it has read their flags, and ACO's static weights charge each
    /// iteration most of a light's evaluation: [`Plan::bevy`] overstates that loop
    /// where its lights are not volumetric (none is in `fog_bench`'s scene), this
    /// understates it (the skipped iterations' reads are left out). The two bound
    /// Bevy's time; the target is judged on this one.
    pub bevy_lower: FramePass,
    /// volfog's frame: its configuration, workload and passes.
    pub config: FogConfig,
    pub workload: Workload,
    pub volfog: Vec<(FramePass, Shader)>,
}

/// The trip count of each loop of Bevy's fog shader (by its label in naga's IR,
/// through calls: `volfog_cost::loops`), from the scene's counts. `lit_only` counts
/// the loop over a cluster's point and spot lights at the volumetric lights that reach
/// each step only (see [`Plan::bevy_lower`]).
fn bevy_loop_trips(
    labels: &[String],
    t: &BevyTrips,
    lit_only: bool,
) -> Result<Vec<(String, f64)>, Error> {
    labels
        .iter()
        .map(|label| {
            let (function, condition) = label.split_once(": ").unwrap_or(("", label));
            let trips = match condition {
                c if c.starts_with("plane_index < 6") => 6.0,
                c if c.starts_with("light_index < directional_light_count") => t.directional_lights,
                "step < step_count" => t.sun_steps,
                "step < step_count #2" => t.light_steps,
                // Over the light's `num_cascades`.
                _ if function.ends_with("get_cascade_index") => t.cascade_search,
                // Up to the cluster's first rect light (field 2 of its ranges).
                c if c.starts_with("i < clusterable_object_index_ranges") => {
                    if lit_only { t.volumetric_reaching } else { t.cluster_lights }
                }
                _ => {
                    return Err(format!(
                        "Bevy's fog shader has a loop the model does not know: {label} (its loops: {labels:?})"
                    )
                    .into());
                }
            };
            Ok((label.clone(), trips))
        })
        .collect()
}

/// volfog's workload in the scene: the plugin's froxels over `depth`'s screen.
fn volfog_workload(e: &ExtractedFroxelFog, depth: &Depth) -> Result<(FogConfig, Workload), Error> {
    let config = e.config.clone();
    let froxels = Froxels::new(
        e.clip_from_view,
        config.volume_size,
        config.near,
        config.far,
        config.slice_curve,
    )?;
    let live = live_slices_from_depth(&froxels, &depth.ndc, depth.width, depth.height);
    let shadowed: Vec<u32> = e.light_shadows.iter().map(|s| s.light).collect();
    let frame = SceneFrame {
        froxels: &froxels,
        world_from_view: e.view_from_world.inverse(),
        lights: &e.lights,
        shadowed_lights: &shadowed,
        local_volumes: &e.volumes,
        cascades: (e.cascades.splits, e.cascades.count),
        live_slices: config.depth_cull.then_some(live.as_slice()),
        screen: (depth.width, depth.height),
        far_tail: e.tail.density > 0.0,
        shadow_taps: match config.shadow_filter {
            ShadowFilter::Compare { taps } => taps,
            ShadowFilter::Esm => 1,
        },
    };
    // Inject's workgroups: 64 invocations with the checkerboard, else 128 (as
    // `volfog gpu-cost` sizes its bench frame).
    let workload = Workload::of(&frame, if config.amortize { 64 } else { 128 });
    Ok((config, workload))
}

/// The plan of the scene: Bevy's pass with its trips, volfog's frame.
pub fn plan(
    fog: &BevyFog,
    trips: &BevyTrips,
    volfog: &ExtractedFroxelFog,
    depth: &Depth,
) -> Result<Plan, Error> {
    check_state(fog)?;
    let module = naga::front::wgsl::parse_str(&fog.wgsl)
        .map_err(|e| format!("Bevy's fog shader: {}", e.emit_to_string(&fog.wgsl)))?;
    let shader = Shader {
        label: format!("{BEVY_FOG}.fragment"),
        module,
        entry: "fragment".to_string(),
        render: Some(BEVY_FOG_STATE),
    };
    let unshared =
        volfog_cost::loops::unshare(&shader.module, "fragment").ok_or("no fragment entry point")?;
    let labels: Vec<String> = volfog_cost::loops::loops(&unshared, "fragment")
        .ok_or("no fragment entry point")?
        .into_iter()
        .map(|l| l.label)
        .collect();
    let pixels = u64::from(fog.screen.0) * u64::from(fog.screen.1);
    let (w, h, layers, texel) = fog.shadow_texture;
    let shadow_bytes = u64::from(w) * u64::from(h) * u64::from(layers) * u64::from(texel);
    // The textures the fragment reads: the depth buffer (Depth32Float), the sun's
    // shadow cascades; the point lights' cube maps only where a light casts shadows
    // (none here: their branch never runs, so they move no bytes).
    let point_shadow_bytes = if fog.lights.iter().any(|l| l.shadows) {
        return Err("the model reads no point or spot shadow map: a light casts shadows".into());
    } else {
        0
    };
    let mut binding_bytes = Vec::new();
    for u in texture_uses(&shader.module, "fragment") {
        let bytes = match u.name.as_str() {
            n if n.ends_with("depth_texture") => pixels * 4,
            n if n.ends_with("directional_shadow_textures") => shadow_bytes,
            n if n.ends_with("point_shadow_textures") => point_shadow_bytes,
            other => return Err(format!("the model does not size Bevy's texture {other}").into()),
        };
        binding_bytes.push((u.name, bytes));
    }
    if fog.density_texture {
        return Err("the model draws the fog without a density texture".into());
    }
    let bevy_pass = FramePass {
        name: format!("Bevy VolumetricFog, {} steps per pixel", fog.step_count),
        ac4: None,
        variant: RuntimeVariant::new(
            BEVY_FOG,
            fog.shader_defs.clone(),
            "fog_bench's scene, Bevy 0.20.1",
        ),
        entry: "fragment".to_string(),
        invocations: pixels as f64,
        culled: false,
        // Rgba16Float, blended: read and written once.
        target: (pixels * 8, pixels * 8),
        binding_bytes,
        trips: bevy_loop_trips(&labels, trips, false)?,
    };
    let bevy_lower = FramePass {
        name: format!("{}, only volumetric lights' iterations", bevy_pass.name),
        trips: bevy_loop_trips(&labels, trips, true)?,
        ..bevy_pass.clone()
    };
    let (config, workload) = volfog_workload(volfog, depth)?;
    let volfog = frame_passes(&config, &workload)
        .into_iter()
        .map(|p| {
            let shader = Shader::of_variant(p.variant.pass, &p.variant.defines, &p.entry)?;
            Ok((p, shader))
        })
        .collect::<Result<_, CostError>>()?;
    Ok(Plan {
        bevy: (bevy_pass, shader),
        bevy_lower,
        config,
        workload,
        volfog,
    })
}

/// One of Bevy's fog pipelines in the scene as one chip's compiler saw it.
#[derive(Debug, Clone, Serialize)]
pub struct PipelineCompiled {
    /// The chip.
    pub chip: Chip,
    /// The pipeline's shader defs.
    pub shader_defs: Vec<String>,
    /// Its statistics (both stages: the fragment shader's registers and cycles).
    pub stats: ShaderStats,
}

/// Compiles every fog pipeline of the capture on `chips` as Bevy creates it (draw
/// state [`BEVY_FOG_STATE`], no runtime checks), one worker per chip, without its
/// loops taken out. Errors when Bevy queued none, when Bevy did not create one, when
/// one's target format or vertex stride is not [`BEVY_FOG_STATE`]'s or when a chip's
/// compiler rejects one.
pub fn compile_pipelines(
    worker: &Worker,
    chips: &[Chip],
    fog: &BevyFog,
) -> Result<Vec<PipelineCompiled>, Error> {
    if fog.pipelines.is_empty() {
        return Err("Bevy queued no fog pipeline".into());
    }
    let mut jobs = Vec::new();
    for (i, p) in fog.pipelines.iter().enumerate() {
        if !p.created {
            return Err(format!("Bevy did not create its fog pipeline {:?}", p.shader_defs).into());
        }
        let state = (p.target_format.as_str(), p.vertex_stride);
        let expected = (
            BEVY_FOG_STATE.formats[0],
            u64::from(BEVY_FOG_STATE.vertex_buffers[0].array_stride),
        );
        if state != expected {
            return Err(format!(
                "Bevy's fog pipeline {:?} draws to {} with a vertex stride of {}, the model as {expected:?}",
                p.shader_defs, state.0, state.1
            )
            .into());
        }
        let module = naga::front::wgsl::parse_str(&p.wgsl)
            .map_err(|e| format!("Bevy's fog shader: {}", e.emit_to_string(&p.wgsl)))?;
        let label = format!("{BEVY_FOG}#{i}.fragment");
        jobs.push(job_with_checks(
            &label,
            &module,
            "fragment",
            Some(&BEVY_FOG_STATE),
            false,
            RuntimeChecks::Unchecked,
        )?);
    }
    let mut out = Vec::new();
    for chip_results in worker.compile_chips(chips, &jobs)? {
        for (p, compiled) in fog.pipelines.iter().zip(&chip_results.results) {
            out.push(PipelineCompiled {
                chip: chip_results.chip,
                shader_defs: p.shader_defs.clone(),
                stats: ShaderStats::of_compiled(chip_results.chip, compiled)?,
            });
        }
    }
    Ok(out)
}

/// Both fogs on one GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// The model.
    pub gpu: GpuModel,
    /// Bevy's fog pass, and the same with only volumetric lights' iterations
    /// ([`Plan::bevy_lower`]).
    pub bevy: PassModel,
    pub bevy_lower: PassModel,
    /// volfog's passes and their total (ms).
    pub volfog: Vec<PassModel>,
    pub volfog_ms: f64,
    /// Bevy's time over volfog's, of each.
    pub ratio: f64,
    pub ratio_lower: f64,
}

/// Compiles both fogs on `chips` (a worker process per chip) and models them on the
/// GPU models of those chips.
pub fn compare(worker: &Worker, chips: &[Chip], plan: &Plan) -> Result<Vec<Comparison>, Error> {
    let mut shaders = vec![plan.bevy.1.clone()];
    for (_, s) in &plan.volfog {
        if !shaders.iter().any(|k| k.label == s.label) {
            shaders.push(s.clone());
        }
    }
    // Bevy creates its shader modules trusted (`RenderDevice::create_shader_module`,
    // `bevy_render-0.20.1/src/renderer/render_device.rs`): no runtime checks; volfog's
    // runtime creates its own checked.
    let bevy_label = plan.bevy.1.label.clone();
    let measured = measure_with_checks(worker, chips, &shaders, |s| {
        if s.label == bevy_label {
            RuntimeChecks::Unchecked
        } else {
            RuntimeChecks::Checked
        }
    })?;
    let sizes = Sizes::new(
        &plan.config,
        plan.workload.screen,
        plan.workload.live_fraction,
    );
    let mut out = Vec::new();
    for gpu in MODELS.iter().filter(|m| chips.contains(&m.chip)) {
        let on = &measured[&gpu.chip];
        let model = |(pass, shader): &(FramePass, Shader)| -> Result<PassModel, Error> {
            let m = on.get(&shader.label).ok_or("a shader was not measured")?;
            Ok(model_pass(m, shader, pass, gpu, &sizes)?)
        };
        let bevy = model(&plan.bevy)?;
        let bevy_lower = model(&(plan.bevy_lower.clone(), plan.bevy.1.clone()))?;
        let volfog: Vec<PassModel> = plan.volfog.iter().map(model).collect::<Result<_, _>>()?;
        let volfog_ms: f64 = volfog.iter().map(|m| m.estimate.ms).sum();
        out.push(Comparison {
            gpu: gpu.clone(),
            ratio: bevy.estimate.ms / volfog_ms,
            ratio_lower: bevy_lower.estimate.ms / volfog_ms,
            bevy,
            bevy_lower,
            volfog,
            volfog_ms,
        });
    }
    Ok(out)
}

fn ms(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

fn row(out: &mut String, m: &PassModel) {
    let (s, c, e) = (&m.stats, &m.corrected, &m.estimate);
    let bound = if e.memory_bound {
        "memory".to_string()
    } else if e.latency_bound {
        format!("latency ({} waves)", s.waves_per_simd)
    } else {
        "issue".to_string()
    };
    let _ = writeln!(
        out,
        "| {} | {} | {} / {} | {} | {:.0} | {:.0} | {} | {} | {} | {} |",
        m.pass.name,
        s.vgprs,
        s.spilled_vgprs,
        s.spilled_sgprs,
        s.instructions,
        c.aco_latency,
        c.latency,
        ms(e.alu_ms),
        ms(e.memory_ms),
        ms(e.ms),
        bound
    );
}

/// The comparison as Markdown tables.
pub fn table(plan: &Plan, trips: &BevyTrips, rows: &[Comparison]) -> String {
    let mut out = String::new();
    let w = &plan.workload;
    let g = plan.config.volume_size;
    let _ = writeln!(
        out,
        "fog_bench's scene at {}x{}: Bevy's VolumetricFog ({} of {} waves march; per wave {:.2} directional lights, \
         {:.1} + {:.1} steps, {:.2} cascade steps and {:.2} cluster lights per step, {:.2} lights reach the step, \
         {:.2} of them volumetric) \
         beside volfog's frame at {}x{}x{} ({:.1} % of the froxels live, {:.2} lights per block)",
        w.screen.0,
        w.screen.1,
        trips.marching_waves,
        trips.waves,
        trips.directional_lights,
        trips.sun_steps,
        trips.light_steps,
        trips.cascade_search,
        trips.cluster_lights,
        trips.lights_reaching,
        trips.volumetric_reaching,
        g.x,
        g.y,
        g.z,
        100.0 * w.live_fraction,
        w.lights_per_block,
    );
    for c in rows {
        let _ = writeln!(
            out,
            "\n## {} ({}, {})\n\n| pass | VGPRs | spilled VGPRs / SGPRs | instructions | ACO latency | latency, loops by trip count | ALU ms | memory ms | estimate ms | bound |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |",
            c.gpu.name,
            c.gpu.chip.family(),
            c.gpu.chip.generation()
        );
        row(&mut out, &c.bevy);
        row(&mut out, &c.bevy_lower);
        for m in &c.volfog {
            row(&mut out, m);
        }
        let _ = writeln!(
            out,
            "| **volfog, froxel pipeline** | | | | | | | | **{}** | |\n\nBevy / volfog: {:.1}x ({:.1}x with only the volumetric lights' iterations)",
            ms(c.volfog_ms),
            c.ratio,
            c.ratio_lower
        );
    }
    out
}

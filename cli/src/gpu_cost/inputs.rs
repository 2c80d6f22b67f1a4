//! What `volfog gpu-cost` compiles and models: the configurations whose pipelines it
//! lists, the bench scene's frame as the passes see it, and the passes beside the
//! froxel pipeline on the same model (the bench's per-pixel raymarch, the floors).

use glam::{Mat4, UVec3, Vec3};
use volfog::cpu::esm::esm_cascade;
use volfog::cpu::froxel::{live_slices_from_depth, ndc_from_uv, view_from_ndc};
use volfog::cpu::stereo::{StereoEye, centre_eye};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, cascade_splits};
use volfog::uniforms::Froxels;
use volfog_codegen::manifest::{FOG_BLEND, RenderState};
use volfog_cost::frame::{FramePass, RuntimeVariant};
use volfog_cost::measure::Shader;
use volfog_cost::workload::{SceneFrame, Workload};

use crate::bench::raymarch::{RAYMARCH_PATH, RAYMARCH_STEPS, Raymarch, RaymarchOptions};
use crate::bench::scene::Scene;
use crate::bench::workloads::{base_config, variant_configs};

use super::GpuCostError;

/// The screen the bench renders at (1080p), which the model applies the fog to.
pub const SCREEN: (u32, u32) = (1920, 1080);
/// The eyes' distance in the bench's stereo comparison (m).
pub const STEREO_IPD: f32 = 0.064;
/// Wronski's grid in Assassin's Creed IV.
pub const WRONSKI_GRID: UVec3 = UVec3::new(160, 90, 64);

/// The configurations whose pipelines are listed: the default, the bench's (its
/// baseline and the cheap-path variants it times), the demo's and stereo fog's of the
/// default configuration ([`STEREO_DEFAULT`]).
pub fn configs() -> Vec<(String, FogConfig)> {
    let base = base_config();
    let names = [
        "bench: culling",
        "bench: checkerboard",
        "bench: noise texture",
        "bench: cheap path",
        "bench: cheap path, temporal apart",
    ];
    let mut list = vec![
        ("default".to_string(), FogConfig::default()),
        ("bench: baseline".to_string(), base.clone()),
    ];
    list.extend(
        names
            .iter()
            .zip(variant_configs(&base))
            .map(|(n, c)| (n.to_string(), c)),
    );
    let demo = <DemoCli as clap::Parser>::parse_from(["demo", "--out", "."]);
    list.push(("demo".to_string(), crate::demo::fog_config(&demo.args)));
    list.push((STEREO_DEFAULT.to_string(), FogConfig::default()));
    list
}

/// The name in [`configs`] of stereo fog (`StereoFog`) of the default configuration:
/// its pipelines are those of [`volfog_cost::stereo::stereo_variants`] and the multiview
/// apply's ([`volfog_cost::stereo_multiview::multiview_apply_variants`]).
pub const STEREO_DEFAULT: &str = "stereo: default";

/// Whether the configuration named `name` in [`configs`] is stereo fog's.
pub fn is_stereo(name: &str) -> bool {
    name.starts_with("stereo")
}

/// The demo's arguments at their defaults.
#[derive(clap::Parser)]
struct DemoCli {
    #[command(flatten)]
    args: crate::demo::DemoArgs,
}

/// The draw state of a fullscreen pass with its own vertex shader.
fn fullscreen(blend: bool) -> RenderState {
    RenderState {
        vertex: None,
        formats: &["rgba16float"],
        blend: blend.then_some(FOG_BLEND),
        vertex_buffers: &[],
        topology: "triangle-list",
        front_face: "ccw",
        cull_mode: "none",
    }
}

/// The bench scene's camera and the froxels of `config` over it.
fn froxels(scene: &Scene, config: &FogConfig) -> Result<Froxels, GpuCostError> {
    Ok(Froxels::new(
        scene.projection,
        config.volume_size,
        config.near,
        config.far,
        config.slice_curve,
    )?)
}

/// The bench scene's frame for `config`, as the passes see it (its 1080p depth
/// culls the froxels when the configuration culls).
pub fn workload(
    scene: &Scene,
    depth: &[f32],
    config: &FogConfig,
) -> Result<Workload, GpuCostError> {
    let froxels = froxels(scene, config)?;
    let live = live_slices_from_depth(&froxels, depth, SCREEN.0, SCREEN.1);
    Ok(workload_of(
        scene,
        &froxels,
        scene.view.inverse(),
        config,
        config.depth_cull.then_some(live.as_slice()),
    ))
}

/// The eyes of the bench's stereo comparison: the scene's camera split into two eyes
/// [`STEREO_IPD`] apart, each with the scene's projection.
pub fn stereo_eyes(scene: &Scene) -> [StereoEye; 2] {
    let world_from_head = scene.view.inverse();
    [-0.5f32, 0.5].map(|side| StereoEye {
        view_from_world: (world_from_head
            * Mat4::from_translation(Vec3::new(side * STEREO_IPD, 0.0, 0.0)))
        .inverse(),
        clip_from_view: scene.projection,
    })
}

/// The bench scene's frame as stereo fog's shared volume sees it: the froxels of the
/// centre eye of [`stereo_eyes`] (its frustum encloses both eyes', its slices shifted
/// by the apex's offset, as `StereoFog::prepare` places them), without culling.
pub fn stereo_workload(scene: &Scene, config: &FogConfig) -> Result<Workload, GpuCostError> {
    let centre = centre_eye(&stereo_eyes(scene))?;
    let froxels = Froxels::new(
        centre.clip_from_view,
        config.volume_size,
        config.near + centre.apex_offset,
        config.far + centre.apex_offset,
        config.slice_curve,
    )?;
    let config = FogConfig {
        near: config.near + centre.apex_offset,
        far: config.far + centre.apex_offset,
        ..volfog_cost::stereo::stereo_config(config)
    };
    Ok(workload_of(
        scene,
        &froxels,
        centre.view_from_world.inverse(),
        &config,
        None,
    ))
}

/// The frame of `froxels` placed by `world_from_view` in the bench scene, `live_slices`
/// culling it.
fn workload_of(
    scene: &Scene,
    froxels: &Froxels,
    world_from_view: Mat4,
    config: &FogConfig,
    live_slices: Option<&[u32]>,
) -> Workload {
    let splits = cascade_splits(config.cascades, config.near, config.far, 0.75);
    let frame = SceneFrame {
        froxels,
        world_from_view,
        lights: &scene.lights,
        shadowed_lights: &[],
        local_volumes: &scene.local_volumes,
        cascades: (splits, config.cascades),
        live_slices,
        screen: SCREEN,
        far_tail: false,
        // The compare filter's taps per froxel with history (the camera stands still,
        // so every froxel has one); the ESM reads one value.
        shadow_taps: match config.shadow_filter {
            ShadowFilter::Compare { taps } => taps,
            ShadowFilter::Esm => 1,
        },
    };
    Workload::of(&frame, if config.amortize { 64 } else { 128 })
}

/// Mean over the pixels (one per 8 x 8 block) of the cascade search's steps per
/// raymarch sample: the ray from the near plane to the scene or the far plane in
/// `steps` equal steps.
fn raymarch_cascade_steps(scene: &Scene, depth: &[f32], config: &FogConfig, steps: u32) -> f64 {
    let view_from_clip = scene.projection.inverse();
    let splits = cascade_splits(config.cascades, config.near, config.far, 0.75);
    let (mut sum, mut n) = (0.0, 0.0);
    for py in (4..SCREEN.1).step_by(8) {
        for px in (4..SCREEN.0).step_by(8) {
            let uv = glam::Vec2::new(
                (px as f32 + 0.5) / SCREEN.0 as f32,
                (py as f32 + 0.5) / SCREEN.1 as f32,
            );
            let ndc = ndc_from_uv(uv);
            let d = depth[(py * SCREEN.0 + px) as usize];
            let end = view_from_ndc(Vec3::new(ndc.x, ndc.y, d), view_from_clip)
                .z
                .abs()
                .min(config.far);
            if end <= config.near {
                continue;
            }
            let dz = (end - config.near) / steps as f32;
            let total: u32 = (0..steps)
                .map(|i| {
                    let z = config.near + (i as f32 + 0.5) * dz;
                    esm_cascade(z, splits, config.cascades)
                })
                .sum();
            sum += f64::from(total) / f64::from(steps);
            n += 1.0;
        }
    }
    if n > 0.0 { sum / n } else { 0.0 }
}

/// The bench's per-pixel raymarch (64 steps, 1080p) of `config`'s medium as a pass of
/// the model, and its shader.
pub fn raymarch(
    scene: &Scene,
    depth: &[f32],
    config: &FogConfig,
) -> Result<(FramePass, Shader), GpuCostError> {
    let options = RaymarchOptions {
        steps: RAYMARCH_STEPS,
        noise_octaves: config.noise_octaves,
        color_format: wgpu::TextureFormat::Rgba16Float,
        max_lights: config.max_lights,
        max_local_volumes: config.max_local_volumes,
    };
    let module = Raymarch::module(&options).map_err(|e| GpuCostError::Shader(e.to_string()))?;
    let pixels = f64::from(SCREEN.0) * f64::from(SCREEN.1);
    let target = u64::from(SCREEN.0) * u64::from(SCREEN.1) * 8;
    let pass = FramePass {
        name: format!("raymarch, {RAYMARCH_STEPS} steps per pixel"),
        ac4: None,
        variant: RuntimeVariant::new(RAYMARCH_PATH, Vec::new(), "the bench's per-pixel reference"),
        entry: "raymarch_fs".to_string(),
        invocations: pixels,
        culled: false,
        target: (target, target),
        binding_bytes: Vec::new(),
        trips: vec![
            (
                "raymarch_fs: i < STEPS".to_string(),
                f64::from(RAYMARCH_STEPS),
            ),
            (
                "raymarch_fs: v < volume_count".to_string(),
                scene.local_volumes.len() as f64,
            ),
            (
                "raymarch_fs: l < light_count".to_string(),
                scene.lights.len() as f64,
            ),
            (
                "esm_cascade:".to_string(),
                raymarch_cascade_steps(scene, depth, config, RAYMARCH_STEPS),
            ),
        ],
    };
    let shader = Shader {
        label: format!("{RAYMARCH_PATH}.raymarch_fs"),
        module,
        entry: "raymarch_fs".to_string(),
        render: Some(fullscreen(true)),
    };
    Ok((pass, shader))
}

/// The floors on the model: a plain write of the volume with inject's dispatch, a
/// plain copy with the scan's, a 1080p blit; and their shaders.
pub fn floors(config: &FogConfig) -> Result<Vec<(FramePass, Shader)>, GpuCostError> {
    let v = config.volume_size;
    let round = |n: u32, g: u32| f64::from(n.div_ceil(g) * g);
    let pixels = f64::from(SCREEN.0) * f64::from(SCREEN.1);
    let screen_bytes = u64::from(SCREEN.0) * u64::from(SCREEN.1) * 8;
    let list = [
        (
            volfog_cost::floor::WRITE,
            "floor: write of the volume",
            round(v.x, 4) * round(v.y, 4) * round(v.z, 4),
            (0, 0),
            Vec::new(),
            None,
        ),
        (
            volfog_cost::floor::COPY,
            "floor: copy of the volume",
            round(v.x, 8) * round(v.y, 8),
            (0, 0),
            vec![("copy_volume: k < ".to_string(), f64::from(v.z))],
            None,
        ),
        (
            volfog_cost::floor::BLIT,
            "floor: 1080p blit",
            pixels,
            (0, screen_bytes),
            Vec::new(),
            Some(fullscreen(false)),
        ),
    ];
    list.into_iter()
        .map(|(floor, name, invocations, target, trips, render)| {
            let module = volfog_cost::floor::compose(floor.source, floor.path, &[])
                .map_err(GpuCostError::Shader)?;
            Ok((
                FramePass {
                    name: name.to_string(),
                    ac4: None,
                    variant: RuntimeVariant::new(floor.path, Vec::new(), "the bench's floors"),
                    entry: floor.entry.to_string(),
                    invocations,
                    culled: false,
                    target,
                    // The blit's source is a texture of the screen's size.
                    binding_bytes: if floor == volfog_cost::floor::BLIT {
                        vec![("source".to_string(), screen_bytes)]
                    } else {
                        Vec::new()
                    },
                    trips,
                },
                Shader {
                    label: format!("{}.{}", floor.path, floor.entry),
                    module,
                    entry: floor.entry.to_string(),
                    render,
                },
            ))
        })
        .collect()
}

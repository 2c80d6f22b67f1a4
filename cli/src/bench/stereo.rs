//! Stereo fog over the bench scene (`StereoFog`): the scene's camera split into two
//! eyes 64 mm apart, each with a 1920x1080 view, against one mono fog (the left eye's
//! camera) and against two mono fogs (one per eye, what stereo costs without sharing).
//! Each measured frame submits six command buffers alone, the order rotating from frame
//! to frame: each of the three with its applies (one per eye view) and without them
//! (the fog's passes alone). All three fogs have the baseline's configuration (stereo
//! fog culls no froxels by depth, and neither does the baseline). The figures are the
//! wall time from submitting a whole frame to its completion, on every adapter: the
//! eyes' scans and applies carry no timestamps of their own.

use super::*;
use glam::{Mat4, Vec3};
use volfog::cpu::stereo::StereoEye;
use volfog::pipeline::StereoFog;

/// The eyes' distance (m), a typical interpupillary distance.
const IPD: f32 = 0.064;
/// Target: stereo / one mono view (the whole frame, the applies included).
const TARGET_STEREO: f64 = 1.6;

/// The six workloads of a frame, in the order of [`StereoSamples`].
const KINDS: usize = 6;

/// The three fogs and the eyes' targets.
pub(super) struct StereoBench {
    eyes: [StereoEye; 2],
    mono: [VolumetricFog; 2],
    stereo: StereoFog,
    apply: ApplyPipeline,
    depth_group: wgpu::BindGroup,
    target: wgpu::Texture,
    layers: [wgpu::TextureView; 2],
}

/// One frame's wall times (ms).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct StereoSamples {
    mono: f64,
    two_mono: f64,
    stereo: f64,
    mono_fog: f64,
    two_mono_fog: f64,
    stereo_fog: f64,
}

impl StereoBench {
    /// The fogs of the baseline configuration with the scene's shadow map, the eyes
    /// from the scene's camera, a two-layer 1920x1080 target, the scene's depth for
    /// both eyes (the apply's cost does not depend on what the depth holds).
    pub(super) fn new(gpu: &Gpu, config: &FogConfig, scene: &Scene) -> Result<Self, BenchError> {
        let (_, layers) = scene.cascades(config);
        let side = config.esm_resolution * 4;
        let refs: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
        let shadow = volfog_testkit::selfcheck::depth_array_texture(gpu, side, side, &refs)?;
        let world_from_head = scene.view.inverse();
        let eyes = [-0.5f32, 0.5].map(|side| StereoEye {
            view_from_world: (world_from_head
                * Mat4::from_translation(Vec3::new(side * IPD, 0.0, 0.0)))
            .inverse(),
            clip_from_view: scene.projection,
        });
        let mono = [0, 1].map(|_| VolumetricFog::new(&gpu.device, config));
        let [a, b] = mono;
        let mut mono = [a?, b?];
        for fog in &mut mono {
            fog.set_shadow_map(&gpu.device, &shadow)?;
        }
        let mut stereo = StereoFog::new(&gpu.device, config)?;
        stereo.shared_mut().set_shadow_map(&gpu.device, &shadow)?;
        let apply = mono[0].create_apply(&gpu.device, COLOR_FORMAT)?;
        let depth = Screen::scene_depth(gpu, scene, SCREEN)?;
        let depth_group = apply.depth_bind_group(&gpu.device, &depth_view(&depth));
        let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("bench stereo target"),
            size: wgpu::Extent3d {
                width: SCREEN.0,
                height: SCREEN.1,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let layers = [0, 1].map(|layer| {
            target.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        });
        Ok(Self {
            eyes,
            mono,
            stereo,
            apply,
            depth_group,
            target,
            layers,
        })
    }

    /// Prepares frame `f` of `scene` in every fog and times its six workloads.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
        f: u32,
    ) -> Result<StereoSamples, BenchError> {
        let inputs = scene.inputs(f as f32 / 60.0, cascades);
        for (fog, eye) in self.mono.iter_mut().zip(&self.eyes) {
            fog.prepare(
                &gpu.queue,
                &volfog::pipeline::FrameInputs {
                    view_from_world: eye.view_from_world,
                    clip_from_view: eye.clip_from_view,
                    ..inputs.clone()
                },
            )?;
        }
        self.stereo.prepare(&gpu.queue, &self.eyes, &inputs)?;
        let mut times = [0.0; KINDS];
        for k in 0..KINDS {
            let which = (k + f as usize) % KINDS;
            let with_apply = which < 3;
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            match which % 3 {
                0 | 1 => {
                    let fogs = if which.is_multiple_of(3) { 1 } else { 2 };
                    for (fog, layer) in self.mono.iter().zip(&self.layers).take(fogs) {
                        fog.encode(&mut encoder)?;
                        if with_apply {
                            fog.record_apply(&mut encoder, &self.apply, layer, &self.depth_group)?;
                        }
                    }
                }
                _ => {
                    self.stereo.encode(&mut encoder)?;
                    if with_apply {
                        let depth = [&self.depth_group, &self.depth_group];
                        self.stereo
                            .record_apply(&mut encoder, &self.apply, &self.target, depth)?;
                    }
                }
            }
            times[which] = submit_and_wait(gpu, encoder.finish())?;
        }
        let [mono, two_mono, stereo, mono_fog, two_mono_fog, stereo_fog] = times;
        Ok(StereoSamples {
            mono,
            two_mono,
            stereo,
            mono_fog,
            two_mono_fog,
            stereo_fog,
        })
    }

    /// Runs the plan's frames; the figures from the measured ones.
    pub(super) fn run(
        &mut self,
        gpu: &Gpu,
        plan: &Plan,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
    ) -> Result<StereoCost, BenchError> {
        let mut measured = Vec::new();
        for f in 0..plan.warmup + plan.frames {
            let s = self.frame(gpu, scene, cascades, f)?;
            eprintln!(
                "stereo frame {}/{}: mono {:.1} ms, two mono {:.1} ms, stereo {:.1} ms",
                f + 1,
                plan.warmup + plan.frames,
                s.mono,
                s.two_mono,
                s.stereo
            );
            if plan.frame(f).0 {
                measured.push(s);
            }
        }
        Ok(stereo_cost(&measured))
    }
}

/// The median of a series.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// What stereo fog costs in the run.
#[derive(Debug, Clone, Serialize)]
pub struct StereoCost {
    /// How the figures were taken.
    pub clock: &'static str,
    /// Each eye's view (pixels).
    pub eye_view: [u32; 2],
    /// The eyes' distance (m).
    pub ipd_m: f32,
    /// Median whole frame of one mono fog, its apply included (ms).
    pub mono_ms: f64,
    /// The same for two mono fogs, one per eye.
    pub two_mono_ms: f64,
    /// The same for stereo fog, both eyes' applies included.
    pub stereo_ms: f64,
    /// Median fog passes alone of one mono fog (ms).
    pub mono_fog_ms: f64,
    /// The same for two mono fogs.
    pub two_mono_fog_ms: f64,
    /// The same for stereo fog (shared passes and both eyes' scans).
    pub stereo_fog_ms: f64,
    /// Per frame, stereo / one mono, applies included: median.
    pub stereo_vs_mono: f64,
    /// Per frame, two mono / one mono, applies included: median.
    pub two_mono_vs_mono: f64,
    /// Per frame, stereo / two mono, applies included: median.
    pub stereo_vs_two_mono: f64,
    /// Per frame, stereo / one mono, fog passes alone: median.
    pub stereo_fog_vs_mono: f64,
    /// Per frame, two mono / one mono, fog passes alone: median.
    pub two_mono_fog_vs_mono: f64,
    /// The target of stereo / one mono (applies included).
    pub target: f64,
    /// Whether the run met it.
    pub met: bool,
}

fn stereo_cost(s: &[StereoSamples]) -> StereoCost {
    let series = |f: fn(&StereoSamples) -> f64| median(s.iter().map(f).collect());
    let stereo_vs_mono = series(|s| s.stereo / s.mono);
    StereoCost {
        clock: "wall time from submitting a whole frame alone to its completion",
        eye_view: [SCREEN.0, SCREEN.1],
        ipd_m: IPD,
        mono_ms: series(|s| s.mono),
        two_mono_ms: series(|s| s.two_mono),
        stereo_ms: series(|s| s.stereo),
        mono_fog_ms: series(|s| s.mono_fog),
        two_mono_fog_ms: series(|s| s.two_mono_fog),
        stereo_fog_ms: series(|s| s.stereo_fog),
        stereo_vs_mono,
        two_mono_vs_mono: series(|s| s.two_mono / s.mono),
        stereo_vs_two_mono: series(|s| s.stereo / s.two_mono),
        stereo_fog_vs_mono: series(|s| s.stereo_fog / s.mono_fog),
        two_mono_fog_vs_mono: series(|s| s.two_mono_fog / s.mono_fog),
        target: TARGET_STEREO,
        met: stereo_vs_mono <= TARGET_STEREO,
    }
}

/// Stereo fog's lines of the table.
pub(super) fn stereo_table(out: &mut String, s: &StereoCost) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "\nstereo fog (two {}x{} eye views {} mm apart; {}):\n  \
         whole frame: mono {:.1} ms, two mono {:.1} ms (x{:.2}), stereo {:.1} ms (x{:.2} \
         mono, <= {} {}; x{:.2} two mono)\n  \
         fog passes alone: mono {:.1} ms, two mono {:.1} ms (x{:.2}), stereo {:.1} ms (x{:.2})",
        s.eye_view[0],
        s.eye_view[1],
        s.ipd_m * 1000.0,
        s.clock,
        s.mono_ms,
        s.two_mono_ms,
        s.two_mono_vs_mono,
        s.stereo_ms,
        s.stereo_vs_mono,
        s.target,
        status(s.met),
        s.stereo_vs_two_mono,
        s.mono_fog_ms,
        s.two_mono_fog_ms,
        s.two_mono_fog_vs_mono,
        s.stereo_fog_ms,
        s.stereo_fog_vs_mono,
    );
}

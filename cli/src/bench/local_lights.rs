//! Shadowed point and spot lights over the bench scene: the same frame with six lights
//! (four spot, two point) lit unshadowed and shadowed through the local-light ESM
//! atlas (`ShadowFilter::Esm`), their depth maps ray cast from the scene's ground,
//! pillars and lintels, and lit by an inject compiled without local shadows; shadowed
//! with their maps unchanged from frame to frame (`ShadowedLight::map_unchanged`: the
//! atlas keeps its layers); and unshadowed and shadowed under the compare filter (the
//! default), which tests the same depth maps in inject and has no atlas.

use super::*;
use glam::Vec3;
use volfog::options::ShadowFilter;
use volfog::pipeline::{FrameInputs, LocalShadowStats, ShadowedLight};
use volfog::uniforms::{FogLight, LightCamera};

/// Depth-map texels per atlas texel (the atlas pass's downsample factor).
pub(super) const MAP_FACTOR: u32 = 4;
/// Near plane of the lights' shadow cameras (m).
const SHADOW_NEAR: f32 = 0.1;
/// Depth bias of the shadowed lights (m).
const SHADOW_BIAS: f32 = 0.05;

/// The six lights: two point lights in the aisle between the pillar rows, whose
/// pillars and lintels cast shadows outward through the fog, and four spot lights
/// outside the colonnade shining into the aisle past a pillar each.
pub(super) fn lights() -> Vec<FogLight> {
    let mut lights = Vec::new();
    for (x, z) in [
        (-10.0f32, -15.0f32),
        (10.0, -24.0),
        (-10.0, -33.0),
        (10.0, -42.0),
    ] {
        let position = Vec3::new(x, 7.0, z);
        lights.push(FogLight::spot(
            position,
            Vec3::new(0.0, 1.0, z) - position,
            Vec3::new(60.0, 48.0, 32.0),
            18.0,
            0.3,
            0.45,
        ));
    }
    for (z, color) in [
        (-10.5, Vec3::new(10.0, 28.0, 40.0)),
        (-28.5, Vec3::new(40.0, 16.0, 8.0)),
    ] {
        lights.push(FogLight::point(Vec3::new(0.0, 3.0, z), color, 10.0));
    }
    lights
}

/// What was set up, for the report.
#[derive(Debug, Clone, Copy)]
pub(super) struct LocalLightSetup {
    /// Texels per side of the lights' depth maps.
    pub(super) map_size: u32,
    /// Texels per side of the atlas maps.
    pub(super) atlas_size: u32,
    /// Bytes of the lights' depth maps (the caller's, not the fog's).
    pub(super) map_bytes: u64,
    /// Bytes the atlas adds to the fog (`memory_bytes` with it minus without).
    pub(super) atlas_bytes: u64,
    /// Bytes the compare filter's shadowed lights add to the fog (the same difference).
    pub(super) compare_bytes: u64,
    /// What the shadowed frame's lights got.
    pub(super) stats: LocalShadowStats,
    /// What the frame with unchanged maps got.
    pub(super) kept_stats: LocalShadowStats,
    /// [`LocalLights::light_through_shadows`] after the measured frames, ESM filter.
    pub(super) light_through_shadows: f64,
    /// The same, compare filter.
    pub(super) compare_light_through_shadows: f64,
}

/// Samples of one frame of [`LocalLights`].
pub(super) struct LocalLightSamples {
    /// Inject of the six lights unshadowed.
    pub(super) inject_unshadowed: Sample,
    /// Inject of the six lights without local shadows compiled in.
    pub(super) inject_compiled_out: Sample,
    /// Inject of the six lights shadowed.
    pub(super) inject_shadowed: Sample,
    /// The atlas pass (downsample and blur of the frame's layers).
    pub(super) atlas: Sample,
    /// Inject of the six lights shadowed, their maps unchanged.
    pub(super) inject_kept: Sample,
    /// The atlas pass of that frame (its layers kept: nothing to fill).
    pub(super) atlas_kept: Sample,
    /// Inject of the six lights unshadowed, compare filter.
    pub(super) compare_unshadowed: Sample,
    /// Inject of the six lights shadowed, compare filter.
    pub(super) compare_shadowed: Sample,
}

/// Six fogs of the bench's baseline configuration over the main screen. Four with the
/// ESM filter: one lighting the six lights unshadowed, one shadowing them through its
/// atlas, one with `FogConfig::local_shadows` `None` (inject compiled without local
/// shadows), and one shadowing them with their maps unchanged since its first frame;
/// and two with the compare filter, lighting them unshadowed and shadowed.
pub(super) struct LocalLights {
    lights: Vec<FogLight>,
    shadowed_lights: Vec<ShadowedLight>,
    kept_lights: Vec<ShadowedLight>,
    unshadowed: Screen,
    shadowed: Screen,
    compiled_out: Screen,
    kept: Screen,
    compare_unshadowed: Screen,
    compare_shadowed: Screen,
    /// Whether `kept`'s atlas holds the lights' maps (filled once, untimed, before its
    /// first frame).
    primed: bool,
    pub(super) setup: LocalLightSetup,
}

impl LocalLights {
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        scene: &Scene,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        let local = config.local_shadows.unwrap_or_default();
        let map_size = MAP_FACTOR * local.resolution;
        let lights = lights();
        let (mut spot_layers, mut point_layers) = (Vec::new(), Vec::new());
        let mut shadowed_lights = Vec::new();
        for (i, light) in lights.iter().enumerate() {
            let point = light.cos_outer <= -1.0;
            let camera = if point {
                LightCamera::point(light, SHADOW_NEAR)?
            } else {
                LightCamera::spot(light, SHADOW_NEAR)?
            };
            let layers = if point {
                &mut point_layers
            } else {
                &mut spot_layers
            };
            let map = (layers.len() / if point { 6 } else { 1 }) as u32;
            layers.extend(scene.light_depth(&camera, map_size));
            shadowed_lights.push(ShadowedLight {
                bias: SHADOW_BIAS,
                ..ShadowedLight::new(i as u32, camera).with_shadow(map)
            });
        }
        let texture = |layers: &[Vec<f32>]| {
            let slices: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
            volfog_testkit::selfcheck::depth_array_texture(gpu, map_size, map_size, &slices)
        };
        let (spot_maps, point_maps) = (texture(&spot_layers)?, texture(&point_layers)?);
        let esm = with_filter(config, ShadowFilter::Esm);
        let unshadowed = Screen::new(gpu, &esm, shadow_map, depth, SCREEN)?;
        let without = FogConfig {
            local_shadows: None,
            ..esm.clone()
        };
        let compiled_out = Screen::new(gpu, &without, shadow_map, depth, SCREEN)?;
        let shadowed_screen = |config: &FogConfig| {
            let mut screen = Screen::new(gpu, config, shadow_map, depth, SCREEN)?;
            screen.fog.set_spot_shadow_maps(&gpu.device, &spot_maps)?;
            screen.fog.set_point_shadow_maps(&gpu.device, &point_maps)?;
            Ok::<_, BenchError>(screen)
        };
        let shadowed = shadowed_screen(&esm)?;
        let kept = shadowed_screen(&esm)?;
        let compare = with_filter(config, ShadowFilter::default());
        let compare_unshadowed = Screen::new(gpu, &compare, shadow_map, depth, SCREEN)?;
        let compare_shadowed = shadowed_screen(&compare)?;
        let kept_lights = shadowed_lights
            .iter()
            .map(|s| s.with_unchanged_map())
            .collect();
        let map_bytes =
            4 * u64::from(map_size * map_size) * (spot_layers.len() + point_layers.len()) as u64;
        let atlas_bytes = shadowed.fog.memory_bytes() - unshadowed.fog.memory_bytes();
        let compare_bytes =
            compare_shadowed.fog.memory_bytes() - compare_unshadowed.fog.memory_bytes();
        Ok(Self {
            lights,
            shadowed_lights,
            kept_lights,
            unshadowed,
            shadowed,
            compiled_out,
            kept,
            compare_unshadowed,
            compare_shadowed,
            primed: false,
            setup: LocalLightSetup {
                map_size,
                atlas_size: local.resolution,
                map_bytes,
                atlas_bytes,
                compare_bytes,
                stats: LocalShadowStats::default(),
                kept_stats: LocalShadowStats::default(),
                light_through_shadows: f64::NAN,
                compare_light_through_shadows: f64::NAN,
            },
        })
    }

    /// Frame `f` of the six fogs over the scene's `inputs` with the six lights in
    /// place of the scene's (rotating which runs first so that drift cancels).
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        inputs: &FrameInputs<'_>,
        f: u32,
    ) -> Result<LocalLightSamples, BenchError> {
        let unshadowed = FrameInputs {
            lights: &self.lights,
            shadowed_lights: &[],
            ..inputs.clone()
        };
        let shadowed = FrameInputs {
            shadowed_lights: &self.shadowed_lights,
            ..unshadowed.clone()
        };
        self.unshadowed.fog.prepare(&gpu.queue, &unshadowed)?;
        self.shadowed.fog.prepare(&gpu.queue, &shadowed)?;
        self.compiled_out.fog.prepare(&gpu.queue, &unshadowed)?;
        self.compare_unshadowed
            .fog
            .prepare(&gpu.queue, &unshadowed)?;
        self.compare_shadowed.fog.prepare(&gpu.queue, &shadowed)?;
        if !self.primed {
            // The static lamps' maps were filtered in an earlier frame.
            self.kept.fog.prepare(&gpu.queue, &shadowed)?;
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            self.kept
                .fog
                .encode_pass(&mut encoder, FogPass::LocalShadows)?;
            submit_and_wait(gpu, encoder.finish())?;
            self.primed = true;
        }
        let kept = FrameInputs {
            shadowed_lights: &self.kept_lights,
            ..unshadowed.clone()
        };
        self.kept.fog.prepare(&gpu.queue, &kept)?;
        self.setup.stats = self.shadowed.fog.local_shadow_stats();
        self.setup.kept_stats = self.kept.fog.local_shadow_stats();
        let screens = [
            &mut self.unshadowed,
            &mut self.shadowed,
            &mut self.compiled_out,
            &mut self.kept,
            &mut self.compare_unshadowed,
            &mut self.compare_shadowed,
        ];
        let n = screens.len();
        let mut timings = [(PassTimings::default(), PassTimings::default()); 6];
        for k in 0..n {
            let which = (k + f as usize) % n;
            timings[which] = screens[which].frame(gpu)?;
        }
        let [u, s, c, k, cu, cs] = timings;
        let both = |pick: fn(&PassTimings) -> f64, t: &(PassTimings, PassTimings)| Sample {
            gpu: pick(&t.0),
            cpu: pick(&t.1),
        };
        Ok(LocalLightSamples {
            inject_unshadowed: both(|p| p.inject, &u),
            inject_compiled_out: both(|p| p.inject, &c),
            inject_shadowed: both(|p| p.inject, &s),
            atlas: both(|p| p.local_shadows, &s),
            inject_kept: both(|p| p.inject, &k),
            atlas_kept: both(|p| p.local_shadows, &k),
            compare_unshadowed: both(|p| p.inject, &cu),
            compare_shadowed: both(|p| p.inject, &cs),
        })
    }

    /// The six lights' in-scattering through their shadows: `inputs` with the sun,
    /// the ambient light and the emission off, inject alone (after the atlas pass), the
    /// scattering volume of the shadowed fog (rgb summed over every froxel) over the
    /// unshadowed one's, under the ESM filter and the compare filter (one frame's
    /// taps). Run after the measured frames: it prepares a frame of its own.
    pub(super) fn light_through_shadows(
        &mut self,
        gpu: &Gpu,
        inputs: &FrameInputs<'_>,
    ) -> Result<[f64; 2], BenchError> {
        let unshadowed = FrameInputs {
            medium: volfog::uniforms::FogMedium {
                emission: Vec3::ZERO,
                ..inputs.medium
            },
            sun: volfog::uniforms::DirectionalLight {
                color: Vec3::ZERO,
                ..inputs.sun
            },
            ambient: volfog::cpu::ambient::AmbientSh::constant(Vec3::ZERO),
            lights: &self.lights,
            shadowed_lights: &[],
            ..inputs.clone()
        };
        let shadowed = FrameInputs {
            shadowed_lights: &self.shadowed_lights,
            ..unshadowed.clone()
        };
        let total = |screen: &mut Screen, inputs: &FrameInputs<'_>| {
            screen.fog.prepare(&gpu.queue, inputs)?;
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            screen
                .fog
                .encode_pass(&mut encoder, FogPass::LocalShadows)?;
            screen.fog.encode_pass(&mut encoder, FogPass::Inject)?;
            submit_and_wait(gpu, encoder.finish())?;
            let volume = gpu.read_texture_rgba16f(screen.fog.scattering_texture())?;
            Ok::<f64, BenchError>(volume.iter().map(|v| f64::from(v.x + v.y + v.z)).sum())
        };
        Ok([
            total(&mut self.shadowed, &shadowed)? / total(&mut self.unshadowed, &unshadowed)?,
            total(&mut self.compare_shadowed, &shadowed)?
                / total(&mut self.compare_unshadowed, &unshadowed)?,
        ])
    }
}

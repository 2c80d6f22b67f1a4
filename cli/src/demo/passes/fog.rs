//! The fog wired to the demo's passes: the demo's `FogConfig`, and `Demo`, which
//! creates once and holds the adapter, the scene, the fog pipeline and its apply
//! pass, the sky, the clouds, the lamp's shadow camera and the demo's renderer.

use glam::{Mat4, Vec4};
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::clouds::{CloudPasses, cloud_map_texture};
use volfog::pipeline::sky::SkyLight;
use volfog::pipeline::{
    FogConfig, LocalShadowConfig, ShadowedLight, VolumetricFog, cascade_splits,
};
use volfog::uniforms::{FrustumRays, LightCamera};
use volfog_testkit::Gpu;

use super::{HDR_FORMAT, Renderer};
use crate::demo::scene::{self, FAR, FOV_Y, LampYard, NEAR};
use crate::demo::{DemoArgs, DemoError};

/// Texels per side of the lamp's cube shadow map, per atlas texel.
const LAMP_SHADOW_FACTOR: u32 = 2;

/// The fog configuration of the demo. The fog reads the sun's shadow map (2048 texels
/// per cascade) and the lamp's cube shadow map (512 texels per face) through the
/// compare filter, the default, so the shafts through the doorway and the arch keep
/// the occluders' edges. The ESM settings are those the demo would take with
/// `ShadowFilter::Esm`: 512 texels per cascade with a 3-tap blur (an exponential
/// shadow map erodes occluders by its filter footprint, and the pillars must keep
/// their shadows in the farther cascades), exponent 200 in log space (a leak band of
/// 1.5 % of a cascade's depth range), the lamp's atlas 256 texels per face.
pub(crate) fn fog_config(args: &DemoArgs, timestamps: bool) -> FogConfig {
    FogConfig {
        volume_size: args.volume,
        near: 0.5,
        far: 128.0,
        slice_curve: 4.0,
        esm_resolution: 512,
        cascades: 4,
        esm_exponent: 200.0,
        esm_log_space: true,
        esm_blur_radius: 1,
        max_lights: 8,
        max_local_volumes: 4,
        max_particles: scene::PUFFS as u32,
        noise_octaves: 2,
        cloud_shadow: true,
        shadow_filter: args.shadow_filter,
        timestamps,
        local_shadows: Some(LocalShadowConfig {
            spot_shadows: 0,
            point_shadows: 1,
            resolution: 256,
            exponent: 200.0,
        }),
        ..FogConfig::default()
    }
}

/// Everything the demo holds while it renders.
pub struct Demo<'a> {
    pub args: &'a DemoArgs,
    pub gpu: Gpu,
    pub scene: scene::Scene,
    pub config: FogConfig,
    pub fog: VolumetricFog,
    pub renderer: Renderer,
    pub apply: ApplyPipeline,
    pub depth_group: wgpu::BindGroup,
    pub clip_from_view: Mat4,
    pub splits: Vec4,
    /// Copies of the HDR target before and after the apply (with `--probe`).
    pub probe_textures: Option<[wgpu::Texture; 3]>,
    /// The sky light, solved once for the scene's sun.
    pub sky: SkyLight,
    /// The cloud passes (shadow on the lit scene, distance clouds), their map and bind
    /// group.
    pub clouds: CloudPasses,
    pub cloud_group: wgpu::BindGroup,
    /// The lamp's cube shadow camera (what its shadow map is rendered with).
    pub lamp_camera: LightCamera,
    /// The lamp as the fog's one shadowed light (its cube 0 of the point shadow maps).
    pub shadowed_lights: [ShadowedLight; 1],
}

impl<'a> Demo<'a> {
    /// Creates everything the demo renders with and solves the sky.
    pub fn new(args: &'a DemoArgs) -> Result<Self, DemoError> {
        let gpu = Gpu::with_features(wgpu::Features::TIMESTAMP_QUERY)?;
        let timestamps = gpu
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY);
        println!("adapter: {}", gpu.describe());
        println!(
            "rendering {}x{}, {} frames, froxel volume {}x{}x{}{}",
            args.width,
            args.height,
            args.frames,
            args.volume.x,
            args.volume.y,
            args.volume.z,
            if timestamps {
                ""
            } else {
                " (no TIMESTAMP_QUERY: no GPU times)"
            }
        );
        let scene = scene::build()?;
        let config = fog_config(args, timestamps);
        let lamp_light = scene.lamp.light;
        let lamp_camera = LampYard::camera(&scene.lights[lamp_light as usize])?;
        let lamp_size = config.local_shadows.map_or(256, |l| l.resolution) * LAMP_SHADOW_FACTOR;
        let mut fog = VolumetricFog::new(&gpu.device, &config)?;
        let mut sky = SkyLight::new(&gpu.device, HDR_FORMAT)
            .map_err(|e| DemoError::Pipeline(e.to_string()))?;
        sky.set_atmosphere(scene.atmosphere)?;
        let renderer = gpu
            .checked(|| {
                Renderer::new(
                    &gpu.device,
                    args.width,
                    args.height,
                    &scene,
                    &fog,
                    &sky,
                    &LampYard::face_matrices(&lamp_camera),
                    lamp_size,
                    timestamps,
                )
            })
            .map_err(|e| DemoError::Pipeline(e.to_string()))?
            .map_err(DemoError::Pipeline)?;
        fog.set_shadow_map(&gpu.device, renderer.shadow_map())?;
        fog.set_point_shadow_maps(&gpu.device, renderer.lamp_shadow_map())?;
        // The opaque pass lays the depth out before the fog runs, so the fog culls the
        // froxels behind this frame's opaque surfaces.
        fog.set_scene_depth(&gpu.device, &renderer.depth, 0)?;
        // The sky for the scene's (fixed) sun, solved once; the cloud map for the
        // clouds' passes and for the fog's cloud shadow.
        let aspect0 = args.width as f32 / args.height as f32;
        let proj0 =
            glam::camera::rh::proj::directx::perspective(FOV_Y.to_radians(), aspect0, NEAR, FAR);
        sky.prepare(&gpu.queue, &FrustumRays::new(Mat4::IDENTITY, proj0)?, 64)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        sky.encode_solve(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let size = (scene::CLOUD_MAP_SIZE, scene::CLOUD_MAP_SIZE);
        let cloud_map = cloud_map_texture(&gpu.device, &gpu.queue, size, &scene.cloud_map)?;
        fog.set_cloud_map(&gpu.device, &cloud_map)?;
        let clouds = CloudPasses::new(&gpu.device, HDR_FORMAT)
            .map_err(|e| DemoError::Pipeline(e.to_string()))?;
        let cloud_group = clouds.bind_group(
            &gpu.device,
            &cloud_map.create_view(&Default::default()),
            renderer.depth_view(),
        );
        let apply = fog.create_apply(&gpu.device, HDR_FORMAT)?;
        let depth_group = apply.depth_bind_group(&gpu.device, renderer.depth_view());
        println!(
            "fog pipeline: {:.1} MiB of GPU memory; sky {:.0} KiB",
            fog.memory_bytes() as f64 / (1024.0 * 1024.0),
            sky.memory_bytes() as f64 / 1024.0
        );
        let aspect = args.width as f32 / args.height as f32;
        let clip_from_view =
            glam::camera::rh::proj::directx::perspective(FOV_Y.to_radians(), aspect, NEAR, FAR);
        let splits = cascade_splits(config.cascades, config.near, config.far, 0.7);
        let probe_textures = args.probe.then(|| {
            [
                renderer.hdr_like(&gpu.device, "probe surface"),
                renderer.hdr_like(&gpu.device, "probe clouded"),
                renderer.hdr_like(&gpu.device, "probe fogged"),
            ]
        });
        Ok(Self {
            args,
            gpu,
            scene,
            config,
            fog,
            renderer,
            apply,
            depth_group,
            clip_from_view,
            splits,
            probe_textures,
            sky,
            clouds,
            cloud_group,
            lamp_camera,
            shadowed_lights: [ShadowedLight::new(lamp_light, lamp_camera).with_shadow(0)],
        })
    }
}

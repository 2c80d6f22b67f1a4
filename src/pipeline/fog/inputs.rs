//! Per-frame inputs of [`VolumetricFog`](super::VolumetricFog) and the uniforms they
//! become.

use glam::{Mat4, Vec3};

use super::config::FogConfig;
use super::local_shadows::ShadowedLight;
use crate::cpu::ambient::AmbientSh;
use crate::cpu::froxel::froxel_jitter_amortised;
use crate::cpu::shadow::{shadow_tap_rays, shadow_taps};
use crate::limits::{InvalidValue, check};
use crate::options::ShadowFilter;
use crate::uniforms::{
    AreaLight, CloudLayer, DirectionalLight, FogCustomParams, FogFrame, FogLight, FogLighting,
    FogMedium, FogParticle, FogView, Froxels, HeightFog, LocalVolume, ShadowCascades, ShadowTaps,
    TransientLighting,
};

/// The uniforms one frame's inputs become: what
/// [`VolumetricFog::prepare`](super::VolumetricFog::prepare) uploads (the light and
/// local volume arrays aside).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FrameUniforms {
    /// Froxel placement (from the projection and the configuration).
    pub froxels: Froxels,
    /// Camera, time, jitter and history switches.
    pub frame: FogFrame,
    /// The medium with its local volume count.
    pub medium: FogMedium,
    /// Sun, ambient and light count.
    pub lighting: FogLighting,
    /// Shadow cascades.
    pub cascades: ShadowCascades,
    /// The far-plane tail in view space.
    pub tail: HeightFog,
    /// The camera for shaders that start from world positions.
    pub view: FogView,
    /// Where the compare filter tests the lights' visibility within a froxel (see
    /// [`ShadowFilter::Compare`]).
    pub shadow_taps: ShadowTaps,
    /// The camera and the count of the transient lights (the scan's
    /// `VOLFOG_SCAN_TRANSIENT_LIGHTS` variant, run on frames with transient lights).
    pub transient: TransientLighting,
}

/// Per-frame inputs.
#[derive(Debug, Clone)]
pub struct FrameInputs<'a> {
    /// World -> view transform of the camera (right-handed, looking down -Z).
    pub view_from_world: Mat4,
    /// Perspective projection (view -> clip, WebGPU depth range; standard, reversed or
    /// infinite). Orthographic projections are rejected.
    pub clip_from_view: Mat4,
    /// Seconds since start (noise animation, density scrolling).
    pub time: f32,
    /// The medium.
    pub medium: FogMedium,
    /// The directional light.
    pub sun: DirectionalLight,
    /// Ambient radiance as L1 SH.
    pub ambient: AmbientSh,
    /// Point and spot lights (at most `FogConfig::max_lights`).
    pub lights: &'a [FogLight],
    /// Short-lived point, spot and directional lights (a muzzle flash, a lightning
    /// strike) that light this frame only, at most `FogConfig::max_transient_lights`.
    /// The scan adds their in-scattering to every live froxel of the volume it
    /// integrates, after the temporal blend: none of it enters the history (the next
    /// frame is as if they never existed), and the fog shows their whole contribution
    /// at once, not the history-weighted share an ordinary light would show in its
    /// first frame. They are evaluated at each froxel's centre (no jitter), unshadowed
    /// (`FogLight::projection` is ignored), without cookies, with the medium's phase and
    /// (with `FogConfig::light_transmittance`) its transmittance.
    pub transient_lights: &'a [FogLight],
    /// Rectangle and disk emitters (at most `FogConfig::max_area_lights`; none unless
    /// it is above 0), their in-scattering integrated over their area in inject
    /// (`volfog::area_lights`), unshadowed, with the medium's phase and (with
    /// `FogConfig::light_transmittance`) its transmittance to each cell.
    pub area_lights: &'a [AreaLight],
    /// Particles added to the medium (at most `FogConfig::max_particles`; none unless
    /// it is above 0): spheres of smoke, dust or glowing gas the application's
    /// particle system writes each frame (`volfog::particles`), added after the local
    /// volumes, lit and shadowed as the medium.
    pub particles: &'a [FogParticle],
    /// Local volumes (at most `FogConfig::max_local_volumes`).
    pub local_volumes: &'a [LocalVolume],
    /// Point and spot lights of `lights` with a shadow camera: their shadow maps and
    /// cookies (needs `FogConfig::local_shadows`), in priority order (those past the
    /// budget light the fog unshadowed).
    pub shadowed_lights: &'a [ShadowedLight],
    /// Shadow cascades; `count` 0 disables shadows. With `count` > 0 a shadow map must
    /// be set ([`VolumetricFog::set_shadow_map`](super::VolumetricFog::set_shadow_map)).
    pub cascades: ShadowCascades,
    /// Drop the history (after a camera cut).
    pub reset_history: bool,
    /// Analytic height fog continuing beyond the far plane when applying (world
    /// space; see [`HeightFog::from_medium`]); [`HeightFog::none`] for none.
    pub tail: HeightFog,
    /// The cloud layer whose shadow the sun's light passes in the fog
    /// (`FogConfig::cloud_shadow`; ignored otherwise). The default has no extinction.
    pub clouds: CloudLayer,
    /// The parameters of the custom density (`FogConfig::custom_density`; ignored
    /// otherwise): what its `params` argument holds this frame. Finite; 0 by default.
    pub custom_params: FogCustomParams,
}

impl FrameInputs<'_> {
    /// Inputs with the default medium and sun, a dim constant ambient, no lights, no
    /// local volumes and no shadows.
    pub fn new(view_from_world: Mat4, clip_from_view: Mat4, time: f32) -> Self {
        Self {
            view_from_world,
            clip_from_view,
            time,
            medium: FogMedium::default(),
            sun: DirectionalLight::default(),
            ambient: AmbientSh::constant(Vec3::new(0.08, 0.1, 0.14)),
            lights: &[],
            transient_lights: &[],
            area_lights: &[],
            particles: &[],
            local_volumes: &[],
            shadowed_lights: &[],
            cascades: ShadowCascades::default(),
            reset_history: false,
            tail: HeightFog::none(),
            clouds: CloudLayer::new(2000.0, 500.0, 0.0, 1.0e4).expect("a valid empty layer"),
            custom_params: FogCustomParams::default(),
        }
    }

    /// Checks every input against the configuration (the projection is checked when
    /// the froxel placement is built from it).
    pub fn validate(&self, config: &FogConfig) -> Result<(), InvalidValue> {
        check(
            self.view_from_world.is_finite() && self.view_from_world.determinant().abs() > 1e-12,
            "FrameInputs.view_from_world",
            self.view_from_world,
            "a finite, invertible transform",
        )?;
        check(
            self.time.is_finite(),
            "FrameInputs.time",
            self.time,
            "a finite time",
        )?;
        self.medium.validate()?;
        self.sun.validate()?;
        self.custom_params.validate()?;
        if config.cloud_shadow {
            self.clouds.validated()?;
        }
        check(
            self.ambient.rgb.iter().all(|v| v.is_finite()),
            "FrameInputs.ambient",
            self.ambient,
            "finite SH coefficients",
        )?;
        check(
            self.lights.len() <= config.max_lights as usize,
            "FrameInputs.lights",
            self.lights.len(),
            format!(
                "at most FogConfig.max_lights = {} lights",
                config.max_lights
            ),
        )?;
        for light in self.lights {
            light.validate()?;
        }
        check(
            self.transient_lights.len() <= config.max_transient_lights as usize,
            "FrameInputs.transient_lights",
            self.transient_lights.len(),
            format!(
                "at most FogConfig.max_transient_lights = {} lights",
                config.max_transient_lights
            ),
        )?;
        for light in self.transient_lights {
            light.validate()?;
        }
        check(
            self.area_lights.len() <= config.max_area_lights as usize,
            "FrameInputs.area_lights",
            self.area_lights.len(),
            format!(
                "at most FogConfig.max_area_lights = {} lights",
                config.max_area_lights
            ),
        )?;
        for light in self.area_lights {
            light.validate()?;
        }
        check(
            self.particles.len() <= config.max_particles as usize,
            "FrameInputs.particles",
            self.particles.len(),
            format!(
                "at most FogConfig.max_particles = {} particles",
                config.max_particles
            ),
        )?;
        for particle in self.particles {
            particle.validate()?;
        }
        check(
            self.local_volumes.len() <= config.max_local_volumes as usize,
            "FrameInputs.local_volumes",
            self.local_volumes.len(),
            format!(
                "at most FogConfig.max_local_volumes = {} volumes",
                config.max_local_volumes
            ),
        )?;
        for volume in self.local_volumes {
            volume.validate()?;
        }
        check(
            self.shadowed_lights.is_empty() || config.local_shadows.is_some(),
            "FrameInputs.shadowed_lights",
            self.shadowed_lights.len(),
            "empty while FogConfig.local_shadows is None",
        )?;
        self.cascades.validate(config.esm_log_space)?;
        check(
            self.cascades.count <= config.cascades,
            "ShadowCascades.count",
            self.cascades.count,
            format!("at most FogConfig.cascades = {}", config.cascades),
        )?;
        self.tail.validate()
    }

    /// Checks the inputs and builds the uniforms of frame `index` (frames prepared
    /// before it: it picks the jitter).
    pub fn uniforms(&self, config: &FogConfig, index: u32) -> Result<FrameUniforms, InvalidValue> {
        let froxels = Froxels::new(
            self.clip_from_view,
            config.volume_size,
            config.near,
            config.far,
            config.slice_curve,
        )?;
        self.validate(config)?;
        let world_from_view = self.view_from_world.inverse();
        let jitter = if config.jitter {
            froxel_jitter_amortised(index, u32::from(config.amortize))
        } else {
            Vec3::ZERO
        };
        let taps = match config.shadow_filter {
            ShadowFilter::Compare { taps } => taps,
            ShadowFilter::Esm => 1,
        };
        let rays = shadow_tap_rays(froxels.view_from_clip, world_from_view);
        let mut shadow_taps = shadow_taps(jitter, taps, config.shadow_reversed_z, rays);
        shadow_taps.camera_depth_terms = crate::uniforms::frustum::depth_terms(
            "FrameInputs.clip_from_view",
            self.clip_from_view,
        )?;
        if !config.temporal {
            // Without a history every froxel takes the taps of one that has none.
            shadow_taps.count = shadow_taps.fresh;
        }
        let transient = TransientLighting {
            camera_position: world_from_view.w_axis.truncate(),
            count: self.transient_lights.len() as u32,
            ray_origin: rays[0],
            transmittance: u32::from(config.light_transmittance),
            ray_x: rays[1],
            ray_y: rays[2],
        };
        let frame = FogFrame {
            world_from_view,
            clip_from_world: self.clip_from_view * self.view_from_world,
            camera_position: world_from_view.w_axis.truncate(),
            time: self.time,
            jitter,
            history_weight: config.history_weight,
            index,
            history_enabled: u32::from(!self.reset_history),
            checkerboard: u32::from(config.amortize),
        };
        Ok(FrameUniforms {
            froxels,
            frame,
            medium: FogMedium {
                local_volume_count: self.local_volumes.len() as u32,
                particle_count: self.particles.len() as u32,
                ..self.medium
            },
            lighting: FogLighting {
                sun: self.sun,
                ambient_r: self.ambient.rgb[0],
                ambient_g: self.ambient.rgb[1],
                ambient_b: self.ambient.rgb[2],
                light_count: self.lights.len() as u32,
                transmittance: u32::from(config.light_transmittance),
            },
            cascades: self.cascades,
            tail: HeightFog {
                sun_transmittance: u32::from(config.light_transmittance),
                ..self.tail
            }
            .to_view_space(self.view_from_world),
            view: FogView {
                view_from_world: self.view_from_world,
            },
            shadow_taps,
            transient,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits;

    #[test]
    fn local_volumes_are_checked_as_their_constructor_checks() {
        let config = FogConfig::default();
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
        let bad = LocalVolume {
            local_from_world: Mat4::IDENTITY,
            emission: glam::Vec3::ZERO,
            density: 2.0e3,
            edge: 0.5,
            shape: 0,
            ..LocalVolume::default()
        };
        let volumes = [bad];
        let inputs = FrameInputs {
            local_volumes: &volumes,
            ..FrameInputs::new(Mat4::IDENTITY, proj, 0.0)
        };
        let err = inputs.validate(&config).unwrap_err();
        assert_eq!(err.field, "LocalVolume.density");
        assert_eq!(err.expected, limits::LOCAL_VOLUME_DENSITY.describe());
    }

    #[test]
    fn transient_lights_are_checked_against_their_capacity_and_as_lights() {
        let config = FogConfig {
            max_transient_lights: 1,
            ..FogConfig::default()
        };
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
        let flash = FogLight::point(Vec3::new(0.0, 1.0, -3.0), Vec3::splat(50.0), 8.0);
        let two = [flash, flash];
        let inputs = FrameInputs {
            transient_lights: &two,
            ..FrameInputs::new(Mat4::IDENTITY, proj, 0.0)
        };
        let err = inputs.validate(&config).unwrap_err();
        assert_eq!(err.field, "FrameInputs.transient_lights");
        assert_eq!(err.value, "2");
        assert_eq!(
            err.expected,
            "at most FogConfig.max_transient_lights = 1 lights"
        );
        let dark = [FogLight {
            color: Vec3::new(1.0, f32::NAN, 0.0),
            ..flash
        }];
        let inputs = FrameInputs {
            transient_lights: &dark,
            ..inputs
        };
        assert_eq!(
            inputs.validate(&config).unwrap_err().field,
            "FogLight.color"
        );
        let one = [flash];
        let inputs = FrameInputs {
            transient_lights: &one,
            ..inputs
        };
        let u = inputs.uniforms(&config, 0).unwrap();
        assert_eq!(u.transient.count, 1);
        assert_eq!(
            u.lighting.light_count, 0,
            "transient lights are not inject's"
        );
        let bad = FogConfig {
            max_transient_lights: limits::MAX_TRANSIENT_LIGHTS + 1,
            ..FogConfig::default()
        };
        assert_eq!(
            bad.validate().unwrap_err().field,
            "FogConfig.max_transient_lights"
        );
    }
}

//! Extraction: each [`FroxelFog`] camera's settings, the lights and the local volumes
//! of the main world become one [`ExtractedFroxelFog`] on the camera's render entity,
//! in volfog's own types and units, checked.
//!
//! Units: Bevy's lights are photometric and scaled by the camera's exposure in its
//! shaders; the fog takes the same light scaled by the same exposure. A directional
//! light's colour is `color * illuminance` (lux); a point or spot light's intensity at
//! 1 m is `color * intensity / 4 pi` (lumens to candela), as Bevy's PBR shader lights
//! surfaces; the ambient radiance is `color * brightness`.
//!
//! The first directional light (the first with shadows, if any) is volfog's sun, with
//! its cascades; every other directional light is a directional `FogLight`,
//! unshadowed. Spot lights take Bevy's cone falloff (`FOG_LIGHT_SPOT_SQUARED`).
//! Lights marked [`TransientFogLight`] become the fog's transient lights instead
//! (`FrameInputs::transient_lights`), unshadowed. The [`FroxelFogParticles`] of every
//! entity, in entity order, are the particles of each camera with room for them.

use std::collections::HashSet;

use bevy::camera::{Camera, Exposure};
use bevy::light::{
    CascadeShadowConfig, Cascades, DirectionalLight, DirectionalLightShadowMap, GlobalAmbientLight,
    PointLight, PointLightShadowMap, SpotLight, VolumetricLight,
};
use bevy::prelude::*;
use bevy::render::Extract;
use bevy::render::sync_world::RenderEntity;
use bevy::shader::Shader;
use volfog::cpu::ambient::AmbientSh;
use volfog::glam as vg;
use volfog::limits::{self, InvalidValue, check};
use volfog::pipeline::FogConfig;
use volfog::uniforms::{
    FOG_LIGHT_SPOT_SQUARED, FogCustomParams, FogLight, FogMedium, FogParticle, HeightFog,
    LocalVolume, ShadowCascades, VolumeShape,
};

use crate::density::{FroxelFogDensity, custom_density};

use crate::light_shadows::{ExtractedLightShadow, local_shadow_config};
use crate::particles::FroxelFogParticles;
use crate::settings::{
    FogLightSelection, FogVolumeShape, FroxelFog, FroxelFogVolume, FroxelFogVolumeTexture,
};
use crate::transient::TransientFogLight;

/// Screen pixels per froxel side that [`FroxelFog::tile_size`] accepts.
pub const TILE_SIZE: limits::Range<u32> = limits::Range::new(1, 256, "pixels");

/// Local volumes a camera's fog holds (the first ones found).
pub const MAX_VOLUMES: u32 = 64;

/// One camera's fog for this frame, in volfog's types: what the render world runs.
#[derive(Component, Clone, Debug)]
pub struct ExtractedFroxelFog {
    /// The pipeline's configuration (rebuilt when it changes).
    pub config: FogConfig,
    /// World -> view transform.
    pub view_from_world: vg::Mat4,
    /// The camera's projection (view -> clip).
    pub clip_from_view: vg::Mat4,
    /// Seconds since start.
    pub time: f32,
    /// The medium.
    pub medium: FogMedium,
    /// The sun (no light: black).
    pub sun: volfog::uniforms::DirectionalLight,
    /// Constant ambient radiance as SH.
    pub ambient: AmbientSh,
    /// Point and spot lights, those that cast shadows in Bevy first, then the
    /// directional lights after the sun, then the others.
    pub lights: Vec<FogLight>,
    /// The lights that cast shadows in Bevy (their shadow maps are looked up in the
    /// render world each frame).
    pub light_shadows: Vec<ExtractedLightShadow>,
    /// The lights marked [`TransientFogLight`]: point and spot lights, then directional
    /// lights (at most `limits::MAX_TRANSIENT_LIGHTS`).
    pub transient_lights: Vec<FogLight>,
    /// Local volumes.
    pub volumes: Vec<LocalVolume>,
    /// The particles (emission scaled by the exposure; none without
    /// `config.max_particles`).
    pub particles: Vec<FogParticle>,
    /// The density texture the textured volumes read (`FroxelFogVolumeTexture`), bound
    /// in the render world once Bevy has prepared it.
    pub density_texture: Option<AssetId<Image>>,
    /// The sun's cascades (count 0 without a shadowed sun).
    pub cascades: ShadowCascades,
    /// The far tail (world space), or none.
    pub tail: HeightFog,
    /// The parameters of the camera's [`FroxelFogDensity`] (whose module is
    /// `config.custom_density`).
    pub custom_params: FogCustomParams,
}

impl ExtractedFroxelFog {
    /// The frame inputs for [`volfog::pipeline::VolumetricFog::prepare`].
    pub fn inputs(&self) -> volfog::pipeline::FrameInputs<'_> {
        volfog::pipeline::FrameInputs {
            medium: self.medium,
            sun: self.sun,
            ambient: self.ambient,
            lights: &self.lights,
            transient_lights: &self.transient_lights,
            local_volumes: &self.volumes,
            particles: &self.particles,
            cascades: self.cascades,
            tail: self.tail,
            custom_params: self.custom_params,
            ..volfog::pipeline::FrameInputs::new(
                self.view_from_world,
                self.clip_from_view,
                self.time,
            )
        }
    }
}

/// Bevy's glam to volfog's glam (the versions differ).
pub(crate) fn mat4(m: Mat4) -> vg::Mat4 {
    vg::Mat4::from_cols_array(&m.to_cols_array())
}

pub(crate) fn vec3(v: Vec3) -> vg::Vec3 {
    vg::Vec3::from_array(v.to_array())
}

fn rgb(c: LinearRgba) -> vg::Vec3 {
    vg::Vec3::new(c.red, c.green, c.blue)
}

/// Maps Bevy's reverse-Z cascade depth (1 at the light's near plane) to standard depth
/// (0 there): z' = w - z.
const STANDARD_FROM_REVERSED_Z: vg::Mat4 = vg::Mat4::from_cols(
    vg::Vec4::X,
    vg::Vec4::Y,
    vg::Vec4::new(0.0, 0.0, -1.0, 0.0),
    vg::Vec4::new(0.0, 0.0, 1.0, 1.0),
);

/// A local volume as the extraction reads it: its settings, world transform and, when
/// it reads the fog's density texture, the texture's offset.
type ExtractedVolume = (FroxelFogVolume, Mat4, Option<Vec3>);

/// A local volume as the extraction queries it.
type VolumeItems = (
    Entity,
    &'static FroxelFogVolume,
    &'static GlobalTransform,
    Option<&'static FroxelFogVolumeTexture>,
);

/// A fog camera as the extraction reads it.
type FogCameraItems = (
    Entity,
    RenderEntity,
    &'static Camera,
    &'static FroxelFog,
    &'static GlobalTransform,
    Option<&'static Exposure>,
    Option<&'static FroxelFogDensity>,
);

/// Cameras without fog (their render entity loses any fog of an earlier frame).
type OtherCameras = (With<Camera>, Without<FroxelFog>);

/// A directional light as the extraction reads it (the last two: whether it has
/// `VolumetricLight`, whether it has `TransientFogLight`).
type SunItem<'a> = (
    Entity,
    &'a DirectionalLight,
    &'a GlobalTransform,
    Option<&'a Cascades>,
    Option<&'a CascadeShadowConfig>,
    bool,
    bool,
);

/// The directional lights as the extraction reads them.
type SunQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static DirectionalLight,
        &'static GlobalTransform,
        Option<&'static Cascades>,
        Option<&'static CascadeShadowConfig>,
        Has<VolumetricLight>,
        Has<TransientFogLight>,
    ),
>;

/// Copies every [`FroxelFog`] camera's fog into the render world, or warns once and
/// leaves the fog off for a camera whose settings are out of range.
#[allow(clippy::too_many_arguments)]
pub fn extract_froxel_fog(
    mut commands: Commands,
    cameras: Extract<Query<FogCameraItems>>,
    others: Extract<Query<RenderEntity, OtherCameras>>,
    suns: Extract<SunQuery>,
    points: Extract<PointQuery>,
    spots: Extract<SpotQuery>,
    volumes: Extract<Query<VolumeItems>>,
    particles: Extract<Query<(Entity, &FroxelFogParticles)>>,
    ambient: Extract<Option<Res<GlobalAmbientLight>>>,
    shadow_map: Extract<Res<DirectionalLightShadowMap>>,
    point_shadow_map: Extract<Res<PointLightShadowMap>>,
    time: Extract<Res<Time>>,
    shaders: Extract<Res<Assets<Shader>>>,
    mut warned: Local<HashSet<Entity>>,
    mut warned_textures: Local<HashSet<Entity>>,
) {
    for render in &others {
        commands.entity(render).remove::<ExtractedFroxelFog>();
    }
    let mut emitters: Vec<_> = particles.iter().collect();
    emitters.sort_by_key(|(entity, _)| *entity);
    let particles: Vec<FogParticle> = emitters
        .iter()
        .flat_map(|(_, p)| p.0.iter().copied())
        .collect();
    for (entity, render, camera, fog, transform, exposure, density) in &cameras {
        let scene = Scene {
            camera,
            entity,
            transform,
            exposure: exposure.copied().unwrap_or_default().exposure(),
            ambient: ambient.as_deref(),
            shadow_map_size: shadow_map.size as u32,
            point_shadow_map_size: point_shadow_map.size as u32,
            time: time.elapsed_secs_wrapped(),
        };
        let lights = collect_lights(&points, &spots, scene.exposure, fog);
        let mut local: Vec<_> = volumes.iter().collect();
        // The volumes blend in their order, ties by entity.
        local.sort_by_key(|(e, v, ..)| (v.order, *e));
        // One density texture per fog: the first textured volume's image.
        let texture = local.iter().find_map(|(.., t)| t.map(|t| t.image.id()));
        let local: Vec<ExtractedVolume> = local
            .into_iter()
            .map(|(volume_entity, v, t, texture_of)| {
                let offset = texture_of.and_then(|x| {
                    if Some(x.image.id()) == texture {
                        Some(x.offset)
                    } else {
                        if warned_textures.insert(volume_entity) {
                            warn!(
                                "volfog: volume {volume_entity}: FroxelFogVolumeTexture.image is \
                                 not the first textured volume's; a fog reads one density \
                                 texture, so this volume is uniform"
                            );
                        }
                        None
                    }
                });
                (v.clone(), t.to_matrix(), offset)
            })
            .collect();
        let result = custom_density(density, &shaders).and_then(|custom| {
            let mut extracted = extracted(
                fog,
                &scene,
                suns.iter(),
                lights,
                &local,
                texture,
                &particles,
            )?;
            if let Some((module, params)) = custom {
                extracted.config.custom_density = Some(module);
                extracted.custom_params = params;
            }
            Ok(extracted)
        });
        match result {
            Ok(extracted) => {
                warned.remove(&entity);
                commands.entity(render).insert(extracted);
            }
            Err(error) => {
                if warned.insert(entity) {
                    warn!("volfog: camera {entity}: {error}; the fog is off for this camera");
                }
                commands.entity(render).remove::<ExtractedFroxelFog>();
            }
        }
    }
}

/// What one camera's fog depends on besides its settings.
struct Scene<'a> {
    camera: &'a Camera,
    entity: Entity,
    transform: &'a GlobalTransform,
    exposure: f32,
    ambient: Option<&'a GlobalAmbientLight>,
    shadow_map_size: u32,
    point_shadow_map_size: u32,
    time: f32,
}

/// The point lights as the extraction reads them.
type PointQuery<'w, 's> = Query<
    'w,
    's,
    (
        RenderEntity,
        &'static PointLight,
        &'static GlobalTransform,
        Has<VolumetricLight>,
        Has<TransientFogLight>,
    ),
>;
/// The spot lights as the extraction reads them.
type SpotQuery<'w, 's> = Query<
    'w,
    's,
    (
        RenderEntity,
        &'static SpotLight,
        &'static GlobalTransform,
        Has<VolumetricLight>,
        Has<TransientFogLight>,
    ),
>;

/// Whether a light with (or without) `VolumetricLight` lights this fog.
fn selected(fog: &FroxelFog, volumetric: bool) -> bool {
    volumetric || fog.lights == FogLightSelection::All
}

/// The point and spot lights as the extraction returns them: the fog's lights (the
/// first [`limits::MAX_LIGHTS`], those with shadow maps first), which of them cast
/// shadows, and the transient ones.
type CollectedLights = (Vec<FogLight>, Vec<ExtractedLightShadow>, Vec<FogLight>);

/// The point and spot lights (the first [`limits::MAX_LIGHTS`], those with shadow maps
/// first), which of them cast shadows, and those marked [`TransientFogLight`].
fn collect_lights(
    points: &PointQuery,
    spots: &SpotQuery,
    exposure: f32,
    fog: &FroxelFog,
) -> CollectedLights {
    let candela = exposure / (4.0 * std::f32::consts::PI);
    let scattering = fog.light_scattering;
    let mut found: Vec<(bool, Entity, FogLight)> = Vec::new();
    let mut transient = Vec::new();
    for (entity, light, transform, volumetric, short) in points.iter() {
        if !selected(fog, volumetric || short) {
            continue;
        }
        let color = rgb(light.color.to_linear()) * (light.intensity * candela);
        let fog_light = FogLight {
            fog_intensity: scattering,
            radius: light.radius.max(0.01),
            ..FogLight::point(vec3(transform.translation()), color, light.range)
        };
        if short {
            transient.push(fog_light);
            continue;
        }
        found.push((light.shadow_maps_enabled, entity, fog_light));
    }
    for (entity, light, transform, volumetric, short) in spots.iter() {
        if !selected(fog, volumetric || short) {
            continue;
        }
        let color = rgb(light.color.to_linear()) * (light.intensity * candela);
        let fog_light = FogLight {
            fog_intensity: scattering,
            radius: light.radius.max(0.01),
            flags: FOG_LIGHT_SPOT_SQUARED,
            ..FogLight::spot(
                vec3(transform.translation()),
                vec3(*transform.forward()),
                color,
                light.range,
                light.inner_angle,
                light.outer_angle,
            )
        };
        if short {
            transient.push(fog_light);
            continue;
        }
        found.push((light.shadow_maps_enabled, entity, fog_light));
    }
    found.sort_by_key(|(shadows, ..)| !shadows);
    found.truncate(limits::MAX_LIGHTS as usize);
    let shadows = found
        .iter()
        .enumerate()
        .filter(|(_, (shadows, ..))| *shadows)
        .map(|(i, (_, entity, _))| ExtractedLightShadow {
            light: i as u32,
            entity: *entity,
        })
        .collect();
    (
        found.into_iter().map(|(.., l)| l).collect(),
        shadows,
        transient,
    )
}

/// Builds one camera's fog, or the first value out of range.
fn extracted<'a>(
    fog: &FroxelFog,
    scene: &Scene<'_>,
    suns: impl Iterator<Item = SunItem<'a>>,
    (mut lights, light_shadows, mut transient_lights): CollectedLights,
    volumes: &[ExtractedVolume],
    density_texture: Option<AssetId<Image>>,
    particles: &[FogParticle],
) -> Result<ExtractedFroxelFog, InvalidValue> {
    TILE_SIZE.check("FroxelFog.tile_size", fog.tile_size)?;
    let viewport = scene.camera.physical_viewport_size().unwrap_or(UVec2::ONE);
    let grid = (viewport + (fog.tile_size - 1)) / fog.tile_size;
    let medium = FogMedium {
        albedo: rgb(fog.medium.albedo),
        density: fog.medium.density,
        height_falloff: fog.medium.height_falloff,
        base_height: fog.medium.base_height,
        phase_g: fog.medium.phase_g,
        noise_strength: fog.medium.noise_strength,
        noise_scale: fog.medium.noise_scale,
        wind: vec3(fog.medium.wind),
        top_height: fog.medium.top_height,
        emission: rgb(fog.medium.emission) * scene.exposure,
        // The density texture is the textured volumes' (FroxelFogVolumeTexture).
        textured: 0,
        ..FogMedium::default()
    };
    medium.validate().map_err(|e| renamed(e, fog))?;
    limits::FOG_RADIANCE.check("FroxelFog.sun_scattering", fog.sun_scattering)?;
    limits::FOG_RADIANCE.check("FroxelFog.light_scattering", fog.light_scattering)?;
    limits::FOG_RADIANCE.check("FroxelFog.ambient_scattering", fog.ambient_scattering)?;

    // The sun: the first directional light (the first with shadows, if any), with its
    // cascades for this camera when it casts shadows; the others are directional fog
    // lights, unshadowed, after the shadowed point and spot lights.
    let mut sun = volfog::uniforms::DirectionalLight {
        color: vg::Vec3::ZERO,
        fog_intensity: 0.0,
        ..Default::default()
    };
    let mut cascades = ShadowCascades {
        exponent: fog.esm_exponent,
        ..Default::default()
    };
    let (short, mut suns): (Vec<_>, Vec<_>) = suns
        .filter(|(.., v, t)| selected(fog, *v || *t))
        .partition(|(.., t)| *t);
    transient_lights.extend(short.iter().map(|(_, light, transform, ..)| FogLight {
        fog_intensity: fog.sun_scattering,
        ..FogLight::directional(
            vec3(-*transform.forward()),
            rgb(light.color.to_linear()) * (light.illuminance * scene.exposure),
        )
    }));
    transient_lights.truncate(limits::MAX_TRANSIENT_LIGHTS as usize);
    suns.sort_by_key(|(entity, light, ..)| (!light.shadow_maps_enabled, *entity));
    let others = suns
        .iter()
        .skip(1)
        .map(|(_, light, transform, ..)| FogLight {
            fog_intensity: fog.sun_scattering,
            ..FogLight::directional(
                vec3(-*transform.forward()),
                rgb(light.color.to_linear()) * (light.illuminance * scene.exposure),
            )
        });
    let at = light_shadows.len().min(lights.len());
    lights.splice(at..at, others);
    lights.truncate(limits::MAX_LIGHTS as usize);
    if let Some((_, light, transform, light_cascades, config, ..)) = suns.first() {
        sun.direction = vec3(-*transform.forward());
        sun.color = rgb(light.color.to_linear()) * (light.illuminance * scene.exposure);
        sun.fog_intensity = fog.sun_scattering;
        if light.shadow_maps_enabled
            && let (Some(light_cascades), Some(config)) = (light_cascades, config)
            && let Some(list) = light_cascades.cascades.get(&scene.entity)
        {
            let count = list
                .len()
                .min(limits::MAX_CASCADES)
                .min(config.bounds.len());
            for (i, cascade) in list.iter().take(count).enumerate() {
                cascades.light_from_world[i] =
                    STANDARD_FROM_REVERSED_Z * mat4(cascade.clip_from_world);
            }
            let mut splits = [0.0f32; 4];
            for (i, bound) in config.bounds.iter().take(count).enumerate() {
                splits[i] = *bound;
            }
            cascades.splits = vg::Vec4::from_array(splits);
            cascades.count = count as u32;
        }
    }
    let ambient_radiance = match fog.ambient_radiance {
        Some(radiance) => rgb(radiance) * scene.exposure,
        None => scene
            .ambient
            .map(|a| rgb(a.color.to_linear()) * (a.brightness * scene.exposure))
            .unwrap_or(vg::Vec3::ZERO),
    };
    check(
        ambient_radiance.is_finite() && ambient_radiance.cmpge(vg::Vec3::ZERO).all(),
        "FroxelFog.ambient_radiance",
        ambient_radiance,
        "finite channels >= 0",
    )?;
    let ambient = AmbientSh::constant(ambient_radiance * fog.ambient_scattering);
    let tail = if fog.tail {
        let albedo = medium.albedo;
        // (from_medium adds the emission's share, emission / density.)
        HeightFog::from_medium(&medium, albedo * ambient_radiance * fog.ambient_scattering)
            .with_sun(
                sun.direction.normalize(),
                albedo * sun.color * sun.fog_intensity,
                medium.phase_g.clamp(-0.999, 0.999),
            )?
    } else {
        HeightFog::none()
    };
    let volumes = volumes
        .iter()
        .map(|(v, world_from_entity, texture_offset)| {
            // The entity's unit shape spans -0.5..0.5; volfog's spans -1..1, and maps
            // to the texture as local * 0.5 + 0.5: Bevy's local + 0.5.
            let world_from_local =
                mat4(*world_from_entity) * vg::Mat4::from_scale(vg::Vec3::splat(0.5));
            let shape = match v.shape {
                FogVolumeShape::Box => VolumeShape::Box,
                FogVolumeShape::Ellipsoid => VolumeShape::Ellipsoid,
            };
            let volume = LocalVolume::new(world_from_local, shape, v.density, v.edge)
                .and_then(|volume| volume.with_blend(v.blend))?;
            match texture_offset {
                Some(offset) => volume.with_density_texture(vec3(*offset)),
                None => Ok(volume),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    check(
        volumes.len() <= MAX_VOLUMES as usize,
        "FroxelFogVolume",
        volumes.len(),
        format!("at most {MAX_VOLUMES} volumes"),
    )?;
    let config = FogConfig {
        volume_size: vg::UVec3::new(grid.x, grid.y, fog.slices),
        near: fog.near,
        far: fog.far,
        slice_curve: fog.slice_curve,
        esm_resolution: (scene.shadow_map_size / 4).max(4),
        cascades: cascades.count.max(1),
        esm_exponent: fog.esm_exponent,
        // Bevy fits each cascade's depth range to its slice of the view, tens of
        // metres deep: sharp shadows then need exponents beyond linear ESM's 88.
        esm_log_space: true,
        shadow_reversed_z: true,
        max_lights: limits::MAX_LIGHTS,
        max_transient_lights: limits::MAX_TRANSIENT_LIGHTS,
        max_local_volumes: MAX_VOLUMES,
        max_particles: fog.max_particles,
        density_texture: density_texture.is_some(),
        jitter: fog.temporal,
        temporal: fog.temporal,
        history_weight: fog.history_weight,
        amortize: fog.amortize && fog.temporal,
        noise_texture: fog.noise_texture,
        light_transmittance: fog.light_transmittance,
        // Bevy's point light cubes and spot light maps (in the directional light
        // texture), filtered into volfog's local-light atlas.
        local_shadows: local_shadow_config(
            fog,
            scene.point_shadow_map_size,
            scene.shadow_map_size,
        )?,
        // The ESM filter: with the compare filter's taps, a froxel beyond a wall that
        // fills a spot light's shadow camera takes a tap outside that camera, which
        // reads as lit (up to 25 % of the light in `light_shadows`' closed room).
        shadow_filter: volfog::options::ShadowFilter::Esm,
        ..FogConfig::default()
    };
    config.validate().map_err(|e| renamed(e, fog))?;
    let extracted = ExtractedFroxelFog {
        config,
        view_from_world: mat4(scene.transform.to_matrix().inverse()),
        clip_from_view: mat4(scene.camera.clip_from_view()),
        time: scene.time,
        medium,
        sun,
        ambient,
        lights,
        light_shadows,
        transient_lights,
        volumes,
        particles: if fog.max_particles == 0 {
            Vec::new()
        } else {
            particles
                .iter()
                .map(|p| FogParticle {
                    emission: p.emission * scene.exposure,
                    ..*p
                })
                .collect()
        },
        density_texture,
        cascades,
        tail,
        custom_params: FogCustomParams::default(),
    };
    extracted.inputs().validate(&extracted.config)?;
    Ok(extracted)
}

/// Names the camera component's field where the configuration's field came from it.
fn renamed(mut e: InvalidValue, fog: &FroxelFog) -> InvalidValue {
    e.field = match e.field {
        "FogConfig.volume_size" => {
            e.expected = format!(
                "{} (the grid is the viewport / FroxelFog.tile_size = {} by FroxelFog.slices)",
                e.expected, fog.tile_size
            )
            .into();
            "FroxelFog.slices"
        }
        "FogConfig.near" => "FroxelFog.near",
        "FogConfig.far" => "FroxelFog.far",
        "FogConfig.slice_curve" => "FroxelFog.slice_curve",
        "FogConfig.esm_exponent" => "FroxelFog.esm_exponent",
        "FogConfig.history_weight" => "FroxelFog.history_weight",
        "FogConfig.max_particles" => "FroxelFog.max_particles",
        "FogMedium.albedo" => "FroxelFog.medium.albedo",
        "FogMedium.density" => "FroxelFog.medium.density",
        "FogMedium.height_falloff" => "FroxelFog.medium.height_falloff",
        "FogMedium.wind" => "FroxelFog.medium.wind",
        "FogMedium.base_height" => "FroxelFog.medium.base_height",
        "FogMedium.noise_strength" => "FroxelFog.medium.noise_strength",
        "FogMedium.noise_scale" => "FroxelFog.medium.noise_scale",
        "FogMedium.phase_g" => "FroxelFog.medium.phase_g",
        "FogMedium.top_height" => "FroxelFog.medium.top_height",
        "FogMedium.emission" => "FroxelFog.medium.emission",
        "LocalShadowConfig.spot_shadows" => "FroxelFog.spot_shadows",
        "LocalShadowConfig.point_shadows" => "FroxelFog.point_shadows",
        "LocalShadowConfig.exponent" => "FroxelFog.light_shadow_exponent",
        other => other,
    };
    e
}

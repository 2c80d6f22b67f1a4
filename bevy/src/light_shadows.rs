//! Bevy's own point and spot light shadow maps in the fog: the atlas resolution and
//! budget of a camera's fog, and each frame's shadowed lights with the layer of Bevy's
//! shadow textures and the shadow camera Bevy rendered them with (bevy_pbr's
//! `prepare_lights` and `shadows.wesl`).
//!
//! Bevy keeps its point and spot lights in one clustered list, sorted by kind (point
//! lights, then spot lights), shadowed first, then volumetric first, then by render
//! entity (`GlobalClusterableObjectMeta::entity_to_index` holds each light's index
//! `i`). A shadowed point light's cube is layers `6 i .. 6 i + 6` of
//! `ViewShadowBindings::point_light_depth_texture` (a cube array); a shadowed spot
//! light's map is layer `i + spot_light_shadowmap_offset` of the directional light
//! texture array, after the directional cascades: `cascades + (i - point lights)`.

use std::f32::consts::FRAC_PI_2;

use bevy::ecs::system::SystemParam;
use bevy::light::{spot_light_clip_from_view, spot_light_world_from_view};
use bevy::pbr::{
    ExtractedDirectionalLight, ExtractedPointLight, GlobalClusterableObjectMeta,
    MAX_CASCADES_PER_LIGHT, MAX_DIRECTIONAL_LIGHTS,
};
use bevy::prelude::*;
use volfog::glam as vg;
use volfog::limits::{self, InvalidValue};
use volfog::pipeline::{LocalShadowConfig, ShadowedLight};
use volfog::uniforms::LightCamera;

use crate::extract::{ExtractedFroxelFog, mat4, vec3};
use crate::settings::FroxelFog;

/// A point or spot light of a camera's fog that casts shadows in Bevy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExtractedLightShadow {
    /// Index of the light in [`ExtractedFroxelFog::lights`].
    pub light: u32,
    /// The light's render-world entity, where Bevy keeps its shadow map.
    pub entity: Entity,
}

/// The local-light atlas resolution (texels per side) for Bevy's shadow maps of these
/// sizes (those the fog reads: `PointLightShadowMap::size` for point lights,
/// `DirectionalLightShadowMap::size` for spot lights): a quarter of the smaller map,
/// at most 1024, unless that is not a whole fraction 1/k (k in 1..=16) of every map;
/// then the nearest resolution that is (the largest below, else the smallest above).
/// `None` when no resolution is.
///
/// ```
/// use volfog_bevy::light_shadow_resolution;
/// // Bevy's defaults: point lights 1024, directional and spot lights 2048.
/// assert_eq!(light_shadow_resolution(&[1024, 2048]), Some(256));
/// // A small point map beside a large spot map: k = 16 for the spot map at most.
/// assert_eq!(light_shadow_resolution(&[256, 2048]), Some(128));
/// assert_eq!(light_shadow_resolution(&[8192]), Some(1024));
/// assert_eq!(light_shadow_resolution(&[1000, 1024]), None);
/// ```
pub fn light_shadow_resolution(sizes: &[u32]) -> Option<u32> {
    let smallest = *sizes.iter().min()?;
    let largest = *sizes.iter().max()?;
    let common = sizes.iter().fold(0, |g, &s| gcd(g, s));
    let target = (smallest / 4).min(limits::LOCAL_SHADOW_RESOLUTION.max);
    let valid = || {
        (1..=common).filter(move |&r| {
            common % r == 0
                && limits::LOCAL_SHADOW_RESOLUTION.contains(r)
                && limits::LOCAL_SHADOW_FACTOR.contains(largest / r)
        })
    };
    valid()
        .filter(|&r| r <= target)
        .max()
        .or_else(|| valid().find(|&r| r > target))
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The fog's local shadows for a camera: its budget and exponent, and the atlas
/// resolution for the shadow maps of the kinds it takes (`None`: no budget, or Bevy's
/// map sizes allow no resolution, with one warning; the lights are then unshadowed).
pub(crate) fn local_shadow_config(
    fog: &FroxelFog,
    point_map: u32,
    spot_map: u32,
) -> Result<Option<LocalShadowConfig>, InvalidValue> {
    limits::SPOT_SHADOWS.check("FroxelFog.spot_shadows", fog.spot_shadows)?;
    limits::POINT_SHADOWS.check("FroxelFog.point_shadows", fog.point_shadows)?;
    limits::ESM_EXPONENT_LOG_SPACE
        .check("FroxelFog.light_shadow_exponent", fog.light_shadow_exponent)?;
    let mut sizes = Vec::new();
    if fog.point_shadows > 0 {
        sizes.push(point_map);
    }
    if fog.spot_shadows > 0 {
        sizes.push(spot_map);
    }
    if sizes.is_empty() {
        return Ok(None);
    }
    let Some(resolution) = light_shadow_resolution(&sizes) else {
        warn_once!(
            "volfog: no local-light atlas resolution divides Bevy's shadow maps of {sizes:?} texels \
             into 1..=16 parts; point and spot lights light the fog unshadowed"
        );
        return Ok(None);
    };
    Ok(Some(LocalShadowConfig {
        spot_shadows: fog.spot_shadows,
        point_shadows: fog.point_shadows,
        resolution,
        exponent: fog.light_shadow_exponent,
    }))
}

/// The render world's lights as bevy_pbr's `prepare_lights` left them this frame.
#[derive(SystemParam)]
pub(crate) struct BevyLights<'w, 's> {
    meta: Option<Res<'w, GlobalClusterableObjectMeta>>,
    lights: Query<'w, 's, (Entity, &'static ExtractedPointLight)>,
    directional: Query<'w, 's, &'static ExtractedDirectionalLight>,
}

impl BevyLights<'_, '_> {
    /// Counts the lights of this frame as `prepare_lights` does: the clustered point and
    /// spot lights, those with shadows, within the texture limits (`None` without
    /// Bevy's clustered lights).
    pub(crate) fn layout(&self, max_texture_array_layers: usize) -> Option<BevyShadowLayout<'_>> {
        let meta = self.meta.as_deref()?;
        let (mut point_lights, mut point_shadows, mut spot_shadows) = (0, 0, 0);
        for (entity, light) in &self.lights {
            if !meta.entity_to_index.contains_key(&entity) {
                continue;
            }
            let shadows = usize::from(light.shadow_maps_enabled);
            if light.spot_light_angles.is_none() {
                point_lights += 1;
                point_shadows += shadows;
            } else {
                spot_shadows += shadows;
            }
        }
        let directional_shadows = self
            .directional
            .iter()
            .take(MAX_DIRECTIONAL_LIGHTS)
            .filter(|l| l.shadow_maps_enabled)
            .count()
            .min(max_texture_array_layers / MAX_CASCADES_PER_LIGHT);
        let spot_layers =
            max_texture_array_layers.saturating_sub(directional_shadows * MAX_CASCADES_PER_LIGHT);
        Some(BevyShadowLayout {
            meta,
            lights: &self.lights,
            point_lights,
            point_maps: point_shadows.min(max_texture_array_layers / 6),
            spot_maps: spot_shadows.min(spot_layers),
        })
    }
}

/// Where this frame's point and spot light shadow maps are in Bevy's textures.
pub(crate) struct BevyShadowLayout<'a> {
    meta: &'a GlobalClusterableObjectMeta,
    lights: &'a Query<'a, 'a, (Entity, &'static ExtractedPointLight)>,
    /// Point lights in the clustered list (the spot lights follow them).
    point_lights: usize,
    /// Cubes of the point light texture rendered (the first shadowed point lights).
    point_maps: usize,
    /// Spot light maps rendered (the first shadowed spot lights).
    spot_maps: usize,
}

impl BevyShadowLayout<'_> {
    /// The first layer of the spot light maps in the directional light texture of
    /// `layers` layers (after the directional cascades), if it holds them.
    pub(crate) fn spot_base(&self, layers: u32) -> Option<u32> {
        (self.spot_maps > 0)
            .then(|| layers.checked_sub(self.spot_maps as u32))
            .flatten()
    }

    /// The fog's lights that Bevy rendered a shadow map for this frame, with that map
    /// (a cube of the point light texture, a layer of the directional light texture from
    /// `spot_base`) and its camera, the nearest to the fog's camera first (by the distance
    /// to the light's range sphere; the fog's budget takes them in this order).
    pub(crate) fn shadowed_lights(
        &self,
        fog: &ExtractedFroxelFog,
        spot_base: Option<u32>,
    ) -> Vec<ShadowedLight> {
        let eye = fog.view_from_world.inverse().w_axis.truncate();
        let mut found: Vec<(f32, usize, ShadowedLight)> = Vec::new();
        for s in &fog.light_shadows {
            let (Ok((_, light)), Some(&index)) = (
                self.lights.get(s.entity),
                self.meta.entity_to_index.get(&s.entity),
            ) else {
                continue;
            };
            if !light.shadow_maps_enabled {
                continue;
            }
            let (camera, map) = match light.spot_light_angles {
                None if index < self.point_maps => (point_camera(light), index as u32),
                Some((_, outer)) => {
                    let spot = index
                        .checked_sub(self.point_lights)
                        .filter(|&k| k < self.spot_maps);
                    let (Some(spot), Some(base)) = (spot, spot_base) else {
                        continue;
                    };
                    (spot_camera(light, outer), base + spot as u32)
                }
                None => continue,
            };
            if camera.depth_terms().is_err() {
                continue;
            }
            let bias = light.shadow_depth_bias;
            let shadowed = ShadowedLight {
                bias: if limits::LOCAL_SHADOW_BIAS.contains(bias) {
                    bias
                } else {
                    0.0
                },
                ..ShadowedLight::new(s.light, camera).with_shadow(map)
            };
            let distance = (vec3(light.transform.translation()) - eye).length() - light.range;
            found.push((distance, index, shadowed));
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        found.into_iter().map(|(_, _, s)| s).collect()
    }
}

/// A point light's cube camera as Bevy renders and samples it: the faces of
/// `CUBE_MAP_FACES` at the light (no rotation), sampled with `(p - light) * (1, 1, -1)`
/// (`flip_z`), each with an infinite reversed-Z 90-degree projection from
/// `shadow_map_near_z`.
fn point_camera(light: &ExtractedPointLight) -> LightCamera {
    let flip_z = vg::Mat4::from_scale(vg::Vec3::new(1.0, 1.0, -1.0));
    LightCamera::Point {
        cube_from_world: flip_z * vg::Mat4::from_translation(-vec3(light.transform.translation())),
        clip_from_view: mat4(bevy::math::proj::perspective_infinite_reverse(
            FRAC_PI_2,
            1.0,
            light.shadow_map_near_z,
        )),
    }
}

/// A spot light's camera as Bevy renders it: `spot_light_world_from_view` (its
/// position, a basis from its direction) and `spot_light_clip_from_view` (infinite
/// reversed Z over the full outer angle, from `shadow_map_near_z`).
fn spot_camera(light: &ExtractedPointLight, outer: f32) -> LightCamera {
    let world_from_view = Mat4::from(spot_light_world_from_view(&light.transform));
    LightCamera::Spot {
        view_from_world: mat4(world_from_view.inverse()),
        clip_from_view: mat4(spot_light_clip_from_view(outer, light.shadow_map_near_z)),
    }
}

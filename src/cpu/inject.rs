//! Mirror of the inject pass: the scattering of one froxel, composed from the module
//! mirrors exactly as the pass composes the WGSL functions (light and local volume
//! culling aside, which only skip lights and volumes that cannot reach the froxel).

use glam::{UVec3, Vec3, Vec4};

use super::clouds::{CloudMap, cloud_shadow};
use super::density::{
    albedo_with_sample, local_volume_blend, local_volume_blend_textured,
    local_volume_texture_coord, medium_light_transmittance, medium_shape, medium_with_sample,
};
use super::esm::{Layer, esm_cascade, esm_shadow};
use super::froxel::froxel_view_position;
use super::froxel::slice_depth;
use super::lights::{
    ambient_inscatter, fog_light_inscatter, fog_light_transmittance, sun_inscatter,
    sun_inscatter_two_color,
};
use super::local_shadow::{
    ColorLayer, light_cookie, local_shadow_compare, local_shadow_visibility,
};
use super::medium_shadow::MediumShadowVolume;
use super::noise::{noise_animated, noise_animated_texture};
use super::particles::medium_with_particles;
use super::shadow::{shadow_cascade_compare, shadow_tap_visible_depth, shadow_tap_world};
pub use super::texture::DensityTexture;
use crate::options::InjectOptions;
use crate::uniforms::{
    CloudLayer, FogCustomParams, FogFrame, FogLight, FogLighting, FogMedium, FogParticle,
    FogSample, Froxels, LightProjection, LocalVolume, ShadowCascades, ShadowTaps,
};

/// The custom density of the `VOLFOG_INJECT_CUSTOM_DENSITY` variant on the CPU: the Rust
/// twin of the user's WGSL `volfog_custom_density` (the formula written twice, as
/// every volfog module is) and the frame's parameters.
#[derive(Clone, Copy)]
pub struct CustomMedium<'a> {
    /// `(world, time, params) -> FogSample`, as the WGSL function.
    pub density: &'a dyn Fn(Vec3, f32, &FogCustomParams) -> FogSample,
    /// The frame's parameters (`FrameInputs::custom_params`).
    pub params: &'a FogCustomParams,
}

impl std::fmt::Debug for CustomMedium<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CustomMedium")
            .field("params", self.params)
            .finish_non_exhaustive()
    }
}

/// Everything the inject pass reads.
#[derive(Debug, Clone, Copy)]
pub struct InjectInputs<'a> {
    /// Froxel placement.
    pub froxels: &'a Froxels,
    /// Camera and time.
    pub frame: &'a FogFrame,
    /// The medium.
    pub medium: &'a FogMedium,
    /// Sun, ambient, light count.
    pub lighting: &'a FogLighting,
    /// Shadow cascades.
    pub cascades: &'a ShadowCascades,
    /// Filtered ESM layers (one per cascade), or with the compare filter
    /// (`InjectOptions::shadow_compare`) the sun's shadow map itself, one layer per
    /// cascade.
    pub esm: &'a [Layer],
    /// The compare filter's taps (ignored by the ESM).
    pub shadow_taps: &'a ShadowTaps,
    /// Point and spot lights.
    pub lights: &'a [FogLight],
    /// Local volumes.
    pub local_volumes: &'a [LocalVolume],
    /// The variant.
    pub options: InjectOptions,
    /// The density texture (`VOLFOG_INJECT_DENSITY_TEXTURE`); `None` reads 1.
    pub density_texture: Option<&'a DensityTexture>,
    /// The baked noise texture (`VOLFOG_INJECT_NOISE_TEXTURE`, see
    /// [`bake_noise_texture`](super::noise::bake_noise_texture)); `None` evaluates the
    /// procedural noise.
    pub noise_texture: Option<&'a DensityTexture>,
    /// The cloud layer and its map (`VOLFOG_INJECT_CLOUD_SHADOW`); `None` casts no
    /// shadow.
    pub clouds: Option<(&'a CloudMap, &'a CloudLayer)>,
    /// The lights' projections, the local-light ESM atlas and the cookies
    /// (`VOLFOG_INJECT_LOCAL_SHADOWS`); `None` lights every point and spot light
    /// unshadowed.
    pub local_shadows: Option<LocalShadowInputs<'a>>,
    /// The scene depth depth culling reads (device depths), where
    /// `ShadowTaps::use_scene_depth` is 1: the compare filter moves its taps in front of
    /// its surface (`shadow_tap_visible_depth`); `None` leaves them where they are.
    pub scene_depth: Option<&'a Layer>,
    /// The medium-shadow volume (`VOLFOG_INJECT_MEDIUM_SHADOW`, see
    /// [`MediumShadowVolume::fill`]); `None` dims the light by the height profile
    /// alone.
    pub medium_shadow: Option<&'a MediumShadowVolume>,
}

/// What the local-shadow variant of inject reads besides the lights.
#[derive(Debug, Clone, Copy)]
pub struct LocalShadowInputs<'a> {
    /// The `LightProjection`s that `FogLight::projection` indexes.
    pub projections: &'a [LightProjection],
    /// The atlas layers (filtered as the passes filter them; the ESM filter).
    pub atlas: &'a [Layer],
    /// The spot lights' shadow maps (the compare filter).
    pub spot_maps: &'a [Layer],
    /// The point lights' cube maps, six layers a cube (the compare filter).
    pub point_maps: &'a [Layer],
    /// The cookie layers.
    pub cookies: &'a [ColorLayer],
}

/// World position of froxel `id`'s sample this frame.
pub fn froxel_world_position(
    froxels: &Froxels,
    frame: &FogFrame,
    id: UVec3,
    jitter: bool,
) -> (Vec3, f32) {
    let offset = if jitter { frame.jitter } else { Vec3::ZERO };
    let view = froxel_view_position(
        id,
        offset,
        froxels.size,
        froxels.view_from_clip,
        froxels.near,
        froxels.far,
        froxels.curve,
    );
    (frame.world_from_view.transform_point3(view), view.z.abs())
}

/// The froxel whose scattering the inject pass writes at `id` (a volume of `slices`
/// slices): `id` itself, or with the checkerboard the froxel of `id`'s pair of slices
/// (2 k, 2 k + 1) that [`froxel_injected`](super::froxel::froxel_injected) picks this
/// frame (the lower one when the pair has no second slice).
pub fn injected_source(id: UVec3, frame: &FogFrame, slices: u32) -> UVec3 {
    if frame.checkerboard == 0 {
        return id;
    }
    let pair = UVec3::new(id.x, id.y, id.z & !1);
    let picks_second = !super::froxel::froxel_injected(pair, frame.index, 1);
    if picks_second && pair.z + 1 < slices {
        pair + UVec3::Z
    } else {
        pair
    }
}

/// The world position and view depth of shadow tap `tap` of froxel `id` (tap 0: the
/// froxel's sample, as [`froxel_world_position`]; the others through the taps' affine
/// rays, [`shadow_tap_world`]). With a scene depth (`ShadowTaps::use_scene_depth` 1) every
/// tap goes through the rays, its depth moved in front of the surface
/// ([`shadow_tap_visible_depth`]).
pub fn shadow_tap_position(inputs: &InjectInputs<'_>, id: UVec3, tap: u32) -> (Vec3, f32) {
    let t = inputs.shadow_taps;
    let f = inputs.froxels;
    let offset = t.offsets[tap as usize].truncate();
    match inputs.scene_depth {
        Some(depth) if t.use_scene_depth != 0 => {
            let cell = (id.as_vec3() + 0.5 + offset) / f.size.as_vec3();
            let (world, view_depth) =
                shadow_tap_world(f, t, inputs.frame.camera_position, id, offset);
            let slice = |z: u32| slice_depth(z as f32 / f.size.z as f32, f.near, f.far, f.curve);
            let moved = shadow_tap_visible_depth(
                depth,
                cell.truncate(),
                view_depth,
                slice(id.z),
                slice(id.z + 1),
                t.camera_depth_terms,
            );
            let camera = inputs.frame.camera_position;
            (camera + (world - camera) * (moved / view_depth), moved)
        }
        _ if tap == 0 => froxel_world_position(f, inputs.frame, id, inputs.options.jitter),
        _ => shadow_tap_world(f, t, inputs.frame.camera_position, id, offset),
    }
}

/// The sun's visibility at a world position and view depth by the compare filter:
/// the cascade that holds it, 1 beyond the last.
fn sun_compare(inputs: &InjectInputs<'_>, world: Vec3, view_depth: f32) -> f32 {
    let c = inputs.cascades;
    let cascade = esm_cascade(view_depth, c.splits, c.count);
    if cascade >= c.count {
        return 1.0;
    }
    shadow_cascade_compare(
        &inputs.esm[cascade as usize],
        c.light_from_world[cascade as usize],
        world,
        inputs.shadow_taps.sun_reversed_z != 0,
    )
}

/// The mean over froxel `id`'s `taps` shadow taps ([`shadow_tap_position`]) of a
/// visibility at a world position and view depth.
fn tap_mean(inputs: &InjectInputs<'_>, id: UVec3, taps: u32, f: impl Fn(Vec3, f32) -> f32) -> f32 {
    let taps = taps.max(1);
    let sum: f32 = (0..taps)
        .map(|t| {
            let (world, depth) = shadow_tap_position(inputs, id, t);
            f(world, depth)
        })
        .sum();
    sum / taps as f32
}

/// The scattering of froxel `id`: rgb = sigma_s L_in, a = sigma_t; the compare filter
/// takes `ShadowTaps::count` taps.
pub fn froxel_scattering(inputs: &InjectInputs<'_>, id: UVec3) -> Vec4 {
    froxel_scattering_taps(inputs, id, inputs.shadow_taps.count)
}

/// [`froxel_scattering`] with `taps` shadow taps for the compare filter (the inject
/// pass takes `ShadowTaps::fresh` where a froxel has no history).
pub fn froxel_scattering_taps(inputs: &InjectInputs<'_>, id: UVec3, taps: u32) -> Vec4 {
    froxel_scattering_with(inputs, id, taps, None)
}

/// [`froxel_scattering_taps`] of the custom-density variant
/// (`VOLFOG_INJECT_CUSTOM_DENSITY`) with `custom` its density, or of the others with
/// `None`: the custom sample at the froxel's position is added to the medium before
/// the local volumes blend, its albedo mixed in by extinction.
pub fn froxel_scattering_with(
    inputs: &InjectInputs<'_>,
    id: UVec3,
    taps: u32,
    custom: Option<CustomMedium<'_>>,
) -> Vec4 {
    froxel_scattering_particles(inputs, id, taps, custom, &[])
}

/// [`froxel_scattering_with`] of the particle variant (`VOLFOG_INJECT_PARTICLES`):
/// the first `FogMedium::particle_count` of `particles` are added to the medium after
/// the local volumes ([`medium_with_particles`]); with `particle_count` 0 (or no
/// particles) it is [`froxel_scattering_with`].
pub fn froxel_scattering_particles(
    inputs: &InjectInputs<'_>,
    id: UVec3,
    taps: u32,
    custom: Option<CustomMedium<'_>>,
    particles: &[FogParticle],
) -> Vec4 {
    let (world, view_depth) =
        froxel_world_position(inputs.froxels, inputs.frame, id, inputs.options.jitter);
    let view_dir = (world - inputs.frame.camera_position).normalize();
    let m = inputs.medium;
    let (mut medium, mut albedo) = medium_at(inputs, world, custom);
    let in_use = &particles[..particles.len().min(m.particle_count as usize)];
    if inputs.options.particles && !in_use.is_empty() {
        (medium, albedo) = medium_with_particles(medium, albedo, in_use, world);
    }
    let emission = medium.truncate().max(Vec3::ZERO);
    let sigma_t = medium.w.max(0.0);
    let compare = inputs.options.shadow_compare;
    let shadow = if !compare {
        esm_shadow(
            inputs.esm,
            inputs.cascades,
            world,
            view_depth,
            inputs.options.esm_log_space,
        )
    } else if inputs.cascades.count > 0 {
        // The sample (tap 0) sits at `world`, as in the pass.
        tap_mean(inputs, id, taps, |w, d| sun_compare(inputs, w, d))
    } else {
        1.0
    };
    let shadow = match (inputs.options.cloud_shadow, inputs.clouds) {
        (true, Some((map, layer))) => shadow * cloud_shadow(map, layer, world),
        _ => shadow,
    };
    let l = inputs.lighting;
    let through = l.transmittance != 0;
    let medium_shadow = inputs
        .medium_shadow
        .filter(|_| inputs.options.medium_shadow);
    let shadow = match (through, medium_shadow) {
        (true, Some(v)) => {
            shadow * (medium_light_transmittance(m, world, l.sun.direction) * v.sun(world)).min(1.0)
        }
        (true, None) => shadow * medium_light_transmittance(m, world, l.sun.direction),
        (false, _) => shadow,
    };
    let mut light = if inputs.options.two_color_phase {
        sun_inscatter_two_color(&l.sun, shadow, view_dir)
    } else {
        sun_inscatter(&l.sun, shadow, view_dir, m.phase_g)
    };
    light += ambient_inscatter(l.ambient_r, l.ambient_g, l.ambient_b, view_dir, m.phase_g);
    for light_source in inputs.lights.iter().take(l.light_count as usize) {
        let mut inscatter = fog_light_inscatter(light_source, world, view_dir, m.phase_g);
        if through {
            let profile = fog_light_transmittance(m, light_source, world);
            inscatter *= match medium_shadow {
                Some(v) => (profile * v.light(light_source, world)).min(1.0),
                None => profile,
            };
        }
        if let Some(local) = inputs
            .local_shadows
            .filter(|_| inputs.options.local_shadows)
            && let Some(p) = local.projections.get(light_source.projection as usize)
        {
            let visibility = if compare {
                tap_mean(inputs, id, taps, |w, _| {
                    local_shadow_compare(local.spot_maps, local.point_maps, p, w)
                })
            } else {
                local_shadow_visibility(local.atlas, p, world, inputs.options.esm_log_space)
            };
            inscatter *= visibility * light_cookie(local.cookies, p, world);
        }
        light += inscatter;
    }
    if sigma_t <= 0.0 {
        return emission.extend(0.0).min(Vec4::splat(HALF_MAX));
    }
    (albedo * sigma_t * light + emission)
        .extend(sigma_t)
        .min(Vec4::splat(HALF_MAX))
}

/// The medium at a world position as the inject pass composes it: rgb the emission
/// per metre, a the extinction (before the clamp at 0), and the albedo: the height
/// profile with noise and density texture, the custom density (`custom`, the
/// custom-density variant) and the local volumes blended in buffer order.
pub fn medium_at(
    inputs: &InjectInputs<'_>,
    world: Vec3,
    custom: Option<CustomMedium<'_>>,
) -> (Vec4, Vec3) {
    let m = inputs.medium;
    let (time, octaves) = (inputs.frame.time, inputs.options.noise_octaves);
    let noise = match (inputs.options.noise_texture, inputs.noise_texture) {
        (true, Some(t)) => noise_animated_texture(t, world, m.noise_scale, m.wind, time, octaves),
        _ => noise_animated(world, m.noise_scale, m.wind, time, octaves),
    };
    let texture_factor = match (inputs.options.density_texture, inputs.density_texture) {
        (true, Some(t)) if m.textured != 0 => {
            let uvw = world * m.texture_scale + m.texture_offset
                - m.wind * inputs.frame.time * m.texture_scale;
            t.sample(uvw)
        }
        _ => 1.0,
    };
    let shape = medium_shape(m, world, noise, texture_factor);
    let mut medium = m.emission.extend(m.density) * shape;
    let mut albedo = m.albedo;
    if let Some(c) = custom {
        let sample = (c.density)(world, inputs.frame.time, c.params);
        albedo = albedo_with_sample(medium, albedo, &sample);
        medium = medium_with_sample(medium, &sample);
    }
    // In buffer order, each by its blend mode.
    for v in inputs
        .local_volumes
        .iter()
        .take(m.local_volume_count as usize)
    {
        medium = match (inputs.options.density_texture, inputs.density_texture) {
            (true, Some(t)) => local_volume_blend_textured(
                medium,
                v,
                world,
                t.sample(local_volume_texture_coord(v, world)),
            ),
            _ => local_volume_blend(medium, v, world),
        };
    }
    (medium, albedo)
}

/// Largest finite rgba16float value; the inject output is clamped to it.
pub const HALF_MAX: f32 = 65504.0;

//! A [`TruthScene`] rendered by volfog's froxel pipeline: one frame of
//! [`VolumetricFog`] (no temporal blending, no jitter, no noise) applied over the
//! scene's depth buffer onto a black and a white target.
//!
//! What the CPU prepares, from the scene's boxes by ray casting (slab tests):
//! - the depth buffer: for each pixel centre the camera ray's first hit, written as the
//!   standard-z depth of the projection (1 where the ray hits nothing);
//! - the sun's cascaded shadow map: for each texel the first hit of a ray cast along
//!   `-sun.direction` from above every box, as the depth of the cascade's orthographic
//!   projection (0 nearest the sun, standard z).
//!
//! The apply pass blends `dst * T + L`: over black it leaves the in-scattered radiance
//! `L`, and white minus black is the transmittance `T` from the eye to the depth
//! buffer's surface.

use glam::{Mat4, UVec3, Vec2, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::froxel::{ndc_from_uv, view_from_ndc};
use volfog::limits::{self, InvalidValue, check};
use volfog::pipeline::{
    FogConfig, FogError, FrameInputs, VolumetricFog, cascade_projection, cascade_splits,
};
use volfog::uniforms::{
    DirectionalLight, FogLight, FogMedium, HeightFog, LocalVolume, ShadowCascades, VolumeShape,
};

use super::scene::{TruthBox, TruthImage, TruthScene, TruthShape};
use crate::gpu::{Gpu, GpuError, texture_2d};
use crate::selfcheck::{depth_array_texture, depth_texture};

/// Near clipping plane of the camera's projection (m), or half of `camera.near` where
/// that is nearer (the froxel volume starts at `camera.near`).
pub const NEAR_CLIP: f32 = 0.05;

/// The projection's far clipping plane is this many times `camera.far`, so surfaces a
/// little beyond the froxel volume still get a depth below 1.
pub const FAR_CLIP_FACTOR: f32 = 4.0;

/// Source radius of the point and spot lights (m): the inverse-square law is clamped
/// at this distance.
pub const LIGHT_RADIUS: f32 = 0.01;

/// A point or spot light's range is this many times the largest distance from it to
/// the froxel volume, so volfog's range window `(1 - (d / range)^4)^2` stays above
/// `1 - 2 / 20^4 = 1 - 1.25e-5` everywhere in view.
pub const LIGHT_RANGE_FACTOR: f32 = 20.0;

/// Split scheme of the cascades: 0.5 blends logarithmic and uniform splits equally.
pub const CASCADE_LAMBDA: f32 = 0.5;

/// Errors of [`render`].
#[derive(Debug, thiserror::Error)]
pub enum TruthError {
    /// The scene or the options hold a value volfog or this renderer rejects.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// The froxel pipeline rejected its configuration, inputs or textures.
    #[error(transparent)]
    Fog(#[from] FogError),
    /// A GPU operation failed (validation error, readback).
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// How the froxel pipeline is configured for a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolfogOptions {
    /// Froxels across the screen (x, y) and depth slices (z), `FogConfig::volume_size`.
    pub volume_size: UVec3,
    /// Attenuate the light reaching each froxel by the medium on its way
    /// (`FogConfig::light_transmittance`): the sun's from the medium's top, point and
    /// spot lights' along the segment to the light.
    pub light_transmittance: bool,
    /// ESM exponent for shadow-map depths in [0, 1] (`FogConfig::esm_exponent`, at most
    /// 88): behind an occluder the sun's visibility falls below 5 % once the receiver
    /// lies `3 / esm_exponent` of the cascade's depth range behind it.
    pub esm_exponent: f32,
    /// ESM texels per side of a cascade (`FogConfig::esm_resolution`); the shadow map
    /// this renderer casts has 4x as many per side.
    pub esm_resolution: u32,
    /// Shadow cascades of the sun, 1 to 4 (`FogConfig::cascades`), between the froxel
    /// volume's near and far planes.
    pub cascades: u32,
}

impl Default for VolfogOptions {
    /// `FogConfig`'s defaults: 160 x 90 x 128 froxels, light transmittance on,
    /// exponent 40, 256-texel ESM, 4 cascades.
    fn default() -> Self {
        let config = FogConfig::default();
        Self {
            volume_size: config.volume_size,
            light_transmittance: config.light_transmittance,
            esm_exponent: config.esm_exponent,
            esm_resolution: config.esm_resolution,
            cascades: config.cascades,
        }
    }
}

/// The camera of a scene as volfog takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthView {
    /// World -> view (`look_at_mat4(position, target, +Y)`).
    pub view_from_world: Mat4,
    /// View -> clip: standard-z perspective from `min(NEAR_CLIP, near / 2)` to
    /// `FAR_CLIP_FACTOR * far`.
    pub clip_from_view: Mat4,
    /// The inverse of `view_from_world`.
    pub world_from_view: Mat4,
    /// The inverse of `clip_from_view`.
    pub view_from_clip: Mat4,
}

impl TruthView {
    /// The matrices of `scene`'s camera. Rejects an empty image, a field of view
    /// outside (0, 180) degrees, planes without `0 < near < far`, and a camera looking
    /// straight up or down (the view's up is +Y).
    pub fn new(scene: &TruthScene) -> Result<Self, InvalidValue> {
        let [w, h] = scene.resolution;
        check(
            w > 0 && h > 0,
            "TruthScene.resolution",
            scene.resolution,
            "at least 1 x 1 pixels",
        )?;
        let c = &scene.camera;
        check(
            c.fov_y_deg.is_finite() && c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0,
            "TruthCamera.fov_y_deg",
            c.fov_y_deg,
            "0 < fov < 180 degrees",
        )?;
        check(
            c.far.is_finite() && c.near.is_finite() && c.near > 0.0 && c.far > c.near,
            "TruthCamera.near",
            (c.near, c.far),
            "0 < near < far (finite, m)",
        )?;
        let forward = (c.target - c.position).normalize_or_zero();
        check(
            c.position.is_finite()
                && c.target.is_finite()
                && forward != Vec3::ZERO
                && forward.cross(Vec3::Y).length() > 1e-4,
            "TruthCamera.target",
            (c.position, c.target),
            "finite points apart, not straight above or below the eye",
        )?;
        let view_from_world = glam::camera::rh::view::look_at_mat4(c.position, c.target, Vec3::Y);
        let clip_from_view = glam::camera::rh::proj::directx::perspective(
            c.fov_y_deg.to_radians(),
            w as f32 / h as f32,
            NEAR_CLIP.min(0.5 * c.near),
            FAR_CLIP_FACTOR * c.far,
        );
        Ok(Self {
            view_from_world,
            clip_from_view,
            world_from_view: view_from_world.inverse(),
            view_from_clip: clip_from_view.inverse(),
        })
    }

    /// The unit world-space direction of the ray through the centre of pixel (x, y)
    /// (row 0 at the top) of an image of `resolution` pixels: the pixel's uv mapped to
    /// normalised device coordinates as volfog's apply pass maps it.
    pub fn pixel_ray(&self, resolution: [u32; 2], x: u32, y: u32) -> Vec3 {
        let uv = Vec2::new(
            (x as f32 + 0.5) / resolution[0].max(1) as f32,
            (y as f32 + 0.5) / resolution[1].max(1) as f32,
        );
        let view = view_from_ndc(ndc_from_uv(uv).extend(0.5), self.view_from_clip);
        self.world_from_view
            .transform_vector3(view)
            .normalize_or_zero()
    }
}

/// The unit world-space direction of the camera ray through the centre of pixel (x, y)
/// (row 0 at the top), as volfog's apply pass maps it; zero for a degenerate camera.
pub fn pixel_ray(scene: &TruthScene, x: u32, y: u32) -> Vec3 {
    TruthView::new(scene).map_or(Vec3::ZERO, |view| view.pixel_ray(scene.resolution, x, y))
}

/// The unit directions of every pixel's camera ray, row-major from the top.
fn pixel_rays<'a>(scene: &'a TruthScene, view: &'a TruthView) -> impl Iterator<Item = Vec3> + 'a {
    let [w, h] = scene.resolution;
    (0..w * h).map(move |i| view.pixel_ray(scene.resolution, i % w, i / w))
}

/// The first hit `t >= 0` (in units of `|dir|`) of the ray `origin + t dir` with the
/// boxes (slab test); 0 when the origin lies inside one, `None` when it hits none.
pub fn trace(origin: Vec3, dir: Vec3, boxes: &[TruthBox]) -> Option<f32> {
    let inv = dir.recip();
    let mut best = f32::INFINITY;
    for b in boxes {
        let a = (b.min - origin) * inv;
        let c = (b.max - origin) * inv;
        let near = a.min(c).max_element();
        let far = a.max(c).min_element();
        if near <= far && far >= 0.0 {
            best = best.min(near.max(0.0));
        }
    }
    best.is_finite().then_some(best)
}

/// Whether `p` lies inside one of the boxes (faces included).
pub fn inside(p: Vec3, boxes: &[TruthBox]) -> bool {
    boxes
        .iter()
        .any(|b| p.cmpge(b.min).all() && p.cmple(b.max).all())
}

/// Per pixel (row-major from the top) the distance (m) along the camera ray from the
/// eye to its first occluder, infinity where it hits none (or the camera is
/// degenerate).
pub fn pixel_depths(scene: &TruthScene) -> Vec<f32> {
    let [w, h] = scene.resolution;
    let Ok(view) = TruthView::new(scene) else {
        return vec![f32::INFINITY; (w * h) as usize];
    };
    let eye = scene.camera.position;
    pixel_rays(scene, &view)
        .map(|dir| trace(eye, dir, &scene.occluders).unwrap_or(f32::INFINITY))
        .collect()
}

/// The distance (m) along the camera ray `dir` from the eye to the froxel volume's far
/// plane (view depth `camera.far`).
pub fn far_distance(scene: &TruthScene, dir: Vec3) -> f32 {
    let c = &scene.camera;
    let forward = (c.target - c.position).normalize_or_zero();
    c.far / dir.dot(forward).max(1e-6)
}

/// Renders `scene` with volfog's froxel pipeline: radiance over black and
/// transmittance per pixel (rgb; volfog's extinction is grey, so the three channels
/// of the transmittance agree).
///
/// The scene maps onto volfog as follows: the medium is a [`FogMedium`] without noise
/// or emission whose `top_height` is the scene's top; the sun a [`DirectionalLight`]
/// (none: colour 0 and no cascades) shadowed by cascades cast from the occluders; each
/// point light a [`FogLight::point`] and each spot a [`FogLight::spot`] of radius
/// [`LIGHT_RADIUS`] and a range [`LIGHT_RANGE_FACTOR`] times their farthest distance
/// to the volume; each local volume a [`LocalVolume`] box or ellipsoid. Ambient light
/// and the far-plane tail are off. Note that volfog's spot cone falls off as a
/// smoothstep in the cosine of the angle, not linearly in the angle.
pub fn render(
    gpu: &Gpu,
    scene: &TruthScene,
    options: &VolfogOptions,
) -> Result<TruthImage, TruthError> {
    let view = TruthView::new(scene)?;
    let [width, height] = scene.resolution;
    let camera = &scene.camera;
    let config = FogConfig {
        volume_size: options.volume_size,
        near: camera.near,
        far: camera.far,
        esm_resolution: options.esm_resolution,
        cascades: options.cascades,
        esm_exponent: options.esm_exponent,
        max_lights: limits::MAX_LIGHTS,
        max_local_volumes: (scene.volumes.len() as u32).max(1),
        jitter: false,
        temporal: false,
        amortize: false,
        local_shadows: None,
        light_transmittance: options.light_transmittance,
        ..FogConfig::default()
    };
    config.validate()?;

    let m = &scene.medium;
    let medium = FogMedium {
        albedo: m.albedo,
        density: m.density,
        up: Vec3::Y,
        height_falloff: m.falloff,
        wind: Vec3::ZERO,
        base_height: m.base_height,
        noise_strength: 0.0,
        phase_g: m.phase_g,
        emission: Vec3::ZERO,
        top_height: m.top,
        ..FogMedium::default()
    };
    let sun = match &scene.sun {
        Some(s) => DirectionalLight {
            direction: s.direction.normalize_or_zero(),
            color: s.color,
            fog_intensity: 1.0,
            ..DirectionalLight::default()
        },
        None => DirectionalLight {
            direction: Vec3::Y,
            color: Vec3::ZERO,
            fog_intensity: 1.0,
            ..DirectionalLight::default()
        },
    };
    sun.validate()?;
    let corners = volume_corners(&view, camera.near, camera.far);
    let range = |position: Vec3| {
        let d = corners
            .iter()
            .map(|c| c.distance(position))
            .fold(0.0f32, f32::max);
        LIGHT_RANGE_FACTOR * d.max(1.0)
    };
    let mut lights = Vec::with_capacity(scene.points.len() + scene.spots.len());
    for p in &scene.points {
        lights.push(FogLight {
            radius: LIGHT_RADIUS,
            ..FogLight::point(p.position, p.color, range(p.position))
        });
    }
    for s in &scene.spots {
        lights.push(FogLight {
            radius: LIGHT_RADIUS,
            ..FogLight::spot(
                s.position,
                s.direction,
                s.color,
                range(s.position),
                s.inner_deg.to_radians(),
                s.outer_deg.to_radians(),
            )
        });
    }
    let volumes = scene
        .volumes
        .iter()
        .map(|v| {
            LocalVolume::new(
                Mat4::from_scale_rotation_translation(
                    v.half_extents,
                    glam::Quat::IDENTITY,
                    v.center,
                ),
                match v.shape {
                    TruthShape::Box => VolumeShape::Box,
                    TruthShape::Ellipsoid => VolumeShape::Ellipsoid,
                },
                v.density,
                v.edge,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let shadow = scene
        .sun
        .as_ref()
        .map(|_| sun_shadow(&config, &view, sun.direction, &scene.occluders));
    let inputs = FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::constant(Vec3::ZERO),
        lights: &lights,
        local_volumes: &volumes,
        cascades: shadow.as_ref().map_or(ShadowCascades::default(), |s| s.0),
        tail: HeightFog::none(),
        ..FrameInputs::new(view.view_from_world, view.clip_from_view, 0.0)
    };
    inputs.validate(&config)?;
    let depths = scene_depth(scene, &view);

    let images = gpu.checked(|| -> Result<[Vec<Vec4>; 2], TruthError> {
        let mut fog = VolumetricFog::new(&gpu.device, &config)?;
        if let Some((_, layers)) = &shadow {
            let side = config.esm_resolution * 4;
            let slices: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
            let map = depth_array_texture(gpu, side, side, &slices)?;
            fog.set_shadow_map(&gpu.device, &map)?;
        }
        let depth = depth_texture(gpu, width, height, &depths)?;
        fog.set_scene_depth(&gpu.device, &depth, 0)?;
        // Temporal blending is off, so the first frame reads no history.
        fog.prepare(&gpu.queue, &inputs)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder)?;
        gpu.queue.submit([encoder.finish()]);
        apply_over(gpu, &fog, &depth, (width, height))
    })??;
    let [black, white] = images;
    Ok(TruthImage {
        width,
        height,
        radiance: black.iter().map(|b| b.truncate()).collect(),
        transmittance: black
            .iter()
            .zip(&white)
            .map(|(b, w)| (w.truncate() - b.truncate()).max(Vec3::ZERO))
            .collect(),
    })
}

/// The eight world-space corners of the view frustum between view depths `near` and
/// `far` (m).
fn volume_corners(view: &TruthView, near: f32, far: f32) -> [Vec3; 8] {
    let mut out = [Vec3::ZERO; 8];
    for (i, corner) in out.iter_mut().enumerate() {
        let ndc = Vec2::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
        );
        let depth = if i & 4 == 0 { near } else { far };
        let ray = view_from_ndc(ndc.extend(0.5), view.view_from_clip);
        *corner = view
            .world_from_view
            .transform_point3(ray * (depth / ray.z.abs().max(1e-30)));
    }
    out
}

/// The depth buffer of the scene: per pixel the projection's standard-z depth of the
/// camera ray's first hit, 1 where it hits nothing.
fn scene_depth(scene: &TruthScene, view: &TruthView) -> Vec<f32> {
    let eye = scene.camera.position;
    pixel_rays(scene, view)
        .map(|dir| match trace(eye, dir, &scene.occluders) {
            Some(t) => {
                let p = view.view_from_world.transform_point3(eye + dir * t);
                view.clip_from_view.project_point3(p).z.clamp(0.0, 1.0)
            }
            None => 1.0,
        })
        .collect()
}

/// The sun's cascades and their shadow-map depths (one layer per cascade, row-major
/// from the top, `4 * esm_resolution` texels per side).
///
/// Cascade `i` covers the bounding sphere (centre `c`, radius `r`) of the view frustum
/// between its split depths. Its orthographic projection spans that sphere's square
/// footprint (2 % wider) across the sun, and along it from `r` below the centre to
/// `r + m` above it (towards the sun): `m` is the height above the sphere of the
/// highest occluder in the footprint, at most `0.35 r`. Occluders higher still are
/// clamped to depth 0 (pancaking): receivers of the cascade lie at least
/// `0.35 r / (2.35 r) = 0.15` below them in depth, where the ESM visibility is below
/// `exp(-0.15 c)` (0.25 % at c = 40).
fn sun_shadow(
    config: &FogConfig,
    view: &TruthView,
    sun: Vec3,
    boxes: &[TruthBox],
) -> (ShadowCascades, Vec<Vec<f32>>) {
    let count = config.cascades;
    let splits = cascade_splits(count, config.near, config.far, CASCADE_LAMBDA);
    let mut cascades = ShadowCascades {
        splits,
        count,
        exponent: config.esm_exponent,
        ..Default::default()
    };
    // Above every box: where the rays towards the ground start.
    let top = boxes
        .iter()
        .flat_map(|b| {
            (0..8).map(move |k| {
                Vec3::new(
                    if k & 1 == 0 { b.min.x } else { b.max.x },
                    if k & 2 == 0 { b.min.y } else { b.max.y },
                    if k & 4 == 0 { b.min.z } else { b.max.z },
                )
                .dot(sun)
            })
        })
        .fold(f32::NEG_INFINITY, f32::max);
    let size = config.esm_resolution * 4;
    let mut layers = Vec::with_capacity(count as usize);
    for i in 0..count as usize {
        let z0 = if i == 0 { config.near } else { splits[i - 1] };
        let corners = volume_corners(view, z0, splits[i]);
        let center = corners.iter().copied().sum::<Vec3>() / 8.0;
        let radius = corners
            .iter()
            .map(|c| c.distance(center))
            .fold(0.0f32, f32::max)
            .max(1e-3);
        let half = radius * 1.02;
        // The lateral grid of the texels does not depend on the depth range: trace
        // first, then place the near plane.
        let probe = cascade_projection(sun, center, half, 2.0 * radius);
        let inv = probe.inverse();
        let texel_world = |x: f32, y: f32| {
            inv.project_point3(Vec3::new(
                2.0 * x / size as f32 - 1.0,
                1.0 - 2.0 * y / size as f32,
                0.0,
            ))
        };
        let origin = texel_world(0.5, 0.5);
        let step_x = texel_world(1.5, 0.5) - origin;
        let step_y = texel_world(0.5, 1.5) - origin;
        let sphere_top = center.dot(sun) + radius;
        let start = top.max(sphere_top) + 1.0;
        let lift = sun * (start - origin.dot(sun));
        // Height along the sun of each texel's first hit, NaN where there is none.
        let hits: Vec<f32> = (0..size * size)
            .map(|t| {
                let p = origin + step_x * (t % size) as f32 + step_y * (t / size) as f32 + lift;
                trace(p, -sun, boxes).map_or(f32::NAN, |t| start - t)
            })
            .collect();
        let highest = hits
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .fold(f32::NEG_INFINITY, f32::max);
        let margin = (highest - sphere_top).clamp(0.0, 0.35 * radius);
        let range = 2.0 * radius + margin;
        let near = sphere_top + margin;
        cascades.light_from_world[i] =
            cascade_projection(sun, center + sun * (0.5 * margin), half, range);
        layers.push(
            hits.iter()
                .map(|&h| {
                    if h.is_nan() {
                        1.0
                    } else {
                        ((near - h) / range).clamp(0.0, 1.0)
                    }
                })
                .collect(),
        );
    }
    (cascades, layers)
}

/// Applies the prepared fog over `depth` onto a black and a white target (rgba32float
/// where the device blends it, else rgba16float) and reads both back.
fn apply_over(
    gpu: &Gpu,
    fog: &VolumetricFog,
    depth: &wgpu::Texture,
    (w, h): (u32, u32),
) -> Result<[Vec<Vec4>; 2], TruthError> {
    let wide = gpu
        .device
        .features()
        .contains(wgpu::Features::FLOAT32_BLENDABLE);
    let format = if wide {
        wgpu::TextureFormat::Rgba32Float
    } else {
        wgpu::TextureFormat::Rgba16Float
    };
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let apply = fog.create_apply(&gpu.device, format)?;
    let group = apply.depth_bind_group(&gpu.device, &depth_view);
    let mut out = [Vec::new(), Vec::new()];
    for (base, image) in [0.0f32, 1.0].into_iter().zip(&mut out) {
        let color = texture_2d(
            &gpu.device,
            "truth colour",
            (w, h),
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
        );
        let texels = (w * h) as usize;
        let bytes: Vec<u8> = if wide {
            bytemuck::cast_slice(&vec![base; 4 * texels]).to_vec()
        } else {
            bytemuck::cast_slice(&vec![half::f16::from_f32(base); 4 * texels]).to_vec()
        };
        let texel_bytes = if wide { 16 } else { 8 };
        gpu.queue.write_texture(
            color.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * texel_bytes),
                rows_per_image: Some(h),
            },
            color.size(),
        );
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.record_apply(
            &mut encoder,
            &apply,
            &color.create_view(&Default::default()),
            &group,
        )?;
        gpu.queue.submit([encoder.finish()]);
        *image = if wide {
            let raw = gpu.read_texture_raw(&color, 16)?;
            bytemuck::pod_collect_to_vec::<u8, f32>(&raw)
                .chunks_exact(4)
                .map(Vec4::from_slice)
                .collect()
        } else {
            gpu.read_texture_rgba16f(&color)?
        };
    }
    Ok(out)
}

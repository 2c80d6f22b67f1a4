//! A [`TruthScene`] rendered by volfog's froxel pipeline: a still camera for
//! [`VolfogOptions::frames`] frames of [`VolumetricFog`] (by default jittered and
//! blended with the reprojected history, `FogConfig`'s defaults), applied over the
//! scene's depth buffer onto a black and a white target after the first frame, one
//! jitter cycle before the last and after the last.
//!
//! What the CPU prepares, from the scene's boxes by ray casting (slab tests):
//! - the depth buffer: for each pixel centre the camera ray's first hit, written as the
//!   standard-z depth of the projection (1 where the ray hits nothing);
//! - the sun's cascaded shadow map and the point and spot lights' depth maps
//!   ([`super::shadow_maps`]).
//!
//! The apply pass blends `dst * T + L`: over black it leaves the in-scattered radiance
//! `L`, and white minus black is the transmittance `T` from the eye to the depth
//! buffer's surface.

use glam::{Mat4, Vec2, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::froxel::{ndc_from_uv, view_from_ndc};
use volfog::limits::{self, InvalidValue, check};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, ShadowedLight, VolumetricFog};
use volfog::uniforms::{
    DirectionalLight, FogLight, FogMedium, HeightFog, LocalVolume, MediumShadowConfig,
    ShadowCascades, VolumeShape,
};

use super::scene::{TruthImage, TruthScene, TruthShape};
pub use super::shadow_maps::{inside, trace};
use super::shadow_maps::{lamp_shadows, sun_shadow};
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
/// `1 - 2 / 20^4 = 1 - 1.25e-5` everywhere in view. The range is also the depth scale
/// of the lamps' exponential shadow maps (`LocalShadowConfig::exponent` applies to
/// depths divided by it).
pub const LIGHT_RANGE_FACTOR: f32 = 20.0;

/// Frames rendered by default: with the history weight 0.9 of `FogConfig`'s default
/// the first frame's share of the last image is `0.9^47 = 7e-3`, and the jitter
/// repeats every [`JITTER_CYCLE`] frames (three cycles).
pub const CONVERGED_FRAMES: u32 = 48;

/// Frames after which volfog's froxel jitter repeats
/// (`volfog::cpu::froxel::froxel_jitter`, Halton (2, 3, 5) of `frame % 16 + 1`): the
/// image this many frames before the last has the same jitter phase, so the change
/// between the two is what remains of the history's convergence.
pub const JITTER_CYCLE: u32 = 16;

/// The lamps' depth maps have this many texels per side for each texel of volfog's
/// local-light atlas (`LocalShadowConfig::resolution`), as the sun's shadow map has 4
/// per ESM texel.
pub const LAMP_MAP_FACTOR: u32 = 4;

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
#[derive(Debug, Clone, PartialEq)]
pub struct VolfogOptions {
    /// The fog's configuration. The renderer takes it as it is (grid, shadow filters,
    /// jitter, temporal blending, light transmittance, ...) except for what the scene
    /// sets: `near` and `far` are the camera's, `max_lights` and `max_local_volumes`
    /// at least the scene's counts. With `local_shadows` the point and spot lights get
    /// depth maps cast from the occluders (`None`: the lamps light the fog
    /// unshadowed).
    pub config: FogConfig,
    /// Frames of a still camera, >= 1 (the jitter and the history settle over them).
    pub frames: u32,
    /// Texels per side of the lamps' depth maps per atlas texel (1 to 16).
    pub lamp_map_factor: u32,
}

impl VolfogOptions {
    /// The options with `config` changed by `f` (the rest as given).
    pub fn with_config(mut self, f: impl FnOnce(&mut FogConfig)) -> Self {
        f(&mut self.config);
        self
    }

    /// The blurred exponential shadow maps of the sun and the lamps
    /// ([`ShadowFilter::Esm`]) at their former default: 256 ESM texels per cascade,
    /// exponent 40, the lamps' atlas at 256 texels and exponent 80, the 11-tap blur.
    pub fn esm_256(self) -> Self {
        self.with_config(|c| {
            c.shadow_filter = ShadowFilter::Esm;
            c.esm_resolution = 256;
            c.esm_exponent = 40.0;
            c.esm_blur_radius = 5;
            c.esm_log_space = false;
            if let Some(local) = c.local_shadows.as_mut() {
                local.resolution = 256;
                local.exponent = 80.0;
            }
        })
    }
}

impl Default for VolfogOptions {
    /// `FogConfig::default()` (160 x 90 x 128 froxels, the compare shadow filter,
    /// jitter, temporal blending at history weight 0.9, light transmittance, shadowed
    /// lamps) with the medium's shadows at `MediumShadowConfig::default()` (they change
    /// nothing where the medium is its bare height profile, as in the scenes without
    /// local volumes), [`CONVERGED_FRAMES`] frames, lamp maps [`LAMP_MAP_FACTOR`] times
    /// the atlas.
    fn default() -> Self {
        Self {
            config: FogConfig {
                medium_shadows: Some(MediumShadowConfig::default()),
                ..FogConfig::default()
            },
            frames: CONVERGED_FRAMES,
            lamp_map_factor: LAMP_MAP_FACTOR,
        }
    }
}

/// What [`render`] makes of a scene.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VolfogRender {
    /// The image after the first frame.
    pub first: TruthImage,
    /// The image after the last frame (the converged image; the first with one frame).
    pub converged: TruthImage,
    /// The image [`JITTER_CYCLE`] frames before the last, if there were more frames.
    pub cycle_before: Option<TruthImage>,
    /// Frames rendered.
    pub frames: u32,
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

/// The configuration [`render`] gives volfog for `scene`: `options.config` with the
/// camera's near and far planes and room for the scene's lights and local volumes.
pub fn fog_config(scene: &TruthScene, options: &VolfogOptions) -> Result<FogConfig, InvalidValue> {
    check(
        options.frames >= 1,
        "VolfogOptions.frames",
        options.frames,
        "at least 1 frame",
    )?;
    limits::LOCAL_SHADOW_FACTOR.check("VolfogOptions.lamp_map_factor", options.lamp_map_factor)?;
    let lights = (scene.points.len() + scene.spots.len()) as u32;
    let config = FogConfig {
        near: scene.camera.near,
        far: scene.camera.far,
        max_lights: options.config.max_lights.max(lights),
        max_area_lights: options.config.max_area_lights.max(scene.areas.len() as u32),
        max_local_volumes: options
            .config
            .max_local_volumes
            .max(scene.volumes.len() as u32),
        ..options.config.clone()
    };
    config.validate()?;
    Ok(config)
}

/// The scene's medium as volfog takes it: no noise or emission, the scene's top.
pub fn fog_medium(scene: &TruthScene) -> FogMedium {
    let m = &scene.medium;
    FogMedium {
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
    }
}

/// The scene's sun as volfog takes it (colour 0 for none).
pub fn fog_sun(scene: &TruthScene) -> DirectionalLight {
    match &scene.sun {
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
    }
}

/// The scene's point lights, then its spot lights, as volfog takes them: radius
/// [`LIGHT_RADIUS`], range [`LIGHT_RANGE_FACTOR`] times the farthest distance from the
/// light to the froxel volume's corners.
pub fn fog_lights(scene: &TruthScene, view: &TruthView) -> Vec<FogLight> {
    let corners = volume_corners(view, scene.camera.near, scene.camera.far);
    let range = |position: Vec3| {
        let d = corners
            .iter()
            .map(|c| c.distance(position))
            .fold(0.0f32, f32::max);
        LIGHT_RANGE_FACTOR * d.max(1.0)
    };
    let points = scene.points.iter().map(|p| FogLight {
        radius: LIGHT_RADIUS,
        ..FogLight::point(p.position, p.color, range(p.position))
    });
    let spots = scene.spots.iter().map(|s| FogLight {
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
    points.chain(spots).collect()
}

/// The scene's local volumes as volfog takes them.
pub fn fog_volumes(scene: &TruthScene) -> Result<Vec<LocalVolume>, InvalidValue> {
    scene
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
        .collect()
}

/// Renders `scene` with volfog's froxel pipeline for `options.frames` frames of a
/// still camera: radiance over black and transmittance per pixel (rgb; volfog's
/// extinction is grey, so the three channels of the transmittance agree) after the
/// first frame, [`JITTER_CYCLE`] frames before the last and after the last.
///
/// The scene maps onto volfog as follows: the medium is a [`FogMedium`] without noise
/// or emission whose `top_height` is the scene's top ([`fog_medium`]); the sun a
/// [`DirectionalLight`] (none: colour 0 and no cascades) shadowed by cascades cast
/// from the occluders; each point light a [`FogLight::point`] and each spot a
/// [`FogLight::spot`] ([`fog_lights`]), with `FogConfig::local_shadows` shadowed by
/// depth maps cast from the occluders ([`super::shadow_maps::lamp_shadows`], marked
/// unchanged after the first frame as a static lamp's are); each local volume a
/// [`LocalVolume`] box or ellipsoid. Ambient light and the far-plane tail are off.
/// Note that volfog's spot cone falls off as a smoothstep in the cosine of the angle,
/// not linearly in the angle.
pub fn render(
    gpu: &Gpu,
    scene: &TruthScene,
    options: &VolfogOptions,
) -> Result<VolfogRender, TruthError> {
    let view = TruthView::new(scene)?;
    let [width, height] = scene.resolution;
    let config = fog_config(scene, options)?;
    let medium = fog_medium(scene);
    let sun = fog_sun(scene);
    sun.validate()?;
    let lights = fog_lights(scene, &view);
    let area_lights = super::area::fog_area_lights(scene, &view);
    let volumes = fog_volumes(scene)?;
    let shadow = scene
        .sun
        .as_ref()
        .map(|_| sun_shadow(&config, &view, sun.direction, &scene.occluders));
    let lamps = match config.local_shadows {
        Some(local) if !lights.is_empty() => Some(lamp_shadows(
            &lights,
            &scene.occluders,
            local.resolution * options.lamp_map_factor,
        )?),
        _ => None,
    };
    let unchanged: Vec<ShadowedLight> = lamps.as_ref().map_or(Vec::new(), |l| {
        l.shadowed.iter().map(|s| s.with_unchanged_map()).collect()
    });
    let first_inputs = FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::constant(Vec3::ZERO),
        lights: &lights,
        area_lights: &area_lights,
        local_volumes: &volumes,
        shadowed_lights: lamps.as_ref().map_or(&[], |l| l.shadowed.as_slice()),
        cascades: shadow.as_ref().map_or(ShadowCascades::default(), |s| s.0),
        tail: HeightFog::none(),
        ..FrameInputs::new(view.view_from_world, view.clip_from_view, 0.0)
    };
    first_inputs.validate(&config)?;
    let later_inputs = FrameInputs {
        shadowed_lights: &unchanged,
        ..first_inputs.clone()
    };
    let depths = scene_depth(scene, &view);
    let frames = options.frames;

    let images = gpu.checked(|| -> Result<_, TruthError> {
        let mut fog = VolumetricFog::new(&gpu.device, &config)?;
        if let Some((_, layers)) = &shadow {
            let (side, _) = config.shadow_map_size();
            let slices: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
            let map = depth_array_texture(gpu, side, side, &slices)?;
            fog.set_shadow_map(&gpu.device, &map)?;
        }
        if let Some(l) = &lamps {
            for (layers, spot) in [(&l.spot_layers, true), (&l.point_layers, false)] {
                if layers.is_empty() {
                    continue;
                }
                let slices: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
                let maps = depth_array_texture(gpu, l.size, l.size, &slices)?;
                if spot {
                    fog.set_spot_shadow_maps(&gpu.device, &maps)?;
                } else {
                    fog.set_point_shadow_maps(&gpu.device, &maps)?;
                }
            }
        }
        let depth = depth_texture(gpu, width, height, &depths)?;
        fog.set_scene_depth(&gpu.device, &depth, 0)?;
        let mut first = None;
        let mut cycle_before = None;
        let mut last = None;
        for frame in 0..frames {
            let inputs = if frame == 0 {
                &first_inputs
            } else {
                &later_inputs
            };
            fog.prepare(&gpu.queue, inputs)?;
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            fog.encode(&mut encoder)?;
            gpu.queue.submit([encoder.finish()]);
            let before_last = frames > JITTER_CYCLE && frame + 1 + JITTER_CYCLE == frames;
            if frame != 0 && frame + 1 != frames && !before_last {
                continue;
            }
            let image = image_of(
                apply_over(gpu, &fog, &depth, (width, height))?,
                width,
                height,
            );
            if frame == 0 {
                first = Some(image.clone());
            }
            if before_last {
                cycle_before = Some(image.clone());
            }
            if frame + 1 == frames {
                last = Some(image);
            }
        }
        Ok((first, cycle_before, last))
    })??;
    let (Some(first), cycle_before, Some(converged)) = images else {
        unreachable!("fog_config checks that at least one frame is rendered")
    };
    Ok(VolfogRender {
        first,
        converged,
        cycle_before,
        frames,
    })
}

/// The radiance over black and the transmittance (white minus black) of a pair of
/// applied targets.
fn image_of([black, white]: [Vec<Vec4>; 2], width: u32, height: u32) -> TruthImage {
    TruthImage {
        width,
        height,
        radiance: black.iter().map(|b| b.truncate()).collect(),
        transmittance: black
            .iter()
            .zip(&white)
            .map(|(b, w)| (w.truncate() - b.truncate()).max(Vec3::ZERO))
            .collect(),
    }
}

/// The eight world-space corners of the view frustum between view depths `near` and
/// `far` (m).
pub(crate) fn volume_corners(view: &TruthView, near: f32, far: f32) -> [Vec3; 8] {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::scenes;
    use volfog::cpu::froxel::froxel_jitter;

    /// The jitter repeats after JITTER_CYCLE frames and not before.
    #[test]
    fn jitter_cycle_is_the_period_of_the_froxel_jitter() {
        for frame in 0..3 * JITTER_CYCLE {
            assert_eq!(
                froxel_jitter(frame),
                froxel_jitter(frame + JITTER_CYCLE),
                "{frame}"
            );
        }
        for period in 1..JITTER_CYCLE {
            assert!(
                (0..JITTER_CYCLE).any(|f| froxel_jitter(f) != froxel_jitter(f + period)),
                "the jitter repeats after {period} frames"
            );
        }
    }

    #[test]
    fn bad_options_name_their_field() {
        let scene = scenes::point_light();
        let field = |o: VolfogOptions| fog_config(&scene, &o).unwrap_err().field;
        let frames = VolfogOptions {
            frames: 0,
            ..VolfogOptions::default()
        };
        assert_eq!(field(frames), "VolfogOptions.frames");
        let factor = VolfogOptions {
            lamp_map_factor: 17,
            ..VolfogOptions::default()
        };
        assert_eq!(field(factor), "VolfogOptions.lamp_map_factor");
        let grid = VolfogOptions::default().with_config(|c| c.volume_size.z = 0);
        assert_eq!(field(grid), "FogConfig.volume_size");
        // The scene's camera sets near and far whatever the configuration says.
        let config = fog_config(&scene, &VolfogOptions::default()).unwrap();
        assert_eq!(
            (config.near, config.far),
            (scene.camera.near, scene.camera.far)
        );
    }
}

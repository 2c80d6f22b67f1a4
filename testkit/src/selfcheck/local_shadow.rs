//! The local-light shadow atlas: a point light at the centre of a closed cube room,
//! whose six cube faces each see a wall at one depth, through `VolumetricFog`'s atlas
//! pass, against the closed form of the ESM.

use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::esm::Layer;
use volfog::cpu::local_shadow::local_shadow_visibility;
use volfog::pipeline::{FogConfig, FrameInputs, LocalShadowConfig, ShadowedLight, VolumetricFog};
use volfog::uniforms::{FogLight, LightCamera, LightProjection};

use super::depth::depth_array_texture;
use crate::gpu::{Gpu, GpuError};

/// What the local-shadow check measured.
#[derive(Debug, Clone, Copy)]
pub struct LocalShadowCheck {
    /// Largest relative error of the atlas texels against `exp(c d / range)`.
    pub atlas: f32,
    /// Visibility `3 range / c` behind the wall: `exp(-3)` in closed form.
    pub behind: f32,
    /// Smallest visibility in front of the walls (1 in closed form).
    pub in_front: f32,
    /// The ESM exponent.
    pub exponent: f32,
}

fn failed(e: impl std::fmt::Display) -> GpuError {
    GpuError::Operation(e.to_string())
}

/// Runs the check: a 2 m half-size room, range 10 m, 32² atlas maps from 64² faces.
pub fn local_shadow_check(gpu: &Gpu) -> Result<LocalShadowCheck, GpuError> {
    let (half, range, exponent) = (2.0f32, 10.0f32, 80.0f32);
    let local = LocalShadowConfig {
        spot_shadows: 0,
        point_shadows: 1,
        resolution: 32,
        exponent,
    };
    let config = FogConfig {
        volume_size: UVec3::new(8, 8, 8),
        esm_resolution: 4,
        cascades: 1,
        temporal: false,
        depth_cull: false,
        local_shadows: Some(local),
        ..FogConfig::default()
    };
    let light = FogLight::point(Vec3::ZERO, Vec3::ONE, range);
    let camera = LightCamera::point(&light, 0.1).map_err(failed)?;
    // Every face sees its wall at view depth `half`.
    let clip = camera.clip_from_view() * Vec4::new(0.0, 0.0, -half, 1.0);
    let face = vec![clip.z / clip.w; 64 * 64];
    let faces: Vec<&[f32]> = (0..6).map(|_| face.as_slice()).collect();
    let maps = depth_array_texture(gpu, 64, 64, &faces)?;
    let mut fog = VolumetricFog::new(&gpu.device, &config).map_err(failed)?;
    fog.set_point_shadow_maps(&gpu.device, &maps)
        .map_err(failed)?;
    let lights = [light];
    let shadowed = [ShadowedLight::new(0, camera).with_shadow(0)];
    let view = glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, Vec3::Y);
    fog.prepare(
        &gpu.queue,
        &FrameInputs {
            lights: &lights,
            shadowed_lights: &shadowed,
            ..FrameInputs::new(view, super::test_projection(), 0.0)
        },
    )
    .map_err(failed)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).map_err(failed)?;
    gpu.queue.submit([encoder.finish()]);
    let texture = fog.local_shadow_atlas().ok_or_else(|| failed("no atlas"))?;
    let raw = gpu.read_texture_raw(texture, 4)?;
    let values: &[f32] = bytemuck::cast_slice(&raw);
    let texels = (local.resolution * local.resolution) as usize;
    let atlas: Vec<Layer> = values
        .chunks_exact(texels)
        .take(6)
        .map(|c| Layer {
            width: local.resolution,
            height: local.resolution,
            texels: c.to_vec(),
        })
        .collect();
    let want = (exponent * half / range).exp();
    let atlas_error = atlas
        .iter()
        .flat_map(|l| &l.texels)
        .map(|v| (v - want).abs() / want)
        .fold(0.0f32, f32::max);
    let projection =
        LightProjection::new(&light, &camera, 0, u32::MAX, exponent, 0.0).map_err(failed)?;
    let (mut behind, mut in_front) = (0.0f32, 1.0f32);
    for axis in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        let side = Vec3::new(0.3, -0.2, 0.25) - axis * axis.dot(Vec3::new(0.3, -0.2, 0.25));
        let at = |d: f32| local_shadow_visibility(&atlas, &projection, axis * d + side, false);
        behind = behind.max(at(half + 3.0 * range / exponent));
        in_front = in_front.min(at(0.9 * half));
    }
    Ok(LocalShadowCheck {
        atlas: atlas_error,
        behind,
        in_front,
        exponent,
    })
}

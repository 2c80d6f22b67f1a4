//! The caller's textures [`VolumetricFog`] reads: the shadow map, the density
//! texture, the cloud map, the scene depth, and the point and spot lights' shadow maps
//! and cookies, checked and bound (or cleared).

use super::local_shadows::LocalShadowStats;
use super::resources::check_filterable;
use super::textures::ShadowMap;
use super::{
    FogError, VolumetricFog, array_view, check_cloud_map, check_density_texture, check_scene_depth,
    check_shadow_map,
};
use crate::limits::InvalidValue;

impl VolumetricFog {
    /// Uses the sun's cascaded shadow map for the ESM passes: a 2D texture with
    /// `4 * esm_resolution` texels per side and a layer per cascade, in one of
    /// [`SHADOW_MAP_FORMATS`], with `TEXTURE_BINDING` usage. Set it once (and again when
    /// the texture is recreated); every frame with `cascades.count > 0` reads it.
    ///
    /// [`SHADOW_MAP_FORMATS`]: super::SHADOW_MAP_FORMATS
    pub fn set_shadow_map(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        check_shadow_map(texture, &self.config)?;
        let group = self.esm.downsample_bind_group(
            device,
            &self.buffers.cascades,
            &array_view(texture),
            &array_view(&self.esm_texture),
        );
        self.shadow_map = Some(ShadowMap {
            texture: texture.clone(),
            group,
        });
        if self.config.shadow_filter.compares() {
            self.rebuild_inject_groups(device);
        }
        Ok(())
    }

    /// Stops reading the shadow map (frames must then have `cascades.count` 0).
    pub fn clear_shadow_map(&mut self) {
        self.shadow_map = None;
    }

    /// Uses a 3D texture (r channel, filterable format, `TEXTURE_BINDING` usage) as
    /// density multiplier, sampled with repeat addressing at
    /// `world * texture_scale + texture_offset`; needs `FogConfig::density_texture`.
    pub fn set_density_texture(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let Some(density) = self.density.as_mut() else {
            return Err(option_off("FogConfig.density_texture", "a density texture"));
        };
        check_density_texture(texture, device)?;
        density.texture = texture.clone();
        density.user = true;
        self.rebuild_inject_groups(device);
        Ok(())
    }

    /// Uses a 2D texture (red channel, filterable, `TEXTURE_BINDING` usage) as the
    /// density map of the cloud layer whose shadow the sun's light passes in the fog;
    /// needs `FogConfig::cloud_shadow`. The layer comes with each frame
    /// ([`FrameInputs::clouds`]).
    ///
    /// [`FrameInputs::clouds`]: super::FrameInputs::clouds
    pub fn set_cloud_map(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let Some(clouds) = self.clouds.as_mut() else {
            return Err(option_off("FogConfig.cloud_shadow", "a cloud map"));
        };
        check_cloud_map(texture, device)?;
        clouds.map = texture.clone();
        clouds.user = true;
        self.rebuild_inject_groups(device);
        Ok(())
    }

    /// Culls froxels by the scene depth (needs `FogConfig::depth_cull`): every frame,
    /// before injection, the `froxel_cull` pass finds for each froxel column how many
    /// slices lie in front of the farthest opaque surface over the column's screen
    /// footprint, and inject, temporal and scan skip the others. `texture` holds
    /// depth-buffer values of this frame's camera (standard, reversed or infinite
    /// projection), written before [`VolumetricFog::encode`] runs: the depth buffer
    /// itself (a depth format, single-sampled) or any R32Float texture covering the
    /// screen that is no nearer than it, such as a farthest-depth level of a
    /// hierarchical depth buffer; `mip_level` picks the level read. Needs
    /// `TEXTURE_BINDING` usage. Transparent surfaces, which lie in front of the opaque
    /// depth, read live froxels through the forward snippet as before.
    pub fn set_scene_depth(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
        mip_level: u32,
    ) -> Result<(), FogError> {
        let Some(culling) = self.culling.as_mut() else {
            return Err(FogError::Invalid(crate::limits::InvalidValue {
                field: "FogConfig.depth_cull",
                value: "false".to_string(),
                expected: "true to cull froxels by a scene depth".into(),
            }));
        };
        check_scene_depth(texture, mip_level)?;
        let depth_view = super::groups::depth_view(texture, mip_level);
        let groups = [0, 1].map(|p| {
            culling.pass.bind_group(
                device,
                &self.buffers.froxels,
                &depth_view,
                &culling.views[p],
                &culling.blocks,
            )
        });
        culling.depth = Some((texture.clone(), mip_level, groups));
        culling.all_live = false;
        // Inject's shadow taps read it too (the compare filter).
        self.rebuild_inject_groups(device);
        Ok(())
    }

    /// Stops culling: from the next `prepare` every froxel is live again.
    pub fn clear_scene_depth(&mut self) {
        if let Some(c) = self.culling.as_mut() {
            c.depth = None;
            c.all_live = false;
        }
    }
}

/// The error of a texture set for an option the configuration has off.
fn option_off(field: &'static str, what: &str) -> FogError {
    FogError::Invalid(crate::limits::InvalidValue {
        field,
        value: "false".to_string(),
        expected: format!("true to use {what}").into(),
    })
}

fn local_shadows_off() -> FogError {
    FogError::Invalid(InvalidValue {
        field: "FogConfig.local_shadows",
        value: "None".to_string(),
        expected: "Some(LocalShadowConfig) to use shadowed point and spot lights or cookies".into(),
    })
}

impl VolumetricFog {
    /// Uses the spot lights' shadow maps: a square 2D depth array (a layer per light,
    /// [`ShadowedLight::shadow`](super::ShadowedLight::shadow)) in one of [`SHADOW_MAP_FORMATS`](super::SHADOW_MAP_FORMATS),
    /// with `TEXTURE_BINDING` usage; standard, reversed or infinite depth as the
    /// [`LightCamera`](crate::uniforms::LightCamera) of each light says. The compare filter reads it directly (any
    /// size); the ESM filter needs `k x LocalShadowConfig::resolution` texels per side
    /// (k from 1 to 16) and filters each frame's shadowed spot lights from it into the
    /// atlas.
    pub fn set_spot_shadow_maps(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let local = self.local_shadows.as_mut().ok_or_else(local_shadows_off)?;
        local.set_maps(device, &self.esm, texture, false)?;
        self.enable_shadowed_inject(device)
    }

    /// Uses the point lights' cube shadow maps: a 2D depth array of six layers per
    /// light (a cube or cube-array texture), faces in the order +X, -X, +Y, -Y, +Z, -Z
    /// as a cube map lays them out ([`LightCamera::cube_face_view`](crate::uniforms::LightCamera::cube_face_view)); otherwise as
    /// [`VolumetricFog::set_spot_shadow_maps`].
    pub fn set_point_shadow_maps(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let local = self.local_shadows.as_mut().ok_or_else(local_shadows_off)?;
        local.set_maps(device, &self.esm, texture, true)?;
        self.enable_shadowed_inject(device)
    }

    /// Uses a 2D array of cookies (a filterable float format, e.g. Rgba8Unorm, with
    /// `TEXTURE_BINDING` usage): a spot light with [`ShadowedLight::cookie`](super::ShadowedLight::cookie) multiplies
    /// its light by the layer's colour where its camera projects it, sampled linearly
    /// with clamp to edge (v down), and gives no light outside the camera's frustum.
    pub fn set_cookies(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let local = self.local_shadows.as_mut().ok_or_else(local_shadows_off)?;
        check_filterable(texture, device, "the cookies", wgpu::TextureDimension::D2)?;
        local.set_cookies(texture);
        self.enable_shadowed_inject(device)
    }

    /// What the prepared frame's [`ShadowedLight`](super::ShadowedLight)s got: the shadowed lights of each
    /// kind, those beyond the budget (lit unshadowed) and the atlas layers filled.
    pub fn local_shadow_stats(&self) -> LocalShadowStats {
        self.local_shadows
            .as_ref()
            .map(|l| l.stats())
            .unwrap_or_default()
    }

    /// The local-light ESM atlas once a shadow map array is set (R32Float, one layer
    /// per spot light, six per point light, filled from layer 0 by each frame); `None`
    /// with the compare filter, which has none.
    pub fn local_shadow_atlas(&self) -> Option<&wgpu::Texture> {
        self.local_shadows.as_ref()?.atlas()
    }
}

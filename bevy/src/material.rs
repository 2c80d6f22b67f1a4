//! [`FoggedGlassMaterial`]: a transparent Bevy material that imports the volfog WESL
//! package and applies the froxel fog at its own depth, and the model for materials
//! of your own that do the same.
//!
//! A material reads the fog from its own bind group (Bevy's four groups are all
//! taken): its layout starts with the fog group of `volfog::bindings` at bindings
//! 0..4 ([`fog_layout_entries`]), its bind group with the fog's resources
//! ([`push_fog_bindings`]), and its pipeline sets the WESL constant
//! `VOLFOG_FOG_GROUP` to the material group ([`set_fog_group`]). One group serves
//! every view: with several fog cameras it holds a `SharedFog` that each camera's fog
//! pass fills before its transparent pass, so materials drawn in the transparent pass
//! read the fog of the camera drawing them.

use bevy::asset::AssetId;
use bevy::ecs::system::SystemParamItem;
use bevy::ecs::system::lifetimeless::SRes;
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::pbr::{MATERIAL_BIND_GROUP_INDEX, Material, MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, AsBindGroupError, BindGroupBuilder, BindGroupLayout, BindGroupLayoutEntry,
    RenderPipelineDescriptor, SpecializedMeshPipelineError, UnpreparedBindingResource,
};
use bevy::render::renderer::RenderDevice;
use bevy::shader::{ShaderDefVal, ShaderRef};
use volfog::options::Filtering;
use wgpu::util::DeviceExt;

use crate::render::FogViews;

/// The material's shader, in the crate's embedded assets.
pub const FOGGED_GLASS_SHADER: &str = "embedded://volfog_bevy/shaders/fogged_glass.wesl";

/// Binding of the material's own parameters, after the fog group's 0..4.
const PARAMS_BINDING: u32 = 5;

/// An unlit transparent surface with the froxel fog applied between the camera and
/// it (`shaders/fogged_glass.wesl`): alpha-blended over the fogged background, it gets
/// exactly the fog the fullscreen pass gives an opaque surface at its depth. Each fog
/// camera's materials read that camera's fog ([`FogViews`]); a camera without
/// `FroxelFog` draws them with the fog of the camera drawn before it.
#[derive(Asset, TypePath, Clone, Debug, PartialEq)]
pub struct FoggedGlassMaterial {
    /// Linear colour; alpha is the coverage.
    pub color: LinearRgba,
    /// Apply the fog (false draws the bare colour, for comparisons).
    pub fog: bool,
    /// `Blend` (the default) draws it in the transparent pass; `Opaque` in the opaque
    /// pass, where the fullscreen pass fogs it (then set `fog` to false).
    pub alpha_mode: AlphaMode,
}

impl Default for FoggedGlassMaterial {
    fn default() -> Self {
        Self {
            color: LinearRgba::new(0.6, 0.75, 0.8, 0.35),
            fog: true,
            alpha_mode: AlphaMode::Blend,
        }
    }
}

/// The fog group's layout entries (`volfog::bindings`, with its sampler) for a
/// material's bind group, visible to the fragment stage.
pub fn fog_layout_entries() -> Vec<BindGroupLayoutEntry> {
    volfog::pipeline::apply::fog_layout_entries(Filtering::Sampler, wgpu::ShaderStages::FRAGMENT)
}

/// Adds the fog's resources at bindings 0..4 of a material's bind group (a group that
/// applies no fog while no camera has fog), or asks Bevy to retry next frame before the
/// plugin's first frame.
pub fn push_fog_bindings(
    fogs: &FogViews,
    output: &mut BindGroupBuilder,
) -> Result<(), AsBindGroupError> {
    let Some(r) = fogs.material_resources() else {
        return Err(AsBindGroupError::RetryNextUpdate);
    };
    output.push((
        0,
        UnpreparedBindingResource::Buffer(r.froxels.clone().into()),
    ));
    output.push((
        1,
        UnpreparedBindingResource::TextureView(
            wgpu::TextureViewDimension::D3,
            r.integrated.clone().into(),
        ),
    ));
    output.push((
        2,
        UnpreparedBindingResource::Sampler(
            wgpu::SamplerBindingType::Filtering,
            r.sampler.clone().into(),
        ),
    ));
    output.push((3, UnpreparedBindingResource::Buffer(r.tail.clone().into())));
    output.push((4, UnpreparedBindingResource::Buffer(r.view.clone().into())));
    Ok(())
}

/// Sets the WESL constant `VOLFOG_FOG_GROUP` (and its feature) to the material bind
/// group in a material pipeline, so `volfog::bindings` declares the fog there.
pub fn set_fog_group(descriptor: &mut RenderPipelineDescriptor) {
    let def = ShaderDefVal::UInt("VOLFOG_FOG_GROUP".into(), MATERIAL_BIND_GROUP_INDEX as u32);
    descriptor.vertex.shader_defs.push(def.clone());
    if let Some(fragment) = descriptor.fragment.as_mut() {
        fragment.shader_defs.push(def);
    }
}

impl AsBindGroup for FoggedGlassMaterial {
    type Data = ();
    type Param = SRes<FogViews>;

    fn label() -> &'static str {
        "volfog_fogged_glass"
    }

    fn bind_group_data(&self) -> Self::Data {}

    fn build_bind_group(
        &self,
        _layout: &BindGroupLayout,
        render_device: &RenderDevice,
        fogs: &mut SystemParamItem<'_, '_, Self::Param>,
        _force_no_bindless: bool,
        output: &mut BindGroupBuilder,
    ) -> Result<(), AsBindGroupError> {
        push_fog_bindings(fogs, output)?;
        let c = self.color;
        let params: [f32; 8] = [
            c.red,
            c.green,
            c.blue,
            c.alpha,
            if self.fog { 1.0 } else { 0.0 },
            0.0,
            0.0,
            0.0,
        ];
        let buffer =
            render_device
                .wgpu_device()
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("volfog fogged glass"),
                    contents: bytemuck::cast_slice(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
        output.push((
            PARAMS_BINDING,
            UnpreparedBindingResource::Buffer(buffer.into()),
        ));
        Ok(())
    }

    fn bind_group_layout_entries(
        _render_device: &RenderDevice,
        _force_no_bindless: bool,
    ) -> Vec<BindGroupLayoutEntry> {
        let mut entries = fog_layout_entries();
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: PARAMS_BINDING,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: wgpu::BufferSize::new(32),
            },
            count: None,
        });
        entries
    }
}

impl Material for FoggedGlassMaterial {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Path(FOGGED_GLASS_SHADER.into())
    }

    fn alpha_mode(&self) -> AlphaMode {
        self.alpha_mode
    }

    fn enable_shadows() -> bool {
        false
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        _key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        set_fog_group(descriptor);
        Ok(())
    }
}

/// Marks every [`FoggedGlassMaterial`] changed, so Bevy rebuilds their bind groups
/// with the fog's new resources (after a camera's fog was rebuilt).
pub fn refresh_materials(materials: &mut Assets<FoggedGlassMaterial>) {
    let ids: Vec<AssetId<FoggedGlassMaterial>> = materials.ids().collect();
    for id in ids {
        materials.get_mut(id);
    }
}

//! The multiview path of [`StereoFog`]: the stereo fog group, which holds both eyes'
//! fog (`volfog::stereo_bindings`), and the apply drawing both eyes in one multiview
//! render pass (`VOLFOG_APPLY_MULTIVIEW`).
//!
//! A multiview render pass (`wgpu::Features::MULTIVIEW`) draws every view of its mask
//! with one draw call, each into its layer of an array target; a shader tells the views
//! apart by `@builtin(view_index)`. The stereo group lets such a shader fog its
//! fragment for the eye it draws: `volfog::stereo_bindings::stereo_fog_at_world(view_index,
//! world_pos)` (or the parameter-taking functions of `volfog::stereo_apply`) reads the
//! eye's froxels, volume, tail and camera.

use std::num::NonZeroU32;

use super::{EyeVolume, StereoFog};
use crate::options::Filtering;
use crate::pipeline::apply::{
    ApplyPipeline, RIGHT_EYE_OFFSET, STEREO_VIEW_MASK, Tail, stereo_fog_layout_entries,
};
use crate::pipeline::fog::{FogError, VolumetricFog, view};
use crate::pipeline::{bind_group, bind_group_layout};

/// The stereo fog group and its layout.
#[derive(Debug)]
pub(super) struct StereoGroup {
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

impl StereoGroup {
    /// Both eyes' fog in one group (layout [`stereo_fog_layout_entries`], visible to
    /// vertex and fragment shaders, as the mono fog group), the shared fog's sampler.
    pub(super) fn new(
        device: &wgpu::Device,
        filtering: Filtering,
        shared: &VolumetricFog,
        eyes: &[EyeVolume; 2],
    ) -> Self {
        let layout = bind_group_layout(
            device,
            "volfog stereo fog",
            &stereo_fog_layout_entries(
                filtering,
                wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ),
        );
        let volumes = eyes.each_ref().map(|e| view(&e.integrated));
        let mut resources = Vec::new();
        for (i, eye) in eyes.iter().enumerate() {
            let base = i as u32 * RIGHT_EYE_OFFSET;
            resources.push((base, eye.froxels.as_entire_binding()));
            resources.push((base + 1, wgpu::BindingResource::TextureView(&volumes[i])));
            resources.push((base + 3, eye.tail.as_entire_binding()));
            resources.push((base + 4, eye.view.as_entire_binding()));
        }
        if filtering == Filtering::Sampler {
            resources.push((2, wgpu::BindingResource::Sampler(&shared.fog_sampler)));
        }
        let group = bind_group(device, "volfog stereo fog", &layout, &resources);
        Self { layout, group }
    }
}

impl StereoFog {
    /// The stereo fog group: both eyes' fog (each eye's `Froxels`, integrated volume,
    /// `HeightFog` tail and `FogView`, as the mono fog group holds them, and one
    /// sampler) at the bindings of `volfog::stereo_bindings` (the left eye at the mono
    /// group's bindings 0 to 4, the right eye's at 5, 6, 8, 9). A shader drawing both
    /// eyes in one multiview render pass binds it and fogs a fragment with
    /// `stereo_bindings::stereo_fog_at_world(view_index, world_pos)`; set
    /// `VOLFOG_STEREO_FOG_GROUP` to the group index it binds it at.
    pub fn stereo_fog_bind_group(&self) -> &wgpu::BindGroup {
        &self.stereo.group
    }

    /// The layout of [`StereoFog::stereo_fog_bind_group`]
    /// ([`stereo_fog_layout_entries`] with the configuration's filtering, visible to
    /// vertex and fragment shaders), for the pipeline layouts of multiview shaders.
    pub fn stereo_fog_bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.stereo.layout
    }

    /// The multiview apply ([`ApplyPipeline::multiview`]) for a two-layer colour target
    /// of `format`, reading the stereo fog group. Errors with
    /// [`FogError::MissingCapability`] naming `wgpu::Features::MULTIVIEW` when `device`
    /// was created without it, or `wgpu::Limits::max_multiview_view_count` when it
    /// allows fewer than two views; [`StereoFog::record_apply`] draws the eyes one
    /// layer at a time without it.
    pub fn create_apply_multiview(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_multiview_views(device, format, STEREO_VIEW_MASK)
    }

    /// [`StereoFog::create_apply_multiview`] for the views of `view_mask`: bit 0 the
    /// left eye (layer 0), bit 1 the right (layer 1). One bit draws that eye alone in
    /// its layer, e.g. to redraw one eye; it needs `wgpu::Features::SELECTIVE_MULTIVIEW`
    /// (a [`FogError::MissingCapability`] without it). A mask with other bits is an
    /// `InvalidValue` naming `view_mask`.
    pub fn create_apply_multiview_views(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        view_mask: NonZeroU32,
    ) -> Result<ApplyPipeline, FogError> {
        check_multiview(device)?;
        if view_mask.get() & !STEREO_VIEW_MASK.get() != 0 {
            return Err(FogError::Invalid(crate::limits::InvalidValue {
                field: "view_mask",
                value: format!("{:#b}", view_mask.get()),
                expected: "0b01 (left eye), 0b10 (right eye) or 0b11 (both)".into(),
            }));
        }
        if view_mask != STEREO_VIEW_MASK
            && !device
                .features()
                .contains(wgpu::Features::SELECTIVE_MULTIVIEW)
        {
            return Err(FogError::MissingCapability {
                what: "wgpu::Features::SELECTIVE_MULTIVIEW",
                detail: format!(
                    "the view mask {:#b} draws one of the two layers",
                    view_mask.get()
                ),
            });
        }
        Ok(ApplyPipeline::multiview_views(
            device,
            &self.stereo.layout,
            self.config.apply_filtering,
            format,
            view_mask,
        )?)
    }

    /// Group 1 of the multiview apply: the eyes' scene depths, layers 0 (left) and 1
    /// (right) of `depth` (a depth texture, or a float texture of view depths in the
    /// layout the apply reads, as the mono apply's), the size of the colour target.
    /// Errors, naming the texture and property, when `depth` has fewer than two layers
    /// or `apply` is not a multiview apply.
    pub fn multiview_depth_bind_group(
        &self,
        device: &wgpu::Device,
        apply: &ApplyPipeline,
        depth: &wgpu::Texture,
    ) -> Result<wgpu::BindGroup, FogError> {
        check_multiview_apply(apply)?;
        check_layers(depth, "the stereo depth array")?;
        let aspect = if depth.format().has_depth_aspect() {
            wgpu::TextureAspect::DepthOnly
        } else {
            wgpu::TextureAspect::All
        };
        let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
            label: Some("volfog stereo depth"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect,
            base_array_layer: 0,
            array_layer_count: Some(2),
            ..Default::default()
        });
        Ok(apply.depth_bind_group(device, &depth_view))
    }

    /// Blends both eyes' fog onto layers 0 (left eye) and 1 (right eye) of `target` in
    /// one multiview render pass (the view mask of `apply`, 0b11: one draw for both
    /// eyes), with `apply` from [`StereoFog::create_apply_multiview`] and `depth_group` from
    /// [`StereoFog::multiview_depth_bind_group`]. The same image as
    /// [`StereoFog::record_apply`], which draws once per layer. Errors, naming the
    /// texture and property, when `target` has fewer than two layers, and when `apply`
    /// is not a multiview apply or reads other fog groups.
    pub fn record_apply_multiview(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &ApplyPipeline,
        target: &wgpu::Texture,
        depth_group: &wgpu::BindGroup,
    ) -> Result<(), FogError> {
        check_multiview_apply(apply)?;
        self.check_apply(apply)?;
        check_layers(target, "the stereo target")?;
        let color = target.create_view(&wgpu::TextureViewDescriptor {
            label: Some("volfog stereo target"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            base_array_layer: 0,
            array_layer_count: Some(2),
            ..Default::default()
        });
        // The variant without the tail only when neither eye has one.
        let tail = match self.eyes.each_ref().map(|e| e.tail_kind) {
            [Tail::Empty, Tail::Empty] => Tail::Empty,
            _ => Tail::Analytic,
        };
        apply.record_tail(encoder, &color, &self.stereo.group, depth_group, None, tail);
        Ok(())
    }
}

/// The device can draw two views in one multiview render pass.
fn check_multiview(device: &wgpu::Device) -> Result<(), FogError> {
    if !device.features().contains(wgpu::Features::MULTIVIEW) {
        return Err(FogError::MissingCapability {
            what: "wgpu::Features::MULTIVIEW",
            detail: "the multiview apply draws both eyes in one multiview render pass; \
                     request the feature where the adapter offers it, or draw one layer \
                     at a time with StereoFog::record_apply"
                .into(),
        });
    }
    let views = device.limits().max_multiview_view_count;
    if views < 2 {
        return Err(FogError::MissingCapability {
            what: "wgpu::Limits::max_multiview_view_count",
            detail: format!("the device allows {views} views, the eyes need 2"),
        });
    }
    Ok(())
}

/// `apply` is a multiview apply of the stereo views.
fn check_multiview_apply(apply: &ApplyPipeline) -> Result<(), FogError> {
    match apply.multiview_mask() {
        Some(mask) if mask.get() & !STEREO_VIEW_MASK.get() == 0 => Ok(()),
        other => Err(FogError::Invalid(crate::limits::InvalidValue {
            field: "ApplyPipeline multiview mask",
            value: format!("{:?}", other.map(NonZeroU32::get)),
            expected: "0b01, 0b10 or 0b11: an apply from StereoFog::create_apply_multiview".into(),
        })),
    }
}

/// `texture` is a 2D texture with a layer per eye.
fn check_layers(texture: &wgpu::Texture, name: &'static str) -> Result<(), FogError> {
    if texture.dimension() != wgpu::TextureDimension::D2 || texture.depth_or_array_layers() < 2 {
        return Err(FogError::Texture {
            texture: name,
            property: "array layers",
            found: texture.depth_or_array_layers().to_string(),
            expected: "2 or more layers of a 2D texture (layer 0 the left eye, layer 1 the \
                       right)"
                .into(),
        });
    }
    Ok(())
}

//! The render world: one [`VolumetricFog`] per fog camera on Bevy's own device and
//! queue, prepared after Bevy's shadow maps and depth textures exist, and run in the
//! `Core3d` schedule between the opaque and the transparent pass.

use std::collections::{HashMap, HashSet};

use bevy::pbr::ViewShadowBindings;
use bevy::prelude::*;
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::view::{ViewDepthStencilTexture, ViewTarget};
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::{FogError, VolumetricFog};

use crate::extract::ExtractedFroxelFog;

/// The fog of every fog camera, by render-world view entity.
#[derive(Resource, Default)]
pub struct FogViews {
    views: HashMap<Entity, ViewFog>,
    /// Counts the fogs built (a material's group must be rebuilt when it changes).
    generation: u64,
}

impl FogViews {
    /// The fog of a view, once prepared.
    pub fn get(&self, view: Entity) -> Option<&ViewFog> {
        self.views.get(&view)
    }

    /// How many views have a fog pipeline.
    pub fn len(&self) -> usize {
        self.views.len()
    }

    /// Whether no view has a fog pipeline.
    pub fn is_empty(&self) -> bool {
        self.views.is_empty()
    }

    /// The fog of the view with the lowest entity index: the one forward materials
    /// read (they support one fog camera per app).
    pub fn primary(&self) -> Option<&ViewFog> {
        self.views.iter().min_by_key(|(e, _)| **e).map(|(_, v)| v)
    }
}

/// One camera's fog pipeline and what it was last bound to.
pub struct ViewFog {
    /// The pipeline.
    pub fog: VolumetricFog,
    /// Which fog this is ([`ViewFog::fog`] is rebuilt when the settings or the
    /// viewport change).
    pub generation: u64,
    apply: Option<(wgpu::TextureFormat, ApplyPipeline)>,
    shadow_map: Option<wgpu::Texture>,
    depth: Option<(wgpu::Texture, wgpu::BindGroup)>,
    ready: bool,
}

type ViewItems = (
    Entity,
    &'static ExtractedFroxelFog,
    &'static ViewTarget,
    &'static ViewDepthStencilTexture,
    Option<&'static ViewShadowBindings>,
);

/// Builds each fog view's pipeline, and rebuilds it when its configuration changed
/// (new settings, viewport or shadow map); drops the fog of views that are gone. It
/// runs before Bevy prepares material assets, so a material reading the fog's
/// resources binds the pipeline of this frame.
pub fn build_froxel_fog(
    views: Query<(Entity, &ExtractedFroxelFog)>,
    device: Res<RenderDevice>,
    mut fogs: ResMut<FogViews>,
    mut warned: Local<HashSet<Entity>>,
) {
    let live: HashSet<Entity> = views.iter().map(|(e, _)| e).collect();
    fogs.views.retain(|e, _| live.contains(e));
    for (entity, extracted) in &views {
        let current = fogs
            .views
            .get(&entity)
            .is_some_and(|v| v.fog.config() == &extracted.config);
        if current {
            continue;
        }
        fogs.views.remove(&entity);
        match VolumetricFog::new(device.wgpu_device(), &extracted.config) {
            Ok(fog) => {
                warned.remove(&entity);
                fogs.generation += 1;
                let generation = fogs.generation;
                fogs.views.insert(
                    entity,
                    ViewFog {
                        fog,
                        generation,
                        apply: None,
                        shadow_map: None,
                        depth: None,
                        ready: false,
                    },
                );
            }
            Err(error) => {
                if warned.insert(entity) {
                    warn!("volfog: view {entity}: {error}; the fog is off for this camera");
                }
            }
        }
    }
}

/// Binds each view's shadow map and depth buffer (once Bevy has prepared them) and
/// uploads the frame's inputs. A view whose fog fails is warned about once and left
/// without fog this frame.
pub fn prepare_froxel_fog(
    views: Query<ViewItems>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut fogs: ResMut<FogViews>,
    mut warned: Local<HashSet<Entity>>,
) {
    for (entity, extracted, target, depth, shadows) in &views {
        let Some(view) = fogs.views.get_mut(&entity) else {
            continue;
        };
        view.ready = false;
        match prepare_view(
            view,
            extracted,
            target,
            depth,
            shadows,
            device.wgpu_device(),
            &queue,
        ) {
            Ok(()) => {
                view.ready = true;
                warned.remove(&entity);
            }
            Err(error) => {
                if warned.insert(entity) {
                    warn!("volfog: view {entity}: {error}; the fog is off for this camera");
                }
            }
        }
    }
}

fn prepare_view(
    view: &mut ViewFog,
    extracted: &ExtractedFroxelFog,
    target: &ViewTarget,
    depth: &ViewDepthStencilTexture,
    shadows: Option<&ViewShadowBindings>,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
) -> Result<(), FogError> {
    let mut inputs = extracted.inputs();
    match shadows {
        Some(bindings) if inputs.cascades.count > 0 => {
            let texture: &wgpu::Texture = &bindings.directional_light_depth_texture;
            if view.shadow_map.as_ref() != Some(texture) {
                view.fog.set_shadow_map(device, texture)?;
                view.shadow_map = Some(texture.clone());
            }
        }
        _ => inputs.cascades.count = 0,
    }

    let format = target.main_texture_format();
    if view.apply.as_ref().is_none_or(|(f, _)| *f != format) {
        view.apply = Some((format, view.fog.create_apply(device, format)?));
        view.depth = None;
    }
    let depth_texture: &wgpu::Texture = &depth.attachment.texture.texture;
    if view.depth.as_ref().is_none_or(|(t, _)| t != depth_texture) {
        view.fog.set_scene_depth(device, depth_texture, 0)?;
        let depth_view = depth_texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("volfog scene depth"),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let (_, apply) = view.apply.as_ref().expect("created above");
        let group = apply.depth_bind_group(device, &depth_view);
        view.depth = Some((depth_texture.clone(), group));
    }
    view.fog.prepare(queue, &inputs)?;
    Ok(())
}

/// Runs the fog passes of the current view and composites the fog over its opaque
/// scene (after Bevy's opaque pass, before its transparent pass).
pub fn froxel_fog_pass(
    view: ViewQuery<(Entity, &ViewTarget), With<ExtractedFroxelFog>>,
    fogs: Res<FogViews>,
    mut ctx: RenderContext,
) {
    let (entity, target) = view.into_inner();
    let Some(fog) = fogs.get(entity).filter(|f| f.ready) else {
        return;
    };
    let (Some((_, apply)), Some((_, depth_group))) = (&fog.apply, &fog.depth) else {
        return;
    };
    let encoder = ctx.command_encoder();
    encoder.push_debug_group("volfog");
    let result = fog.fog.encode(encoder).and_then(|()| {
        fog.fog
            .record_apply(encoder, apply, target.main_texture_view(), depth_group)
    });
    encoder.pop_debug_group();
    if let Err(error) = result {
        // prepare_froxel_fog ran for this view, so encoding cannot fail; log if it does.
        error!("volfog: view {entity}: {error}");
    }
}

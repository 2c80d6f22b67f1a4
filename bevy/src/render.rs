//! The render world: one [`VolumetricFog`] per fog camera on Bevy's own device and
//! queue, prepared after Bevy's shadow maps and depth textures exist, and run in the
//! `Core3d` schedule between the opaque and the transparent pass.

use std::collections::{HashMap, HashSet};

use bevy::pbr::ViewShadowBindings;
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::render_asset::RenderAssets;
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::texture::GpuImage;
use bevy::render::view::{ViewDepthStencilTexture, ViewTarget};
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::{FogConfig, FogError, SharedFog, VolumetricFog};

use crate::extract::ExtractedFroxelFog;
use crate::light_shadows::{BevyLights, BevyShadowLayout};
use crate::msaa::DepthResolve;

/// The fog of every fog camera, by render-world view entity.
///
/// Materials bind one group for every view. With one fog camera it holds that
/// camera's fog resources; with several, a [`SharedFog`] that each camera's fog pass
/// fills before its transparent pass, so each camera's materials read its own fog.
#[derive(Resource, Default)]
pub struct FogViews {
    views: HashMap<Entity, ViewFog>,
    /// With two or more fog cameras: the group their materials read, sized for the
    /// volume of [`FogViews::primary`].
    shared: Option<SharedFog>,
    /// What materials bind while no camera has fog: a one-froxel group that holds no
    /// fog and no tail.
    fallback: Option<SharedFog>,
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

    /// The fog of the view with the lowest entity index (the one whose volume size
    /// the shared group of several fog cameras takes).
    pub fn primary(&self) -> Option<&ViewFog> {
        self.views.iter().min_by_key(|(e, _)| **e).map(|(_, v)| v)
    }

    /// The group the materials of several fog cameras read (`None` with fewer than
    /// two).
    pub fn shared(&self) -> Option<&SharedFog> {
        self.shared.as_ref()
    }

    /// The resources a material binds: with one fog camera its own, with several the
    /// shared group each camera fills before drawing its materials, and while no
    /// camera has fog a group that applies none (`None` before the first frame).
    pub fn material_resources(&self) -> Option<volfog::pipeline::apply::FogResources<'_>> {
        if let Some(shared) = &self.shared {
            return Some(shared.resources());
        }
        match (self.primary(), &self.fallback) {
            (Some(view), _) => Some(view.fog.fog_resources()),
            (None, Some(fallback)) => Some(fallback.resources()),
            (None, None) => None,
        }
    }
}

/// One camera's fog pipeline and what it was last bound to.
pub struct ViewFog {
    /// The pipeline (rebuilt when the settings, the viewport or the shadow map
    /// change).
    pub fog: VolumetricFog,
    /// The apply pass, for the colour format and samples per pixel it was built for.
    apply: Option<((wgpu::TextureFormat, u32), ApplyPipeline)>,
    shadow_map: Option<wgpu::Texture>,
    /// Bevy's point light cube array and directional (and spot) light array, as set.
    point_maps: Option<wgpu::Texture>,
    spot_maps: Option<wgpu::Texture>,
    /// The density texture as set (Bevy's texture of the volumes' image).
    density_texture: Option<wgpu::Texture>,
    depth: Option<(wgpu::Texture, wgpu::BindGroup)>,
    /// A multisampled camera's depth, resolved to one depth per pixel.
    depth_resolve: Option<DepthResolve>,
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
    queue: Res<RenderQueue>,
    mut fogs: ResMut<FogViews>,
    mut warned: Local<HashSet<Entity>>,
    mut failed: Local<HashMap<Entity, FogConfig>>,
) {
    if fogs.fallback.is_none() {
        fogs.fallback = SharedFog::new(device.wgpu_device(), &queue, volfog::glam::UVec3::ONE).ok();
    }
    let live: HashSet<Entity> = views.iter().map(|(e, _)| e).collect();
    fogs.views.retain(|e, _| live.contains(e));
    for (entity, extracted) in &views {
        let current = fogs
            .views
            .get(&entity)
            .is_some_and(|v| v.fog.config() == &extracted.config);
        // A configuration that failed (a custom density that does not compose) is not
        // built again each frame.
        if current || failed.get(&entity) == Some(&extracted.config) {
            continue;
        }
        fogs.views.remove(&entity);
        match VolumetricFog::new(device.wgpu_device(), &extracted.config) {
            Ok(fog) => {
                warned.remove(&entity);
                failed.remove(&entity);
                fogs.views.insert(
                    entity,
                    ViewFog {
                        fog,
                        apply: None,
                        shadow_map: None,
                        point_maps: None,
                        spot_maps: None,
                        density_texture: None,
                        depth: None,
                        depth_resolve: None,
                        ready: false,
                    },
                );
            }
            Err(error) => {
                if warned.insert(entity) {
                    warn!("volfog: view {entity}: {error}; the fog is off for this camera");
                }
                failed.insert(entity, extracted.config.clone());
            }
        }
    }
    update_shared(&mut fogs, device.wgpu_device(), &queue);
}

/// Keeps the shared group of several fog cameras, sized for the primary's volume (a
/// new one when that size changes; the main world refreshes the materials then, as
/// the fog settings or the viewport changed).
fn update_shared(fogs: &mut FogViews, device: &wgpu::Device, queue: &wgpu::Queue) {
    let size = (fogs.views.len() >= 2)
        .then(|| fogs.primary().map(|v| v.fog.config().volume_size))
        .flatten();
    let Some(size) = size else {
        fogs.shared = None;
        return;
    };
    if fogs
        .shared
        .as_ref()
        .is_some_and(|s| s.volume_size() == size)
    {
        return;
    }
    // The size is that of a fog that was built, so it is valid.
    fogs.shared = SharedFog::new(device, queue, size).ok();
}

/// Binds each view's shadow maps (the sun's cascades, the point and spot lights' maps)
/// and depth buffer (once Bevy has prepared them) and uploads the frame's inputs. A
/// view whose fog fails is warned about once and left without fog this frame.
pub fn prepare_froxel_fog(
    views: Query<ViewItems>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut fogs: ResMut<FogViews>,
    lights: BevyLights,
    images: Res<RenderAssets<GpuImage>>,
    mut warned: Local<HashSet<Entity>>,
) {
    let layers = device.limits().max_texture_array_layers as usize;
    let layout = lights.layout(layers);
    for (entity, extracted, target, depth, shadows) in &views {
        let Some(view) = fogs.views.get_mut(&entity) else {
            continue;
        };
        view.ready = false;
        // The volumes' density texture, once Bevy has prepared its image (until then
        // the fog's texture is 1 everywhere: the volumes are uniform).
        let density = extracted.density_texture.and_then(|id| images.get(id));
        if let Some(image) = density {
            let texture: &wgpu::Texture = &image.texture;
            if view.density_texture.as_ref() != Some(texture) {
                view.density_texture = Some(texture.clone());
                if let Err(error) = view.fog.set_density_texture(device.wgpu_device(), texture)
                    && warned.insert(entity)
                {
                    warn!(
                        "volfog: view {entity}: FroxelFogVolumeTexture.image: {error}; the \
                         volumes are uniform"
                    );
                }
            }
        }
        match prepare_view(
            view,
            extracted,
            target,
            depth,
            shadows.map(|s| (s, layout.as_ref())),
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
    shadows: Option<(&ViewShadowBindings, Option<&BevyShadowLayout>)>,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
) -> Result<(), FogError> {
    let mut inputs = extracted.inputs();
    let shadowed = match shadows {
        Some((bindings, Some(layout))) => {
            bind_light_shadows(view, extracted, bindings, layout, device)?
        }
        _ => Vec::new(),
    };
    inputs.shadowed_lights = &shadowed;
    match shadows.map(|(b, _)| b) {
        Some(bindings) if inputs.cascades.count > 0 => {
            let texture: &wgpu::Texture = &bindings.directional_light_depth_texture;
            if view.shadow_map.as_ref() != Some(texture) {
                view.fog.set_shadow_map(device, texture)?;
                view.shadow_map = Some(texture.clone());
            }
        }
        _ => inputs.cascades.count = 0,
    }

    let bevy_depth: &wgpu::Texture = &depth.attachment.texture.texture;
    let samples = bevy_depth.sample_count();
    let key = (target.main_texture_format(), samples);
    if view.apply.as_ref().is_none_or(|(k, _)| *k != key) {
        let apply = view.fog.create_apply_multisampled(device, key.0, samples)?;
        view.apply = Some((key, apply));
        view.depth = None;
    }
    // A multisampled camera: the fog reads the farthest sample of each pixel.
    if samples == 1 {
        view.depth_resolve = None;
    } else if view
        .depth_resolve
        .as_ref()
        .is_none_or(|r| r.source() != bevy_depth)
    {
        view.depth_resolve = Some(DepthResolve::new(device, bevy_depth));
    }
    let depth_texture = view
        .depth_resolve
        .as_ref()
        .map_or(bevy_depth, |r| r.resolved());
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

/// Sets Bevy's point and spot light shadow textures as the fog's depth maps (when they
/// change) and returns the frame's shadowed lights in them.
fn bind_light_shadows(
    view: &mut ViewFog,
    extracted: &ExtractedFroxelFog,
    bindings: &ViewShadowBindings,
    layout: &BevyShadowLayout,
    device: &wgpu::Device,
) -> Result<Vec<volfog::pipeline::ShadowedLight>, FogError> {
    let Some(local) = extracted.config.local_shadows else {
        return Ok(Vec::new());
    };
    let points: &wgpu::Texture = &bindings.point_light_depth_texture;
    if local.point_shadows > 0 && view.point_maps.as_ref() != Some(points) {
        view.fog.set_point_shadow_maps(device, points)?;
        view.point_maps = Some(points.clone());
    }
    let spots: &wgpu::Texture = &bindings.directional_light_depth_texture;
    if local.spot_shadows > 0 && view.spot_maps.as_ref() != Some(spots) {
        view.fog.set_spot_shadow_maps(device, spots)?;
        view.spot_maps = Some(spots.clone());
    }
    let spot_base = layout.spot_base(spots.size().depth_or_array_layers);
    Ok(layout
        .shadowed_lights(extracted, spot_base)
        .into_iter()
        .filter(|s| match s.camera {
            volfog::uniforms::LightCamera::Point { .. } => local.point_shadows > 0,
            volfog::uniforms::LightCamera::Spot { .. } => local.spot_shadows > 0,
        })
        .collect())
}

/// Runs the fog passes of the current view and composites the fog over its opaque
/// scene (after Bevy's opaque pass, before its transparent pass).
pub fn froxel_fog_pass(
    view: ViewQuery<(Entity, &ViewTarget), With<ExtractedFroxelFog>>,
    fogs: Res<FogViews>,
    mut ctx: RenderContext,
    mut warned: Local<HashSet<Entity>>,
) {
    let (entity, target) = view.into_inner();
    let Some(fog) = fogs.get(entity).filter(|f| f.ready) else {
        return;
    };
    let (Some((_, apply)), Some((_, depth_group))) = (&fog.apply, &fog.depth) else {
        return;
    };
    // A span of Bevy's render diagnostics (GPU time with RenderDiagnosticsPlugin and
    // timestamp queries), as Bevy's own passes record.
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let span = diagnostics.time_span(ctx.command_encoder(), "volfog");
    let encoder = ctx.command_encoder();
    encoder.push_debug_group("volfog");
    if let Some(resolve) = &fog.depth_resolve {
        resolve.encode(encoder);
    }
    let result = fog.fog.encode(encoder).and_then(|()| {
        if apply.samples() == 1 {
            fog.fog
                .record_apply(encoder, apply, target.main_texture_view(), depth_group)
        } else {
            // Every sample of the multisampled target, resolved when the pass ends;
            // Bevy's transparent pass then loads the fogged samples.
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("volfog apply (multisampled)"),
                color_attachments: &[Some(target.get_color_attachment())],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            fog.fog.draw_apply(&mut pass, apply, depth_group)
        }
    });
    // Several fog cameras: this camera's materials, drawn next, read its fog.
    if let (Some(shared), Ok(())) = (fogs.shared(), &result)
        && let Err(error) = fog.fog.encode_share(encoder, shared)
        && warned.insert(entity)
    {
        warn!(
            "volfog: view {entity}: {error}; its materials read the fog of the camera \
             drawn before it (give every fog camera whose materials read the fog the same \
             slices, tile size and viewport size)"
        );
    }
    encoder.pop_debug_group();
    span.end(ctx.command_encoder());
    if let Err(error) = result {
        // prepare_froxel_fog ran for this view, so encoding cannot fail; log if it does.
        error!("volfog: view {entity}: {error}");
    }
}

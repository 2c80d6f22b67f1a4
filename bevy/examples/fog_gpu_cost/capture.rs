//! What the GPU model needs from `fog_bench`'s scene, taken from Bevy apps of that
//! scene on the machine's Vulkan device (lavapipe here):
//!
//! - Bevy 0.20.1's own `VolumetricFog` pipeline: the descriptor Bevy queued in its
//!   `PipelineCache` (label `volumetric lighting pipeline`, the variant without a
//!   density texture, which the scene's `FogVolume` draws with), its shader composed
//!   from Bevy's shader assets by Bevy's own `ShaderCache` with the same shader defs
//!   (the pipeline's, and the three global ones `PipelineCache::new` adds on a native
//!   Vulkan device: `bevy_render-0.20.1/src/render_resource/pipeline_cache.rs`), so
//!   the WGSL is the text Bevy handed wgpu; and the scene as its loops see it: the
//!   camera, the fog volume, the sun's cascade bounds, Bevy's light clusters and the
//!   shadow map texture it samples; and every fog pipeline Bevy queued for the scene
//!   (the one with a density texture too), composed the same way, for the compile
//!   check on each chip;
//! - volfog's fog of the same scene as the plugin extracts it (`ExtractedFroxelFog`:
//!   the `FogConfig`, lights, volumes, cascades), at the plugin's default tile size as
//!   `fog_bench` times it.
//!
//! A frame or two is enough: the apps run until the fog's pipelines exist.

use bevy::light::cluster::{ClusterableObjects, Clusters, GlobalClusterSettings};
use bevy::light::{
    CascadeShadowConfig, DirectionalLightShadowMap, FogVolume, VolumetricFog, VolumetricLight,
};
use bevy::pbr::ViewShadowBindings;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::render_resource::{CachedPipelineState, PipelineCache, PipelineDescriptor};
use bevy::render::renderer::RenderDevice;
use bevy::shader::{
    ShaderCache, ShaderCacheError, ShaderCacheSource, ShaderDefVal, ValidateShader,
};
use volfog_bevy::{ExtractedFroxelFog, FroxelFog};

use crate::scene::{self, FogKind, SceneCamera, SceneOptions, Sun};

/// The label Bevy 0.20.1 gives the fog's render pipeline
/// (`bevy_pbr-0.20.1/src/volumetric_fog/render.rs`, `specialize`).
pub const PIPELINE_LABEL: &str = "volumetric lighting pipeline";
/// The fog shader's asset path in Bevy 0.20.1.
pub const SHADER_PATH: &str = "bevy_pbr/src/volumetric_fog/volumetric_fog.wesl";

/// A light of Bevy's clusters: where it is and how far it reaches.
#[derive(Clone, Debug)]
pub struct ClusteredLight {
    /// World position (m).
    pub position: Vec3,
    /// `range` (m).
    pub range: f32,
    /// A spot light's direction and outer half-angle (radians).
    pub spot: Option<(Vec3, f32)>,
    /// Whether it has a `VolumetricLight` (Bevy's fog lights the medium with it).
    pub volumetric: bool,
    /// Whether it casts shadows (Bevy's fog then samples its shadow map).
    pub shadows: bool,
}

/// Bevy's light clusters of the camera, as the shader indexes them.
#[derive(Clone, Debug)]
pub struct ClusterGrid {
    /// Clusters in x, y (screen tiles) and z (depth slices).
    pub dimensions: UVec3,
    /// View depth of the first slice's far plane and of the last slice (m).
    pub near: f32,
    pub far: f32,
    /// Point and spot lights per cluster (index `(y dx + x) dz + z`).
    pub lights: Vec<u32>,
}

/// One of the fog pipelines Bevy queued in its `PipelineCache` for the scene.
#[derive(Clone, Debug)]
pub struct FogPipeline {
    /// The pipeline's shader defs, the global ones first, `NAME` or `NAME=value`.
    pub shader_defs: Vec<String>,
    /// Its composed WGSL (vertex and fragment entry points).
    pub wgsl: String,
    /// Whether Bevy created it (its cache state is `Ok`).
    pub created: bool,
    /// Its colour target's format and its hull's vertex stride (bytes).
    pub target_format: String,
    pub vertex_stride: u64,
}

/// Bevy's fog in the scene, captured.
#[derive(Clone, Debug)]
pub struct BevyFog {
    /// Every fog pipeline of the scene in Bevy's cache (the one modelled among them).
    pub pipelines: Vec<FogPipeline>,
    /// The composed WGSL of the fog shader (vertex and fragment entry points).
    pub wgsl: String,
    /// The pipeline's shader defs, the global ones first, `NAME` or `NAME=value`.
    pub shader_defs: Vec<String>,
    /// The hull's vertex buffer: stride, and its one attribute (location, format).
    pub vertex_stride: u64,
    pub vertex_attribute: (u32, String),
    /// The colour target's format and blend ((src, dst) colour, (src, dst) alpha).
    pub target_format: String,
    pub blend: ((String, String), (String, String)),
    /// The screen (pixels).
    pub screen: (u32, u32),
    /// Camera: world -> view inverse and projection.
    pub world_from_view: Mat4,
    pub clip_from_view: Mat4,
    /// `VolumetricFog::step_count`.
    pub step_count: u32,
    /// The fog volume: world -> its unit cube, extinction (1/m), whether it has a
    /// density texture.
    pub local_from_world: Mat4,
    pub extinction: f32,
    pub density_texture: bool,
    /// Directional lights with a `VolumetricLight`, of all directional lights.
    pub volumetric_directional: u32,
    pub directional: u32,
    /// The sun's cascade far bounds (m).
    pub cascade_bounds: Vec<f32>,
    /// The directional shadow texture array: width, height, layers, bytes per texel.
    pub shadow_texture: (u32, u32, u32, u32),
    /// Bevy's clusters (computed on the CPU for the capture, see [`capture_bevy`]).
    pub clusters: ClusterGrid,
    /// The point and spot lights.
    pub lights: Vec<ClusteredLight>,
}

fn def_string(d: &ShaderDefVal) -> String {
    match d {
        ShaderDefVal::Bool(k, true) => k.to_string(),
        ShaderDefVal::Bool(k, false) => format!("{k}=false"),
        ShaderDefVal::Int(k, v) => format!("{k}={v}"),
        ShaderDefVal::UInt(k, v) => format!("{k}={v}"),
    }
}

/// The global shader defs Bevy 0.20.1's `PipelineCache::new` adds on native Vulkan
/// (`bevy_render-0.20.1/src/render_resource/pipeline_cache.rs`): the storage buffer
/// bindings per stage and two comparisons of it.
fn global_defs(device: &RenderDevice) -> Vec<ShaderDefVal> {
    let n = device.limits().max_storage_buffers_per_shader_stage;
    vec![
        ShaderDefVal::UInt("AVAILABLE_STORAGE_BUFFER_BINDINGS".into(), n),
        ShaderDefVal::Bool("AVAILABLE_STORAGE_BUFFER_BINDINGS__GE_3".into(), n >= 3),
        ShaderDefVal::Bool("AVAILABLE_STORAGE_BUFFER_BINDINGS__GE_6".into(), n >= 6),
    ]
}

/// `ShaderCache`'s module loader for the capture: the composed WGSL itself.
fn keep_wgsl(
    _: &(),
    source: ShaderCacheSource,
    _: &ValidateShader,
) -> Result<String, ShaderCacheError> {
    match source {
        ShaderCacheSource::Wgsl(text) => Ok(text),
        ShaderCacheSource::SpirV(_) => Err(ShaderCacheError::ProcessShaderError(
            "the fog shader came as SPIR-V".to_string(),
        )),
    }
}

fn blend_factor(f: wgpu::BlendFactor) -> String {
    use wgpu::BlendFactor as F;
    match f {
        F::One => "one",
        F::Zero => "zero",
        F::SrcAlpha => "src-alpha",
        F::OneMinusSrcAlpha => "one-minus-src-alpha",
        F::DstAlpha => "dst-alpha",
        F::Src => "src",
        other => return format!("{other:?}"),
    }
    .to_string()
}

type Error = Box<dyn std::error::Error>;

/// Runs frames of `app` until `ready` finds what it waits for (at most `frames`).
fn run_until<T>(
    app: &mut App,
    frames: u32,
    what: &str,
    mut ready: impl FnMut(&mut App) -> Option<T>,
) -> Result<T, Error> {
    for _ in 0..frames {
        app.update();
        if let Some(t) = ready(app) {
            return Ok(t);
        }
    }
    Err(format!("no {what} after {frames} frames").into())
}

type Descriptor = Box<bevy::render::render_resource::RenderPipelineDescriptor>;

/// Every fog pipeline in Bevy's cache: its descriptor, and whether Bevy created it.
fn fog_pipelines(app: &App) -> Vec<(Descriptor, bool)> {
    let cache = app.sub_app(RenderApp).world().resource::<PipelineCache>();
    cache
        .pipelines()
        .filter_map(|p| match &p.descriptor {
            PipelineDescriptor::RenderPipelineDescriptor(d)
                if d.label.as_deref() == Some(PIPELINE_LABEL) =>
            {
                Some((d.clone(), matches!(p.state, CachedPipelineState::Ok(_))))
            }
            _ => None,
        })
        .collect()
}

/// Bevy's fog pipeline of the scene, once Bevy has created it: its descriptor's
/// shader, defs and draw state.
fn fog_pipeline(app: &App) -> Option<Descriptor> {
    fog_pipelines(app).into_iter().find_map(|(d, created)| {
        (created && !d.vertex.shader_defs.contains(&"DENSITY_TEXTURE".into())).then_some(d)
    })
}

/// Bevy's `VolumetricFog` in `fog_bench`'s scene at `width` x `height`: its pipeline
/// and shader as Bevy built them, and the scene as the shader's loops see it.
///
/// Bevy 0.20 assigns lights to clusters on the GPU where compute shaders exist; the
/// capture switches its app to Bevy's CPU clustering (`GlobalClusterSettings::
/// gpu_clustering = None`), which fills the same buffers the fog shader reads (no
/// shader def depends on it), so that the lights of every cluster are known here.
pub fn capture_bevy(width: u32, height: u32) -> Result<BevyFog, Error> {
    let options = SceneOptions {
        width,
        height,
        fog: FogKind::BevyBuiltIn,
        ..SceneOptions::default()
    };
    let mut app = scene::app(&options);
    app.world_mut()
        .resource_mut::<GlobalClusterSettings>()
        .gpu_clustering = None;
    // The scene's fog as `fog_bench` runs it; the capture's frames then march one step
    // per pixel (the step count is a uniform: the pipeline is the same), which spares
    // a software rasterizer most of their time.
    app.update();
    let step_count = {
        let world = app.world_mut();
        let mut fogs = world.query_filtered::<&mut VolumetricFog, With<SceneCamera>>();
        let mut fog = fogs.single_mut(world)?;
        std::mem::replace(&mut fog.step_count, 1)
    };
    let descriptor = run_until(&mut app, 12, "Bevy fog pipeline", |app| fog_pipeline(app))?;
    // One more frame: the clusters' far plane follows the last frame's lights.
    app.update();

    let render = app.sub_app(RenderApp).world();
    let device = render.resource::<RenderDevice>().clone();
    let mut cache = ShaderCache::<String, ()>::new((), keep_wgsl);
    let shaders = app.world().resource::<Assets<Shader>>();
    for (id, shader) in shaders.iter() {
        let mut shader = shader.clone();
        shader.shader_defs.splice(0..0, global_defs(&device));
        cache.set_shader(id, shader);
    }
    let fragment = descriptor
        .fragment
        .as_ref()
        .ok_or("the fog pipeline has no fragment state")?;
    let compose =
        |cache: &mut ShaderCache<String, ()>, shader: &Handle<Shader>, defs: &[ShaderDefVal]| {
            cache
                .get(0, shader.id(), defs)
                .map(|m| (*m).clone())
                .map_err(|e| format!("composing the fog shader: {e}"))
        };
    // Every fog pipeline, composed as the modelled one: each stage's shader with its
    // defs (one module for both stages).
    let mut pipelines = Vec::new();
    for (d, created) in fog_pipelines(&app) {
        let f = d
            .fragment
            .as_ref()
            .ok_or("a fog pipeline has no fragment state")?;
        let vertex = compose(&mut cache, &d.vertex.shader, &d.vertex.shader_defs)?;
        let wgsl = compose(&mut cache, &f.shader, &f.shader_defs)?;
        if vertex != wgsl {
            return Err("the fog's vertex and fragment shaders differ".into());
        }
        let mut defs: Vec<String> = global_defs(&device).iter().map(def_string).collect();
        defs.extend(f.shader_defs.iter().map(def_string));
        let target = f.targets.first().cloned().flatten();
        pipelines.push(FogPipeline {
            shader_defs: defs,
            wgsl,
            created,
            target_format: target
                .map_or_else(String::new, |t| format!("{:?}", t.format).to_lowercase()),
            vertex_stride: d.vertex.buffers.first().map_or(0, |b| b.array_stride),
        });
    }
    let wgsl = compose(&mut cache, &fragment.shader, &fragment.shader_defs)?;
    let path = shaders
        .get(&fragment.shader)
        .map(|s| s.path.clone())
        .unwrap_or_default();
    if !path.ends_with("volumetric_fog.wesl") {
        return Err(format!("the fog pipeline's shader is {path}, not {SHADER_PATH}").into());
    }
    let mut shader_defs: Vec<String> = global_defs(&device).iter().map(def_string).collect();
    shader_defs.extend(fragment.shader_defs.iter().map(def_string));

    let buffer = descriptor
        .vertex
        .buffers
        .first()
        .ok_or("the fog pipeline has no vertex buffer")?;
    let attribute = buffer
        .attributes
        .first()
        .ok_or("the fog hull's vertex buffer has no attribute")?;
    let target = fragment
        .targets
        .first()
        .cloned()
        .flatten()
        .ok_or("the fog pipeline has no colour target")?;
    let blend = target.blend.ok_or("the fog pipeline does not blend")?;
    let pair = |c: wgpu::BlendComponent| (blend_factor(c.src_factor), blend_factor(c.dst_factor));

    let shadow = {
        let mut q = render
            .try_query::<&ViewShadowBindings>()
            .ok_or("no view shadow bindings")?;
        let b = q
            .iter(render)
            .next()
            .ok_or("the camera has no shadow bindings")?;
        let t = &b.directional_light_depth_texture;
        let size = t.size();
        let texel = t
            .format()
            .block_copy_size(Some(wgpu::TextureAspect::DepthOnly))
            .ok_or("the shadow format has no texel size")?;
        (size.width, size.height, size.depth_or_array_layers, texel)
    };

    let world = app.world_mut();
    let mut cameras =
        world.query_filtered::<(&Camera, &GlobalTransform, &Clusters), With<SceneCamera>>();
    let (camera, transform, clusters) = cameras.single(world)?;
    let lists = match &clusters.clusterable_objects {
        ClusterableObjects::Cpu(list) => list
            .iter()
            .map(|c| c.counts.point_lights + c.counts.spot_lights)
            .collect(),
        ClusterableObjects::Gpu => return Err("Bevy clustered the lights on the GPU".into()),
    };
    let grid = ClusterGrid {
        dimensions: clusters.dimensions,
        near: clusters.near,
        far: clusters.far,
        lights: lists,
    };
    let (world_from_view, clip_from_view) = (transform.to_matrix(), camera.clip_from_view());
    let mut volumes = world.query::<(&FogVolume, &GlobalTransform)>();
    let mut volume_list = volumes.iter(world);
    let (volume, volume_transform) = volume_list.next().ok_or("no FogVolume")?;
    if volume_list.next().is_some() {
        return Err("the model takes one FogVolume".into());
    }
    let (local_from_world, extinction, density_texture) = (
        volume_transform.to_matrix().inverse(),
        volume.density_factor * (volume.absorption + volume.scattering),
        volume.density_texture.is_some(),
    );
    let mut suns = world.query_filtered::<&CascadeShadowConfig, With<Sun>>();
    let cascade_bounds = suns.single(world)?.bounds.clone();
    let mut directional = world.query::<(&DirectionalLight, Has<VolumetricLight>)>();
    let (n_dir, n_vol) = directional
        .iter(world)
        .fold((0, 0), |(n, v), (_, vol)| (n + 1, v + u32::from(vol)));
    let mut points = world.query::<(&PointLight, &GlobalTransform, Has<VolumetricLight>)>();
    let mut lights: Vec<ClusteredLight> = points
        .iter(world)
        .map(|(l, t, volumetric)| ClusteredLight {
            position: t.translation(),
            range: l.range,
            spot: None,
            volumetric,
            shadows: l.shadow_maps_enabled,
        })
        .collect();
    let mut spots = world.query::<(&SpotLight, &GlobalTransform, Has<VolumetricLight>)>();
    lights.extend(spots.iter(world).map(|(l, t, volumetric)| ClusteredLight {
        position: t.translation(),
        range: l.range,
        spot: Some((t.forward().as_vec3(), l.outer_angle)),
        volumetric,
        shadows: l.shadow_maps_enabled,
    }));
    if world.resource::<DirectionalLightShadowMap>().size as u32 != shadow.0 {
        return Err("the directional shadow texture is not DirectionalLightShadowMap::size".into());
    }
    Ok(BevyFog {
        pipelines,
        wgsl,
        shader_defs,
        vertex_stride: buffer.array_stride,
        vertex_attribute: (
            attribute.shader_location,
            format!("{:?}", attribute.format).to_lowercase(),
        ),
        target_format: format!("{:?}", target.format).to_lowercase(),
        blend: (pair(blend.color), pair(blend.alpha)),
        screen: (width, height),
        world_from_view,
        clip_from_view,
        step_count,
        local_from_world,
        extinction,
        density_texture,
        volumetric_directional: n_vol,
        directional: n_dir,
        cascade_bounds,
        shadow_texture: shadow,
        clusters: grid,
        lights,
    })
}

/// volfog's fog of `fog_bench`'s scene at `width` x `height` as the plugin extracts
/// it, at the plugin's default tile size (as `fog_bench` runs it).
pub fn capture_volfog(width: u32, height: u32) -> Result<ExtractedFroxelFog, Error> {
    let options = SceneOptions {
        width,
        height,
        fog: FogKind::Froxel,
        ..SceneOptions::default()
    };
    let mut app = scene::app(&options);
    app.update();
    {
        let world = app.world_mut();
        let mut cameras = world.query_filtered::<&mut FroxelFog, With<SceneCamera>>();
        cameras.single_mut(world)?.tile_size = FroxelFog::default().tile_size;
    }
    let tile = FroxelFog::default().tile_size;
    let grid = (width.div_ceil(tile), height.div_ceil(tile));
    run_until(&mut app, 6, "volfog fog at the default tile size", |app| {
        let world = app.sub_app_mut(RenderApp).world_mut();
        let mut fogs = world.try_query::<&ExtractedFroxelFog>()?;
        fogs.iter(world)
            .find(|f| (f.config.volume_size.x, f.config.volume_size.y) == grid)
            .cloned()
    })
}

//! Truth scenes rendered by Bevy 0.20's own ray-marched fog (`VolumetricFog` on the
//! camera, `FogVolume`s, `VolumetricLight` on every light, Bevy's shadow maps), headless
//! into an `Rgba16Float` image before tonemapping, and read back.
//!
//! The camera: `Hdr`, `Tonemapping::None`, `DebandDither::Disabled`, `Msaa::Off` (Bevy's
//! default 4x MSAA would have the fog read sample 0 of the depth; off, a pixel is the
//! ray through its centre, as in volfog's rows), the scene's field of view and near
//! plane, a black clear colour. Shadow maps at Bevy's defaults: the sun's four cascades
//! of 2048 texels (`DirectionalLightShadowMap`, the last reaching 1.5 times the camera's
//! far plane, at least Bevy's 150 m), the point lights' cubes of 1024
//! (`PointLightShadowMap`), spot maps of 2048, Bevy's default biases and shadow
//! filtering (`ShadowFilteringMethod::Gaussian` for lamps; the fog reads the sun's
//! cascades through a 2x2 hardware compare).
//!
//! One image with the occluders black (the in-scattered radiance) and one with them
//! white (white minus black: the transmittance). Bevy's fog has no jitter by default,
//! so a still camera repeats its frames: a scene is read back once its image repeats
//! in two successive frames.

use std::sync::{Arc, Mutex};

use bevy::app::PluginsState;
use bevy::asset::RenderAssetUsages;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::image::{ImageAddressMode, ImageFilterMode, ImageSampler, ImageSamplerDescriptor};
use bevy::light::{GlobalAmbientLight, VolumetricLight};
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat, TextureUsages};
use bevy::render::settings::{RenderCreation, WgpuSettings};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use volfog::glam as vg;
use volfog::limits::InvalidValue;
use volfog_testkit::truth::scene::{TruthImage, TruthScene};

use crate::mapping::{DensityGrid, MappedScene, map_scene};

/// Frames run after a scene is spawned before its image is first read back.
const WARMUP_FRAMES: u32 = 3;
/// Read-backs of one image before [`RenderError::Unsettled`].
const SETTLE_TRIES: u32 = 8;
/// Frames waited for one read-back before [`RenderError::NoReadback`].
const READBACK_FRAMES: u32 = 20;

/// Why a scene could not be rendered.
#[derive(Debug)]
pub enum RenderError {
    /// The scene holds a value Bevy's fog cannot take (the field is named).
    Invalid(InvalidValue),
    /// No read-back of the image arrived.
    NoReadback {
        /// The scene.
        scene: String,
    },
    /// The image kept changing from frame to frame.
    Unsettled {
        /// The scene.
        scene: String,
    },
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Invalid(e) => write!(f, "{e}"),
            Self::NoReadback { scene } => write!(
                f,
                "{scene}: no read-back of Bevy's image in {READBACK_FRAMES} frames"
            ),
            Self::Unsettled { scene } => write!(
                f,
                "{scene}: Bevy's image still changed after {SETTLE_TRIES} read-backs of a still camera"
            ),
        }
    }
}

impl std::error::Error for RenderError {}

impl From<InvalidValue> for RenderError {
    fn from(e: InvalidValue) -> Self {
        Self::Invalid(e)
    }
}

/// Marks what a scene spawned (despawned after it is rendered).
#[derive(Component)]
struct TruthEntity;

/// A headless Bevy app that renders truth scenes one after the other.
pub struct BevyTruth {
    app: App,
}

impl Default for BevyTruth {
    fn default() -> Self {
        Self::new()
    }
}

impl BevyTruth {
    /// Bevy's default plugins on the Vulkan adapter wgpu picks (`WGPU_ADAPTER_NAME`
    /// chooses), without a window or log, pipelines compiled as they are asked for.
    pub fn new() -> Self {
        let mut app = App::new();
        let render = RenderPlugin {
            render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                backends: Some(wgpu::Backends::VULKAN),
                ..Default::default()
            })),
            synchronous_pipeline_compilation: true,
            ..Default::default()
        };
        app.add_plugins(
            DefaultPlugins
                .set(render)
                .disable::<bevy::log::LogPlugin>()
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    ..Default::default()
                })
                .disable::<WinitPlugin>(),
        )
        .insert_resource(GlobalAmbientLight {
            brightness: 0.0,
            ..Default::default()
        });
        while app.plugins_state() == PluginsState::Adding {
            bevy::tasks::tick_global_task_pools_on_main_thread();
        }
        app.finish();
        app.cleanup();
        Self { app }
    }

    /// The adapter Bevy renders on.
    pub fn adapter(&self) -> String {
        let info = self
            .app
            .sub_app(bevy::render::RenderApp)
            .world()
            .resource::<bevy::render::renderer::RenderAdapterInfo>();
        format!("{} ({:?}, {})", info.name, info.backend, info.driver_info)
    }

    /// Renders `scene` with `steps` ray-march steps per pixel: the in-scattered
    /// radiance over black occluders and the transmittance (white occluders minus
    /// black), per pixel, row-major from the top.
    pub fn render(&mut self, scene: &TruthScene, steps: u32) -> Result<TruthImage, RenderError> {
        let mapped = map_scene(scene, steps)?;
        let (target, material) = spawn(self.app.world_mut(), &mapped);
        let result = self.read_pair(&mapped, &target, &material);
        let world = self.app.world_mut();
        let spawned: Vec<Entity> = world
            .query_filtered::<Entity, With<TruthEntity>>()
            .iter(world)
            .collect();
        for entity in spawned {
            world.despawn(entity);
        }
        // One frame to take the scene out of the render world.
        self.app.update();
        result
    }

    fn read_pair(
        &mut self,
        mapped: &MappedScene,
        target: &Handle<Image>,
        material: &Handle<StandardMaterial>,
    ) -> Result<TruthImage, RenderError> {
        for _ in 0..WARMUP_FRAMES {
            self.app.update();
        }
        let black = self.settled(mapped, target)?;
        set_color(self.app.world_mut(), material, Color::WHITE);
        let white = self.settled(mapped, target)?;
        let [width, height] = mapped.size;
        Ok(TruthImage {
            width,
            height,
            radiance: black.iter().map(|b| b.truncate()).collect(),
            transmittance: black
                .iter()
                .zip(&white)
                .map(|(b, w)| (w.truncate() - b.truncate()).max(vg::Vec3::ZERO))
                .collect(),
        })
    }

    /// Reads the image back until two successive frames agree.
    fn settled(
        &mut self,
        mapped: &MappedScene,
        target: &Handle<Image>,
    ) -> Result<Vec<vg::Vec4>, RenderError> {
        let mut last = self.read(mapped, target)?;
        for _ in 0..SETTLE_TRIES {
            let next = self.read(mapped, target)?;
            if next == last {
                return Ok(next);
            }
            last = next;
        }
        Err(RenderError::Unsettled {
            scene: mapped.name.clone(),
        })
    }

    /// Runs frames until a read-back of `target` arrives.
    fn read(
        &mut self,
        mapped: &MappedScene,
        target: &Handle<Image>,
    ) -> Result<Vec<vg::Vec4>, RenderError> {
        let sink = Arc::new(Mutex::new(None::<Vec<u8>>));
        let filled = sink.clone();
        self.app
            .world_mut()
            .spawn(Readback::texture(target.clone()))
            .observe(move |event: On<ReadbackComplete>, mut commands: Commands| {
                *filled.lock().unwrap() = Some(event.data.clone());
                commands.entity(event.entity).despawn();
            });
        for _ in 0..READBACK_FRAMES {
            self.app.update();
            if let Some(bytes) = sink.lock().unwrap().take() {
                return Ok(bytes
                    .chunks_exact(8)
                    .map(|p| {
                        let h =
                            |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
                        vg::Vec4::new(h(0), h(1), h(2), h(3))
                    })
                    .collect());
            }
        }
        Err(RenderError::NoReadback {
            scene: mapped.name.clone(),
        })
    }
}

/// Sets the occluders' unlit colour.
fn set_color(world: &mut World, material: &Handle<StandardMaterial>, color: Color) {
    let mut materials = world.resource_mut::<Assets<StandardMaterial>>();
    if let Some(mut m) = materials.get_mut(material) {
        m.base_color = color;
    }
}

/// An `Rgba16Float` image the camera renders into and the read-back copies from.
fn render_target(size: [u32; 2]) -> Image {
    let mut target = Image::new_fill(
        Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        &[0; 8],
        TextureFormat::Rgba16Float,
        RenderAssetUsages::default(),
    );
    target.texture_descriptor.usage =
        TextureUsages::TEXTURE_BINDING | TextureUsages::COPY_SRC | TextureUsages::RENDER_ATTACHMENT;
    target
}

/// A density texture as Bevy samples it: `R16Float`, linear filtering, clamped to the
/// edge texels.
fn density_image(grid: &DensityGrid) -> Image {
    let bytes: Vec<u8> = grid
        .values
        .iter()
        .flat_map(|v| half::f16::from_f32(*v).to_le_bytes())
        .collect();
    let mut image = Image::new(
        Extent3d {
            width: grid.size.x,
            height: grid.size.y,
            depth_or_array_layers: grid.size.z,
        },
        TextureDimension::D3,
        bytes,
        TextureFormat::R16Float,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
        address_mode_u: ImageAddressMode::ClampToEdge,
        address_mode_v: ImageAddressMode::ClampToEdge,
        address_mode_w: ImageAddressMode::ClampToEdge,
        mag_filter: ImageFilterMode::Linear,
        min_filter: ImageFilterMode::Linear,
        ..Default::default()
    });
    image
}

/// Spawns the mapped scene (marked [`TruthEntity`]); returns the camera's target and
/// the occluders' material.
fn spawn(world: &mut World, mapped: &MappedScene) -> (Handle<Image>, Handle<StandardMaterial>) {
    let target = world
        .resource_mut::<Assets<Image>>()
        .add(render_target(mapped.size));
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::BLACK,
            unlit: true,
            ..Default::default()
        });
    let cube = world
        .resource_mut::<Assets<Mesh>>()
        .add(Cuboid::new(1.0, 1.0, 1.0));
    world.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(Color::BLACK),
            ..Default::default()
        },
        RenderTarget::Image(target.clone().into()),
        Projection::Perspective(mapped.projection.clone()),
        mapped.camera,
        Hdr,
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        mapped.exposure(),
        mapped.fog,
        TruthEntity,
    ));
    if let Some((light, transform, cascades)) = &mapped.sun {
        world.spawn((
            *light,
            *transform,
            cascades.clone(),
            VolumetricLight,
            TruthEntity,
        ));
    }
    for (light, transform) in &mapped.points {
        world.spawn((*light, *transform, VolumetricLight, TruthEntity));
    }
    for (light, transform) in &mapped.spots {
        world.spawn((*light, *transform, VolumetricLight, TruthEntity));
    }
    for v in &mapped.volumes {
        let mut volume = v.volume.clone();
        if let Some(grid) = &v.grid {
            volume.density_texture = Some(
                world
                    .resource_mut::<Assets<Image>>()
                    .add(density_image(grid)),
            );
        }
        world.spawn((volume, v.transform, TruthEntity));
    }
    for transform in &mapped.occluders {
        world.spawn((
            Mesh3d(cube.clone()),
            MeshMaterial3d(material.clone()),
            *transform,
            TruthEntity,
        ));
    }
    (target, material)
}

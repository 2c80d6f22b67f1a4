//! volfog for Bevy 0.20: froxel volumetric fog on Bevy's own wgpu device, and volfog's
//! shader modules as a WESL package.
//!
//! The fog's components, built and put on entities of a plain `World` (no app, no
//! renderer), and a gameplay query on the CPU through the camera's medium:
//!
//! ```
//! use bevy::prelude::*;
//! use volfog_bevy::volfog::cpu::height_fog::height_fog_transmittance;
//! use volfog_bevy::volfog::{glam as vg, limits};
//! use volfog_bevy::{FogMediumSettings, FogVolumeShape, FroxelFog, FroxelFogVolume};
//!
//! // A camera's fog: a denser medium than the default, froxels out to 200 m.
//! let fog = FroxelFog {
//!     far: 200.0,
//!     medium: FogMediumSettings { density: 0.05, height_falloff: 0.1, ..default() },
//!     ..default()
//! };
//! assert_eq!((fog.tile_size, fog.slices), (12, 128)); // 12x12-pixel froxels, 128 slices
//!
//! let mut world = World::new();
//! let camera = world.spawn((Camera3d::default(), fog.clone())).id();
//! let bank = world
//!     .spawn(FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5, ..default() })
//!     .id();
//! assert_eq!(world.get::<FroxelFog>(camera), Some(&fog));
//! // A fog volume is placed by its transform, which it requires.
//! assert_eq!(world.get::<Transform>(bank), Some(&Transform::IDENTITY));
//!
//! // The plugin checks the settings against volfog's limits when it extracts the
//! // camera; a value out of range switches that camera's fog off with one warning.
//! assert!(limits::MEDIUM_DENSITY.check("FroxelFog.medium.density", fog.medium.density).is_ok());
//! assert!(limits::MEDIUM_DENSITY.check("FroxelFog.medium.density", -1.0).is_err());
//!
//! // Gameplay: the fraction of a lamp's light, 60 m away along the ground, that reaches
//! // a player's eyes through the medium's height fog (its noise and volumes aside).
//! let m = &fog.medium;
//! let (eye, lamp) = (vg::Vec3::new(0.0, 1.7, 0.0), vg::Vec3::new(60.0, 1.7, 0.0));
//! let (b, c, h0) = (m.density, m.height_falloff, m.base_height);
//! let seen = height_fog_transmittance(b, c, h0, vg::Vec3::Y, eye, lamp - eye);
//! let density_at_eye = 0.05 * (-0.1f32 * 1.7).exp();
//! assert!((seen - (-density_at_eye * 60.0).exp()).abs() < 1e-5);
//! ```
//!
//! Add [`VolumetricFogPlugin`], put [`FroxelFog`] on a `Camera3d` (multisampled or
//! not) and, if you like, [`FroxelFogVolume`]s in the scene. The fog is lit by the first
//! shadowed `DirectionalLight` through its shadow cascades and by the other directional
//! lights unshadowed, by every `PointLight` and `SpotLight` (those with shadows through
//! Bevy's own shadow maps, within [`FroxelFog`]'s budget; spot cones as on Bevy's
//! surfaces), and by the `GlobalAmbientLight`; [`FroxelFog::lights`] can restrict it to
//! the lights with `VolumetricLight`, as Bevy's fog. A light marked
//! [`TransientFogLight`] (a muzzle flash, a lightning strike) lights the fog of the
//! frames it is in only, whole, and leaves no trail in its history. It is applied to
//! the opaque scene after Bevy's opaque pass, and transparent materials apply it
//! themselves by importing the `volfog` WESL package (see [`FoggedGlassMaterial`]). A
//! scene written for Bevy's `VolumetricFog` and `FogVolume` renders with volfog under
//! [`BevyFogCompat`].
//!
//! ```no_run
//! use bevy::prelude::*;
//! use volfog_bevy::{FroxelFog, FroxelFogVolume, FogVolumeShape, VolumetricFogPlugin};
//!
//! fn setup(mut commands: Commands) {
//!     commands.spawn((Camera3d::default(), FroxelFog::default()));
//!     commands.spawn((
//!         FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5, ..default() },
//!         Transform::from_xyz(0.0, 2.0, -10.0).with_scale(Vec3::splat(6.0)),
//!     ));
//! }
//! # let mut app = App::new();
//! # app.add_plugins(VolumetricFogPlugin).add_systems(Startup, setup);
//! ```

mod compat;
mod density;
mod extract;
mod light_shadows;
pub mod material;
mod msaa;
pub mod particles;
mod render;
mod settings;
mod transient;
pub mod wesl;

use bevy::asset::embedded_asset;
use bevy::core_pipeline::core_3d::{main_opaque_pass_3d, main_transparent_pass_3d};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::pbr::MaterialPlugin;
use bevy::prelude::*;
use bevy::render::{Render, RenderApp, RenderSystems};

pub use compat::{
    BevyFogCompat, FromBevyFog, FromDistanceFog, distance_fog_medium, distance_froxel_fog,
    froxel_fog, froxel_fog_volume,
};
pub use density::FroxelFogDensity;
pub use extract::{ExtractedFroxelFog, MAX_VOLUMES, TILE_SIZE};
pub use light_shadows::{ExtractedLightShadow, light_shadow_resolution};
pub use material::FoggedGlassMaterial;
pub use particles::{FogParticle, FroxelFogParticles};
pub use render::{FogViews, ViewFog};
pub use settings::{
    BlendMode, FogLightSelection, FogMediumSettings, FogVolumeShape, FroxelFog, FroxelFogVolume,
    FroxelFogVolumeTexture,
};
pub use transient::TransientFogLight;
pub use volfog;

/// Froxel volumetric fog for every camera with [`FroxelFog`], the `volfog` WESL
/// package for materials, and [`FoggedGlassMaterial`].
pub struct VolumetricFogPlugin;

impl Plugin for VolumetricFogPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(wesl::WeslPackagePlugin);
        embedded_asset!(app, "shaders/fogged_glass.wesl");
        app.add_plugins(MaterialPlugin::<FoggedGlassMaterial>::default())
            .add_systems(Update, request_depth_binding)
            .add_systems(PostUpdate, refresh_materials_on_rebuild);
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<FogViews>()
            .add_systems(ExtractSchedule, extract::extract_froxel_fog)
            .add_systems(
                Render,
                (
                    render::build_froxel_fog
                        .after(RenderSystems::ExtractCommands)
                        .before(RenderSystems::PrepareAssets),
                    render::prepare_froxel_fog.in_set(RenderSystems::PrepareBindGroups),
                ),
            )
            .add_systems(
                Core3d,
                render::froxel_fog_pass
                    .after(main_opaque_pass_3d)
                    .before(main_transparent_pass_3d)
                    .in_set(Core3dSystems::MainPass),
            );
    }
}

/// The fog reads the depth buffer: fog cameras need it bindable.
fn request_depth_binding(mut cameras: Query<&mut Camera3d, With<FroxelFog>>) {
    for mut camera in &mut cameras {
        let usage = wgpu::TextureUsages::TEXTURE_BINDING.bits();
        if camera.depth_texture_usages.0 & usage == 0 {
            camera.depth_texture_usages.0 |= usage;
        }
    }
}

/// What a camera's fog pipeline is built from, as the main world sees it.
#[derive(PartialEq)]
struct FogKey {
    fog: FroxelFog,
    viewport: Option<UVec2>,
    shadow_map: usize,
    point_shadow_map: usize,
    cascades: usize,
}

/// Rebuilds the bind groups of fogged materials when a fog camera's pipeline is
/// rebuilt (its settings, viewport or shadow map changed): they hold its resources.
fn refresh_materials_on_rebuild(
    cameras: Query<(Entity, &Camera, &FroxelFog)>,
    suns: Query<(
        &bevy::light::DirectionalLight,
        Option<&bevy::light::Cascades>,
    )>,
    shadow_map: Res<bevy::light::DirectionalLightShadowMap>,
    point_shadow_map: Res<bevy::light::PointLightShadowMap>,
    mut materials: ResMut<Assets<FoggedGlassMaterial>>,
    mut seen: Local<Vec<(Entity, FogKey)>>,
) {
    let keys: Vec<(Entity, FogKey)> = cameras
        .iter()
        .map(|(entity, camera, fog)| {
            let cascades = suns
                .iter()
                .filter(|(l, _)| l.shadow_maps_enabled)
                .filter_map(|(_, c)| c?.cascades.get(&entity).map(Vec::len))
                .next()
                .unwrap_or(0);
            let key = FogKey {
                fog: fog.clone(),
                viewport: camera.physical_viewport_size(),
                shadow_map: shadow_map.size,
                point_shadow_map: point_shadow_map.size,
                cascades,
            };
            (entity, key)
        })
        .collect();
    if *seen != keys {
        material::refresh_materials(&mut materials);
        *seen = keys;
    }
}

//! volfog for Bevy 0.20: froxel volumetric fog on Bevy's own wgpu device, and volfog's
//! shader modules as a WESL package.
//!
//! Add [`VolumetricFogPlugin`], put [`FroxelFog`] on a `Camera3d` (with `Msaa::Off`)
//! and, if you like, [`FroxelFogVolume`]s in the scene. The fog is lit by the first
//! `DirectionalLight` through its shadow cascades, by every `PointLight` and
//! `SpotLight`, and by the `GlobalAmbientLight`; it is applied to the opaque scene
//! after Bevy's opaque pass, and transparent materials apply it themselves by
//! importing the `volfog` WESL package (see [`FoggedGlassMaterial`]).
//!
//! ```no_run
//! use bevy::prelude::*;
//! use volfog_bevy::{FroxelFog, FroxelFogVolume, FogVolumeShape, VolumetricFogPlugin};
//!
//! fn setup(mut commands: Commands) {
//!     commands.spawn((Camera3d::default(), Msaa::Off, FroxelFog::default()));
//!     commands.spawn((
//!         FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5 },
//!         Transform::from_xyz(0.0, 2.0, -10.0).with_scale(Vec3::splat(6.0)),
//!     ));
//! }
//! # let mut app = App::new();
//! # app.add_plugins(VolumetricFogPlugin).add_systems(Startup, setup);
//! ```

mod extract;
pub mod material;
mod render;
mod settings;
pub mod wesl;

use bevy::asset::embedded_asset;
use bevy::core_pipeline::core_3d::{main_opaque_pass_3d, main_transparent_pass_3d};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::pbr::MaterialPlugin;
use bevy::prelude::*;
use bevy::render::{Render, RenderApp, RenderSystems};

pub use extract::{ExtractedFroxelFog, MAX_VOLUMES, TILE_SIZE};
pub use material::FoggedGlassMaterial;
pub use render::{FogViews, ViewFog};
pub use settings::{FogMediumSettings, FogVolumeShape, FroxelFog, FroxelFogVolume};
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

//! The medium as a Bevy app authors it, on the `fog_scene` scene: `FroxelFogVolume`'s
//! blend mode and order reach the fog (a subtractive box around the scene clears all of
//! its fog, the scene's additive pocket included when it comes after it, not when it
//! comes before), and a `FroxelFogDensity` shader asset written in WESL becomes the
//! fog's custom density (the scene's height fog written as a density function gives
//! the fog of the same medium; a shader without the function turns the fog off with
//! one warning naming it and the signature).

#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "support/warnings.rs"]
mod warnings;

use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::shader::Shader;
use scene::{FogKind, SceneCamera, SceneOptions, read_volume};
use volfog_bevy::{
    BlendMode, ExtractedFroxelFog, FogViews, FogVolumeShape, FroxelFog, FroxelFogDensity,
    FroxelFogVolume,
};
use warnings::{volfog_warnings, warnings};

fn options() -> SceneOptions {
    SceneOptions::still(96, 54, FogKind::Froxel)
}

fn camera_of(app: &mut App) -> Entity {
    let world = app.world_mut();
    let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
    q.single(world).unwrap()
}

fn frames(app: &mut App, n: u32) {
    for _ in 0..n {
        app.update();
    }
}

fn extracted(app: &mut App) -> Option<ExtractedFroxelFog> {
    let world = app.sub_app_mut(RenderApp).world_mut();
    let mut q = world.query::<&ExtractedFroxelFog>();
    q.iter(world).next().cloned()
}

/// The least transmittance over the integrated volume's last slice.
fn least_far_transmittance(app: &App) -> f32 {
    let v = read_volume(app);
    let s = v.fog.config.volume_size;
    let last = ((s.z - 1) * s.y * s.x) as usize;
    v.texels[last..]
        .iter()
        .map(|t| t.w)
        .fold(f32::MAX, f32::min)
}

#[test]
fn blend_mode_and_order_reach_the_fog() {
    warnings();
    let mut app = scene::app(&options());
    frames(&mut app, 4);
    let fogged = least_far_transmittance(&app);
    // A box 1 km wide around the scene that subtracts more than there is, after the
    // scene's additive pocket (order 1 > 0).
    let clear = app
        .world_mut()
        .spawn((
            FroxelFogVolume {
                shape: FogVolumeShape::Box,
                density: 1000.0,
                edge: 0.02,
                blend: BlendMode::Subtract,
                order: 1,
            },
            Transform::from_scale(Vec3::splat(1000.0)),
        ))
        .id();
    frames(&mut app, 3);
    let fog = extracted(&mut app).expect("an extracted fog");
    let blends: Vec<(u32, f32)> = fog.volumes.iter().map(|v| (v.blend, v.density)).collect();
    assert_eq!(
        blends,
        [(0, 0.12), (1, 1000.0)],
        "the pocket, then the subtractive box"
    );
    let cleared = least_far_transmittance(&app);
    // Before the pocket (order -1): the pocket's fog comes back.
    app.world_mut()
        .get_mut::<FroxelFogVolume>(clear)
        .unwrap()
        .order = -1;
    frames(&mut app, 3);
    let fog = extracted(&mut app).expect("an extracted fog");
    assert_eq!(fog.volumes[0].blend, BlendMode::Subtract as u32);
    let pocket_only = least_far_transmittance(&app);
    eprintln!(
        "least transmittance at the far slice: {fogged:.4} in the scene's fog, {cleared:.4} \
         with a subtractive box after the pocket, {pocket_only:.4} with it before"
    );
    assert!(fogged < 0.5, "{fogged}");
    assert!(cleared > 0.999, "the box clears all the fog: {cleared}");
    assert!(
        pocket_only < 0.99 && pocket_only > fogged,
        "only the pocket's fog: {pocket_only}"
    );
    let ours: Vec<String> = volfog_warnings()
        .into_iter()
        .filter(|w| !w.contains("tests/broken.wesl"))
        .collect();
    assert!(ours.is_empty(), "{ours:?}");
}

/// The scene's height fog `0.035 exp(-0.2 y)` of albedo 0.9 written as a WESL density.
const HEIGHT_FOG: &str = "import volfog::types::{FogSample, FogCustomParams};

fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {
    let p = params.values[0];
    return FogSample(vec3<f32>(p.z), p.x * exp(-p.y * world.y), vec3<f32>(0.0));
}
";

#[test]
fn a_wesl_density_shader_becomes_the_fogs_custom_density() {
    warnings();
    // The scene's medium, unattenuated light (the custom density is not on the light's
    // path, as the medium's noise is not).
    let mut medium_app = scene::app(&options());
    frames(&mut medium_app, 1);
    let camera = camera_of(&mut medium_app);
    medium_app
        .world_mut()
        .get_mut::<FroxelFog>(camera)
        .unwrap()
        .light_transmittance = false;
    frames(&mut medium_app, 4);
    let medium = read_volume(&medium_app).texels;

    // The same fog as a density shader asset, the medium's density 0.
    let mut custom_app = scene::app(&options());
    frames(&mut custom_app, 1);
    let camera = camera_of(&mut custom_app);
    let shader = custom_app
        .world_mut()
        .resource_mut::<Assets<Shader>>()
        .add(Shader::from_wesl(HEIGHT_FOG, "tests/height_fog.wesl"));
    let mut density = FroxelFogDensity::new(shader);
    density.params[0] = Vec4::new(0.035, 0.2, 0.9, 0.0);
    custom_app.world_mut().entity_mut(camera).insert(density);
    {
        let mut fog = custom_app.world_mut().get_mut::<FroxelFog>(camera).unwrap();
        fog.light_transmittance = false;
        fog.medium.density = 0.0;
    }
    frames(&mut custom_app, 4);
    let fog = extracted(&mut custom_app).expect("an extracted fog");
    let module = fog
        .config
        .custom_density
        .as_ref()
        .expect("the custom density");
    assert_eq!(module.file, "tests/height_fog.wesl");
    let custom = read_volume(&custom_app).texels;
    assert_eq!(custom.len(), medium.len());
    let (mut worst_t, mut worst_l) = (0.0f32, 0.0f32);
    for (c, m) in custom.iter().zip(&medium) {
        worst_t = worst_t.max((c.w - m.w).abs());
        let scale = m.truncate().max_element().max(1e-3);
        worst_l = worst_l.max((c.truncate() - m.truncate()).abs().max_element() / scale);
    }
    eprintln!(
        "the scene's height fog as a WESL density shader vs as the medium: transmittance \
         within {worst_t:.2e}, in-scattering within {:.3}% (bound 2e-3 and 0.5%)",
        worst_l * 100.0
    );
    assert!(worst_t <= 2e-3 && worst_l <= 5e-3, "{worst_t} {worst_l}");

    // A shader without the function: the fog goes off with one warning naming it and
    // the signature.
    let broken = custom_app
        .world_mut()
        .resource_mut::<Assets<Shader>>()
        .add(Shader::from_wesl(
            "fn other() -> f32 { return 1.0; }\n",
            "tests/broken.wesl",
        ));
    custom_app
        .world_mut()
        .entity_mut(camera)
        .insert(FroxelFogDensity::new(broken));
    frames(&mut custom_app, 3);
    let views = custom_app
        .sub_app(RenderApp)
        .world()
        .resource::<FogViews>()
        .len();
    let warned: Vec<String> = volfog_warnings()
        .into_iter()
        .filter(|w| w.contains("tests/broken.wesl"))
        .collect();
    assert_eq!(views, 0, "the fog is off");
    assert_eq!(warned.len(), 1, "one warning: {warned:?}");
    assert!(
        warned[0].contains("fn volfog_custom_density("),
        "{}",
        warned[0]
    );
}

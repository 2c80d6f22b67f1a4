//! Short-lived lights in Bevy: a `PointLight` or `DirectionalLight` with
//! `TransientFogLight` becomes a transient light of the fog (`FrameInputs::
//! transient_lights`), not one of its lights or its sun, also where the fog takes only
//! the lights with `VolumetricLight`; and on the `fog_scene` scene at 160 x 90 with
//! temporal reprojection (history weight 0.9, checkerboard amortisation, noise off) a
//! flash marked so raises the fog by its whole contribution in its frame and leaves
//! nothing the frame after, where the same flash as an ordinary light shows a twentieth
//! of it (the blend's tenth of the half of the froxels injected) and then a ghost.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "support/warnings.rs"]
mod warnings;

use bevy::prelude::*;
use bevy::render::RenderApp;
use scene::{FogKind, SceneCamera, SceneOptions, read_volume};
use volfog::uniforms::FOG_LIGHT_DIRECTIONAL;
use volfog_bevy::{ExtractedFroxelFog, FogLightSelection, FroxelFog, TransientFogLight};
use warnings::{volfog_warnings, warnings};

fn extracted(app: &mut App) -> ExtractedFroxelFog {
    let world = app.sub_app_mut(RenderApp).world_mut();
    let mut q = world.query::<&ExtractedFroxelFog>();
    q.iter(world).next().expect("an extracted fog").clone()
}

fn set_fog(app: &mut App, change: impl FnOnce(&mut FroxelFog)) {
    let world = app.world_mut();
    let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
    let camera = q.single(world).unwrap();
    change(&mut app.world_mut().get_mut::<FroxelFog>(camera).unwrap());
}

fn frames(app: &mut App, n: u32) {
    for _ in 0..n {
        app.update();
    }
}

/// A muzzle flash 3 m in front of the camera.
fn flash() -> (PointLight, Transform) {
    (
        PointLight {
            color: Color::linear_rgb(1.0, 0.7, 0.3),
            intensity: 4.0e6,
            range: 15.0,
            radius: 0.05,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_translation(scene::EYE + (scene::TARGET - scene::EYE).normalize() * 3.0),
    )
}

/// The in-scattering of the integrated volume's last slice (the fog in front of
/// everything), summed over the screen.
fn fog_sum(app: &App) -> f32 {
    let volume = read_volume(app);
    let size = volume.fog.config.volume_size;
    let slice = (size.x * size.y) as usize;
    let start = (size.z as usize - 1) * slice;
    volume.texels[start..start + slice]
        .iter()
        .map(|t| t.x + t.y + t.z)
        .sum()
}

#[test]
fn marked_lights_become_transient_lights() {
    warnings();
    let mut app = scene::app(&SceneOptions::still(160, 90, FogKind::Froxel));
    frames(&mut app, 3);
    let before = extracted(&mut app);
    assert!(before.transient_lights.is_empty());
    assert_eq!(
        before.config.max_transient_lights,
        volfog::limits::MAX_TRANSIENT_LIGHTS
    );
    let point = app.world_mut().spawn((flash(), TransientFogLight)).id();
    let strike = app
        .world_mut()
        .spawn((
            DirectionalLight {
                illuminance: 5000.0,
                shadow_maps_enabled: true,
                ..default()
            },
            Transform::IDENTITY.looking_to(Vec3::new(0.2, -1.0, -0.3), Vec3::Y),
            TransientFogLight,
        ))
        .id();
    frames(&mut app, 1);
    let lit = extracted(&mut app);
    assert_eq!(lit.transient_lights.len(), 2, "{:?}", lit.transient_lights);
    assert_eq!(lit.transient_lights[0].flags, 0, "the flash: a point light");
    let position = Vec3::from_array(lit.transient_lights[0].position.to_array());
    assert!((position - flash().1.translation).length() < 1e-4);
    assert_eq!(lit.transient_lights[1].flags, FOG_LIGHT_DIRECTIONAL);
    assert_eq!(lit.lights, before.lights, "not among the fog's lights");
    assert_eq!(
        lit.sun, before.sun,
        "a transient directional light is not the sun"
    );
    assert_eq!(lit.cascades.count, before.cascades.count);

    // A fog lit only by lights with `VolumetricLight` still takes them.
    set_fog(&mut app, |f| f.lights = FogLightSelection::Volumetric);
    frames(&mut app, 1);
    assert_eq!(extracted(&mut app).transient_lights.len(), 2);

    app.world_mut().despawn(point);
    app.world_mut()
        .entity_mut(strike)
        .remove::<TransientFogLight>();
    set_fog(&mut app, |f| f.lights = FogLightSelection::All);
    frames(&mut app, 1);
    let after = extracted(&mut app);
    assert!(after.transient_lights.is_empty());
    assert!(
        after.lights.iter().any(|l| l.is_directional()) || after.sun != before.sun,
        "without the component the strike is an ordinary directional light"
    );
    assert_eq!(volfog_warnings(), Vec::<String>::new());
}

/// Settles the history, then the fog sum of that frame, of the next (with a flash,
/// transient when `Some(true)`, ordinary when `Some(false)`) and of the one after it
/// (the flash despawned).
fn step(app: &mut App, spawn: Option<bool>) -> (f32, f32, f32) {
    frames(app, 40);
    let base = fog_sum(app);
    let light = spawn.map(|marked| {
        let mut e = app.world_mut().spawn(flash());
        if marked {
            e.insert(TransientFogLight);
        }
        e.id()
    });
    frames(app, 1);
    let lit = fog_sum(app);
    if let Some(light) = light {
        app.world_mut().despawn(light);
    }
    frames(app, 1);
    (base, lit, fog_sum(app))
}

#[test]
fn a_transient_flash_lights_its_frame_whole_and_leaves_no_ghost() {
    warnings();
    let mut app = scene::app(&SceneOptions {
        temporal: true,
        ..SceneOptions::still(160, 90, FogKind::Froxel)
    });
    frames(&mut app, 1);
    set_fog(&mut app, |f| f.history_weight = 0.9);
    let (base, still, still_after) = step(&mut app, None);
    let (t_base, t_lit, t_after) = step(&mut app, Some(true));
    let (o_base, o_lit, o_after) = step(&mut app, Some(false));
    // Frame to frame without any flash: the jitter moves each froxel's sample.
    let noise = (still - base).abs().max((still_after - base).abs());
    let whole = t_lit - t_base;
    let share = o_lit - o_base;
    let ghost = t_after - t_base;
    let ordinary_ghost = o_after - o_base;
    eprintln!(
        "fog sum {base:.3}; frame-to-frame change without a flash {noise:.4}; the flash as a \
         transient light +{whole:.3}, the frame after {ghost:+.4}; as an ordinary light \
         +{share:.3} ({:.3} of the transient's), the frame after {ordinary_ghost:+.4}",
        share / whole
    );
    assert!(whole > 50.0 * noise.max(1e-3), "the flash lights the fog");
    // The blend's 10 %, of the half of the froxels the checkerboard injects this frame
    // (`FroxelFog::amortize`, on by default): 5 %.
    assert!(
        (share / whole - 0.05).abs() < 0.02,
        "an ordinary light shows the blend's share: {}",
        share / whole
    );
    assert!(
        ghost.abs() <= 2.0 * noise + 1e-3 * whole,
        "no ghost: {ghost}"
    );
    // The next frame keeps nine tenths of it in the history.
    assert!(
        ordinary_ghost > 0.03 * whole && ordinary_ghost > 10.0 * noise,
        "the ordinary light leaves a ghost: {ordinary_ghost}"
    );
    assert_eq!(volfog_warnings(), Vec::<String>::new());
}

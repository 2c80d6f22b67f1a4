//! The plugin as a drop-in for Bevy's fog, on the `fog_scene` scene at 160 x 90 (noise
//! and temporal off, so frames repeat exactly):
//!
//! - every light: a second `DirectionalLight` lights the fog (unshadowed, as a
//!   directional fog light), linearly in its illuminance; spot lights take Bevy's cone;
//!   `FogLightSelection::Volumetric` keeps only the lights with `VolumetricLight`;
//! - Bevy's own components: a camera with Bevy's `VolumetricFog` and the scene's
//!   `FogVolume` render, under `BevyFogCompat`, the image of the `FroxelFog` and
//!   `FroxelFogVolume` they map to, with fog in it and no Bevy volumetric view in the
//!   render world (while Bevy's own pass, without `BevyFogCompat`, changes the image);
//!   what volfog does not take warns once, naming the field; Bevy's exponential
//!   `DistanceFog` renders as Bevy draws it, and fogs the sky with its colour.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "support/warnings.rs"]
mod warnings;

use bevy::camera::Exposure;
use bevy::light::{FogVolume, VolumetricFog, VolumetricLight};
use bevy::pbr::DistanceFog;
use bevy::prelude::*;
use bevy::render::RenderApp;
use scene::{FogKind, SceneCamera, SceneOptions, Sun, read_volume};
use volfog::uniforms::{FOG_LIGHT_DIRECTIONAL, FOG_LIGHT_SPOT_SQUARED};
use volfog_bevy::{
    ExtractedFroxelFog, FogLightSelection, FromBevyFog, FroxelFog, FroxelFogVolume, froxel_fog,
    froxel_fog_volume,
};
use warnings::{volfog_warnings, warnings};

fn options(fog: FogKind) -> SceneOptions {
    SceneOptions::still(160, 90, fog)
}

fn extracted(app: &mut App) -> ExtractedFroxelFog {
    let world = app.sub_app_mut(RenderApp).world_mut();
    let mut q = world.query::<&ExtractedFroxelFog>();
    q.iter(world).next().expect("an extracted fog").clone()
}

fn camera_of(app: &mut App) -> Entity {
    let world = app.world_mut();
    let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
    q.single(world).unwrap()
}

fn set_fog(app: &mut App, change: impl FnOnce(&mut FroxelFog)) {
    let camera = camera_of(app);
    let mut fog = app.world_mut().get_mut::<FroxelFog>(camera).unwrap();
    change(&mut fog);
}

fn frames(app: &mut App, n: u32) {
    for _ in 0..n {
        app.update();
    }
}

const MOON: Vec3 = Vec3::new(0.6, 0.5, 0.62);

/// A second, unshadowed directional light from the other side of the sky, of
/// illuminance `lux`.
fn moon(lux: f32) -> DirectionalLight {
    DirectionalLight {
        color: Color::linear_rgb(0.55, 0.65, 1.0),
        illuminance: lux,
        shadow_maps_enabled: false,
        ..default()
    }
}

/// The integrated volume's last slice (the fog in front of everything), rgb.
fn far_slice(app: &App) -> Vec<Vec3> {
    let volume = read_volume(app);
    let size = volume.fog.config.volume_size;
    let slice = (size.x * size.y) as usize;
    let start = (size.z as usize - 1) * slice;
    volume.texels[start..start + slice]
        .iter()
        .map(|t| t.truncate())
        .collect()
}

#[test]
fn every_light_lights_the_fog() {
    let mut app = scene::app(&options(FogKind::Froxel));
    frames(&mut app, 4);
    let without = far_slice(&app);
    let before = extracted(&mut app);
    assert!(
        before
            .lights
            .iter()
            .all(|l| l.flags & FOG_LIGHT_DIRECTIONAL == 0),
        "no directional fog light before the moon rises"
    );
    let spots: Vec<_> = before
        .lights
        .iter()
        .filter(|l| l.cos_outer > -1.0)
        .collect();
    assert_eq!(spots.len(), 2, "the scene's two spot lights");
    assert!(
        spots.iter().all(|l| l.flags == FOG_LIGHT_SPOT_SQUARED),
        "spot lights take Bevy's cone falloff"
    );

    // The moon: a second directional light, unshadowed, from the other side.
    let lux = 2500.0;
    let toward = MOON.normalize();
    let moon_entity = app
        .world_mut()
        .spawn((moon(lux), Transform::IDENTITY.looking_to(-toward, Vec3::Y)))
        .id();
    frames(&mut app, 4);
    let lit = far_slice(&app);
    let fog = extracted(&mut app);
    let exposure = Exposure {
        ev100: scene::EV100,
    }
    .exposure();
    let directional: Vec<_> = fog.lights.iter().filter(|l| l.is_directional()).collect();
    assert_eq!(
        directional.len(),
        1,
        "the moon is one directional fog light"
    );
    let m = directional[0];
    let want = Vec3::new(0.55, 0.65, 1.0) * lux * exposure;
    let got = Vec3::from_array(m.color.to_array());
    assert!(
        (got - want).length() <= 1e-4 * want.length(),
        "{got} {want}"
    );
    let direction = Vec3::from_array(m.direction.to_array());
    assert!(
        (direction + toward).length() < 1e-4,
        "{direction} travels away from the moon"
    );
    assert_eq!(
        m.fog_intensity,
        scene::fog_settings(&options(FogKind::Froxel)).sun_scattering
    );
    assert_eq!(
        fog.sun.color, before.sun.color,
        "the shadowed sun stays volfog's sun"
    );

    // Twice the illuminance scatters twice the moon's light into the fog.
    app.world_mut()
        .get_mut::<DirectionalLight>(moon_entity)
        .unwrap()
        .illuminance = 2.0 * lux;
    frames(&mut app, 4);
    let doubled = far_slice(&app);
    let (mut added, mut ratios) = (0usize, Vec::new());
    for ((w, l), d) in without.iter().zip(&lit).zip(&doubled) {
        let (one, two) = ((*l - *w).element_sum(), (*d - *w).element_sum());
        if one > 1e-3 * w.element_sum().max(1e-3) {
            added += 1;
        }
        if one > 0.02 * w.element_sum() {
            ratios.push(two / one);
        }
    }
    ratios.sort_by(f32::total_cmp);
    let median = ratios[ratios.len() / 2];
    let (lo, hi) = (ratios[ratios.len() / 20], ratios[ratios.len() * 19 / 20]);
    eprintln!(
        "moon: {added} of {} far-slice texels brighter; doubled / single illuminance: \
         median {median:.4}, 5-95 % {lo:.4}..{hi:.4} over {} texels (bound 2 +- 0.05)",
        without.len(),
        ratios.len()
    );
    assert!(
        added * 10 > without.len() * 9,
        "the moon lights the fog everywhere"
    );
    assert!((median - 2.0).abs() < 0.05 && lo > 1.9 && hi < 2.1);

    // Only the lights with VolumetricLight: the sun (which has it in the scene), not the
    // point and spot lights nor the moon, until the moon gets it.
    set_fog(&mut app, |f| f.lights = FogLightSelection::Volumetric);
    frames(&mut app, 2);
    let volumetric = extracted(&mut app);
    assert!(volumetric.lights.is_empty(), "{:?}", volumetric.lights);
    assert_eq!(volumetric.sun.color, before.sun.color);
    app.world_mut()
        .entity_mut(moon_entity)
        .insert(VolumetricLight);
    frames(&mut app, 2);
    let volumetric = extracted(&mut app);
    assert_eq!(volumetric.lights.len(), 1);
    assert!(volumetric.lights[0].is_directional());
    // Without VolumetricLight on the sun either, the moon becomes the sun.
    let world = app.world_mut();
    let mut suns = world.query_filtered::<Entity, With<Sun>>();
    let sun = suns.single(world).unwrap();
    world.entity_mut(sun).remove::<VolumetricLight>();
    frames(&mut app, 2);
    let only_moon = extracted(&mut app);
    assert!(only_moon.lights.is_empty());
    assert_eq!(only_moon.cascades.count, 0, "the moon casts no shadows");
    let sun_color = Vec3::from_array(only_moon.sun.color.to_array());
    assert!((sun_color - 2.0 * want).length() <= 1e-4 * want.length());
}

/// Mean over pixels of |a - b| / max(|b|, 1e-3) (luminance-like sum of rgb).
fn mean_relative(a: &[Vec4], b: &[Vec4]) -> f32 {
    let sum: f32 = a
        .iter()
        .zip(b)
        .map(|(a, b)| {
            let (a, b) = (a.truncate().element_sum(), b.truncate().element_sum());
            (a - b).abs() / b.abs().max(1e-3)
        })
        .sum();
    sum / a.len() as f32
}

#[test]
fn bevy_volumetric_fog_renders_with_volfog() {
    warnings();
    // Bevy's components under BevyFogCompat.
    let mut compat = scene::app(&options(FogKind::BevyCompat));
    let image = scene::capture(&mut compat, 8);
    let camera = camera_of(&mut compat);
    assert!(
        compat.world().get::<FromBevyFog>(camera).is_some(),
        "the camera's FroxelFog comes from its VolumetricFog"
    );
    let render = compat.sub_app_mut(RenderApp).world_mut();
    let mut views = render.query_filtered::<Entity, With<VolumetricFog>>();
    let bevy_views = views.iter(render).count();
    assert_eq!(bevy_views, 0, "no view runs Bevy's volumetric pass");
    let fog = extracted(&mut compat);
    let volume = FogVolume {
        density_factor: 0.035,
        absorption: 0.1,
        scattering: 0.9,
        scattering_asymmetry: 0.7,
        ..default()
    };
    assert!((fog.medium.phase_g - 0.7).abs() < 1e-6);
    assert!((fog.medium.albedo.x - 0.9).abs() < 1e-6);
    assert_eq!(fog.medium.density, 0.0, "no fog outside the volumes");
    assert!(
        fog.volumes.iter().any(|v| (v.density - 0.035).abs() < 1e-6),
        "the FogVolume is a froxel volume of extinction 0.035 / m"
    );
    assert!(
        fog.lights.is_empty(),
        "the scene's point and spot lights have no VolumetricLight"
    );

    // The FroxelFog and FroxelFogVolume the components map to, set by hand on a scene
    // without fog: the same image, so no other fog was drawn.
    // The fog goes on in the first frame's PostUpdate, as BevyFogCompat's does, so the
    // temporal history of both runs has the same frames.
    let mut by_hand = scene::app(&options(FogKind::None));
    let exposure = Exposure {
        ev100: scene::EV100,
    }
    .exposure();
    let fog_by_hand = froxel_fog(&VolumetricFog::default(), Some(&volume), exposure);
    by_hand.add_systems(
        PostUpdate,
        move |mut commands: Commands,
              cameras: Query<Entity, (With<SceneCamera>, Without<FroxelFog>)>| {
            for camera in &cameras {
                commands.entity(camera).insert(fog_by_hand.clone());
            }
        },
    );
    by_hand.world_mut().spawn((
        froxel_fog_volume(&volume),
        Transform::from_xyz(0.0, 10.0, -20.0).with_scale(Vec3::new(120.0, 20.0, 120.0)),
    ));
    let expected = scene::capture(&mut by_hand, 8);
    let unfogged = {
        let mut app = scene::app(&options(FogKind::None));
        scene::capture(&mut app, 8)
    };
    // Bevy's own pass, which BevyFogCompat leaves out: a different image.
    let bevy_pass = {
        let mut app = scene::app(&options(FogKind::BevyBuiltIn));
        scene::capture(&mut app, 8)
    };
    let by_bevy = mean_relative(&bevy_pass, &expected);
    let same = mean_relative(&image, &expected);
    let worst = image
        .iter()
        .zip(&expected)
        .map(|(a, b)| {
            (*a - *b).truncate().abs().max_element() / b.truncate().max_element().max(1e-3)
        })
        .fold(0.0f32, f32::max);
    let fogged = mean_relative(&image, &unfogged);
    eprintln!(
        "BevyFogCompat vs the FroxelFog it maps to: mean relative difference {same:e}, \
         worst {worst:e} (bounds 1e-3, 1e-2); vs no fog {fogged:.3} (> 0.05); Bevy's own \
         pass vs the FroxelFog {by_bevy:.3} (> 0.05)"
    );
    assert!(same < 1e-3 && worst < 1e-2);
    assert!(fogged > 0.05, "the image has fog");
    assert!(by_bevy > 0.05, "Bevy's pass would change the image");

    // A second volume with another colour and a density texture, and a third with
    // another density texture: one warning for each field, however many frames (a fog
    // reads one density texture, the first textured volume's).
    let before = volfog_warnings().len();
    let mut images = compat.world_mut().resource_mut::<Assets<Image>>();
    let [first, other] = [255u8, 128].map(|v| {
        images.add(Image::new_fill(
            bevy::render::render_resource::Extent3d::default(),
            bevy::render::render_resource::TextureDimension::D3,
            &[v],
            bevy::render::render_resource::TextureFormat::R8Unorm,
            bevy::asset::RenderAssetUsages::RENDER_WORLD,
        ))
    });
    compat.world_mut().spawn((
        FogVolume {
            fog_color: Color::linear_rgb(1.0, 0.2, 0.2),
            density_texture: Some(first),
            ..volume.clone()
        },
        Transform::from_xyz(0.0, 2.0, -12.0).with_scale(Vec3::splat(4.0)),
    ));
    compat.world_mut().spawn((
        FogVolume {
            density_texture: Some(other),
            ..volume.clone()
        },
        Transform::from_xyz(3.0, 2.0, -14.0).with_scale(Vec3::splat(3.0)),
    ));
    frames(&mut compat, 3);
    let new = volfog_warnings()[before..].to_vec();
    eprintln!("{new:#?}");
    for field in ["FogVolume.fog_color", "FroxelFogVolumeTexture.image"] {
        let count = new.iter().filter(|m| m.contains(field)).count();
        assert_eq!(count, 1, "one warning naming {field}: {new:?}");
    }
    assert_eq!(new.len(), 2, "{new:?}");
    assert!(image.iter().all(|p| p.is_finite()));
    let world = by_hand.world_mut();
    let mut volumes = world.query::<&FroxelFogVolume>();
    assert_eq!(
        volumes.iter(world).count(),
        2,
        "the scene's pocket and the box"
    );
}

/// The plugin's default cheap path (amortised injection and depth culling) against the
/// full path: the same image within a stated bound once the history has settled; and
/// the baked noise texture (off by default), whose different noise pattern changes the
/// image more. Noise on, wind off (the noise then does not depend on the apps'
/// wall-clock time), temporal on, 40 frames, then the mean of `CAPTURES` read-backs.
#[test]
fn the_default_cheap_path_holds_the_image() {
    const CAPTURES: u32 = 12;
    let options = SceneOptions {
        noise: true,
        temporal: true,
        ..options(FogKind::Froxel)
    };
    let run = |change: fn(&mut FroxelFog)| {
        let mut app = scene::app(&options);
        app.update();
        set_fog(&mut app, |f| {
            f.medium.wind = Vec3::ZERO;
            change(f);
        });
        // The compare shadow filter takes one jittered tap a froxel a frame, so a frame
        // carries the history blend's sampling noise (the two paths sample in another
        // order); the mean of 12 read-backs over the frames after the 40th compares
        // what each path converges to.
        let mut image = scene::capture(&mut app, 40);
        for _ in 1..CAPTURES {
            for (sum, p) in image.iter_mut().zip(scene::capture(&mut app, 1)) {
                *sum += p;
            }
        }
        image.iter_mut().for_each(|p| *p /= CAPTURES as f32);
        let config = extracted(&mut app).config;
        (image, config)
    };
    let (cheap, cheap_config) = run(|_| {});
    let (full, full_config) = run(|f| f.amortize = false);
    let (baked, baked_config) = run(|f| f.noise_texture = true);
    assert!(cheap_config.amortize && cheap_config.depth_cull && !cheap_config.noise_texture);
    assert!(!full_config.amortize && baked_config.noise_texture);
    let figures = |d: &[f32]| {
        let mean = d.iter().sum::<f32>() / d.len() as f32;
        (d[d.len() / 2], d[d.len() * 95 / 100], mean)
    };
    let (median, p95, mean) = figures(&scene::relative_differences(&cheap, &full));
    let (b_median, b_p95, b_mean) = figures(&scene::relative_differences(&baked, &cheap));
    eprintln!(
        "default (amortised) vs full injection, 160x90 after 40 frames, mean of \
         {CAPTURES} read-backs: relative \
         difference median {median:.2e}, p95 {p95:.2e}, mean {mean:.2e} (bounds: mean \
         2e-2, p95 5e-2); noise texture vs computed noise: median {b_median:.2e}, p95 \
         {b_p95:.2e}, mean {b_mean:.2e}"
    );
    assert!(mean < 2e-2 && p95 < 5e-2);
    assert!(b_mean > 0.0, "the noise texture is read");
}

/// Bevy's exponential `DistanceFog` under `BevyFogCompat` (a glowing medium that
/// scatters nothing, froxels then tail) against Bevy's own per-fragment fog, on every
/// pixel Bevy fogs (Bevy leaves the sky alone; volfog's sky takes the fog colour,
/// `1 - exp(-0.03 * infinity)` of it).
#[test]
fn exponential_distance_fog_renders_as_bevys() {
    let mut bevy = scene::app(&options(FogKind::BevyDistance));
    // The glass sphere's material applies volfog's fog and not Bevy's distance fog:
    // hidden in both.
    let hide_glass = |app: &mut App| {
        app.update();
        let world = app.world_mut();
        let mut q = world.query_filtered::<&mut Visibility, With<scene::GlassSphere>>();
        *q.single_mut(world).unwrap() = Visibility::Hidden;
    };
    hide_glass(&mut bevy);
    // Bevy needs a few frames before every light reaches the surfaces.
    let by_bevy = scene::capture(&mut bevy, 12);
    let mut compat = scene::app(&options(FogKind::BevyDistanceCompat));
    hide_glass(&mut compat);
    // The mapped FroxelFog keeps the plugin's defaults (temporal reprojection, history
    // weight 0.9): 60 frames leave 0.9^60 = 0.2 % of the first frames' history.
    let by_volfog = scene::capture(&mut compat, 60);
    let camera = camera_of(&mut compat);
    assert!(compat.world().get::<FroxelFog>(camera).is_some());
    let render = compat.sub_app_mut(RenderApp).world_mut();
    let mut views = render.query_filtered::<Entity, With<DistanceFog>>();
    assert_eq!(
        views.iter(render).count(),
        0,
        "Bevy's materials draw no distance fog"
    );
    let fog = extracted(&mut compat);
    assert!(
        (fog.medium.density - 0.03).abs() < 1e-7 && fog.medium.albedo == volfog::glam::Vec3::ZERO
    );

    let sky = Vec4::new(0.35, 0.42, 0.55, 1.0);
    let color = Vec3::new(0.5, 0.55, 0.62);
    let (mut surfaces, mut sky_pixels) = (Vec::new(), Vec::new());
    for (b, v) in by_bevy.iter().zip(&by_volfog) {
        if (*b - sky).truncate().abs().max_element() < 2e-3 {
            sky_pixels.push((v.truncate() - color).abs().max_element() / color.max_element());
        } else {
            let (b, v) = (b.truncate(), v.truncate());
            surfaces.push((v - b).abs().max_element() / b.max_element().max(1e-3));
        }
    }
    surfaces.sort_by(f32::total_cmp);
    sky_pixels.sort_by(f32::total_cmp);
    let mean = surfaces.iter().sum::<f32>() / surfaces.len() as f32;
    let p95 = surfaces[surfaces.len() * 95 / 100];
    let sky_p95 = sky_pixels[sky_pixels.len() * 95 / 100];
    eprintln!(
        "exponential DistanceFog, volfog vs Bevy over {} fogged pixels: relative difference \
         mean {mean:.2e}, p95 {p95:.2e}, max {:.2e} (bounds: mean 1.5e-2, p95 4e-2); {} sky \
         pixels: 95 % within {sky_p95:.2e} of the fog colour (bound 2.5e-2)",
        surfaces.len(),
        surfaces[surfaces.len() - 1],
        sky_pixels.len()
    );
    assert!(sky_pixels.len() > 100 && surfaces.len() > 5000);
    assert!(
        fog.config.near <= 0.1,
        "the fog starts at Bevy's near plane"
    );
    assert!(mean < 1.5e-2 && p95 < 4e-2);
    // The sky pixels off the fog colour lie next to the roof and the pillars, where the
    // volume's bilinear look-up reaches a column culled behind the surface: within a
    // 12-pixel froxel (the default tile) of it: 1.2e-2 at 8-pixel tiles, 2.0e-2 at 12.
    assert!(sky_p95 < 2.5e-2);
}

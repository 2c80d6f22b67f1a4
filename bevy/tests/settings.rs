//! Settings out of range, Bevy's way: the fog of that camera goes off with one warning
//! that names the field and its range, and comes back when the settings are fixed;
//! nothing panics and the image stays finite. Also: a camera with 4x MSAA keeps its
//! fog and matches the single-sampled image away from silhouettes, a resized view gets
//! a grid of its new size, and a camera that loses its `FroxelFog` drops its fog
//! pipeline.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "support/warnings.rs"]
mod warnings;

use bevy::prelude::*;
use bevy::render::RenderApp;
use scene::{FogKind, SceneCamera, SceneOptions};
use volfog_bevy::{ExtractedFroxelFog, FogViews, FroxelFog};
use warnings::{volfog_warnings, warnings};

fn camera_entity(app: &mut App) -> Entity {
    let world = app.world_mut();
    let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
    q.single(world).unwrap()
}

/// (the camera's render entity has an extracted fog, fog pipelines in the render world)
fn fog_state(app: &mut App) -> (bool, usize) {
    let world = app.sub_app_mut(RenderApp).world_mut();
    let extracted = world.query::<&ExtractedFroxelFog>().iter(world).count() > 0;
    let views = world.resource::<FogViews>().len();
    (extracted, views)
}

#[test]
fn out_of_range_settings_turn_the_fog_off_with_one_warning() {
    warnings();
    let options = SceneOptions::still(96, 54, FogKind::Froxel);
    let mut app = scene::app(&options);
    app.update();
    let camera = camera_entity(&mut app);
    let good = scene::fog_settings(&options);
    for _ in 0..2 {
        app.update();
    }
    assert_eq!(
        fog_state(&mut app),
        (true, 1),
        "the fog runs with valid settings"
    );
    // Bevy needs a few frames before every light reaches the surfaces.
    let fogged = scene::capture(&mut app, 10);

    for (bad, field) in [
        (
            FroxelFog {
                tile_size: 0,
                ..good.clone()
            },
            "FroxelFog.tile_size",
        ),
        (
            FroxelFog {
                far: 0.2,
                ..good.clone()
            },
            "FroxelFog.far",
        ),
        (
            FroxelFog {
                slices: 5000,
                ..good.clone()
            },
            "FroxelFog.slices",
        ),
        (
            FroxelFog {
                history_weight: 1.5,
                temporal: true,
                ..good.clone()
            },
            "FroxelFog.history_weight",
        ),
        (
            FroxelFog {
                sun_scattering: f32::NAN,
                ..good.clone()
            },
            "FroxelFog.sun_scattering",
        ),
        (
            FroxelFog {
                medium: volfog_bevy::FogMediumSettings {
                    density: -1.0,
                    ..good.medium.clone()
                },
                ..good.clone()
            },
            "FroxelFog.medium.density",
        ),
        (
            FroxelFog {
                medium: volfog_bevy::FogMediumSettings {
                    top_height: f32::INFINITY,
                    ..good.medium.clone()
                },
                ..good.clone()
            },
            "FroxelFog.medium.top_height",
        ),
        (
            FroxelFog {
                spot_shadows: 100,
                ..good.clone()
            },
            "FroxelFog.spot_shadows",
        ),
        (
            FroxelFog {
                light_shadow_exponent: 0.0,
                ..good.clone()
            },
            "FroxelFog.light_shadow_exponent",
        ),
    ] {
        let before = volfog_warnings().len();
        app.world_mut().entity_mut(camera).insert(bad);
        let image = scene::capture(&mut app, 3);
        let new: Vec<String> = volfog_warnings()[before..].to_vec();
        eprintln!("{field}: {new:?}");
        assert_eq!(
            new.len(),
            1,
            "one warning over several frames for {field}: {new:?}"
        );
        assert!(
            new[0].contains(field),
            "the warning names {field}: {}",
            new[0]
        );
        assert!(new[0].contains("fog is off"), "{}", new[0]);
        assert_eq!(
            fog_state(&mut app),
            (false, 0),
            "the fog is off for {field}"
        );
        assert!(image.iter().all(|p| p.is_finite()), "finite image");
        app.world_mut().entity_mut(camera).insert(good.clone());
        let back = scene::capture(&mut app, 2);
        assert_eq!(
            fog_state(&mut app),
            (true, 1),
            "the fog comes back after {field}"
        );
        let differs = back
            .iter()
            .zip(&fogged)
            .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-3)
            .count();
        assert_eq!(differs, 0, "the same fogged image after {field}");
    }

    // MSAA (Bevy's default 4x): the fog stays on, without a warning, and away from
    // silhouettes the image is the one without MSAA.
    let single = scene::capture(&mut app, 3);
    let before = volfog_warnings().len();
    app.world_mut().entity_mut(camera).insert(Msaa::Sample4);
    let multisampled = scene::capture(&mut app, 3);
    assert_eq!(volfog_warnings()[before..].to_vec(), Vec::<String>::new());
    assert_eq!(fog_state(&mut app), (true, 1), "the fog runs with MSAA");
    check_msaa_image(
        &single,
        &multisampled,
        &fogged,
        options.width,
        options.height,
    );
    app.world_mut().entity_mut(camera).insert(Msaa::Off);
    for _ in 0..2 {
        app.update();
    }
    assert_eq!(fog_state(&mut app), (true, 1));

    // Resized with the view: the grid follows the render target.
    let grid = |app: &mut App| {
        let world = app.sub_app_mut(RenderApp).world_mut();
        let mut q = world.query::<&ExtractedFroxelFog>();
        q.iter(world).next().map(|f| f.config.volume_size)
    };
    assert_eq!(grid(&mut app), Some(volfog::glam::UVec3::new(12, 7, 128)));
    let target = app.world().resource::<scene::Capture>().image.clone();
    app.world_mut()
        .resource_mut::<Assets<Image>>()
        .get_mut(&target)
        .unwrap()
        .resize(bevy::render::render_resource::Extent3d {
            width: 160,
            height: 90,
            depth_or_array_layers: 1,
        });
    let resized = scene::capture(&mut app, 3);
    assert_eq!(grid(&mut app), Some(volfog::glam::UVec3::new(20, 12, 128)));
    assert_eq!(fog_state(&mut app), (true, 1));
    assert_eq!(resized.len(), 160 * 90);
    assert!(resized.iter().all(|p| p.is_finite()));

    // Without FroxelFog the camera's fog and its pipeline go.
    app.world_mut().entity_mut(camera).remove::<FroxelFog>();
    for _ in 0..2 {
        app.update();
    }
    assert_eq!(fog_state(&mut app), (false, 0));
}

/// The 4x MSAA image against the single-sampled one, away from silhouettes: pixels
/// whose 3x3 neighbourhood in the single-sampled image spans less than 10 % of its
/// luminance. There every sample of a pixel lies at one depth, so the fog (and the
/// surface) is the same; only rgba16float rounding and Bevy's sample positions
/// remain.
fn check_msaa_image(single: &[Vec4], msaa: &[Vec4], fogged: &[Vec4], w: u32, h: u32) {
    let lum = |p: Vec4| p.x * 0.2126 + p.y * 0.7152 + p.z * 0.0722;
    let (w, h) = (w as i32, h as i32);
    let mut errors = Vec::new();
    let mut edges = 0usize;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let around: Vec<f32> = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| ((y + dy) * w + x + dx) as usize))
                .map(|i| lum(single[i]))
                .collect();
            let (lo, hi) = around
                .iter()
                .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
            let i = (y * w + x) as usize;
            if hi - lo > 0.1 * hi.max(1e-6) {
                edges += 1;
                continue;
            }
            errors.push(
                (msaa[i] - single[i]).truncate().abs().max_element()
                    / single[i].truncate().max_element().max(1e-3),
            );
        }
    }
    errors.sort_by(f32::total_cmp);
    let at = |q: f64| errors[((errors.len() - 1) as f64 * q) as usize];
    let mean = errors.iter().map(|e| f64::from(*e)).sum::<f64>() / errors.len().max(1) as f64;
    eprintln!(
        "MSAA 4x against Msaa::Off away from silhouettes: {} pixels ({edges} on edges), \
         relative difference median {:.2e}, p95 {:.2e}, max {:.2e} (sub-pixel detail MSAA \
         resolves), mean {mean:.2e}",
        errors.len(),
        at(0.5),
        at(0.95),
        at(1.0)
    );
    assert!(
        errors.len() > (w * h / 5) as usize,
        "enough flat pixels: {}",
        errors.len()
    );
    assert!(
        at(0.95) <= 1e-2 && mean <= 5e-3,
        "p95 {}, mean {mean}",
        at(0.95)
    );
    assert!(
        msaa.iter().all(|p| p.is_finite()),
        "the MSAA image is finite"
    );
    // The fog is there: the MSAA image is the fogged one, not the bare scene.
    let same = msaa
        .iter()
        .zip(fogged)
        .filter(|(a, b)| (**a - **b).truncate().abs().max_element() <= 1e-2)
        .count();
    assert!(
        same * 2 > msaa.len(),
        "the MSAA image is fogged: {same} of {}",
        msaa.len()
    );
}

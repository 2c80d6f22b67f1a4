//! Two fog cameras, each rendering into its own image, with their own fog: the second
//! stands on the other side of the glass sphere at the same distance, in a medium four
//! times as dense. The sphere's `FoggedGlassMaterial` (one bind group for both views)
//! must get in each camera the fog that camera's fullscreen pass gives the same colour
//! drawn opaque, which it can only do by reading that camera's fog.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;

use bevy::camera::{Exposure, Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::RenderApp;
use scene::{FogKind, GlassSphere, SceneOptions};
use volfog_bevy::{FogViews, FoggedGlassMaterial};

const W: u32 = 160;
const H: u32 = 90;

/// The sphere's colour, drawn with coverage 1.
const GLASS: LinearRgba = LinearRgba::new(0.6, 0.75, 0.8, 1.0);

/// The second camera: mirrored through the sphere's vertical axis from the scene
/// camera, so both see it from the same distance.
fn second_eye() -> Vec3 {
    let c = scene::GLASS_CENTER;
    let d = scene::EYE - c;
    c + Vec3::new(-d.x, d.y + 0.5, d.z)
}

/// The ray through a pixel's centre of a camera at `eye` looking at `target`.
fn pixel_ray(eye: Vec3, target: Vec3, x: u32, y: u32) -> Vec3 {
    let camera = Transform::from_translation(eye).looking_at(target, Vec3::Y);
    let tan = (scene::FOV_Y_DEGREES.to_radians() * 0.5).tan();
    let aspect = W as f32 / H as f32;
    let ndc_x = (x as f32 + 0.5) / W as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
    (camera.rotation * Vec3::new(ndc_x * tan * aspect, ndc_y * tan, -1.0)).normalize()
}

/// Pixels well inside the sphere's silhouette (0.9 of its radius) for a camera.
fn sphere_pixels(eye: Vec3, target: Vec3) -> Vec<usize> {
    let mut pixels = Vec::new();
    for y in 0..H {
        for x in 0..W {
            let d = pixel_ray(eye, target, x, y);
            let oc = eye - scene::GLASS_CENTER;
            let b = oc.dot(d);
            let c = oc.dot(oc) - (scene::GLASS_RADIUS * 0.9).powi(2);
            if b * b - c >= 0.0 {
                pixels.push((y * W + x) as usize);
            }
        }
    }
    pixels
}

fn set_glass(app: &mut App, material: FoggedGlassMaterial) {
    let world = app.world_mut();
    let mut q = world.query_filtered::<&MeshMaterial3d<FoggedGlassMaterial>, With<GlassSphere>>();
    let handle = q.single(world).unwrap().0.clone();
    *world
        .resource_mut::<Assets<FoggedGlassMaterial>>()
        .get_mut(&handle)
        .unwrap() = material;
}

#[test]
fn each_camera_s_materials_read_its_own_fog() {
    let options = SceneOptions::still(W, H, FogKind::Froxel);
    let mut app = scene::app(&options);
    app.update();
    let first = app.world().resource::<scene::Capture>().image.clone();
    let second = {
        let mut images = app.world_mut().resource_mut::<Assets<Image>>();
        scene::render_target(&mut images, W, H)
    };
    let mut dense = scene::fog_settings(&options);
    dense.medium.density *= 4.0;
    app.world_mut().spawn((
        Camera3d::default(),
        Camera {
            order: 1,
            clear_color: ClearColorConfig::Custom(Color::linear_rgb(0.35, 0.42, 0.55)),
            ..Default::default()
        },
        RenderTarget::Image(second.clone().into()),
        Projection::Perspective(PerspectiveProjection {
            fov: scene::FOV_Y_DEGREES.to_radians(),
            near: 0.1,
            ..Default::default()
        }),
        Transform::from_translation(second_eye()).looking_at(scene::GLASS_CENTER, Vec3::Y),
        Hdr,
        Msaa::Off,
        Tonemapping::None,
        Exposure {
            ev100: scene::EV100,
        },
        dense,
    ));
    let images = [first, second];
    // The sphere opaque, fogged by each camera's fullscreen pass; then in the
    // transparent pass, fogged by its material.
    set_glass(
        &mut app,
        FoggedGlassMaterial {
            color: GLASS,
            fog: false,
            alpha_mode: AlphaMode::Opaque,
        },
    );
    let applied = scene::capture_images(&mut app, &images, 4);
    set_glass(
        &mut app,
        FoggedGlassMaterial {
            color: GLASS,
            fog: true,
            alpha_mode: AlphaMode::Blend,
        },
    );
    let material = scene::capture_images(&mut app, &images, 3);
    let fog_views = app.sub_app(RenderApp).world().resource::<FogViews>();
    assert_eq!(fog_views.len(), 2, "two fog cameras");
    assert!(
        fog_views.shared().is_some(),
        "their materials share a group"
    );

    let cameras = [
        ("scene camera", scene::EYE, scene::TARGET),
        (
            "second camera (4x density)",
            second_eye(),
            scene::GLASS_CENTER,
        ),
    ];
    let mut fog_amounts = Vec::new();
    for (i, (name, eye, target)) in cameras.into_iter().enumerate() {
        let pixels = sphere_pixels(eye, target);
        assert!(pixels.len() >= 20, "{name}: {} sphere pixels", pixels.len());
        let (mut sum, mut worst, mut amount) = (0.0f32, 0.0f32, 0.0f32);
        for &p in &pixels {
            let (a, m) = (applied[i][p], material[i][p]);
            let error = (a - m).abs().max_element() / a.max_element().max(1e-3);
            sum += error;
            worst = worst.max(error);
            // How far the fog moves the surface from its own colour.
            let bare = GLASS.to_vec4().truncate();
            amount += ((a.truncate() - bare).abs() / bare).max_element();
        }
        let n = pixels.len() as f32;
        let (mean, amount) = (sum / n, amount / n);
        eprintln!(
            "{name}: {} sphere px, material vs its fullscreen fog mean relative error {mean:.2e}, worst {worst:.2e} (bounds 5e-3, 2e-2); the fog moves the glass by {:.1} % on average",
            pixels.len(),
            100.0 * amount
        );
        assert!(mean <= 5e-3, "{name}: mean {mean}");
        assert!(worst <= 2e-2, "{name}: worst {worst}");
        assert!(material[i].iter().all(|p| p.is_finite()));
        fog_amounts.push(amount);
    }
    // The cameras' fogs differ far beyond the bounds, so a material reading the other
    // camera's fog fails them.
    assert!(
        fog_amounts[1] >= 1.5 * fog_amounts[0] && fog_amounts[0] >= 0.02,
        "{fog_amounts:?}"
    );
}

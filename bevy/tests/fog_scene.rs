//! The `fog_scene` example's scene rendered by Bevy on the GPU with the plugin, at
//! 320 x 180, in several states of one app, read back as linear floats:
//!
//! - `fogged`: the scene with the froxel fog (noise off, temporal off: the closed-form
//!   height fog is the reference);
//! - `inscatter`: the same with every surface black and a black sky: only the fog's
//!   in-scattered light L remains; `inscatter_unshadowed`: the same with the sun's
//!   shadow maps off;
//! - `surface`: the scene without fog.
//!
//! With fogged = surface * T + L, each ground pixel's transmittance T is measured and
//! compared with the closed-form optical depth of the medium along its ray; light
//! shafts show in the integrated volume, where the sun's shadows take the sun's share
//! of the scattered light (the CPU mirror's, through the medium's transmittance
//! towards the sun) out of froxels in a pillar's shadow and not out of sunlit ones (a
//! CPU ray test against the scene's boxes classifies them); the glass sphere, whose
//! material applies the fog through the WESL package, gets the fog the fullscreen pass
//! gives the same colour drawn opaque; nothing is NaN.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;

use std::sync::OnceLock;

use bevy::prelude::*;
use scene::{FogKind, GlassSphere, SceneCamera, SceneOptions, Sun, Volume, read_volume};
use volfog::cpu::density::medium_light_transmittance;
use volfog::glam as vg;
use volfog_bevy::{FoggedGlassMaterial, FroxelFog};

const W: u32 = 320;
const H: u32 = 180;

struct Renders {
    fogged: Vec<Vec4>,
    inscatter: Vec<Vec4>,
    inscatter_unshadowed: Vec<Vec4>,
    surface: Vec<Vec4>,
    /// The sphere, colour GLASS opaque, fogged by the fullscreen pass.
    glass_apply: Vec<Vec4>,
    /// The sphere, colour GLASS with alpha 1 in the transparent pass, fogged by its
    /// material through the WESL package.
    glass_wesl: Vec<Vec4>,
    /// The default glass (alpha 0.35) with and without its fog.
    glass_fogged: Vec<Vec4>,
    glass_bare: Vec<Vec4>,
    /// The same two without fog on the camera.
    unfogged_bare: Vec<Vec4>,
    unfogged_glass: Vec<Vec4>,
    /// The integrated volume of the fogged frame and of the frame without the sun's
    /// shadows.
    volume: Volume,
    volume_unshadowed: Volume,
    options: SceneOptions,
}

const GLASS: LinearRgba = LinearRgba::new(0.6, 0.75, 0.8, 1.0);

fn set_glass(app: &mut App, material: Option<FoggedGlassMaterial>) {
    let world = app.world_mut();
    let mut q = world.query_filtered::<(&MeshMaterial3d<FoggedGlassMaterial>, &mut Visibility), With<GlassSphere>>();
    let (handle, mut visibility) = q.single_mut(world).unwrap();
    let handle = handle.0.clone();
    match material {
        None => *visibility = Visibility::Hidden,
        Some(m) => {
            *visibility = Visibility::Inherited;
            *world
                .resource_mut::<Assets<FoggedGlassMaterial>>()
                .get_mut(&handle)
                .unwrap() = m;
        }
    }
}

fn set_black(
    app: &mut App,
    black: bool,
    saved: &mut Vec<(AssetId<StandardMaterial>, StandardMaterial)>,
) {
    let world = app.world_mut();
    let mut materials = world.resource_mut::<Assets<StandardMaterial>>();
    if black {
        saved.clear();
        let ids: Vec<_> = materials.ids().collect();
        for id in ids {
            let mut m = materials.get_mut(id).unwrap();
            saved.push((id, m.clone()));
            m.base_color = Color::BLACK;
            m.reflectance = 0.0;
            m.perceptual_roughness = 1.0;
        }
    } else {
        for (id, m) in saved.drain(..) {
            *materials.get_mut(id).unwrap() = m;
        }
    }
    let mut q = world.query_filtered::<&mut Camera, With<SceneCamera>>();
    let mut camera = q.single_mut(world).unwrap();
    camera.clear_color = ClearColorConfig::Custom(if black {
        Color::BLACK
    } else {
        Color::linear_rgb(0.35, 0.42, 0.55)
    });
}

fn set_sun_shadows(app: &mut App, on: bool) {
    let world = app.world_mut();
    let mut q = world.query_filtered::<&mut DirectionalLight, With<Sun>>();
    q.single_mut(world).unwrap().shadow_maps_enabled = on;
}

fn set_fog(app: &mut App, fog: Option<FroxelFog>) {
    let world = app.world_mut();
    let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
    let camera = q.single(world).unwrap();
    match fog {
        Some(f) => {
            world.entity_mut(camera).insert(f);
        }
        None => {
            world.entity_mut(camera).remove::<FroxelFog>();
        }
    }
}

fn renders() -> &'static Renders {
    static RUN: OnceLock<Renders> = OnceLock::new();
    RUN.get_or_init(|| {
        let options = SceneOptions::still(W, H, FogKind::Froxel);
        let mut app = scene::app(&options);
        // The first frame spawns the scene.
        app.update();
        let frames = 3;
        set_glass(&mut app, None);
        let fogged = scene::capture(&mut app, 10);
        let volume = read_volume(&app);
        let mut saved = Vec::new();
        set_black(&mut app, true, &mut saved);
        let inscatter = scene::capture(&mut app, frames);
        set_sun_shadows(&mut app, false);
        let inscatter_unshadowed = scene::capture(&mut app, frames);
        let volume_unshadowed = read_volume(&app);
        set_sun_shadows(&mut app, true);
        set_black(&mut app, false, &mut saved);
        set_fog(&mut app, None);
        let surface = scene::capture(&mut app, frames);
        set_fog(&mut app, Some(scene::fog_settings(&options)));
        set_glass(
            &mut app,
            Some(FoggedGlassMaterial {
                color: GLASS,
                fog: false,
                alpha_mode: AlphaMode::Opaque,
            }),
        );
        let glass_apply = scene::capture(&mut app, frames);
        set_glass(
            &mut app,
            Some(FoggedGlassMaterial {
                color: GLASS,
                fog: true,
                alpha_mode: AlphaMode::Blend,
            }),
        );
        let glass_wesl = scene::capture(&mut app, frames);
        set_glass(&mut app, Some(FoggedGlassMaterial::default()));
        let glass_fogged = scene::capture(&mut app, frames);
        set_glass(
            &mut app,
            Some(FoggedGlassMaterial {
                fog: false,
                ..FoggedGlassMaterial::default()
            }),
        );
        let glass_bare = scene::capture(&mut app, frames);
        // Without a fog camera the material binds a group that applies no fog.
        set_fog(&mut app, None);
        let unfogged_bare = scene::capture(&mut app, frames);
        set_glass(&mut app, Some(FoggedGlassMaterial::default()));
        let unfogged_glass = scene::capture(&mut app, frames);
        // The renders as PNGs for inspection.
        let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fog_scene");
        std::fs::create_dir_all(&out).unwrap();
        for (name, image) in [
            ("fogged", &fogged),
            ("inscatter", &inscatter),
            ("inscatter_unshadowed", &inscatter_unshadowed),
            ("surface", &surface),
            ("glass_apply", &glass_apply),
            ("glass_wesl", &glass_wesl),
            ("glass_fogged", &glass_fogged),
            ("glass_bare", &glass_bare),
            ("unfogged_bare", &unfogged_bare),
            ("unfogged_glass", &unfogged_glass),
        ] {
            scene::write_png(&out.join(format!("{name}.png")), W, H, image).unwrap();
            let raw: Vec<u8> = image
                .iter()
                .flat_map(|p| p.to_array())
                .flat_map(f32::to_le_bytes)
                .collect();
            std::fs::write(out.join(format!("{name}.f32")), raw).unwrap();
        }
        Renders {
            fogged,
            inscatter,
            inscatter_unshadowed,
            surface,
            glass_apply,
            glass_wesl,
            glass_fogged,
            glass_bare,
            unfogged_bare,
            unfogged_glass,
            volume,
            volume_unshadowed,
            options,
        }
    })
}

/// The camera ray through a pixel's centre: (origin, unit direction).
fn pixel_ray(x: u32, y: u32) -> (Vec3, Vec3) {
    let camera = Transform::from_translation(scene::EYE).looking_at(scene::TARGET, Vec3::Y);
    let tan = (scene::FOV_Y_DEGREES.to_radians() * 0.5).tan();
    let aspect = W as f32 / H as f32;
    let ndc_x = (x as f32 + 0.5) / W as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
    let dir = camera.rotation * Vec3::new(ndc_x * tan * aspect, ndc_y * tan, -1.0);
    (scene::EYE, dir.normalize())
}

/// The ground point a pixel sees, if nothing else is in front of it.
fn ground_hit(x: u32, y: u32, boxes: &[scene::SceneBox]) -> Option<Vec3> {
    let (o, d) = pixel_ray(x, y);
    if d.y >= -1e-4 {
        return None;
    }
    let t = -o.y / d.y;
    if boxes
        .iter()
        .any(|b| b.hit(o, d).is_some_and(|tb| tb < t + 0.05))
    {
        return None;
    }
    // The glass sphere (hidden in these renders) and its light are off the ground.
    Some(o + d * t)
}

/// Whether a ray from `o` along `d` crosses the local fog volume (the ellipsoid under
/// the magenta spot).
fn crosses_volume(o: Vec3, d: Vec3, length: f32) -> bool {
    let center = Vec3::new(-7.2, 2.0, scene::ROW_Z + 3.0);
    let radii = Vec3::new(2.2, 2.6, 2.2) * 1.05;
    let (lo, ld) = ((o - center) / radii, d / radii);
    let (a, b, c) = (ld.dot(ld), 2.0 * lo.dot(ld), lo.dot(lo) - 1.0);
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return false;
    }
    let t0 = (-b - disc.sqrt()) / (2.0 * a);
    t0 < length && (-b + disc.sqrt()) / (2.0 * a) > 0.0
}

/// Closed-form optical depth of the exponential height fog sigma0 exp(-k y) along a
/// ray from `o` to `p` (f64).
fn optical_depth(o: Vec3, p: Vec3, density: f64, falloff: f64) -> f64 {
    let (y0, y1) = (f64::from(o.y), f64::from(p.y));
    let length = f64::from((p - o).length());
    let dy = y1 - y0;
    let mean = if (falloff * dy).abs() < 1e-9 {
        (-falloff * y0).exp()
    } else {
        ((-falloff * y0).exp() - (-falloff * y1).exp()) / (falloff * dy)
    };
    density * length * mean
}

fn lum(v: Vec4) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

#[test]
fn renders_have_no_nan() {
    let r = renders();
    for (name, image) in [
        ("fogged", &r.fogged),
        ("inscatter", &r.inscatter),
        ("inscatter_unshadowed", &r.inscatter_unshadowed),
        ("surface", &r.surface),
        ("glass_apply", &r.glass_apply),
        ("glass_wesl", &r.glass_wesl),
        ("glass_fogged", &r.glass_fogged),
        ("glass_bare", &r.glass_bare),
        ("unfogged_bare", &r.unfogged_bare),
        ("unfogged_glass", &r.unfogged_glass),
    ] {
        assert_eq!(image.len(), (W * H) as usize, "{name}");
        let bad = image.iter().filter(|p| !p.is_finite()).count();
        assert_eq!(bad, 0, "{name}: {bad} NaN or infinite pixels");
        assert!(
            image.iter().all(|p| p.min_element() >= 0.0),
            "{name} is non-negative"
        );
    }
    // The fog changes the image, and the fog-only render is not empty.
    let differs = r
        .fogged
        .iter()
        .zip(&r.surface)
        .filter(|(a, b)| (lum(**a) - lum(**b)).abs() > 1e-3)
        .count();
    assert!(
        differs > (W * H / 2) as usize,
        "fog changes {differs} pixels"
    );
}

/// The ground's transmittance, T = (fogged - L) / surface per pixel, against the
/// closed-form optical depth of the medium from the camera to the ground point.
#[test]
fn ground_transmittance_matches_the_closed_form() {
    let r = renders();
    let fog = scene::fog_settings(&r.options);
    let boxes = scene::boxes();
    let mut bins: Vec<(f32, Vec<f32>, Vec<f32>)> =
        [(4.0, 8.0), (8.0, 14.0), (14.0, 22.0), (22.0, 40.0)]
            .iter()
            .map(|(lo, _)| (*lo, Vec::new(), Vec::new()))
            .collect();
    let edges = [4.0f32, 8.0, 14.0, 22.0, 40.0];
    let mut worst = 0.0f32;
    let mut errors = Vec::new();
    for y in 1..H - 1 {
        for x in 1..W - 1 {
            // The pixel and its four neighbours see open ground.
            let Some(p) = ground_hit(x, y, &boxes) else {
                continue;
            };
            if [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .any(|&(a, b)| ground_hit(a, b, &boxes).is_none())
            {
                continue;
            }
            let i = (y * W + x) as usize;
            let (u, f, l) = (r.surface[i], r.fogged[i], r.inscatter[i]);
            if lum(u) < 0.05 {
                continue;
            }
            let distance = (p - scene::EYE).length();
            if crosses_volume(scene::EYE, (p - scene::EYE) / distance, distance) {
                continue;
            }
            let measured = (lum(f) - lum(l)) / lum(u);
            let expected = (-optical_depth(
                scene::EYE,
                p,
                f64::from(fog.medium.density),
                f64::from(fog.medium.height_falloff),
            ))
            .exp() as f32;
            let Some(bin) = edges
                .windows(2)
                .position(|e| distance >= e[0] && distance < e[1])
            else {
                continue;
            };
            bins[bin].1.push(measured);
            bins[bin].2.push(expected);
            let error = (measured - expected).abs();
            errors.push(error);
            worst = worst.max(error);
        }
    }
    let mut medians = Vec::new();
    for (lo, measured, expected) in &bins {
        let n = measured.len();
        assert!(n >= 20, "{n} ground pixels from {lo} m");
        let (m, e) = (median(measured.clone()), median(expected.clone()));
        eprintln!("ground from {lo} m: median transmittance {m:.4}, closed form {e:.4} ({n} px)");
        medians.push(m);
    }
    let n = errors.len();
    let mean = errors.iter().sum::<f32>() / n as f32;
    let p95 = {
        let mut e = errors.clone();
        e.sort_by(f32::total_cmp);
        e[n * 95 / 100]
    };
    eprintln!(
        "ground transmittance vs closed form over {n} px: mean abs error {mean:.4}, 95th percentile {p95:.4}, worst {worst:.4} (bounds: mean 0.02, p95 0.03)"
    );
    assert!(mean <= 0.02, "mean error {mean}");
    assert!(p95 <= 0.03, "95th percentile error {p95}");
    assert!(
        medians.windows(2).all(|w| w[1] < w[0] - 0.02),
        "transmittance falls with distance: {medians:?}"
    );
}

/// Light shafts in the fog: in the integrated volume, the radiance each froxel
/// scatters towards the eye, J = dL / (-dT) between consecutive slices (the source
/// function, independent of the density), 3 to 13 m from the camera, with and without
/// the sun's shadows. A CPU ray test towards the sun against the scene's boxes
/// classifies the froxels at their centres as sunlit or in a pillar's shadow. The two
/// renders differ only in the sun's shadows, so J_open - J_shadowed is the sun's light
/// the shadows took out, and the CPU mirror gives the sun's whole share J_sun (its
/// in-scattering through the medium's transmittance towards the sun, times the albedo):
/// the shadows take nearly all of J_sun from froxels in a pillar's shadow and almost
/// none from sunlit ones. With the shadows off, the two sets scatter about alike (they
/// differ only in where they lie: angle to the sun, height, nearby lamps).
#[test]
fn fog_shows_light_shafts() {
    let r = renders();
    let boxes = scene::boxes();
    let sun = scene::sun_direction();
    let (on, off) = (&r.volume, &r.volume_unshadowed);
    let f = &on.fog;
    let size = f.config.volume_size;
    let froxels = volfog::uniforms::Froxels::new(
        f.clip_from_view,
        size,
        f.config.near,
        f.config.far,
        f.config.slice_curve,
    )
    .expect("valid froxels");
    let world_from_view = f.view_from_world.inverse();
    let camera = world_from_view.transform_point3(vg::Vec3::ZERO);
    let texel =
        |v: &Volume, x: u32, y: u32, z: u32| v.texels[((z * size.y + y) * size.x + x) as usize];
    // J of the froxel (x, y, z) in a volume.
    let source = |v: &Volume, x: u32, y: u32, z: u32| {
        let (front, back) = (texel(v, x, y, z - 1), texel(v, x, y, z));
        (back - front).truncate().element_sum() / (front.w - back.w)
    };
    // Per class (sunlit, shadowed): J with shadows, J without, and the share of the sun
    // the shadows took out, (J_open - J_shadowed) / J_sun.
    let (mut lit, mut shade) = ((vec![], vec![], vec![]), (vec![], vec![], vec![]));
    for z in 1..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let front = texel(on, x, y, z - 1);
                let d_t = front.w - texel(on, x, y, z).w;
                let view = volfog::cpu::froxel::froxel_view_position(
                    vg::UVec3::new(x, y, z),
                    vg::Vec3::ZERO,
                    size,
                    froxels.view_from_clip,
                    f.config.near,
                    f.config.far,
                    f.config.slice_curve,
                );
                if !(3.0..13.0).contains(&-view.z) || d_t <= 2e-3 * front.w {
                    continue;
                }
                let world_v = world_from_view.transform_point3(view);
                let world = Vec3::from_array(world_v.to_array());
                if world.y < 0.05 {
                    continue;
                }
                let through = if f.config.light_transmittance {
                    medium_light_transmittance(&f.medium, world_v, f.sun.direction)
                } else {
                    1.0
                };
                let view_dir = (world_v - camera).normalize();
                let j_sun = (f.medium.albedo
                    * volfog::cpu::lights::sun_inscatter(
                        &f.sun,
                        through,
                        view_dir,
                        f.medium.phase_g,
                    ))
                .element_sum();
                let (j_on, j_off) = (source(on, x, y, z), source(off, x, y, z));
                let class = if boxes.iter().any(|b| b.hit(world, sun).is_some()) {
                    &mut shade
                } else {
                    &mut lit
                };
                class.0.push(j_on);
                class.1.push(j_off);
                class.2.push((j_off - j_on) / j_sun.max(1e-6));
            }
        }
    }
    let (n_lit, n_shade) = (lit.0.len(), shade.0.len());
    assert!(
        n_lit >= 1000 && n_shade >= 1000,
        "{n_lit} sunlit, {n_shade} shadowed froxels"
    );
    let with = median(lit.0) / median(shade.0);
    let without = median(lit.1) / median(shade.1);
    let (taken_lit, taken_shade) = (median(lit.2), median(shade.2));
    eprintln!(
        "froxels 3..13 m from the camera: {n_lit} sunlit, {n_shade} in shadow; median J sunlit / shadowed {with:.2} with the sun's shadows, {without:.2} without (bound <= 1.3); the shadows take out a median {:.1} % of the sun's share J_sun (CPU mirror, light transmittance {}) in shadow (bound >= 80 %), {:.1} % in the sun (bound <= 10 %)",
        100.0 * taken_shade,
        f.config.light_transmittance,
        100.0 * taken_lit
    );
    assert!(
        (0.8..=1.1).contains(&taken_shade),
        "shadowed froxels keep the sun: {taken_shade}"
    );
    assert!(
        taken_lit.abs() <= 0.1,
        "sunlit froxels lose the sun: {taken_lit}"
    );
    assert!(with > 1.5, "no visible shafts: {with}");
    assert!(without <= 1.3, "without shadows: {without}");
}

/// The glass sphere's material applies the fog through the WESL package exactly as
/// the fullscreen pass fogs the same colour drawn opaque; and the default
/// semi-transparent glass is fogged: it differs from the unfogged glass, in its most
/// changed channel, by at least 5 % on average (its luminance alone can hardly change,
/// where the fog's light makes up for the light it takes).
#[test]
fn glass_gets_the_fullscreen_fog() {
    let r = renders();
    let (mut count, mut sum, mut worst) = (0usize, 0.0f32, 0.0f32);
    let (mut fog_sum, mut fog_count) = (0.0f32, 0usize);
    for y in 0..H {
        for x in 0..W {
            let (o, d) = pixel_ray(x, y);
            // Pixels well inside the sphere's silhouette.
            let oc = o - scene::GLASS_CENTER;
            let b = oc.dot(d);
            let c = oc.dot(oc) - (scene::GLASS_RADIUS * 0.9).powi(2);
            if b * b - c < 0.0 {
                continue;
            }
            let i = (y * W + x) as usize;
            let (a, w) = (r.glass_apply[i], r.glass_wesl[i]);
            let error = (a - w).abs().max_element() / a.max_element().max(1e-3);
            sum += error;
            worst = worst.max(error);
            count += 1;
            let (fogged, bare) = (r.glass_fogged[i].truncate(), r.glass_bare[i].truncate());
            fog_sum += ((fogged - bare).abs() / bare.max(Vec3::splat(1e-3))).max_element();
            fog_count += 1;
        }
    }
    assert!(count >= 30, "{count} sphere pixels");
    let mean = sum / count as f32;
    let fog_share = fog_sum / fog_count as f32;
    eprintln!(
        "glass sphere ({count} px): WESL material vs fullscreen apply, mean relative error {mean:.2e}, worst {worst:.2e} (bounds 5e-3, 2e-2); the default glass's fog changes its most changed channel by {:.1} % on average",
        100.0 * fog_share
    );
    assert!(mean <= 5e-3, "mean {mean}");
    assert!(worst <= 2e-2, "worst {worst}");
    assert!(fog_share >= 0.05, "the glass is fogged: {fog_share}");
    // Without a fog camera the glass draws, unfogged.
    let worst_unfogged = r
        .unfogged_glass
        .iter()
        .zip(&r.unfogged_bare)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    let drawn = r
        .unfogged_glass
        .iter()
        .zip(&r.surface)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-2)
        .count();
    eprintln!(
        "without a fog camera the glass covers {drawn} px and its fog changes nothing (worst {worst_unfogged:.1e}, bound 1e-3)"
    );
    assert!(
        drawn >= 30,
        "the glass draws without a fog camera: {drawn} px"
    );
    assert!(worst_unfogged <= 1e-3, "{worst_unfogged}");
}

/// The lights reach the fog in Bevy's units scaled by the camera's exposure, as Bevy's
/// PBR shader lights surfaces: a point or spot light's intensity at 1 m is
/// `color * lumens / 4 pi`, the sun's `color * lux`, the ambient `color * brightness`.
/// The scene gives its lamps in lumens from the demo's intensities at 1 m, so the fog
/// must get those intensities back.
#[test]
fn lights_reach_the_fog_in_bevys_units() {
    let r = renders();
    let fog = &r.volume.fog;
    let exposure = bevy::camera::Exposure {
        ev100: scene::EV100,
    }
    .exposure();
    let close =
        |a: vg::Vec3, b: vg::Vec3| (a - b).abs().max_element() <= 1e-4 * b.max_element().max(1.0);
    assert_eq!(fog.lights.len(), 5, "three point and two spot lights");
    // The red light by the glass sphere: 35 at 1 m, range 6 m.
    let red = fog
        .lights
        .iter()
        .find(|l| l.range == 6.0)
        .expect("the light by the sphere");
    assert!(
        close(red.color, vg::Vec3::new(1.0, 0.17, 0.09) * 35.0),
        "{:?}",
        red.color
    );
    assert!(red.cos_outer <= -1.0, "a point light has no cone");
    // The magenta spot: 110 at 1 m, cone 0.3..0.5 rad, pointing down and forward.
    let spot = fog
        .lights
        .iter()
        .find(|l| (l.position.x + 7.2).abs() < 1e-4 && l.cos_outer > -1.0)
        .expect("the magenta spot");
    assert!(
        close(spot.color, vg::Vec3::new(1.0, 0.16, 0.86) * 110.0),
        "{:?}",
        spot.color
    );
    assert!(
        (spot.cos_outer - 0.5f32.cos()).abs() < 1e-5
            && (spot.cos_inner - 0.3f32.cos()).abs() < 1e-5
    );
    assert!(
        spot.direction
            .dot(vg::Vec3::new(0.0, -1.0, 0.25).normalize())
            > 0.9999
    );
    // The sun: 7800 lux, direction towards it.
    assert!(close(
        fog.sun.color,
        vg::Vec3::new(1.0, 0.75, 0.48) * 7800.0 * exposure
    ));
    let sun = scene::sun_direction();
    assert!(fog.sun.direction.dot(vg::Vec3::from_array(sun.to_array())) > 0.9999);
    // The ambient light: SH of a constant radiance (L0 coefficient times 1 / (2 sqrt(pi))).
    let ambient = vg::Vec3::new(0.57, 0.71, 1.0) * 140.0 * exposure;
    let l0 = vg::Vec3::new(
        fog.ambient.rgb[0].x,
        fog.ambient.rgb[1].x,
        fog.ambient.rgb[2].x,
    );
    let back = volfog::cpu::ambient::AmbientSh::constant(ambient);
    let want = vg::Vec3::new(back.rgb[0].x, back.rgb[1].x, back.rgb[2].x);
    assert!(close(l0, want), "{l0:?} vs {want:?}");
    eprintln!(
        "lights in the fog: red lamp {:?} (want 35 x (1, 0.17, 0.09)), magenta spot {:?} (want 110 x (1, 0.16, 0.86)), sun {:?}",
        red.color, spot.color, fog.sun.color
    );
}

//! The reference scenes, each at [`WIDTH`] x [`HEIGHT`] pixels, and the geometry
//! helpers they are checked with.
//!
//! Every scene stands on a black ground box whose top face is y = 0 and is built so
//! that (checked by [`check`]):
//! - every camera ray meets an occluder before `camera.far` (the camera looks down far
//!   enough that its highest ray still meets the ground within `far`);
//! - the medium's box holds the camera, the lights and the occluders (the ground's
//!   top face), its bottom lies in the ground and its top above the camera;
//! - every shadow ray from a visible medium point towards the sun leaves the medium
//!   through the top face. A sun ray climbing from height y to the top travels
//!   (top - y) / tan(elevation) horizontally, so the box reaches that far beyond the
//!   visible area on the sun's side (each scene computes its box so).

use glam::{Vec2, Vec3};

use super::scene::{
    TruthArea, TruthAreaShape, TruthBox, TruthCamera, TruthMedium, TruthPoint, TruthScene,
    TruthShape, TruthSpot, TruthSun, TruthVolume,
};

/// Image width of the scenes (pixels).
pub const WIDTH: u32 = 160;
/// Image height of the scenes (pixels).
pub const HEIGHT: u32 = 90;

/// Margin (m) around the area the camera sees and its sun-side reach.
const MARGIN: f32 = 10.0;
/// Depth (m) of the medium's box bottom below the ground's top face.
const BOTTOM: f32 = 0.5;
/// Film positions per pixel side at which [`check`] casts rays (corners included).
const CHECK_SUBSTEPS: u32 = 2;

/// The camera's unit forward, right and up vectors (right-handed, world up +Y).
pub fn camera_basis(camera: &TruthCamera) -> (Vec3, Vec3, Vec3) {
    let forward = (camera.target - camera.position).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    (forward, right, up)
}

/// The unit direction of the pinhole ray through the film position `(x, y)` in pixels
/// from the image's top-left corner (pixel `(i, j)` covers `[i, i + 1] x [j, j + 1]`).
pub fn film_ray(camera: &TruthCamera, resolution: [u32; 2], x: f32, y: f32) -> Vec3 {
    let (forward, right, up) = camera_basis(camera);
    let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let aspect = resolution[0] as f32 / resolution[1] as f32;
    let ndc_x = 2.0 * x / resolution[0] as f32 - 1.0;
    let ndc_y = 1.0 - 2.0 * y / resolution[1] as f32;
    (forward + right * (ndc_x * tan_half * aspect) + up * (ndc_y * tan_half)).normalize()
}

/// Entry and exit distances of a ray through an axis-aligned box (slab test), if it
/// meets the box at a distance >= 0.
pub fn ray_box(origin: Vec3, dir: Vec3, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let inv = dir.recip();
    let t0 = (min - origin) * inv;
    let t1 = (max - origin) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element();
    (near <= far).then_some((near, far))
}

/// Distance along a ray to the first occluder it meets.
pub fn first_occluder(scene: &TruthScene, origin: Vec3, dir: Vec3) -> Option<f32> {
    scene
        .occluders
        .iter()
        .filter_map(|b| ray_box(origin, dir, b.min, b.max).map(|(near, _)| near))
        .min_by(f32::total_cmp)
}

/// The medium's box: `bounds_min` to (`bounds_max_xz[0]`, `top`, `bounds_max_xz[1]`).
pub fn medium_box(medium: &TruthMedium) -> (Vec3, Vec3) {
    let max = Vec3::new(medium.bounds_max_xz[0], medium.top, medium.bounds_max_xz[1]);
    (medium.bounds_min, max)
}

fn inside(p: Vec3, (min, max): (Vec3, Vec3)) -> bool {
    p.cmpge(min).all() && p.cmple(max).all()
}

/// Where the ray from `p` towards the sun (unit `towards`) leaves the medium's top
/// face, in xz.
fn sun_exit(p: Vec3, towards: Vec3, top: f32) -> Vec2 {
    let t = (top - p.y) / towards.y;
    Vec2::new(p.x + towards.x * t, p.z + towards.z * t)
}

/// Film positions [`check`] casts rays through: a lattice of `CHECK_SUBSTEPS` per
/// pixel side, corners and edges included.
fn check_positions(resolution: [u32; 2]) -> impl Iterator<Item = (f32, f32)> {
    let nx = resolution[0] * CHECK_SUBSTEPS;
    let ny = resolution[1] * CHECK_SUBSTEPS;
    (0..=ny).flat_map(move |j| {
        (0..=nx).map(move |i| {
            (
                i as f32 / CHECK_SUBSTEPS as f32,
                j as f32 / CHECK_SUBSTEPS as f32,
            )
        })
    })
}

/// Checks the geometry contract of the module documentation; the error names the
/// first violation found.
pub fn check(scene: &TruthScene) -> Result<(), String> {
    let cam = &scene.camera;
    let bounds = medium_box(&scene.medium);
    if !inside(cam.position, bounds) {
        return Err(format!(
            "{}: the camera is outside the medium's box",
            scene.name
        ));
    }
    if scene.medium.bounds_min.y > 0.0 {
        return Err(format!(
            "{}: the medium's box starts above the ground",
            scene.name
        ));
    }
    let lights = scene
        .points
        .iter()
        .map(|p| p.position)
        .chain(scene.spots.iter().map(|s| s.position));
    if lights.into_iter().any(|p| !inside(p, bounds)) {
        return Err(format!(
            "{}: a light is outside the medium's box",
            scene.name
        ));
    }
    let within_xz =
        |p: Vec3| p.x >= bounds.0.x && p.x <= bounds.1.x && p.z >= bounds.0.z && p.z <= bounds.1.z;
    let occluders_inside = scene
        .occluders
        .iter()
        .all(|b| within_xz(b.min) && within_xz(b.max) && b.max.y <= scene.medium.top);
    if !occluders_inside {
        return Err(format!(
            "{}: an occluder reaches outside the medium's box",
            scene.name
        ));
    }
    let exits_top = |p: Vec3, towards: Vec3| {
        let e = sun_exit(p, towards, scene.medium.top);
        e.x >= bounds.0.x && e.x <= bounds.1.x && e.y >= bounds.0.z && e.y <= bounds.1.z
    };
    for (x, y) in check_positions(scene.resolution) {
        let dir = film_ray(cam, scene.resolution, x, y);
        let Some(t) = first_occluder(scene, cam.position, dir) else {
            return Err(format!(
                "{}: the ray through ({x}, {y}) meets no occluder",
                scene.name
            ));
        };
        if t > cam.far {
            return Err(format!(
                "{}: the ray through ({x}, {y}) meets its occluder at {t} m, beyond far = {} m",
                scene.name, cam.far
            ));
        }
        if let Some(sun) = &scene.sun {
            // The exit point moves linearly along the camera ray: its ends bound it.
            let hit = cam.position + dir * t;
            if !exits_top(cam.position, sun.direction) || !exits_top(hit, sun.direction) {
                return Err(format!(
                    "{}: a sun ray from the camera ray through ({x}, {y}) leaves the medium's box through a side",
                    scene.name
                ));
            }
        }
    }
    Ok(())
}

/// A camera at `position` looking along the horizontal heading `yaw_deg` (0 looks
/// towards -Z, 90 towards +X) tilted down by `pitch_deg`.
fn camera(position: Vec3, yaw_deg: f32, pitch_deg: f32, far: f32) -> TruthCamera {
    let (yaw, pitch) = (yaw_deg.to_radians(), pitch_deg.to_radians());
    let forward = Vec3::new(
        yaw.sin() * pitch.cos(),
        -pitch.sin(),
        -yaw.cos() * pitch.cos(),
    );
    TruthCamera {
        position,
        target: position + forward * 10.0,
        fov_y_deg: 40.0,
        near: 0.1,
        far,
    }
}

/// The sun at `elevation_deg` above the horizon in the heading `azimuth_deg` (0
/// towards -Z, 90 towards +X).
fn sun(elevation_deg: f32, azimuth_deg: f32, color: Vec3) -> TruthSun {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    TruthSun {
        direction: Vec3::new(a.sin() * e.cos(), e.sin(), -a.cos() * e.cos()),
        color,
    }
}

/// A medium whose box [`finish`] fills in.
fn medium(density: f32, falloff: f32, g: f32, top: f32) -> TruthMedium {
    TruthMedium {
        density,
        falloff,
        base_height: 0.0,
        albedo: Vec3::splat(0.9),
        phase_g: g,
        top,
        bounds_min: Vec3::ZERO,
        bounds_max_xz: [0.0, 0.0],
    }
}

/// A scene with no lights, volumes or occluders yet.
fn scene(name: &str, camera: TruthCamera, medium: TruthMedium) -> TruthScene {
    TruthScene {
        name: name.to_string(),
        resolution: [WIDTH, HEIGHT],
        camera,
        medium,
        sun: None,
        points: Vec::new(),
        spots: Vec::new(),
        areas: Vec::new(),
        volumes: Vec::new(),
        occluders: Vec::new(),
    }
}

/// The ground box under the xz rectangle [min, max], top face at y = 0.
fn ground(min: Vec2, max: Vec2) -> TruthBox {
    TruthBox {
        min: Vec3::new(min.x, -1.0, min.y),
        max: Vec3::new(max.x, 0.0, max.y),
    }
}

/// Sizes the medium's box and the ground: the xz area the camera rays reach (over a
/// provisional wide ground) and, with a sun, that area moved by the horizontal reach
/// of a sun ray climbing from the ground to the top, plus a margin; the box also holds
/// the lights and the other occluders. The ground is put
/// first among the occluders, under the whole box.
fn finish(mut scene: TruthScene) -> TruthScene {
    let wide = 1.0e4;
    scene
        .occluders
        .insert(0, ground(Vec2::splat(-wide), Vec2::splat(wide)));
    let cam = scene.camera;
    let mut lo = Vec2::new(cam.position.x, cam.position.z);
    let mut hi = lo;
    for (x, y) in check_positions(scene.resolution) {
        let dir = film_ray(&cam, scene.resolution, x, y);
        let t = first_occluder(&scene, cam.position, dir)
            .unwrap_or(cam.far)
            .min(cam.far);
        let p = cam.position + dir * t;
        lo = lo.min(Vec2::new(p.x, p.z));
        hi = hi.max(Vec2::new(p.x, p.z));
    }
    let lights = scene.points.iter().map(|p| p.position);
    let lights = lights.chain(scene.spots.iter().map(|s| s.position));
    let lights = lights.chain(scene.areas.iter().map(|a| a.center));
    let walls = scene.occluders[1..].iter().flat_map(|b| [b.min, b.max]);
    for p in lights.chain(walls) {
        lo = lo.min(Vec2::new(p.x, p.z));
        hi = hi.max(Vec2::new(p.x, p.z));
    }
    if let Some(sun) = &scene.sun {
        let reach =
            Vec2::new(sun.direction.x, sun.direction.z) * (scene.medium.top / sun.direction.y);
        lo = lo.min(lo + reach);
        hi = hi.max(hi + reach);
    }
    lo -= Vec2::splat(MARGIN);
    hi += Vec2::splat(MARGIN);
    scene.medium.bounds_min = Vec3::new(lo.x, -BOTTOM, lo.y);
    scene.medium.bounds_max_xz = [hi.x, hi.y];
    scene.occluders[0] = ground(lo, hi);
    scene
}

/// Uniform fog in sunlight: extinction 0.04 / m, albedo 0.9, g 0.4, the sun 35 degrees
/// up ahead and to the right; the camera 6 m up looking 25 degrees down.
pub fn homogeneous_sun() -> TruthScene {
    let mut s = scene(
        "homogeneous_sun",
        camera(Vec3::new(0.0, 6.0, 0.0), 0.0, 25.0, 100.0),
        medium(0.04, 0.0, 0.4, 25.0),
    );
    s.sun = Some(sun(35.0, 30.0, Vec3::new(3.0, 2.8, 2.5)));
    finish(s)
}

/// Exponential height fog (0.08 / m at the ground, falloff 0.15 / m, g 0.6) under a
/// low sun (10 degrees) ahead; the camera 10 m up looking 30 degrees down. The medium
/// ends at 40 m, where the extinction is 0.08 e^-6 = 2.0e-4 / m.
pub fn height_fog_low_sun() -> TruthScene {
    let mut s = scene(
        "height_fog_low_sun",
        camera(Vec3::new(0.0, 10.0, 0.0), 0.0, 30.0, 100.0),
        medium(0.08, 0.15, 0.6, 40.0),
    );
    s.sun = Some(sun(10.0, 20.0, Vec3::new(4.0, 3.4, 2.6)));
    finish(s)
}

/// A black wall 30 m ahead (z in [-30.4, -30] m, 27 m high) between the view and the
/// sun (35 degrees up, straight ahead), with an 8 m wide, 6 m high slot (x in [-4, 4],
/// y in [5.5, 11.5]) whose shaft slants towards the camera down to the ground 14 to
/// 22 m ahead. The wall shades everything else the camera sees (5 m up, looking 20
/// degrees down at the wall below the slot). Homogeneous fog 0.04 / m, g 0.5 (the view
/// looks into the shaft's forward lobe), ending 2 m above the wall.
pub fn slot_shaft() -> TruthScene {
    let mut s = scene(
        "slot_shaft",
        camera(Vec3::new(0.0, 5.0, 0.0), 0.0, 20.0, 60.0),
        medium(0.04, 0.0, 0.5, 29.0),
    );
    s.sun = Some(sun(35.0, 0.0, Vec3::new(6.0, 5.6, 5.0)));
    let (z0, z1) = (-30.4, -30.0);
    let (x0, x1) = (-60.0, 60.0);
    let (slot_x, slot_y) = ((-4.0, 4.0), (5.5, 11.5));
    let wall = |x: (f32, f32), y: (f32, f32)| TruthBox {
        min: Vec3::new(x.0, y.0, z0),
        max: Vec3::new(x.1, y.1, z1),
    };
    s.occluders = vec![
        wall((x0, x1), (0.0, slot_y.0)),
        wall((x0, x1), (slot_y.1, 27.0)),
        wall((x0, slot_x.0), slot_y),
        wall((slot_x.1, x1), slot_y),
    ];
    finish(s)
}

/// A point light of 200 W / sr (warm) 3 m above the ground, ahead and to the right, in
/// homogeneous fog 0.05 / m, g 0.3; no sun.
pub fn point_light() -> TruthScene {
    let mut s = scene(
        "point_light",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    s.points = vec![TruthPoint {
        position: Vec3::new(2.5, 3.0, -12.0),
        color: Vec3::new(200.0, 170.0, 130.0),
    }];
    finish(s)
}

/// A spot light 7 m up pointing down and sideways (inner 20, outer 25 degrees, 600 W /
/// sr on its axis) in homogeneous fog 0.05 / m, g 0.3; no sun.
pub fn spot_light() -> TruthScene {
    let mut s = scene(
        "spot_light",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    s.spots = vec![TruthSpot {
        position: Vec3::new(-4.0, 7.0, -14.0),
        direction: Vec3::new(0.5, -1.0, -0.2).normalize(),
        color: Vec3::new(600.0, 560.0, 500.0),
        inner_deg: 20.0,
        outer_deg: 25.0,
    }];
    finish(s)
}

/// A point light of 200 W / sr (warm) 3.5 m above the ground and 20 m ahead, just
/// above the view's top edge, behind a pillar (1 x 1 m, 7 m high) 3 m nearer the
/// camera and 1 m to the left: the pillar's shadow, a wedge of 18 degrees, runs from
/// the pillar towards the camera's left, across the fog in view. Homogeneous fog 0.05
/// / m, g 0.3; no sun.
pub fn pillar_lamp() -> TruthScene {
    let mut s = scene(
        "pillar_lamp",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    let lamp = Vec3::new(2.5, 3.5, -20.0);
    s.points = vec![TruthPoint {
        position: lamp,
        color: Vec3::new(200.0, 170.0, 130.0),
    }];
    let center = Vec3::new(lamp.x - 1.0, 0.0, lamp.z + 3.0);
    s.occluders = vec![TruthBox {
        min: Vec3::new(center.x - 0.5, 0.0, center.z - 0.5),
        max: Vec3::new(center.x + 0.5, 7.0, center.z + 0.5),
    }];
    finish(s)
}

/// A spot light (inner 25, outer 30 degrees, 800 W / sr on its axis) 7.5 m up behind a
/// wall on the left of the view (x in [-6.4, -6] m, 9 m high, from 2 to 40 m ahead),
/// shining down to the right through a window in it (z in [-12, -8] m, y in [2.5, 6]
/// m) crossed by a 0.3 m bar at mid-height: two shafts of the spot's cone, cut by the
/// window's frame and the bar, slant across the view to the ground about 10 m ahead.
/// The wall holds the rest of the cone. Homogeneous fog 0.05 / m, g 0.3; no sun.
pub fn spot_window() -> TruthScene {
    let mut s = scene(
        "spot_window",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    s.spots = vec![TruthSpot {
        position: Vec3::new(-11.0, 7.5, -10.0),
        direction: Vec3::new(11.0, -7.5, 0.0).normalize(),
        color: Vec3::new(800.0, 760.0, 680.0),
        inner_deg: 25.0,
        outer_deg: 30.0,
    }];
    let (x0, x1) = (-6.4, -6.0);
    let wall = |y: (f32, f32), z: (f32, f32)| TruthBox {
        min: Vec3::new(x0, y.0, z.0),
        max: Vec3::new(x1, y.1, z.1),
    };
    let (window_y, window_z) = ((2.5, 6.0), (-12.0, -8.0));
    let (bar_y, ends) = ((4.1, 4.4), (-40.0, -2.0));
    s.occluders = vec![
        wall((0.0, window_y.0), ends),
        wall((window_y.1, 9.0), ends),
        wall(window_y, (ends.0, window_z.0)),
        wall(window_y, (window_z.1, ends.1)),
        wall(bar_y, window_z),
    ];
    finish(s)
}

/// Thin fog (0.01 / m, g 0.4) in sunlight (40 degrees up, ahead and to the left) with
/// a box volume (0.15 / m, edge 0.2) and an ellipsoid (0.1 / m, edge 0.3) standing on
/// the ground in view.
pub fn local_volumes() -> TruthScene {
    let mut s = scene(
        "local_volumes",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.01, 0.0, 0.4, 25.0),
    );
    s.sun = Some(sun(40.0, -60.0, Vec3::new(3.0, 2.8, 2.5)));
    s.volumes = vec![
        TruthVolume {
            shape: TruthShape::Box,
            center: Vec3::new(-4.0, 2.0, -16.0),
            half_extents: Vec3::new(3.0, 2.0, 2.5),
            density: 0.15,
            edge: 0.2,
        },
        TruthVolume {
            shape: TruthShape::Ellipsoid,
            center: Vec3::new(5.0, 2.5, -20.0),
            half_extents: Vec3::new(3.0, 2.5, 3.0),
            density: 0.1,
            edge: 0.3,
        },
    ];
    finish(s)
}

/// Thin fog (0.02 / m, g 0.4) under a sun 25 degrees up ahead and a little to the
/// right, and a dense column (a box 2.4 m x 12 m x 2.4 m of 1 / m, edge 0.1) standing
/// on the ground 30 m ahead: its shadow, about exp(-2.4) of the sunlight, reaches back
/// towards the camera through the fog and down to the ground 26 m closer, so the view
/// looks along a dark shaft in the forward-scattered glow.
pub fn shadow_column() -> TruthScene {
    let mut s = scene(
        "shadow_column",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.02, 0.0, 0.4, 25.0),
    );
    s.sun = Some(sun(25.0, 10.0, Vec3::new(3.0, 2.8, 2.5)));
    s.volumes = vec![TruthVolume {
        shape: TruthShape::Box,
        center: Vec3::new(1.5, 6.0, -30.0),
        half_extents: Vec3::new(1.2, 6.0, 1.2),
        density: 1.0,
        edge: 0.1,
    }];
    finish(s)
}

/// A 2 m x 1 m panel facing down, 6 m up and 12 m ahead, 2 m above the eye and out of
/// view (its radiance 100 W / (m^2 sr), warm: 200 W / sr straight down, as
/// point_light's lamp), in homogeneous fog 0.05 / m, g 0.3; no sun.
pub fn rect_light() -> TruthScene {
    let mut s = scene(
        "rect_light",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    s.areas = vec![TruthArea {
        shape: TruthAreaShape::Rectangle,
        center: Vec3::new(1.5, 6.0, -12.0),
        axis_x: Vec3::X,
        axis_y: Vec3::Z,
        half_x: 1.0,
        half_y: 0.5,
        radiance: Vec3::new(100.0, 85.0, 65.0),
    }];
    finish(s)
}

/// A disk of radius 0.8 m, 5 m up and 10 m ahead to the left, out of view, facing down
/// and a little towards the camera and the right (radiance 150 W / (m^2 sr) in blue,
/// cool), in homogeneous fog 0.05 / m, g 0.3; no sun.
pub fn disk_light() -> TruthScene {
    let mut s = scene(
        "disk_light",
        camera(Vec3::new(0.0, 4.0, 0.0), 0.0, 25.0, 80.0),
        medium(0.05, 0.0, 0.3, 20.0),
    );
    let normal = Vec3::new(0.3, -1.0, 0.2).normalize();
    let (axis_x, axis_y) = normal.any_orthonormal_pair();
    s.areas = vec![TruthArea {
        shape: TruthAreaShape::Disk,
        center: Vec3::new(-2.0, 5.0, -10.0),
        axis_x,
        axis_y,
        half_x: 0.8,
        half_y: 0.8,
        radiance: Vec3::new(90.0, 110.0, 150.0),
    }];
    finish(s)
}

/// All scenes, in the order above.
pub fn all() -> Vec<TruthScene> {
    vec![
        homogeneous_sun(),
        height_fog_low_sun(),
        slot_shaft(),
        point_light(),
        spot_light(),
        local_volumes(),
        pillar_lamp(),
        spot_window(),
        shadow_column(),
    ]
}

/// The area-light scenes, in the order above. Apart from [`all`]: the grid floor
/// (`truth::floor`) does not light the fog with area lights.
pub fn area_lights() -> Vec<TruthScene> {
    vec![rect_light(), disk_light()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_meet_the_geometry_contract() {
        for scene in all().into_iter().chain(area_lights()) {
            check(&scene).unwrap();
            assert!(scene.medium.top > scene.camera.position.y, "{}", scene.name);
        }
    }

    #[test]
    fn names_are_distinct_snake_case() {
        let scenes = all();
        for (i, s) in scenes.iter().enumerate() {
            assert!(s.name.chars().all(|c| c.is_ascii_lowercase() || c == '_'));
            assert!(scenes[..i].iter().all(|o| o.name != s.name));
            assert_eq!(s.resolution, [WIDTH, HEIGHT]);
        }
    }

    #[test]
    fn film_rays_span_the_field_of_view() {
        let cam = homogeneous_sun().camera;
        let (forward, _, up) = camera_basis(&cam);
        let top = film_ray(&cam, [WIDTH, HEIGHT], WIDTH as f32 * 0.5, 0.0);
        let half = top.dot(up).atan2(top.dot(forward)).to_degrees();
        assert!((half - 20.0).abs() < 1e-3, "{half}");
    }
}

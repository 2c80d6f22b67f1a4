//! A point light inside a closed room lights no fog outside it: the light that leaks
//! through the walls against the ESM bound (the visibility behind an occluder falls as
//! `exp(-c (r - d) / range)`, below 5 % once the fog is `3 range / c` behind the wall),
//! and the fog inside against the unshadowed light.

use super::*;

/// Inside of the room (m) and its wall thickness.
const ROOM_MIN: Vec3 = Vec3::new(-2.0, 0.0, -10.0);
const ROOM_MAX: Vec3 = Vec3::new(2.0, 3.0, -6.0);
const WALL: f32 = 0.2;

/// The six walls, floor and ceiling of the room, closed.
pub(super) fn walls(min: Vec3, max: Vec3, wall: f32) -> Vec<Occluder> {
    let (lo, hi) = (min - Vec3::splat(wall), max + Vec3::splat(wall));
    (0..3)
        .flat_map(|axis| {
            let a_min = lo;
            let mut a_max = hi;
            a_max[axis] = min[axis];
            let mut b_min = lo;
            let b_max = hi;
            b_min[axis] = max[axis];
            [Occluder::aabb(a_min, a_max), Occluder::aabb(b_min, b_max)]
        })
        .collect()
}

/// The largest view depth (m) of the depth map within `reach` texels of uv.
fn footprint_depth(
    depth: &[f32],
    size: u32,
    uv: glam::Vec2,
    camera: &LightCamera,
    reach: u32,
) -> f32 {
    let terms = camera.depth_terms().unwrap();
    let (cx, cy) = ((uv.x * size as f32) as i32, (uv.y * size as f32) as i32);
    let r = reach as i32;
    let mut far = 0.0f32;
    for y in (cy - r).max(0)..=(cy + r).min(size as i32 - 1) {
        for x in (cx - r).max(0)..=(cx + r).min(size as i32 - 1) {
            let d = depth[(y as u32 * size + x as u32) as usize];
            far = far.max(volfog::cpu::frustum::frustum_depth_from_terms(terms, d));
        }
    }
    far
}

#[test]
fn a_point_light_in_a_closed_room_lights_no_fog_outside() {
    let occluders = walls(ROOM_MIN, ROOM_MAX, WALL);
    let lamp = FogLight::point(Vec3::new(0.4, 1.6, -8.3), Vec3::new(60.0, 45.0, 30.0), 12.0);
    for (log_space, exponent) in [(false, 80.0), (true, 400.0)] {
        let local = LocalShadowConfig {
            spot_shadows: 0,
            point_shadows: 1,
            resolution: 64,
            exponent,
        };
        let config = config(local, log_space);
        let map = 128;
        let cam = LightCamera::point(&lamp, 0.05).unwrap();
        let view = camera(Vec3::new(0.5, 1.7, -0.5), Vec3::new(0.0, 1.5, -9.0));
        let OneLight {
            maps,
            got,
            open: unshadowed,
            positions,
            ..
        } = one_light(&config, lamp, cam, &occluders, map, view);

        let band = 3.0 * lamp.range / exponent;
        // Shadow-map texels each side of a filtered atlas texel: the blur radius and
        // the bilinear look-up, in atlas texels, times the maps' factor.
        let footprint = (config.esm_blur_radius + 1) * (map / local.resolution);
        let (mut inside, mut outside, mut in_band) = (0, 0, 0);
        let (mut worst_outside, mut worst_inside) = (0.0f32, 1.0f32);
        let (mut leaked, mut outside_open) = (0.0f64, 0.0f64);
        for ((g, u), p) in got.iter().zip(&unshadowed).zip(&positions) {
            let open_light = u.truncate().max_element();
            if open_light < 1e-4 {
                continue;
            }
            let visibility = g.truncate().max_element() / open_light;
            let to = *p - lamp.position;
            let hit = trace(&occluders, lamp.position, to.normalize());
            let inner = p.cmpgt(ROOM_MIN).all() && p.cmplt(ROOM_MAX).all();
            if inner {
                let margin = (*p - ROOM_MIN).min(ROOM_MAX - *p).min_element();
                if margin > 0.3 {
                    inside += 1;
                    worst_inside = worst_inside.min(visibility);
                }
            } else if hit < to.length() {
                // Depth behind the farthest occluder the filtered texel averages, along
                // the cube face's axis (what the ESM compares).
                let c = volfog::cpu::local_shadow::local_shadow_cube(to);
                let behind =
                    c.depth - footprint_depth(&maps[c.face as usize], map, c.uv, &cam, footprint);
                leaked += f64::from(g.truncate().max_element());
                outside_open += f64::from(open_light);
                if behind >= band {
                    outside += 1;
                    worst_outside = worst_outside.max(visibility);
                } else {
                    in_band += 1;
                }
            }
        }
        eprintln!(
            "point light in a closed room (c = {exponent}, log space {log_space}, leak band 3 range / c = {band:.3} m): \
             {outside} froxels outside, beyond the band behind the farthest wall depth within the blur footprint, get at most {:.2} % of the lamp's light (bound 5 %), \
             {in_band} within the band; all the fog outside gets {:.3} % of the light it would get unshadowed; \
             {inside} froxels inside (0.3 m from the walls) get at least {:.2} % (bound 95 %)",
            100.0 * worst_outside,
            100.0 * leaked / outside_open,
            100.0 * worst_inside
        );
        assert!(outside > 2000 && inside > 200, "{outside} {inside}");
        assert!(worst_outside <= 0.05, "{worst_outside}");
        assert!(worst_inside >= 0.95, "{worst_inside}");
        assert!(leaked / outside_open < 0.05, "{}", leaked / outside_open);
    }
}

/// The world positions of the eight corners of every froxel, in the volume's order.
fn froxel_corners(config: &FogConfig, inputs: &FrameInputs<'_>) -> Vec<[Vec3; 8]> {
    let u = crate::common::scene::expected_uniforms(config, inputs, 0);
    let f = &u.froxels;
    let size = config.volume_size;
    let mut out = Vec::with_capacity((size.x * size.y * size.z) as usize);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                out.push(std::array::from_fn(|k| {
                    let o = Vec3::new(
                        if k & 1 == 0 { -0.5 } else { 0.5 },
                        if k & 2 == 0 { -0.5 } else { 0.5 },
                        if k & 4 == 0 { -0.5 } else { 0.5 },
                    );
                    let view = volfog::cpu::froxel::froxel_view_position(
                        UVec3::new(x, y, z),
                        o,
                        f.size,
                        f.view_from_clip,
                        f.near,
                        f.far,
                        f.curve,
                    );
                    u.frame.world_from_view.transform_point3(view)
                }));
            }
        }
    }
    out
}

/// The compare filter in the closed room, through all six cube faces and their seams:
/// every froxel wholly outside the walls gets no light at all, and every froxel wholly
/// inside the room, a map texel (1/64 of the depth) and the bias from the walls, gets
/// all of it (within rgba16float rounding). No leak band: the compares see the walls
/// themselves.
#[test]
fn the_compare_filter_keeps_the_room_dark_outside_and_lit_inside() {
    let occluders = walls(ROOM_MIN, ROOM_MAX, WALL);
    let lamp = FogLight::point(Vec3::new(0.4, 1.6, -8.3), Vec3::new(60.0, 45.0, 30.0), 12.0);
    let local = LocalShadowConfig {
        spot_shadows: 0,
        point_shadows: 1,
        ..LocalShadowConfig::default()
    };
    let config = compare_config(local, 1);
    let map = 128;
    let cam = LightCamera::point(&lamp, 0.05).unwrap();
    let view = camera(Vec3::new(0.5, 1.7, -0.5), Vec3::new(0.0, 1.5, -9.0));
    let OneLight {
        got,
        want,
        open: unshadowed,
        ..
    } = one_light(&config, lamp, cam, &occluders, map, view);
    let mirror = worst_relative(&got, &want, 1e-3);
    let shadowed = [ShadowedLight::new(0, cam).with_shadow(0)];
    let lamps = [lamp];
    let frame = inputs(view, medium(0.05), &lamps, &shadowed, &[]);
    let corners = froxel_corners(&config, &frame);
    let (outer_min, outer_max) = (ROOM_MIN - Vec3::splat(WALL), ROOM_MAX + Vec3::splat(WALL));
    let (mut inside, mut outside) = (0, 0);
    let (mut worst_outside, mut worst_inside) = (0.0f32, 0.0f32);
    for ((g, u), c) in got.iter().zip(&unshadowed).zip(&corners) {
        let open_light = u.truncate().max_element();
        if open_light < 1e-4 {
            continue;
        }
        let out_of = |p: &Vec3| p.cmplt(outer_min).any() || p.cmpgt(outer_max).any();
        let within = |p: &Vec3| {
            let texel = (*p - lamp.position).abs().max_element() / 64.0;
            let margin = (*p - ROOM_MIN).min(ROOM_MAX - *p).min_element();
            margin > texel
        };
        if c.iter().all(out_of) {
            outside += 1;
            worst_outside = worst_outside.max(g.truncate().max_element() / open_light);
        } else if c.iter().all(within) {
            inside += 1;
            let e = (g.truncate() - u.truncate()).abs().max_element() / open_light;
            worst_inside = worst_inside.max(e);
        }
    }
    eprintln!(
        "compare filter, point light in a closed room: inject vs CPU {mirror:.2e} relative (bound 4e-3); \
         {outside} froxels wholly outside get at most {worst_outside:.1e} of the lamp's light (bound 0), \
         {inside} wholly inside differ from the unshadowed light by at most {worst_inside:.1e} (bound 2e-3)"
    );
    assert!(mirror <= 4e-3, "{mirror}");
    assert!(outside > 2000 && inside > 200, "{outside} {inside}");
    assert_eq!(worst_outside, 0.0);
    assert!(worst_inside <= 2e-3, "{worst_inside}");
}

//! A spot light's shadow through a slot in a wall matches the analytic lit wedge
//! within the ESM blur footprint: fog in the wedge is lit, fog outside it by more than
//! the footprint (and beyond the leak band behind the wall) is dark.

use super::*;

/// The spot light 3 m in front of the wall, on the slot's axis.
const LIGHT: Vec3 = Vec3::new(0.0, 2.0, -3.0);
/// The wall's faces (z, m) and the slot's half-height around y = 2.
const WALL_FRONT: f32 = -6.0;
const WALL_BACK: f32 = -6.2;
const SLOT: f32 = 0.3;

#[test]
fn a_spot_light_through_a_slot_lights_the_wedge_behind_it() {
    let occluders = [
        Occluder::aabb(
            Vec3::new(-8.0, -2.0, WALL_BACK),
            Vec3::new(8.0, 2.0 - SLOT, WALL_FRONT),
        ),
        Occluder::aabb(
            Vec3::new(-8.0, 2.0 + SLOT, WALL_BACK),
            Vec3::new(8.0, 6.0, WALL_FRONT),
        ),
        Occluder::aabb(Vec3::new(-10.0, -2.0, -17.0), Vec3::new(10.0, 8.0, -16.5)),
    ];
    let spot = FogLight::spot(
        LIGHT,
        Vec3::NEG_Z,
        Vec3::new(80.0, 80.0, 80.0),
        14.0,
        0.2,
        0.3,
    );
    let local = LocalShadowConfig {
        spot_shadows: 1,
        point_shadows: 0,
        resolution: 128,
        exponent: 80.0,
    };
    let config = config(local, false);
    let cam = LightCamera::spot(&spot, 0.1).unwrap();
    let view = camera(Vec3::new(4.0, 3.0, -1.0), Vec3::new(0.0, 2.0, -11.0));
    let OneLight {
        got,
        want,
        open: unshadowed,
        positions,
        ..
    } = one_light(&config, spot, cam, &occluders, 256, view);
    let mirror = worst_relative(&got, &want, 1e-3);

    // The wedge in the shadow camera's tangent space: |y / depth| below the slot's
    // edge seen through the back face (the narrower of its two edges).
    let edge = SLOT / (LIGHT.z - WALL_BACK);
    let LightCamera::Spot {
        clip_from_view,
        view_from_world,
    } = cam
    else {
        unreachable!()
    };
    let tan_half = 1.0 / clip_from_view.y_axis.y;
    // The footprint of a filtered atlas texel: the blur radius, the bilinear look-up
    // and half a texel of the downsample, in tangent units.
    let footprint =
        (config.esm_blur_radius as f32 + 1.5) * 2.0 * tan_half / local.resolution as f32;
    let band = 3.0 * spot.range / local.exponent;
    let (mut lit, mut dark, mut between) = (0, 0, 0);
    let (mut worst_lit, mut worst_dark) = (1.0f32, 0.0f32);
    let mut widest = 0.0f32;
    for ((g, u), p) in got.iter().zip(&unshadowed).zip(positions) {
        let open_light = u.truncate().max_element();
        if open_light < 1e-3 || p.z > WALL_BACK {
            continue;
        }
        let visibility = g.truncate().max_element() / open_light;
        let v = view_from_world.transform_point3(p);
        let tan_y = (v.y / -v.z).abs();
        if tan_y <= edge - footprint {
            lit += 1;
            worst_lit = worst_lit.min(visibility);
        } else if tan_y >= edge + footprint && (LIGHT.z - p.z) - (LIGHT.z - WALL_FRONT) >= band {
            dark += 1;
            worst_dark = worst_dark.max(visibility);
        } else {
            between += 1;
        }
        // How far from the wedge's edge the fog's own edge (visibility 1/2) lies.
        if (visibility >= 0.5) != (tan_y <= edge) {
            widest = widest.max((tan_y - edge).abs());
        }
    }
    eprintln!(
        "spot light through a slot: inject vs CPU {mirror:.2e} relative (bound 4e-3); the wedge \
         (|tan| <= {edge:.4}) with the blur footprint {footprint:.4}: {lit} froxels inside it \
         by more than the footprint get at least {:.1} % of the light (bound 90 %), {dark} outside \
         it by more (and {band:.2} m behind the wall) at most {:.2} % (bound 5 %), {between} between; \
         the fog's edge (half the light) lies within {:.2} footprints of the wedge's",
        100.0 * worst_lit,
        100.0 * worst_dark,
        widest / footprint
    );
    assert!(mirror <= 4e-3, "{mirror}");
    assert!(lit > 100 && dark > 200, "{lit} {dark}");
    assert!(worst_lit >= 0.9, "{worst_lit}");
    assert!(worst_dark <= 0.05, "{worst_dark}");
    assert!(widest <= footprint, "{widest} {footprint}");
}

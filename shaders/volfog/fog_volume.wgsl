// volfog::fog_volume — analytic box, ellipsoid, plane, cylinder and cone fog volumes,
// ray traced per pixel.
//
// Use:      #import volfog::fog_volume::{fog_volume, fog_over, FOG_NONE}
//           var fog = FOG_NONE;
//           for each volume, farthest first: fog = fog_over(fog_volume(v, eye, p), fog);
//           color = apply_fog(color, fog);      // volfog::apply::apply_fog
// Defines:  none
// Method:   the view segment from the camera (t = 0) to the shaded point (t = 1, the
//           scene depth) is transformed into the volume's local space, where the volume
//           is the unit box [-1, 1]^3, the unit sphere, the half-space y <= 0 (a plane
//           volume: fog below a plane, Wenzel's special type for rivers and water
//           areas, with the camera above or below it), the unit cylinder (radius 1
//           around the y axis, |y| <= 1) or the unit cone (apex at y = 1, a base of
//           radius 1 at y = -1), and intersected there. For an
//           affine transform the ray parameters are the same in both spaces, so the
//           clipped segment [t0, t1] is taken back to world space exactly. Start: the
//           camera when it is inside, else the entry point; end: the exit point or the
//           shaded point, whichever is nearer. The exponential-gradient density is then
//           integrated along the clipped world-space segment in closed form
//           (volfog::height_fog, Wenzel eq. 2 with gradient direction and offset).
// Output:   vec4(in-scattered radiance rgb, transmittance a), as the froxel volume.
//           Volumes are composited back to front with fog_over (exact for volumes
//           that do not overlap along the ray).
// Units:    metres, world space; extinction 1/m.
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "Fog
//           Volumes"; ray/sphere intersection through the closest point to the centre
//           (Haines et al. 2019, "Precision Improvements for Ray/Sphere Intersection").
#define_import_path volfog::fog_volume

#import volfog::types::FogVolume
#import volfog::height_fog::{height_fog_optical_depth, fog_inscatter, FOG_POSITION_LIMIT}

// Shape codes of FogVolume.shape.
const FOG_VOLUME_BOX: u32 = 0u;
const FOG_VOLUME_ELLIPSOID: u32 = 1u;
const FOG_VOLUME_PLANE: u32 = 2u;
const FOG_VOLUME_CYLINDER: u32 = 3u;
const FOG_VOLUME_CONE: u32 = 4u;
// No fog: no in-scattering, full transmittance (the start of back-to-front compositing).
const FOG_NONE: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, 1.0);
// Direction components below this magnitude are treated as this value (slab test).
const FOG_VOLUME_MIN_DIRECTION: f32 = 1e-12;

// Line parameters (t_near, t_far) where ro + t rd enters and leaves the unit box
// [-1, 1]^3 (slab test); t_near > t_far when the line misses it.
fn ray_unit_box(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    // Scalar conditions: HLSL 2021 rejects a vector condition in `?:`, which is what a
    // vector select becomes there.
    let m = FOG_VOLUME_MIN_DIRECTION;
    let safe = vec3<f32>(
        select(rd.x, m, abs(rd.x) < m),
        select(rd.y, m, abs(rd.y) < m),
        select(rd.z, m, abs(rd.z) < m),
    );
    let inv = 1.0 / safe;
    let ta = (vec3<f32>(-1.0) - ro) * inv;
    let tb = (vec3<f32>(1.0) - ro) * inv;
    let lo = min(ta, tb);
    let hi = max(ta, tb);
    return vec2<f32>(max(lo.x, max(lo.y, lo.z)), min(hi.x, min(hi.y, hi.z)));
}

// Line parameters (t_near, t_far) where ro + t rd enters and leaves the unit sphere;
// t_near > t_far when the line misses it or rd is zero. The chord is found from the
// point of the line closest to the centre, which keeps its precision for a distant ro.
fn ray_unit_sphere(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let s = max(abs(rd.x), max(abs(rd.y), abs(rd.z)));
    let du = rd / max(s, 1e-30);
    let lu = length(du);
    let dn = du / max(lu, 1e-30);
    let len = max(s * lu, 1e-30);
    let tc = -dot(ro, dn);
    let closest = clamp(ro + tc * dn, vec3<f32>(-2.0), vec3<f32>(2.0));
    let h2 = 1.0 - dot(closest, closest);
    let h = sqrt(max(h2, 0.0));
    let hit = vec2<f32>(tc - h, tc + h) / len;
    return select(vec2<f32>(1.0, 0.0), hit, h2 >= 0.0 && s > 1e-30);
}

// Line parameters (t_near, t_far) where ro + t rd lies in the half-space y <= 0
// (unbounded ends are +-1e30); t_near > t_far when the line misses it. A line in the
// plane y = 0 lies inside.
fn ray_half_space(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let far = 1e30;
    if abs(rd.y) < FOG_VOLUME_MIN_DIRECTION {
        return select(vec2<f32>(1.0, 0.0), vec2<f32>(-far, far), ro.y <= 0.0);
    }
    let t = -ro.y / rd.y;
    return select(vec2<f32>(t, far), vec2<f32>(-far, t), rd.y > 0.0);
}

// Line parameters (t_near, t_far) where ro + t rd lies in the slab |y| <= 1 (unbounded
// ends are +-1e30 / s for a direction of largest component s); the caps of the
// cylinder and the cone. Takes the direction scaled to a largest component of 1.
fn ray_unit_slab_y(ro: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let far = 1e30;
    if abs(d.y) < FOG_VOLUME_MIN_DIRECTION {
        return select(vec2<f32>(1.0, 0.0), vec2<f32>(-far, far), abs(ro.y) <= 1.0);
    }
    let ta = (-1.0 - ro.y) / d.y;
    let tb = (1.0 - ro.y) / d.y;
    return vec2<f32>(min(ta, tb), max(ta, tb));
}

// Line parameters (t_near, t_far) where ro + t rd lies in the unit cylinder (radius 1
// around the y axis, |y| <= 1); t_near > t_far when the line misses it. The side is
// found from the line's closest approach to the axis (as ray_unit_sphere).
fn ray_unit_cylinder(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let far = 1e30;
    let none = vec2<f32>(1.0, 0.0);
    let s = max(abs(rd.x), max(abs(rd.y), abs(rd.z)));
    if s <= 1e-30 {
        return select(none, vec2<f32>(-far, far), max(abs(ro.y), length(ro.xz)) <= 1.0);
    }
    let d = rd / s;
    var side = vec2<f32>(-far, far);
    let l = length(d.xz);
    if l > FOG_VOLUME_MIN_DIRECTION {
        let dn = d.xz / l;
        let uc = -dot(ro.xz, dn);
        let closest = clamp(ro.xz + uc * dn, vec2<f32>(-2.0), vec2<f32>(2.0));
        let h2 = 1.0 - dot(closest, closest);
        let h = sqrt(max(h2, 0.0));
        side = select(none, vec2<f32>(uc - h, uc + h) / l, h2 >= 0.0);
    } else if dot(ro.xz, ro.xz) > 1.0 {
        side = none;
    }
    let caps = ray_unit_slab_y(ro, d);
    return vec2<f32>(max(side.x, caps.x), min(side.y, caps.y)) / s;
}

// Line parameters (t_near, t_far) where ro + t rd lies in the unit cone (apex at y = 1,
// a base of radius 1 at y = -1: 4 |xz|^2 <= (1 - y)^2 and |y| <= 1); t_near > t_far
// when the line misses it. The quadratic 4 |xz(u)|^2 - (1 - y(u))^2 = a u^2 + b u + c
// is solved in its stable form; of the double cone it bounds, the nappe below the
// apex is kept.
fn ray_unit_cone(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let far = 1e30;
    let none = vec2<f32>(1.0, 0.0);
    let s = max(abs(rd.x), max(abs(rd.y), abs(rd.z)));
    if s <= 1e-30 {
        let inside = max(abs(ro.y), length(ro.xz) + 0.5 * (ro.y + 1.0)) <= 1.0;
        return select(none, vec2<f32>(-far, far), inside);
    }
    let d = rd / s;
    let k0 = 1.0 - ro.y;
    let a = 4.0 * dot(d.xz, d.xz) - d.y * d.y;
    let b = 8.0 * dot(ro.xz, d.xz) + 2.0 * k0 * d.y;
    let c = 4.0 * dot(ro.xz, ro.xz) - k0 * k0;
    var side = none;
    if abs(a) < 1e-6 {
        // Parallel to a line of the cone's side: b u + c <= 0 on a half-line.
        if abs(b) < 1e-12 {
            side = select(none, vec2<f32>(-far, far), c <= 0.0);
        } else {
            let u = -c / b;
            side = select(vec2<f32>(-far, u), vec2<f32>(u, far), b < 0.0);
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        // A line steeper than the side (a < 0) crosses both nappes; rounding may put
        // one through the apex just below 0.
        if disc >= 0.0 || a < 0.0 {
            let q = -0.5 * (b + select(-1.0, 1.0, b >= 0.0) * sqrt(max(disc, 0.0)));
            var u1 = 0.0;
            var u2 = 0.0;
            if q != 0.0 {
                u1 = q / a;
                u2 = c / q;
            }
            let lo = min(u1, u2);
            let hi = max(u1, u2);
            if a > 0.0 {
                // Inside between the roots, on one nappe: the lower one if the middle
                // lies below the apex.
                side = select(none, vec2<f32>(lo, hi), k0 - 0.5 * (lo + hi) * d.y >= 0.0);
            } else {
                // Inside outside the roots: the half-line below the apex.
                side = select(vec2<f32>(hi, far), vec2<f32>(-far, lo), d.y > 0.0);
            }
        }
    }
    let caps = ray_unit_slab_y(ro, d);
    return vec2<f32>(max(side.x, caps.x), min(side.y, caps.y)) / s;
}

// Ray parameters [t0, t1] within [0, 1] of the part of the segment from camera_pos
// (t = 0) to point (t = 1) inside the volume (world space, m); t0 == t1 when the
// segment misses it. t0 = 0 when the camera is inside, t1 = 1 when the point is.
fn fog_volume_entry_exit(volume: FogVolume, camera_pos: vec3<f32>, point: vec3<f32>) -> vec2<f32> {
    let lim = vec3<f32>(FOG_POSITION_LIMIT);
    let eye = clamp(camera_pos, -lim, lim);
    let seg = clamp(point, -lim, lim) - eye;
    let ro = (volume.local_from_world * vec4<f32>(eye, 1.0)).xyz;
    let rd = (volume.local_from_world * vec4<f32>(seg, 0.0)).xyz;
    var t: vec2<f32>;
    if volume.shape == FOG_VOLUME_ELLIPSOID {
        t = ray_unit_sphere(ro, rd);
    } else if volume.shape == FOG_VOLUME_PLANE {
        t = ray_half_space(ro, rd);
    } else if volume.shape == FOG_VOLUME_CYLINDER {
        t = ray_unit_cylinder(ro, rd);
    } else if volume.shape == FOG_VOLUME_CONE {
        t = ray_unit_cone(ro, rd);
    } else {
        t = ray_unit_box(ro, rd);
    }
    let t0 = clamp(t.x, 0.0, 1.0);
    return vec2<f32>(t0, clamp(t.y, t0, 1.0));
}

// Optical depth of the volume's fog along the segment from camera_pos to point.
fn fog_volume_optical_depth(volume: FogVolume, camera_pos: vec3<f32>, point: vec3<f32>) -> f32 {
    let t = fog_volume_entry_exit(volume, camera_pos, point);
    let lim = vec3<f32>(FOG_POSITION_LIMIT);
    let eye = clamp(camera_pos, -lim, lim);
    let seg = clamp(point, -lim, lim) - eye;
    let entry = eye + t.x * seg;
    return height_fog_optical_depth(volume.density, volume.falloff, volume.offset, volume.gradient,
                                    entry - volume.center, (t.y - t.x) * seg);
}

// Fog of one volume between the camera and the shaded point: vec4(in-scattered
// radiance rgb, transmittance a).
fn fog_volume(volume: FogVolume, camera_pos: vec3<f32>, point: vec3<f32>) -> vec4<f32> {
    return fog_inscatter(volume.color, fog_volume_optical_depth(volume, camera_pos, point));
}

// Composites the fog of a volume in front over fog accumulated behind it:
// in-scattering front + T_front * behind, transmittance T_front * T_behind.
fn fog_over(front: vec4<f32>, behind: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(front.rgb + front.a * behind.rgb, front.a * behind.a);
}

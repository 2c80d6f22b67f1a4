// volfog::area_lights — in-scattering of rectangle and disk (ellipse) emitters,
// integrated over the emitter's area.
//
// Use:      #import volfog::area_lights::{area_light_inscatter, area_light_touches_sphere}
// Defines:  none
// Units:    positions and extents in metres; an emitter's radiance in W / (m^2 sr) per
//           channel; results are radiance scattered per unit sigma_s (multiply by
//           sigma_s to get W / (sr m^3)), as volfog::lights.
// Method:   the in-scattering at x is L_e * integral over the emitter's solid angle of
//           phase(view, w) T(x, y(w)) dw (one-sided Lambertian emitter: the radiance is
//           the same in every direction of its front side). The emitter is cut into
//           planar cells (a rectangle into AREA_LIGHT_GRID x AREA_LIGHT_GRID rectangles,
//           a disk into AREA_LIGHT_SECTORS sectors of two rings, an area-preserving
//           polygon); each cell's solid angle is exact (Van Oosterom and Strackee's
//           triangle formula, two triangles a cell), and the phase and the medium's
//           transmittance are taken at the cell's centre. For an isotropic phase in
//           clear air a rectangle's result is exact at every distance, including
//           inside the emitter's near field where a point-sampled r^-2 would diverge.
// Reference: Van Oosterom and Strackee 1983, "The solid angle of a plane triangle".
#define_import_path volfog::area_lights

#import volfog::types::{AreaLight, FogMedium}
#import volfog::density::medium_segment_transmittance
#import volfog::phase::phase_hg

// AreaLight.shape: a rectangle of 2 half_x by 2 half_y.
const AREA_LIGHT_RECT: u32 = 0u;
// AreaLight.shape: a disk (an ellipse of semi-axes half_x, half_y).
const AREA_LIGHT_DISK: u32 = 1u;
// Cells per side of a rectangle.
const AREA_LIGHT_GRID: u32 = 4u;
// Sectors of a disk; each has an inner triangle and an outer quadrilateral.
const AREA_LIGHT_SECTORS: u32 = 16u;
// Radius of the inner ring, a fraction of the outer one: the rings have equal areas.
const AREA_LIGHT_INNER: f32 = 0.70710678;
// The disk's polygon radius over its radius: the 16-gon of the disk's area,
// sqrt(2 pi / (16 sin(2 pi / 16))).
const AREA_LIGHT_DISK_SCALE: f32 = 1.0130029;
const AREA_TAU: f32 = 6.2831853;

// Solid angle (sr, in [0, 2 pi)) of the triangle with corners a, b, c, given relative
// to the point that sees it (Van Oosterom and Strackee):
// tan(omega / 2) = |a . (b x c)| / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
fn triangle_solid_angle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    let la = length(a);
    let lb = length(b);
    let lc = length(c);
    // a . (b x c) from the edges: exact in real numbers, and without f32's
    // cancellation between the nearly parallel b and c of a small or distant cell.
    let numerator = abs(dot(a, cross(b - a, c - a)));
    let denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2.0 * atan2(numerator, denominator);
}

// The contribution of one planar cell per unit radiance: its solid angle `omega` (sr)
// times the HG phase towards its centre `mid` (relative to the point) and, where
// `through`, the medium's transmittance from the point `world` to that centre.
fn area_cell(medium: FogMedium, through: bool, world: vec3<f32>, view_dir: vec3<f32>, g: f32,
    omega: f32, mid: vec3<f32>) -> f32 {
    let length_mid = length(mid);
    let to_cell = select(view_dir, mid / length_mid, length_mid > 1e-6);
    var weight = omega * phase_hg(dot(view_dir, to_cell), g);
    if through {
        weight *= medium_segment_transmittance(medium, world, world + mid);
    }
    return weight;
}

// Solid angle (sr) of the quadrilateral a, b, c, d (relative to the point), cut along
// a-c.
fn quad_solid_angle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, d: vec3<f32>) -> f32 {
    return triangle_solid_angle(a, b, c) + triangle_solid_angle(a, c, d);
}

// Whether an area light's range sphere (about its centre) touches a sphere of the given
// centre and radius (a block of froxels); an unused slot (range <= 0) touches nothing.
fn area_light_touches_sphere(light: AreaLight, center: vec3<f32>, radius: f32) -> bool {
    let d = light.center - center;
    let r = light.range + radius;
    return light.range > 0.0 && dot(d, d) <= r * r;
}

// Radiance scattered towards the eye per unit sigma_s by an area light at a world
// position: view_dir is the unit direction from the eye to the point, g the HG mean
// cosine, and `through` attenuates each cell's light by the medium's height profile on
// its way (FogLighting.transmittance). 0 behind the emitter's plane and beyond its range.
fn area_light_inscatter(light: AreaLight, medium: FogMedium, through: bool, world: vec3<f32>,
    view_dir: vec3<f32>, g: f32) -> vec3<f32> {
    let normal = cross(light.axis_x, light.axis_y);
    let offset = light.center - world;
    let distance = length(offset);
    if dot(offset, normal) >= 0.0 || light.range <= 0.0 {
        return vec3<f32>(0.0);
    }
    let x = distance / light.range;
    let x2 = x * x;
    let window = clamp(1.0 - x2 * x2, 0.0, 1.0);
    let ex = light.axis_x * light.half_x;
    let ey = light.axis_y * light.half_y;
    var sum = 0.0;
    if light.shape == AREA_LIGHT_DISK {
        let step = AREA_TAU / f32(AREA_LIGHT_SECTORS);
        for (var k = 0u; k < AREA_LIGHT_SECTORS; k++) {
            let p = AREA_LIGHT_DISK_SCALE * (ex * cos(step * f32(k)) + ey * sin(step * f32(k)));
            let q = AREA_LIGHT_DISK_SCALE * (ex * cos(step * f32(k + 1u)) + ey * sin(step * f32(k + 1u)));
            let pi = AREA_LIGHT_INNER * p;
            let qi = AREA_LIGHT_INNER * q;
            // The inner ring's triangle and the outer ring's quadrilateral.
            let inner = triangle_solid_angle(offset, offset + pi, offset + qi);
            sum += area_cell(medium, through, world, view_dir, g, inner, offset + (pi + qi) / 3.0);
            let outer = quad_solid_angle(offset + pi, offset + p, offset + q, offset + qi);
            sum += area_cell(medium, through, world, view_dir, g, outer, offset + 0.25 * (pi + p + q + qi));
        }
    } else {
        let n = f32(AREA_LIGHT_GRID);
        for (var j = 0u; j < AREA_LIGHT_GRID; j++) {
            let v0 = 2.0 * f32(j) / n - 1.0;
            let v1 = 2.0 * f32(j + 1u) / n - 1.0;
            for (var i = 0u; i < AREA_LIGHT_GRID; i++) {
                let u0 = 2.0 * f32(i) / n - 1.0;
                let u1 = 2.0 * f32(i + 1u) / n - 1.0;
                let corner = offset + ex * u0 + ey * v0;
                let du = ex * (u1 - u0);
                let dv = ey * (v1 - v0);
                let omega = quad_solid_angle(corner, corner + du, corner + du + dv, corner + dv);
                sum += area_cell(medium, through, world, view_dir, g, omega, corner + 0.5 * (du + dv));
            }
        }
    }
    return light.radiance * (light.fog_intensity * window * window * sum);
}

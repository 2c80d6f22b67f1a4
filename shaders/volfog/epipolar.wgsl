// volfog::epipolar — sun shafts sampled along epipolar lines and marched through a 1D
// min/max tree of the shadow map per line (Yusov 2012, after Engelhardt & Dachsbacher
// 2010 and Chen et al. 2011).
//
// Use:      the epipolar_* passes run the whole method (EpipolarShafts in the runtime);
//           a forward shader that only wants the result reads the shaft texture at its
//           pixel and calls epipolar_fog (alone) or volfog::apply::fog_tail_shafts (the
//           far field of a froxel volume).
// Defines:  VOLFOG_EPIPOLAR_COLORED — coloured shafts: the marches take a light-space
//           colour texture (the colour of the light after stained glass, texel-aligned
//           with the shadow map's cascade) and multiply the light of every lit section
//           by it; the tree then skips only shadowed nodes (Yusov 2012, 6.4).
// Geometry: the epipole e is the sun's position on the screen (EpipolarFrame.
//           light_screen, normalised device coordinates). Slice j of n runs from its
//           entry point (e itself when e is on the screen, else where the line from e
//           enters the screen) to an exit point on the border at slice coordinate
//           s = (j + 0.5) / n: the border is walked counter-clockwise from the top-left
//           corner, s in [0, 0.25) the left edge, then bottom, right and top. A line
//           shorter than `samples` pixels is stretched to `samples` pixels so samples
//           lie about a pixel apart; samples off the screen are invalid.
// Shadows:  a directional light with an orthographic cascade. Every view ray of a slice
//           lies in the plane of the camera and the sun direction, so its projection
//           into the shadow map runs along one half-line from the camera's texel: the
//           slice's 1D height map h(k), k = 0 .. shadow_size - 1, is the shadow depth at
//           the texel under origin + (k + 0.5) dir plus EpipolarFrame.depth_bias (dir
//           one texel long in its larger axis; outside the map h = 2, lit). Section k of a ray is the part whose
//           projection lies in [k, k + 1); it is lit when the light depth at its
//           middle is <= h(k). A min/max binary tree over h (level l holds min and max of
//           2^l entries) lets the march decide long sections at once (Yusov's
//           Algorithm 2); epipolar_march_steps visits every section (Algorithm 1) and
//           gives the same sum.
// In-scattering: the medium is a HeightFog (view space: its base and top heights are
//           measured from the camera; falloff 0 is uniform fog, capped by top_height)
//           whose scattering is a constant fraction of its extinction. The sun light
//           scattered towards the eye over a lit section [a, b] of the ray is P times
//           the section's share (epipolar_lit_section, dimensionless): without
//           fog.sun_transmittance the integral of sigma T over it, exactly T(a) - T(b),
//           T the transmittance from the start of the march; with it the integral of
//           sigma T T_sun, T_sun the transmittance of the medium from the point to its
//           top towards the sun (volfog::height_fog::height_fog_lit_integral), exactly
//           exp(-min(F(a), F(b))) tau_ab E(|r| tau_ab) with F = tau_view + tau_light,
//           tau_ab the optical depth of [a, b] and r = 1 - v / mu (v, mu the up
//           components of the ray's and the sun's unit directions). P is the phase term
//           (epipolar_phase). A march gives the shaft term S = the sum of the shares of
//           the lit sections (in [0, S_open], S_open the same sum with every section lit:
//           1 - T, or height_fog_lit_integral over the ray); the passes carry the lit
//           fraction F = S / S_open in [0, 1] per colour channel (1 where nothing
//           shadows; coloured shafts weight each lit section by the light's colour
//           there) and apply the medium per pixel, S_open included: F only changes where
//           shadows do, while 1 - T and S_open / (1 - T) change with every ray's height
//           and length, and P fastest near the epipole, so none of those is
//           interpolated. Where nothing shadows, F = 1 and the fog equals
//           volfog::height_fog's (the sun's attenuation included); the far field
//           (volfog::apply::fog_tail_shafts) scales the tail's sun lobe, attenuated the
//           same way, by F.
// Reference: Yusov 2012, "Outdoor Light Scattering Sample" (sections 4 and 6: the
//           coordinate texture, refinement, the min/max tree, Algorithm 2, the
//           transform back to the screen with bilateral weights, correction and
//           upscaling); Engelhardt & Dachsbacher 2010; Chen, Baran, Durand & Jarosz 2011.
#define_import_path volfog::epipolar

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::height_fog::{height_fog_optical_depth_below, height_fog_lit_integral, height_fog_sun_share, fog_inscatter}
#import volfog::froxel::view_from_ndc
#import volfog::phase::{phase_hg, phase_cornette_shanks, phase_rayleigh}

// Coordinate of samples off the screen (both components).
const EPIPOLAR_INVALID: f32 = -1e4;
// View depth stored for invalid samples: every difference to it is a depth break.
const EPIPOLAR_INVALID_DEPTH: f32 = -1e6;
// Samples per refinement workgroup (four words of packed depth-break flags).
const EPIPOLAR_GROUP: u32 = 128u;
// Shadow depth of the 1D height map outside the shadow map: always lit.
const EPIPOLAR_LIT_DEPTH: f32 = 2.0;
// Tolerance of the screen border, in normalised device units.
const EPIPOLAR_BORDER: f32 = 1e-4;

// A view ray's segment set up for the march: view-space start and extent (m), its
// projection onto the slice's 1D height map (positions start, end in texels) and its
// light depths at both ends.
struct EpipolarRay {
    origin: vec3<f32>,
    segment: vec3<f32>,
    start: f32,
    end: f32,
    light_start: f32,
    light_end: f32,
}

// Exit point (normalised device coordinates) of slice coordinate s in [0, 1]: the
// screen border walked counter-clockwise from the top-left corner (left, bottom,
// right, top; 0, 0.25, 0.5, 0.75 and 1 are the corners).
fn epipolar_exit_point(s: f32) -> vec2<f32> {
    let f4 = clamp(s, 0.0, 1.0) * 4.0;
    let edge = min(u32(f4), 3u);
    let c = 2.0 * (f4 - f32(edge)) - 1.0;
    if edge == 0u {
        return vec2<f32>(-1.0, -c);
    } else if edge == 1u {
        return vec2<f32>(c, -1.0);
    } else if edge == 2u {
        return vec2<f32>(1.0, c);
    }
    return vec2<f32>(-c, 1.0);
}

// Slice coordinate s in [0, 1) of a point on the screen border (inverse of
// epipolar_exit_point); `edge` is 0 left, 1 bottom, 2 right, 3 top.
fn epipolar_border_coord(p: vec2<f32>, edge: u32) -> f32 {
    var f = 0.5 - 0.5 * p.x;
    if edge == 0u {
        f = 0.5 - 0.5 * p.y;
    } else if edge == 1u {
        f = 0.5 + 0.5 * p.x;
    } else if edge == 2u {
        f = 0.5 + 0.5 * p.y;
    }
    return fract((f32(edge) + clamp(f, 0.0, 1.0)) * 0.25);
}

// Distance along the unit direction dir from p (inside the screen) to the border, and
// the edge it leaves through (0 left, 1 bottom, 2 right, 3 top).
fn epipolar_border_distance(p: vec2<f32>, dir: vec2<f32>) -> vec2<f32> {
    var best = 3.0e38;
    var edge = 0u;
    if dir.x < -1e-12 {
        best = (-1.0 - p.x) / dir.x;
        edge = 0u;
    } else if dir.x > 1e-12 {
        best = (1.0 - p.x) / dir.x;
        edge = 2u;
    }
    if dir.y < -1e-12 {
        let t = (-1.0 - p.y) / dir.y;
        if t < best {
            best = t;
            edge = 1u;
        }
    } else if dir.y > 1e-12 {
        let t = (1.0 - p.y) / dir.y;
        if t < best {
            best = t;
            edge = 3u;
        }
    }
    return vec2<f32>(max(best, 0.0), f32(edge));
}

// Entry point of the epipolar line from the epipole `light` to `exit` (on the border):
// the epipole when it is on the screen, else where the line enters the screen; equal to
// exit when the line misses the screen. Walks back from the exit point, so a far
// epipole (|light| >> 1) loses no precision.
fn epipolar_entry_point(light: vec2<f32>, exit: vec2<f32>) -> vec2<f32> {
    let to_light = light - exit;
    let len = length(to_light);
    if len < 1e-12 {
        return exit;
    }
    let back = to_light / len;
    // The largest step back that stays inside the screen (slabs in x and y).
    var u = len;
    if back.x > 1e-12 {
        u = min(u, (1.0 - exit.x) / back.x);
    } else if back.x < -1e-12 {
        u = min(u, (-1.0 - exit.x) / back.x);
    }
    if back.y > 1e-12 {
        u = min(u, (1.0 - exit.y) / back.y);
    } else if back.y < -1e-12 {
        u = min(u, (-1.0 - exit.y) / back.y);
    }
    return exit + back * max(u, 0.0);
}

// The epipolar line of slice j: vec4(entry.xy, exit.xy) with the exit point moved out
// so that the line is at least `samples` pixels long (Yusov 2012, 6.1); entry.x =
// EPIPOLAR_INVALID when the slice misses the screen.
fn epipolar_line(frame: EpipolarFrame, slice: u32) -> vec4<f32> {
    let s = (f32(slice) + 0.5) / f32(frame.slices);
    let exit = epipolar_exit_point(s);
    let entry = epipolar_entry_point(frame.light_screen, exit);
    let pixels = length((exit - entry) * frame.screen_size * 0.5);
    if pixels < 1e-3 {
        return vec4<f32>(EPIPOLAR_INVALID, EPIPOLAR_INVALID, exit);
    }
    let stretch = max(f32(frame.samples) / pixels, 1.0);
    return vec4<f32>(entry, entry + (exit - entry) * stretch);
}

// Is a normalised device position on the screen (within EPIPOLAR_BORDER)?
fn epipolar_on_screen(p: vec2<f32>) -> bool {
    return all(abs(p) <= vec2<f32>(1.0 + EPIPOLAR_BORDER));
}

// Position (normalised device coordinates) of sample k of `samples` on a line from
// epipolar_line: sample 0 at the entry, the last at the exit; both components
// EPIPOLAR_INVALID when the slice misses the screen or the sample is off it.
fn epipolar_sample_position(line: vec4<f32>, samples: u32, k: u32) -> vec2<f32> {
    let p = mix(line.xy, line.zw, f32(k) / f32(samples - 1u));
    if line.x == EPIPOLAR_INVALID || !epipolar_on_screen(p) {
        return vec2<f32>(EPIPOLAR_INVALID);
    }
    return p;
}

// Continuous slice index in [0, slices) of a screen point: the slice whose exit point
// the ray from the epipole through p reaches. The exit is found by walking from p (on
// the screen) away from the epipole to the border, which selects the same edge as
// Yusov's four sectors for an epipole on or off the screen.
fn epipolar_pixel_slice(frame: EpipolarFrame, p: vec2<f32>) -> f32 {
    let d = p - frame.light_screen;
    let len = length(d);
    let dir = select(vec2<f32>(1.0, 0.0), d / len, len > 1e-12);
    let hit = epipolar_border_distance(p, dir);
    let exit = p + dir * hit.x;
    return epipolar_border_coord(exit, u32(hit.y)) * f32(frame.slices);
}

// Continuous sample index (0 at the entry, samples - 1 at the exit) of a screen point
// projected onto a line from epipolar_line.
fn epipolar_line_position(line: vec4<f32>, samples: u32, p: vec2<f32>) -> f32 {
    let d = line.zw - line.xy;
    let t = dot(p - line.xy, d) / max(dot(d, d), 1e-30);
    return t * f32(samples - 1u);
}

// Section [start, end] of ray-marching samples around sample k: initial_step apart,
// a quarter of it (at least 2) over the first two initial steps from the entry, where
// the epipole makes the light vary fastest; the last sample closes the last section.
fn epipolar_section(initial_step: u32, samples: u32, k: u32) -> vec2<u32> {
    var step = initial_step;
    if k < 2u * initial_step {
        step = max(initial_step / 4u, 2u);
    }
    let start = k - k % step;
    return vec2<u32>(start, min(start + step, samples - 1u));
}

// Is there no depth break between two neighbouring samples of view depth z0 and z1 (m)?
// Invalid samples (negative depth) always break.
fn epipolar_continuous(z0: f32, z1: f32, threshold: f32) -> bool {
    return min(z0, z1) >= 0.0 && abs(z0 - z1) <= threshold * min(z0, z1);
}

// Interpolation sources (local indices) of local sample k in the section [a, b] of a
// refinement group: bit j of the packed flags is set when samples j and j + 1 have no
// depth break between them (Yusov 2012, 6.2). Walks to the nearest break on each side
// with firstLeadingBit / firstTrailingBit; a sample at a section end or next to a
// break is a ray-marching sample, interpolated from itself.
fn epipolar_sources(flags: vec4<u32>, k: u32, a: u32, b: u32) -> vec2<u32> {
    if k == a || k == b {
        return vec2<u32>(k, k);
    }
    // left: above the highest break j in [a, k) (a break at j splits j and j + 1).
    var left = a;
    for (var w = 3i; w >= 0; w -= 1) {
        let lo = u32(w) * 32u;
        if lo >= k || lo + 32u <= a {
            continue;
        }
        let first = max(a, lo) - lo;
        let last = min(k, lo + 32u) - lo; // exclusive
        let width = last - first;
        var mask = 0xffffffffu;
        if width < 32u {
            mask = ((1u << width) - 1u) << first;
        }
        let breaks = ~flags[w] & mask;
        if breaks != 0u {
            left = lo + u32(firstLeadingBit(breaks)) + 1u;
            break;
        }
    }
    // right: at the lowest break j in [k, b).
    var right = b;
    for (var w = 0i; w < 4; w += 1) {
        let lo = u32(w) * 32u;
        if lo + 32u <= k || lo >= b {
            continue;
        }
        let first = max(k, lo) - lo;
        let last = min(b, lo + 32u) - lo;
        let width = last - first;
        var mask = 0xffffffffu;
        if width < 32u {
            mask = ((1u << width) - 1u) << first;
        }
        let breaks = ~flags[w] & mask;
        if breaks != 0u {
            right = lo + u32(firstTrailingBit(breaks));
            break;
        }
    }
    if left == k || right == k {
        return vec2<u32>(k, k);
    }
    return vec2<u32>(left, right);
}

// Normalised device xy of a position on the full-resolution target (pixels, y down;
// pixel centres at + 0.5).
fn epipolar_pixel_ndc(frame: EpipolarFrame, position: vec2<f32>) -> vec2<f32> {
    let uv = position / frame.screen_size;
    return vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
}

// View depth (m) of depth-buffer value `depth` at normalised device xy, at most
// frame.max_depth (sky pixels stop there).
fn epipolar_view_depth(frame: EpipolarFrame, ndc: vec2<f32>, depth: f32) -> f32 {
    return min(abs(view_from_ndc(vec3<f32>(ndc, depth), frame.view_from_clip).z), frame.max_depth);
}

// View-space point at view depth 1 on the ray through normalised device xy.
fn epipolar_view_ray(view_from_clip: mat4x4<f32>, ndc: vec2<f32>) -> vec3<f32> {
    let p = view_from_ndc(vec3<f32>(ndc, 0.5), view_from_clip);
    return p / max(abs(p.z), 1e-30);
}

// Light-space texel position (xy, in shadow_size units, v down) and depth (z) of a
// view-space point.
fn epipolar_light_texel(frame: EpipolarFrame, view: vec3<f32>) -> vec3<f32> {
    let clip = frame.light_from_view * vec4<f32>(view, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    return vec3<f32>(uv * f32(frame.shadow_size), ndc.z);
}

// The 1D height map of a slice: vec4(origin.xy, dir.xy) in texels, origin the camera's
// texel position and dir the projection of the slice's rays, one texel long in its
// larger axis (+x when the rays run along the sun).
fn epipolar_slice_map(frame: EpipolarFrame, slice: u32) -> vec4<f32> {
    let s = (f32(slice) + 0.5) / f32(frame.slices);
    let ray = epipolar_view_ray(frame.view_from_clip, epipolar_exit_point(s));
    let o = epipolar_light_texel(frame, vec3<f32>(0.0));
    let d = epipolar_light_texel(frame, ray).xy - o.xy;
    let m = max(abs(d.x), abs(d.y));
    let dir = select(vec2<f32>(1.0, 0.0), d / m, m > 1e-12);
    return vec4<f32>(o.xy, dir);
}

// h(k): the shadow depth under entry k of a slice's height map plus the depth bias
// (EPIPOLAR_LIT_DEPTH off the map). `shadow` holds the cascades as array layers of side
// `size`.
fn epipolar_height(shadow: texture_2d_array<f32>, layer: u32, map: vec4<f32>, k: u32, size: u32, bias: f32) -> f32 {
    let q = floor(map.xy + (f32(k) + 0.5) * map.zw);
    if any(q < vec2<f32>(0.0)) || any(q >= vec2<f32>(f32(size))) {
        return EPIPOLAR_LIT_DEPTH;
    }
    return textureLoad(shadow, vec2<i32>(q), i32(layer), 0).r + bias;
}

// The segment of the view ray through ndc from view depth depth0 to depth1 (m) on a
// slice's height map.
fn epipolar_ray(frame: EpipolarFrame, map: vec4<f32>, ndc: vec2<f32>, depth0: f32, depth1: f32) -> EpipolarRay {
    let dir = epipolar_view_ray(frame.view_from_clip, ndc);
    let p0 = dir * depth0;
    let p1 = dir * max(depth1, depth0);
    let l0 = epipolar_light_texel(frame, p0);
    let l1 = epipolar_light_texel(frame, p1);
    let dd = dot(map.zw, map.zw);
    var ray: EpipolarRay;
    ray.origin = p0;
    ray.segment = p1 - p0;
    ray.start = dot(l0.xy - map.xy, map.zw) / dd;
    ray.end = dot(l1.xy - map.xy, map.zw) / dd;
    ray.light_start = l0.z;
    ray.light_end = l1.z;
    return ray;
}

// Transmittance of the medium (below its top) from the start of the ray to the
// fraction t of it.
fn epipolar_transmittance(fog: HeightFog, ray: EpipolarRay, t: f32) -> f32 {
    return exp(-height_fog_optical_depth_below(fog.density, fog.falloff, fog.base_height, fog.up,
        fog.top_height, ray.origin, ray.segment * t));
}

// The share of a lit part [ta, tb] (fractions) of the ray in the shaft term
// (dimensionless, per unit of the phase term P), given the transmittances t_at_a =
// T(ta) and t_at_b = T(tb) from the start of the ray: without fog.sun_transmittance
// T(ta) - T(tb), the integral of sigma T over the part; with it the integral of
// sigma T T_sun, which is T(ta) times volfog::height_fog::height_fog_lit_integral of
// the part (whose tau_view starts at ta), together exp(-min(F(ta), F(tb))) tau E(|r| tau)
// with F(t) = tau_view(0..t) + tau_light(p(t)), tau the optical depth of the part and
// r = 1 - v / mu. The shares of consecutive parts add up to the share of their union.
fn epipolar_lit_section(fog: HeightFog, ray: EpipolarRay, ta: f32, tb: f32, t_at_a: f32, t_at_b: f32) -> f32 {
    if fog.sun_transmittance != 0u {
        return t_at_a * height_fog_lit_integral(fog.density, fog.falloff, fog.base_height, fog.up,
            fog.top_height, ray.origin + ray.segment * ta, ray.segment * (tb - ta), fog.sun_direction);
    }
    return t_at_a - t_at_b;
}

// S_open: the shaft term of the ray with nothing shadowing it (epipolar_lit_section of
// the whole ray): 1 - T(1), or with fog.sun_transmittance the light of the sun that
// reaches the ray through the medium and is scattered on it.
fn epipolar_lit_open(fog: HeightFog, ray: EpipolarRay) -> f32 {
    return epipolar_lit_section(fog, ray, 0.0, 1.0, 1.0, epipolar_transmittance(fog, ray, 1.0));
}

// The lit fraction F = S / S_open of a ray's shaft term s, in [0, 1]; 1 when the ray
// absorbs almost nothing (1 - T <= 1e-6) or the sun reaches none of it (S_open = 0),
// where S carries no information.
fn epipolar_lit_fraction(fog: HeightFog, ray: EpipolarRay, s: vec3<f32>) -> vec3<f32> {
    let absorbed = 1.0 - epipolar_transmittance(fog, ray, 1.0);
    let open = epipolar_lit_open(fog, ray);
    if absorbed <= 1e-6 || open <= 0.0 {
        return vec3<f32>(1.0);
    }
    return clamp(s / open, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Colour of the light at height-map entry k of a slice: the light-space colour texture
// at the texel of epipolar_height (white off the map).
fn epipolar_color(colors: texture_2d<f32>, map: vec4<f32>, k: u32, size: u32) -> vec3<f32> {
    let q = floor(map.xy + (f32(k) + 0.5) * map.zw);
    if any(q < vec2<f32>(0.0)) || any(q >= vec2<f32>(f32(size))) {
        return vec3<f32>(1.0);
    }
    return textureLoad(colors, vec2<i32>(q), 0).rgb;
}

// Fraction of the ray where its projection reaches height-map position i.
fn epipolar_ray_fraction(ray: EpipolarRay, i: f32) -> f32 {
    return clamp((i - ray.start) / (ray.end - ray.start), 0.0, 1.0);
}

// Is the part [ta, tb] of the ray under the height value h at its middle?
fn epipolar_lit(ray: EpipolarRay, ta: f32, tb: f32, h: f32) -> bool {
    return mix(ray.light_start, ray.light_end, 0.5 * (ta + tb)) <= h;
}

// Index of the first entry of tree level l in a slice's row (level 0 is h itself).
fn epipolar_level_offset(size: u32, level: u32) -> u32 {
    return 2u * size - ((2u * size) >> level);
}

// Shaft term S (per colour channel, dimensionless: the sum of epipolar_lit_section over
// the lit sections) of a ray visiting every section of the slice's height map, read
// from the shadow map (Yusov 2012, Algorithm 1). Rays whose projection is shorter than a
// texel take one section.
fn epipolar_march_steps(
    shadow: texture_2d_array<f32>,
    layer: u32,
    map: vec4<f32>,
    size: u32,
    bias: f32,
    fog: HeightFog,
    ray: EpipolarRay,
#ifdef VOLFOG_EPIPOLAR_COLORED
    colors: texture_2d<f32>,
#endif
) -> vec3<f32> {
    if ray.end - ray.start < 1.0 {
        let k = u32(clamp(floor(0.5 * (ray.start + ray.end)), 0.0, f32(size)));
        var h = EPIPOLAR_LIT_DEPTH;
        var c = vec3<f32>(1.0);
        if k < size {
            h = epipolar_height(shadow, layer, map, k, size, bias);
#ifdef VOLFOG_EPIPOLAR_COLORED
            c = epipolar_color(colors, map, k, size);
#endif
        }
        let lit = epipolar_lit(ray, 0.0, 1.0, h);
        return select(vec3<f32>(0.0), c * epipolar_lit_open(fog, ray), lit);
    }
    let stop = epipolar_ray_fraction(ray, f32(size));
    var k = u32(max(floor(ray.start), 0.0));
    var ta = 0.0;
    var t_at_a = 1.0;
    var sum = vec3<f32>(0.0);
    while ta < stop && k < size {
        let tb = min(epipolar_ray_fraction(ray, f32(k + 1u)), stop);
        let t_at_b = epipolar_transmittance(fog, ray, tb);
        if epipolar_lit(ray, ta, tb, epipolar_height(shadow, layer, map, k, size, bias)) {
            var c = vec3<f32>(1.0);
#ifdef VOLFOG_EPIPOLAR_COLORED
            c = epipolar_color(colors, map, k, size);
#endif
            sum += c * epipolar_lit_section(fog, ray, ta, tb, t_at_a, t_at_b);
        }
        ta = tb;
        t_at_a = t_at_b;
        k += 1u;
    }
    // Beyond the map everything is lit, in white.
    return sum + vec3<f32>(epipolar_lit_section(fog, ray, ta, 1.0, t_at_a, epipolar_transmittance(fog, ray, 1.0)));
}

// min and max of tree node `index` of level `level` of slice `slice`. Row `slice` of
// the tree texture (rgba32float) holds the slice's levels one after the other, two
// nodes per texel: node n of the row (n = epipolar_level_offset(size, level) + index)
// in texel n / 2, as (min, max) in xy for even n and in zw for odd n.
fn epipolar_tree_node(tree: texture_2d<f32>, slice: u32, size: u32, level: u32, index: u32) -> vec2<f32> {
    let n = epipolar_level_offset(size, level) + index;
    let texel = textureLoad(tree, vec2<i32>(i32(n >> 1u), i32(slice)), 0);
    return select(texel.xy, texel.zw, (n & 1u) == 1u);
}

// Interpolation sources packed in one u32 (first in the low 16 bits), as the refine
// pass stores them; samples < 65536.
fn epipolar_pack_sources(sources: vec2<u32>) -> u32 {
    return (sources.x & 0xffffu) | (sources.y << 16u);
}

// The two sources of a packed u32.
fn epipolar_unpack_sources(packed: u32) -> vec2<u32> {
    return vec2<u32>(packed & 0xffffu, packed >> 16u);
}

// Shaft term S (per colour channel) of a ray through the slice's min/max tree (Yusov
// 2012, Algorithm 2): climb a level when the position starts the parent node, then
// descend until a node is wholly lit (max light depth of the part <= node min), wholly
// shadowed (min light depth > node max) or a single section; the same sum as
// epipolar_march_steps. Coloured shafts descend lit nodes too, to weight each section by
// its colour (the slice's map is then needed to find its texel).
fn epipolar_march_tree(
    tree: texture_2d<f32>,
    slice: u32,
    size: u32,
    fog: HeightFog,
    ray: EpipolarRay,
#ifdef VOLFOG_EPIPOLAR_COLORED
    map: vec4<f32>,
    colors: texture_2d<f32>,
#endif
) -> vec3<f32> {
    if ray.end - ray.start < 1.0 {
        let k = u32(clamp(floor(0.5 * (ray.start + ray.end)), 0.0, f32(size)));
        var h = EPIPOLAR_LIT_DEPTH;
        var c = vec3<f32>(1.0);
        if k < size {
            h = epipolar_tree_node(tree, slice, size, 0u, k).x;
#ifdef VOLFOG_EPIPOLAR_COLORED
            c = epipolar_color(colors, map, k, size);
#endif
        }
        let lit = epipolar_lit(ray, 0.0, 1.0, h);
        return select(vec3<f32>(0.0), c * epipolar_lit_open(fog, ray), lit);
    }
    let top = countTrailingZeros(size);
    let stop = epipolar_ray_fraction(ray, f32(size));
    var k = u32(max(floor(ray.start), 0.0));
    var level = 0u;
    var ta = 0.0;
    // Consecutive lit nodes form one run [lit_from, ta]: its share (epipolar_lit_section)
    // is taken once, when a shadowed node (or the end) closes it.
    var lit_from = 0.0;
    var open = false;
    var sum = vec3<f32>(0.0);
    var guard = 0u;
    while ta < stop && k < size && guard < 8u * size {
        guard += 1u;
        // Step 5.1: one level coarser when k starts the parent node (in the benchmark's
        // scene 32 node visits per ray, against 43 climbing as far as k allows).
        if level < top && (k & ((2u << level) - 1u)) == 0u {
            level += 1u;
        }
        var lit = false;
        var tb = ta;
        loop {
            let n = 1u << level;
            tb = min(epipolar_ray_fraction(ray, f32(k + n)), stop);
            let da = mix(ray.light_start, ray.light_end, ta);
            let db = mix(ray.light_start, ray.light_end, tb);
            let node = epipolar_tree_node(tree, slice, size, level, k >> level);
#ifdef VOLFOG_EPIPOLAR_COLORED
            if max(da, db) <= node.x && level == 0u {
#else
            if max(da, db) <= node.x {
#endif
                lit = true;
                break;
            }
            if min(da, db) > node.y {
                break;
            }
            if level == 0u {
                lit = epipolar_lit(ray, ta, tb, node.x);
                break;
            }
            level -= 1u;
        }
#ifdef VOLFOG_EPIPOLAR_COLORED
        if lit {
            let c = epipolar_color(colors, map, k, size);
            sum += c * epipolar_lit_section(fog, ray, ta, tb, epipolar_transmittance(fog, ray, ta),
                epipolar_transmittance(fog, ray, tb));
        }
#else
        if lit && !open {
            lit_from = ta;
            open = true;
        } else if !lit && open {
            sum += vec3<f32>(epipolar_lit_section(fog, ray, lit_from, ta,
                epipolar_transmittance(fog, ray, lit_from), epipolar_transmittance(fog, ray, ta)));
            open = false;
        }
#endif
        ta = tb;
        k += 1u << level;
    }
    // Beyond the map everything is lit (in white): the remainder joins an open run.
    if !open {
        lit_from = ta;
    }
    return sum + vec3<f32>(epipolar_lit_section(fog, ray, lit_from, 1.0,
        epipolar_transmittance(fog, ray, lit_from), epipolar_transmittance(fog, ray, 1.0)));
}

// Lit fraction F (see epipolar_lit_fraction) of the view ray through ndc from view
// depth depth0 to depth1 (m) by brute force: `steps` equal steps, each lit when the
// light depth at its middle is not behind the shadow map texel there (nearest texel,
// lit off the map), coloured by the light-space colour texture there under
// VOLFOG_EPIPOLAR_COLORED. The per-pixel reference and the correction of pixels
// interpolation cannot serve.
fn epipolar_march_pixel(
    shadow: texture_2d_array<f32>,
    frame: EpipolarFrame,
    fog: HeightFog,
    ndc: vec2<f32>,
    depth0: f32,
    depth1: f32,
    steps: u32,
#ifdef VOLFOG_EPIPOLAR_COLORED
    colors: texture_2d<f32>,
#endif
) -> vec3<f32> {
    let dir = epipolar_view_ray(frame.view_from_clip, ndc);
    var ray: EpipolarRay;
    ray.origin = dir * depth0;
    ray.segment = dir * (max(depth1, depth0) - depth0);
    let size = f32(frame.shadow_size);
    let n = max(steps, 1u);
    var t_at_a = 1.0;
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < n; i += 1u) {
        let ta = f32(i) / f32(n);
        let tb = f32(i + 1u) / f32(n);
        let l = epipolar_light_texel(frame, ray.origin + ray.segment * (0.5 * (ta + tb)));
        let q = floor(l.xy);
        var h = EPIPOLAR_LIT_DEPTH;
        var c = vec3<f32>(1.0);
        if all(q >= vec2<f32>(0.0)) && all(q < vec2<f32>(size)) {
            h = textureLoad(shadow, vec2<i32>(q), i32(frame.cascade), 0).r + frame.depth_bias;
#ifdef VOLFOG_EPIPOLAR_COLORED
            c = textureLoad(colors, vec2<i32>(q), 0).rgb;
#endif
        }
        let t_at_b = epipolar_transmittance(fog, ray, tb);
        if l.z <= h {
            sum += c * epipolar_lit_section(fog, ray, ta, tb, t_at_a, t_at_b);
        }
        t_at_a = t_at_b;
    }
    return epipolar_lit_fraction(fog, ray, sum);
}

// Phase term P (linear rgb radiance per unit S) for a view direction (unit, eye into
// the scene): the medium's sun lobe (fog.sun_color with Henyey-Greenstein or, with
// phase_model 1, Cornette-Shanks of mean cosine fog.sun_g) plus frame.rayleigh times
// the Rayleigh phase.
fn epipolar_phase(frame: EpipolarFrame, fog: HeightFog, view_dir: vec3<f32>) -> vec3<f32> {
    let c = clamp(dot(view_dir, fog.sun_direction), -1.0, 1.0);
    let g = clamp(fog.sun_g, -0.999, 0.999);
    var lobe = phase_hg(c, g);
    if frame.phase_model == 1u {
        lobe = phase_cornette_shanks(c, g);
    }
    return fog.sun_color * lobe + frame.rayleigh * phase_rayleigh(c);
}

// Fog of a view-space point (m) with lit fraction `shafts` (the shaft texture's rgb):
// vec4(in-scattered radiance, transmittance) from frame.start_depth to the point (or to
// frame.max_depth): (fog.color + P * F * R) * (1 - T), the medium's constant colour over
// the whole segment, the sun's light where it reaches: R = S_open / (1 - T) the share
// the medium lets through to the segment (height_fog_sun_share; 1 without
// fog.sun_transmittance), so P * F * R * (1 - T) = P * S. Combine with
// volfog::apply::apply_fog.
fn epipolar_fog(frame: EpipolarFrame, fog: HeightFog, view_pos: vec3<f32>, shafts: vec3<f32>) -> vec4<f32> {
    let depth = abs(view_pos.z);
    let end = min(depth, frame.max_depth);
    if end <= frame.start_depth || depth <= 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let origin = view_pos * (frame.start_depth / depth);
    let segment = view_pos * (end / depth) - origin;
    let od = height_fog_optical_depth_below(fog.density, fog.falloff, fog.base_height, fog.up,
        fog.top_height, origin, segment);
    let view_dir = view_pos / length(view_pos);
    let lit = clamp(shafts, vec3<f32>(0.0), vec3<f32>(1.0)) * height_fog_sun_share(fog, origin, segment, od);
    let radiance = fog.color + epipolar_phase(frame, fog, view_dir) * lit;
    return fog_inscatter(radiance, od);
}

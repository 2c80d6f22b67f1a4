//! Mirror of `volfog::epipolar`: sun shafts sampled along epipolar lines and marched
//! through a 1D min/max tree of the shadow map per line (Yusov 2012, after Engelhardt &
//! Dachsbacher 2010 and Chen et al. 2011).
//!
//! The textures of the WGSL become plain data: a [`ShadowLayer`] is the layer of the
//! shadow map the shafts are marched in, a [`MinMaxTree`] the two ping-pong tree
//! textures of the `epipolar_tree` pass. [`coordinates`] and [`refine_slice`] are the
//! `epipolar_coords` and `epipolar_refine` passes on the CPU.
//!
//! ```
//! use volfog::cpu::epipolar::{border_coord, exit_point};
//!
//! // The border is walked counter-clockwise from the top-left corner.
//! assert_eq!(exit_point(0.0), glam::Vec2::new(-1.0, 1.0));
//! assert_eq!(exit_point(0.25), glam::Vec2::new(-1.0, -1.0));
//! // 0.6 lies on the right edge (edge 2): the point maps back to its coordinate.
//! assert!((border_coord(exit_point(0.6), 2) - 0.6).abs() < 1e-6);
//! ```

use glam::{Mat4, UVec2, Vec2, Vec3, Vec3Swizzles, Vec4, Vec4Swizzles};

use super::froxel::view_from_ndc;
use super::height_fog::height_fog_optical_depth;
use super::phase::{phase_cornette_shanks, phase_hg, phase_rayleigh};
use crate::uniforms::{EpipolarFrame, HeightFog};

/// Coordinate (both components) of samples off the screen; mirror of
/// `volfog::epipolar::EPIPOLAR_INVALID`.
pub const INVALID: f32 = -1e4;
/// View depth (m) stored for invalid samples: every difference to it is a depth break;
/// mirror of `volfog::epipolar::EPIPOLAR_INVALID_DEPTH`.
pub const INVALID_DEPTH: f32 = -1e6;
/// Samples per refinement workgroup (four words of packed depth-break flags); mirror of
/// `volfog::epipolar::EPIPOLAR_GROUP`.
pub const GROUP: u32 = 128;
/// Shadow depth of the 1D height map outside the shadow map (always lit); mirror of
/// `volfog::epipolar::EPIPOLAR_LIT_DEPTH`.
pub const LIT_DEPTH: f32 = 2.0;
/// Tolerance of the screen border, normalised device units; mirror of
/// `volfog::epipolar::EPIPOLAR_BORDER`.
pub const BORDER: f32 = 1e-4;

/// WGSL `mix` of scalars: `a (1 - t) + b t`.
fn mix(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// WGSL `fract`: `x - floor(x)`.
fn fract(x: f32) -> f32 {
    x - x.floor()
}

/// One layer of the shadow map (light depth in [0, 1] per texel, row-major,
/// `depths[y * size + x]`): the layer `frame.cascade` the WGSL reads from its
/// `texture_2d_array<f32>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowLayer<'a> {
    /// Side of the layer in texels (`EpipolarFrame::shadow_size`).
    pub size: u32,
    /// `size * size` depths, row-major (v down, as the texture).
    pub depths: &'a [f32],
}

impl ShadowLayer<'_> {
    /// The depth of texel (x, y), as WGSL `textureLoad` (both below `size`).
    pub fn load(&self, x: u32, y: u32) -> f32 {
        self.depths[(y * self.size + x) as usize]
    }
}

/// The light-space colour texture of coloured shafts (`VOLFOG_EPIPOLAR_COLORED`): the
/// light's colour after stained glass per texel of the cascade, row-major
/// (`colors[y * size + x]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorLayer<'a> {
    /// Side in texels (`EpipolarFrame::shadow_size`).
    pub size: u32,
    /// `size * size` colours (linear rgb), row-major, v down.
    pub colors: &'a [Vec3],
}

/// Colour of the light at height-map entry `k` of a slice (white off the map, or
/// without colours); mirror of `volfog::epipolar::epipolar_color`.
pub fn color(colors: Option<&ColorLayer>, map: Vec4, k: u32) -> Vec3 {
    let Some(c) = colors else {
        return Vec3::ONE;
    };
    let q = (map.xy() + (k as f32 + 0.5) * map.zw()).floor();
    if q.cmplt(Vec2::ZERO).any() || q.cmpge(Vec2::splat(c.size as f32)).any() {
        return Vec3::ONE;
    }
    c.colors[(q.y as u32 * c.size + q.x as u32) as usize]
}

/// A view ray's segment set up for the march: view-space start and extent (m), its
/// projection onto the slice's 1D height map (texels) and its light depths at both
/// ends; mirror of `volfog::epipolar::EpipolarRay`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EpipolarRay {
    /// View-space start of the segment (m).
    pub origin: Vec3,
    /// View-space extent of the segment (m).
    pub segment: Vec3,
    /// Height-map position (texels) of the start.
    pub start: f32,
    /// Height-map position (texels) of the end.
    pub end: f32,
    /// Light depth of the start.
    pub light_start: f32,
    /// Light depth of the end.
    pub light_end: f32,
}

/// The 1D min/max trees of all slices: the two ping-pong tree textures of the
/// `epipolar_tree` pass as one array; replaces `volfog::epipolar::epipolar_tree_node`'s
/// textures.
#[derive(Debug, Clone, PartialEq)]
pub struct MinMaxTree {
    /// Shadow map side (texels), the entries of level 0.
    pub size: u32,
    /// Slices (rows).
    pub slices: u32,
    /// `2 * size` (min, max) nodes per slice, level `l` from [`level_offset`]`(size, l)`
    /// (level 0 is h itself as (h, h)); row `j` is slice `j`.
    pub nodes: Vec<Vec2>,
}

impl MinMaxTree {
    /// The trees of every slice of `frame` over `shadow` (side `frame.shadow_size`),
    /// level 0 as `epipolar_tree_init` and levels 1 ..= log2(size) as
    /// `epipolar_tree_level` build them.
    pub fn build(frame: &EpipolarFrame, shadow: &ShadowLayer) -> Self {
        let size = frame.shadow_size;
        assert_eq!(
            shadow.size, size,
            "the shadow layer's side is frame.shadow_size"
        );
        assert_eq!(shadow.depths.len(), (size * size) as usize);
        let row = 2 * size as usize;
        let mut nodes = vec![Vec2::ZERO; row * frame.slices as usize];
        for slice in 0..frame.slices {
            let at = row * slice as usize;
            let map = slice_map(frame, slice);
            for x in 0..size {
                let h = height(shadow, map, x, frame.depth_bias);
                nodes[at + x as usize] = Vec2::new(h, h);
            }
            for level in 1..=size.trailing_zeros() {
                let src = at + level_offset(size, level - 1) as usize;
                let dst = at + level_offset(size, level) as usize;
                for i in 0..(size >> level) as usize {
                    let a = nodes[src + 2 * i];
                    let b = nodes[src + 2 * i + 1];
                    nodes[dst + i] = Vec2::new(a.x.min(b.x), a.y.max(b.y));
                }
            }
        }
        Self {
            size,
            slices: frame.slices,
            nodes,
        }
    }

    /// min and max (light depth) of tree node `index` of level `level` in row `slice`;
    /// mirror of `volfog::epipolar::epipolar_tree_node`.
    pub fn node(&self, slice: u32, level: u32, index: u32) -> Vec2 {
        let at = 2 * self.size as usize * slice as usize
            + (level_offset(self.size, level) + index) as usize;
        self.nodes[at]
    }
}

/// Exit point (normalised device coordinates) of slice coordinate `s` in [0, 1] on the
/// border walked counter-clockwise from the top-left corner (left, bottom, right, top);
/// mirror of `volfog::epipolar::epipolar_exit_point`.
pub fn exit_point(s: f32) -> Vec2 {
    let f4 = s.clamp(0.0, 1.0) * 4.0;
    let edge = (f4 as u32).min(3);
    let c = 2.0 * (f4 - edge as f32) - 1.0;
    match edge {
        0 => Vec2::new(-1.0, -c),
        1 => Vec2::new(c, -1.0),
        2 => Vec2::new(1.0, c),
        _ => Vec2::new(-c, 1.0),
    }
}

/// Slice coordinate in [0, 1) of a point on the screen border, `edge` 0 left, 1 bottom,
/// 2 right, 3 top (inverse of [`exit_point`]); mirror of
/// `volfog::epipolar::epipolar_border_coord`.
pub fn border_coord(p: Vec2, edge: u32) -> f32 {
    let f = match edge {
        0 => 0.5 - 0.5 * p.y,
        1 => 0.5 + 0.5 * p.x,
        2 => 0.5 + 0.5 * p.y,
        _ => 0.5 - 0.5 * p.x,
    };
    fract((edge as f32 + f.clamp(0.0, 1.0)) * 0.25)
}

/// `(distance, edge)`: the distance (normalised device units) along the unit `dir` from
/// `p` (on the screen) to the border and the edge it leaves through (0 left, 1 bottom,
/// 2 right, 3 top, as f32); mirror of `volfog::epipolar::epipolar_border_distance`.
pub fn border_distance(p: Vec2, dir: Vec2) -> Vec2 {
    let mut best = 3.0e38f32;
    let mut edge = 0u32;
    if dir.x < -1e-12 {
        best = (-1.0 - p.x) / dir.x;
        edge = 0;
    } else if dir.x > 1e-12 {
        best = (1.0 - p.x) / dir.x;
        edge = 2;
    }
    if dir.y < -1e-12 {
        let t = (-1.0 - p.y) / dir.y;
        if t < best {
            best = t;
            edge = 1;
        }
    } else if dir.y > 1e-12 {
        let t = (1.0 - p.y) / dir.y;
        if t < best {
            best = t;
            edge = 3;
        }
    }
    Vec2::new(best.max(0.0), edge as f32)
}

/// Entry point (normalised device coordinates) of the line from the epipole `light` to
/// `exit` (on the border): the epipole on the screen, else where the line enters it,
/// `exit` when it misses; mirror of `volfog::epipolar::epipolar_entry_point`.
pub fn entry_point(light: Vec2, exit: Vec2) -> Vec2 {
    let to_light = light - exit;
    let len = to_light.length();
    if len < 1e-12 {
        return exit;
    }
    let back = to_light / len;
    // The largest step back that stays inside the screen (slabs in x and y).
    let mut u = len;
    if back.x > 1e-12 {
        u = u.min((1.0 - exit.x) / back.x);
    } else if back.x < -1e-12 {
        u = u.min((-1.0 - exit.x) / back.x);
    }
    if back.y > 1e-12 {
        u = u.min((1.0 - exit.y) / back.y);
    } else if back.y < -1e-12 {
        u = u.min((-1.0 - exit.y) / back.y);
    }
    exit + back * u.max(0.0)
}

/// The epipolar line of `slice`: `(entry.xy, exit.xy)` (normalised device
/// coordinates), the exit moved out to at least `samples` pixels from the entry;
/// `entry.x = INVALID` when the slice misses the screen; mirror of
/// `volfog::epipolar::epipolar_line`.
pub fn line(frame: &EpipolarFrame, slice: u32) -> Vec4 {
    let s = (slice as f32 + 0.5) / frame.slices as f32;
    let exit = exit_point(s);
    let entry = entry_point(frame.light_screen, exit);
    let pixels = ((exit - entry) * frame.screen_size * 0.5).length();
    if pixels < 1e-3 {
        return Vec4::new(INVALID, INVALID, exit.x, exit.y);
    }
    let stretch = (frame.samples as f32 / pixels).max(1.0);
    let far = entry + (exit - entry) * stretch;
    Vec4::new(entry.x, entry.y, far.x, far.y)
}

/// Is a normalised device position on the screen (within [`BORDER`])? Mirror of
/// `volfog::epipolar::epipolar_on_screen`.
pub fn on_screen(p: Vec2) -> bool {
    p.abs().cmple(Vec2::splat(1.0 + BORDER)).all()
}

/// Position (normalised device coordinates) of sample `k` of `samples` on a [`line()`]
/// (0 at the entry, `samples - 1` at the exit), `(INVALID, INVALID)` off the screen;
/// mirror of `volfog::epipolar::epipolar_sample_position`.
pub fn sample_position(line: Vec4, samples: u32, k: u32) -> Vec2 {
    let p = line.xy().lerp(line.zw(), k as f32 / (samples - 1) as f32);
    if line.x == INVALID || !on_screen(p) {
        return Vec2::splat(INVALID);
    }
    p
}

/// Continuous slice index in [0, slices) of the screen point `p` (normalised device
/// coordinates); mirror of `volfog::epipolar::epipolar_pixel_slice`.
pub fn pixel_slice(frame: &EpipolarFrame, p: Vec2) -> f32 {
    let d = p - frame.light_screen;
    let len = d.length();
    let dir = if len > 1e-12 { d / len } else { Vec2::X };
    let hit = border_distance(p, dir);
    let exit = p + dir * hit.x;
    border_coord(exit, hit.y as u32) * frame.slices as f32
}

/// Continuous sample index (0 at the entry, `samples - 1` at the exit) of the screen
/// point `p` projected onto a [`line()`]; mirror of
/// `volfog::epipolar::epipolar_line_position`.
pub fn line_position(line: Vec4, samples: u32, p: Vec2) -> f32 {
    let d = line.zw() - line.xy();
    let t = (p - line.xy()).dot(d) / d.dot(d).max(1e-30);
    t * (samples - 1) as f32
}

/// Section `(start, end)` (sample indices) of ray-marching samples around sample `k`:
/// `initial_step` apart, a quarter of it (at least 2) over the first two initial steps;
/// mirror of `volfog::epipolar::epipolar_section`.
pub fn section(initial_step: u32, samples: u32, k: u32) -> UVec2 {
    let mut step = initial_step;
    if k < 2 * initial_step {
        step = (initial_step / 4).max(2);
    }
    let start = k - k % step;
    UVec2::new(start, (start + step).min(samples - 1))
}

/// Is there no depth break between neighbouring samples of view depth `z0` and `z1`
/// (m), `threshold` relative? Invalid (negative) depths always break; mirror of
/// `volfog::epipolar::epipolar_continuous`.
pub fn continuous(z0: f32, z1: f32, threshold: f32) -> bool {
    z0.min(z1) >= 0.0 && (z0 - z1).abs() <= threshold * z0.min(z1)
}

/// Interpolation sources (local indices) of local sample `k` in the section `[a, b]` of
/// a refinement group, bit `j` of `flags` set when samples `j` and `j + 1` have no depth
/// break; mirror of `volfog::epipolar::epipolar_sources`.
pub fn sources(flags: [u32; 4], k: u32, a: u32, b: u32) -> UVec2 {
    if k == a || k == b {
        return UVec2::new(k, k);
    }
    // left: above the highest break j in [a, k) (a break at j splits j and j + 1).
    let mut left = a;
    for w in (0..4u32).rev() {
        let lo = w * 32;
        if lo >= k || lo + 32 <= a {
            continue;
        }
        let first = a.max(lo) - lo;
        let last = k.min(lo + 32) - lo; // exclusive
        let width = last - first;
        let mut mask = 0xffff_ffffu32;
        if width < 32 {
            mask = ((1u32 << width) - 1) << first;
        }
        let breaks = !flags[w as usize] & mask;
        if breaks != 0 {
            left = lo + (31 - breaks.leading_zeros()) + 1;
            break;
        }
    }
    // right: at the lowest break j in [k, b).
    let mut right = b;
    for w in 0..4u32 {
        let lo = w * 32;
        if lo + 32 <= k || lo >= b {
            continue;
        }
        let first = k.max(lo) - lo;
        let last = b.min(lo + 32) - lo;
        let width = last - first;
        let mut mask = 0xffff_ffffu32;
        if width < 32 {
            mask = ((1u32 << width) - 1) << first;
        }
        let breaks = !flags[w as usize] & mask;
        if breaks != 0 {
            right = lo + breaks.trailing_zeros();
            break;
        }
    }
    if left == k || right == k {
        return UVec2::new(k, k);
    }
    UVec2::new(left, right)
}

/// Normalised device xy of a position on the full-resolution target (pixels, y down);
/// mirror of `volfog::epipolar::epipolar_pixel_ndc`.
pub fn pixel_ndc(frame: &EpipolarFrame, position: Vec2) -> Vec2 {
    let uv = position / frame.screen_size;
    Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0)
}

/// View depth (m) of depth-buffer value `depth` at normalised device xy, at most
/// `frame.max_depth`; mirror of `volfog::epipolar::epipolar_view_depth`.
pub fn view_depth(frame: &EpipolarFrame, ndc: Vec2, depth: f32) -> f32 {
    view_from_ndc(ndc.extend(depth), frame.view_from_clip)
        .z
        .abs()
        .min(frame.max_depth)
}

/// View-space point at view depth 1 (m) on the ray through normalised device `ndc`;
/// mirror of `volfog::epipolar::epipolar_view_ray`.
pub fn view_ray(view_from_clip: Mat4, ndc: Vec2) -> Vec3 {
    let p = view_from_ndc(ndc.extend(0.5), view_from_clip);
    p / p.z.abs().max(1e-30)
}

/// Light-space texel position (xy, in `shadow_size` texels, v down) and light depth (z)
/// of a view-space point (m); mirror of `volfog::epipolar::epipolar_light_texel`.
pub fn light_texel(frame: &EpipolarFrame, view: Vec3) -> Vec3 {
    let clip = frame.light_from_view * view.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let uv = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    (uv * frame.shadow_size as f32).extend(ndc.z)
}

/// The 1D height map of `slice`: `(origin.xy, dir.xy)` in texels, origin the camera's
/// texel and dir the projection of the slice's rays, one texel long in its larger axis;
/// mirror of `volfog::epipolar::epipolar_slice_map`.
pub fn slice_map(frame: &EpipolarFrame, slice: u32) -> Vec4 {
    let s = (slice as f32 + 0.5) / frame.slices as f32;
    let ray = view_ray(frame.view_from_clip, exit_point(s));
    let o = light_texel(frame, Vec3::ZERO);
    let d = light_texel(frame, ray).xy() - o.xy();
    let m = d.x.abs().max(d.y.abs());
    let dir = if m > 1e-12 { d / m } else { Vec2::X };
    Vec4::new(o.x, o.y, dir.x, dir.y)
}

/// h(k): the shadow depth under entry `k` of a slice's height map `map`
/// ([`LIT_DEPTH`] off the map, side `shadow.size`); mirror of
/// `volfog::epipolar::epipolar_height`.
pub fn height(shadow: &ShadowLayer, map: Vec4, k: u32, bias: f32) -> f32 {
    let size = shadow.size;
    let q = (map.xy() + (k as f32 + 0.5) * map.zw()).floor();
    if q.cmplt(Vec2::ZERO).any() || q.cmpge(Vec2::splat(size as f32)).any() {
        return LIT_DEPTH;
    }
    shadow.load(q.x as u32, q.y as u32) + bias
}

/// The segment of the view ray through `ndc` from view depth `depth0` to `depth1` (m) on
/// a slice's height map `map`; mirror of `volfog::epipolar::epipolar_ray`.
pub fn ray(frame: &EpipolarFrame, map: Vec4, ndc: Vec2, depth0: f32, depth1: f32) -> EpipolarRay {
    let dir = view_ray(frame.view_from_clip, ndc);
    let p0 = dir * depth0;
    let p1 = dir * depth1.max(depth0);
    let l0 = light_texel(frame, p0);
    let l1 = light_texel(frame, p1);
    let dd = map.zw().dot(map.zw());
    EpipolarRay {
        origin: p0,
        segment: p1 - p0,
        start: (l0.xy() - map.xy()).dot(map.zw()) / dd,
        end: (l1.xy() - map.xy()).dot(map.zw()) / dd,
        light_start: l0.z,
        light_end: l1.z,
    }
}

/// Transmittance of the medium `fog` (view space) from the start of `ray` to the
/// fraction `t` of it; mirror of `volfog::epipolar::epipolar_transmittance`.
pub fn transmittance(fog: &HeightFog, ray: &EpipolarRay, t: f32) -> f32 {
    (-height_fog_optical_depth(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        ray.origin,
        ray.segment * t,
    ))
    .exp()
}

/// Fraction in [0, 1] of `ray` where its projection reaches height-map position `i`
/// (texels); mirror of `volfog::epipolar::epipolar_ray_fraction`.
pub fn ray_fraction(ray: &EpipolarRay, i: f32) -> f32 {
    ((i - ray.start) / (ray.end - ray.start)).clamp(0.0, 1.0)
}

/// Is the part `[ta, tb]` (fractions) of `ray` lit under the height value `h` (its light
/// depth at the middle not beyond `h`)? Mirror of `volfog::epipolar::epipolar_lit`.
pub fn lit(ray: &EpipolarRay, ta: f32, tb: f32, h: f32) -> bool {
    mix(ray.light_start, ray.light_end, 0.5 * (ta + tb)) <= h
}

/// Index of the first node of tree level `level` in a slice's row of `2 * size` nodes
/// (level 0 is h itself); mirror of `volfog::epipolar::epipolar_level_offset`.
pub fn level_offset(size: u32, level: u32) -> u32 {
    2 * size - ((2 * size) >> level)
}

/// Shaft term S (dimensionless) of `ray` visiting every section of the height map `map`
/// read from `shadow` (Yusov 2012, Algorithm 1); mirror of
/// `volfog::epipolar::epipolar_march_steps`.
pub fn march_steps(
    shadow: &ShadowLayer,
    map: Vec4,
    bias: f32,
    fog: &HeightFog,
    ray: &EpipolarRay,
    colors: Option<&ColorLayer>,
) -> Vec3 {
    let size = shadow.size;
    if ray.end - ray.start < 1.0 {
        let k = (0.5 * (ray.start + ray.end))
            .floor()
            .clamp(0.0, size as f32) as u32;
        let (h, c) = if k < size {
            (height(shadow, map, k, bias), color(colors, map, k))
        } else {
            (LIT_DEPTH, Vec3::ONE)
        };
        return if lit(ray, 0.0, 1.0, h) {
            c * (1.0 - transmittance(fog, ray, 1.0))
        } else {
            Vec3::ZERO
        };
    }
    let stop = ray_fraction(ray, size as f32);
    let mut k = ray.start.floor().max(0.0) as u32;
    let mut ta = 0.0f32;
    let mut t_at_a = 1.0f32;
    let mut sum = Vec3::ZERO;
    while ta < stop && k < size {
        let tb = ray_fraction(ray, (k + 1) as f32).min(stop);
        let t_at_b = transmittance(fog, ray, tb);
        if lit(ray, ta, tb, height(shadow, map, k, bias)) {
            sum += color(colors, map, k) * (t_at_a - t_at_b);
        }
        ta = tb;
        t_at_a = t_at_b;
        k += 1;
    }
    // Beyond the map everything is lit, in white.
    sum + Vec3::splat(t_at_a - transmittance(fog, ray, 1.0))
}

/// Shaft term S (per colour channel) of `ray` through row `slice` of the min/max
/// `tree` (Yusov 2012, Algorithm 2), the same sum as [`march_steps`]; with `colors`
/// (the slice's `map` locates their texels) lit nodes are descended too; mirror of
/// `volfog::epipolar::epipolar_march_tree`.
pub fn march_tree(
    tree: &MinMaxTree,
    slice: u32,
    fog: &HeightFog,
    ray: &EpipolarRay,
    colors: Option<(Vec4, &ColorLayer)>,
) -> Vec3 {
    let size = tree.size;
    let layer = colors.map(|(_, c)| c);
    let map = colors.map_or(Vec4::ZERO, |(m, _)| m);
    if ray.end - ray.start < 1.0 {
        let k = (0.5 * (ray.start + ray.end))
            .floor()
            .clamp(0.0, size as f32) as u32;
        let (h, c) = if k < size {
            (tree.node(slice, 0, k).x, color(layer, map, k))
        } else {
            (LIT_DEPTH, Vec3::ONE)
        };
        return if lit(ray, 0.0, 1.0, h) {
            c * (1.0 - transmittance(fog, ray, 1.0))
        } else {
            Vec3::ZERO
        };
    }
    let top = size.trailing_zeros();
    let stop = ray_fraction(ray, size as f32);
    let mut k = ray.start.floor().max(0.0) as u32;
    let mut level = 0u32;
    let mut ta = 0.0f32;
    // Consecutive lit nodes form one run [lit_from, ta], taken once when it closes.
    let mut lit_from = 0.0f32;
    let mut open = false;
    let mut sum = Vec3::ZERO;
    let mut guard = 0u32;
    while ta < stop && k < size && guard < 8 * size {
        guard += 1;
        // Step 5.1: one level coarser when k starts the parent node.
        if level < top && (k & ((2u32 << level) - 1)) == 0 {
            level += 1;
        }
        let mut is_lit = false;
        let mut tb;
        loop {
            let n = 1u32 << level;
            tb = ray_fraction(ray, (k + n) as f32).min(stop);
            let da = mix(ray.light_start, ray.light_end, ta);
            let db = mix(ray.light_start, ray.light_end, tb);
            let node = tree.node(slice, level, k >> level);
            if da.max(db) <= node.x && (layer.is_none() || level == 0) {
                is_lit = true;
                break;
            }
            if da.min(db) > node.y {
                break;
            }
            if level == 0 {
                is_lit = lit(ray, ta, tb, node.x);
                break;
            }
            level -= 1;
        }
        if layer.is_some() {
            if is_lit {
                sum += color(layer, map, k)
                    * (transmittance(fog, ray, ta) - transmittance(fog, ray, tb));
            }
        } else if is_lit && !open {
            lit_from = ta;
            open = true;
        } else if !is_lit && open {
            sum += Vec3::splat(transmittance(fog, ray, lit_from) - transmittance(fog, ray, ta));
            open = false;
        }
        ta = tb;
        k += 1u32 << level;
    }
    // Beyond the map everything is lit (in white): the remainder joins an open run.
    if !open {
        lit_from = ta;
    }
    sum + Vec3::splat(transmittance(fog, ray, lit_from) - transmittance(fog, ray, 1.0))
}

/// Lit fraction F (see [`lit_fraction`]) of the view ray through `ndc` between the view
/// depths `(depth0, depth1)` (m) by brute force in `steps` equal steps over `shadow`
/// (side `frame.shadow_size`), coloured by `colors` when given; mirror of
/// `volfog::epipolar::epipolar_march_pixel`.
pub fn march_pixel(
    (shadow, colors): (&ShadowLayer, Option<&ColorLayer>),
    frame: &EpipolarFrame,
    fog: &HeightFog,
    ndc: Vec2,
    (depth0, depth1): (f32, f32),
    steps: u32,
) -> Vec3 {
    let dir = view_ray(frame.view_from_clip, ndc);
    let ray = EpipolarRay {
        origin: dir * depth0,
        segment: dir * (depth1.max(depth0) - depth0),
        ..EpipolarRay::default()
    };
    let size = frame.shadow_size as f32;
    let n = steps.max(1);
    let mut t_at_a = 1.0f32;
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        let ta = i as f32 / n as f32;
        let tb = (i + 1) as f32 / n as f32;
        let l = light_texel(frame, ray.origin + ray.segment * (0.5 * (ta + tb)));
        let q = l.xy().floor();
        let mut h = LIT_DEPTH;
        let mut c = Vec3::ONE;
        if q.cmpge(Vec2::ZERO).all() && q.cmplt(Vec2::splat(size)).all() {
            h = shadow.load(q.x as u32, q.y as u32) + frame.depth_bias;
            if let Some(layer) = colors {
                c = layer.colors[(q.y as u32 * layer.size + q.x as u32) as usize];
            }
        }
        let t_at_b = transmittance(fog, &ray, tb);
        if l.z <= h {
            sum += c * (t_at_a - t_at_b);
        }
        t_at_a = t_at_b;
    }
    lit_fraction(fog, &ray, sum)
}

/// Interpolation sources packed in one u32 (first in the low 16 bits); mirror of
/// `volfog::epipolar::epipolar_pack_sources`.
pub fn pack_sources(sources: UVec2) -> u32 {
    (sources.x & 0xffff) | (sources.y << 16)
}

/// The two sources of a packed u32; mirror of `volfog::epipolar::epipolar_unpack_sources`.
pub fn unpack_sources(packed: u32) -> UVec2 {
    UVec2::new(packed & 0xffff, packed >> 16)
}

/// The lit fraction F = S / (1 - T(1)) of a ray's shaft term `s`, in [0, 1]; 1 when
/// the ray absorbs almost nothing; mirror of `volfog::epipolar::epipolar_lit_fraction`.
pub fn lit_fraction(fog: &HeightFog, ray: &EpipolarRay, s: Vec3) -> Vec3 {
    let absorbed = 1.0 - transmittance(fog, ray, 1.0);
    if absorbed <= 1e-6 {
        return Vec3::ONE;
    }
    (s / absorbed).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Phase term P (linear rgb radiance per unit S) for the unit view direction
/// `view_dir` (eye into the scene): the medium's sun lobe plus `frame.rayleigh` times
/// the Rayleigh phase; mirror of `volfog::epipolar::epipolar_phase`.
pub fn phase(frame: &EpipolarFrame, fog: &HeightFog, view_dir: Vec3) -> Vec3 {
    let c = view_dir.dot(fog.sun_direction).clamp(-1.0, 1.0);
    let g = fog.sun_g.clamp(-0.999, 0.999);
    let mut lobe = phase_hg(c, g);
    if frame.phase_model == 1 {
        lobe = phase_cornette_shanks(c, g);
    }
    fog.sun_color * lobe + frame.rayleigh * phase_rayleigh(c)
}

/// Fog `(in-scattered radiance rgb, transmittance)` from `frame.start_depth` to the
/// view-space point `view_pos` (m, at most `frame.max_depth`) with lit fraction `shafts` (per channel);
/// mirror of `volfog::epipolar::epipolar_fog`.
pub fn fog(frame: &EpipolarFrame, fog: &HeightFog, view_pos: Vec3, shafts: Vec3) -> Vec4 {
    let depth = view_pos.z.abs();
    let end = depth.min(frame.max_depth);
    if end <= frame.start_depth || depth <= 0.0 {
        return Vec4::new(0.0, 0.0, 0.0, 1.0);
    }
    let origin = view_pos * (frame.start_depth / depth);
    let segment = view_pos * (end / depth) - origin;
    let od = height_fog_optical_depth(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        origin,
        segment,
    );
    let view_dir = view_pos / view_pos.length();
    let radiance = fog.color + phase(frame, fog, view_dir) * shafts.clamp(Vec3::ZERO, Vec3::ONE);
    super::height_fog::fog_inscatter(radiance, od)
}

/// The interpolation sources of every sample of one slice (sample indices; equal for
/// ray-marching samples) from its view depths (m, `INVALID_DEPTH` off the screen), as
/// the `epipolar_refine` pass computes them (128-sample groups, packed flags).
pub fn refine_slice(frame: &EpipolarFrame, depths: &[f32]) -> Vec<UVec2> {
    let samples = frame.samples;
    assert_eq!(depths.len(), samples as usize, "one depth per sample");
    let depth = |k: u32| {
        if k < samples {
            depths[k as usize]
        } else {
            INVALID_DEPTH
        }
    };
    let mut out = Vec::with_capacity(depths.len());
    for group in 0..samples.div_ceil(GROUP) {
        let base = group * GROUP;
        let mut flags = [0u32; 4];
        for local in 0..GROUP {
            let k = base + local;
            if continuous(depth(k), depth(k + 1), frame.depth_threshold) {
                flags[(local / 32) as usize] |= 1u32 << (local % 32);
            }
        }
        for local in 0..GROUP.min(samples - base) {
            let k = base + local;
            let section = section(frame.initial_step, samples, k);
            let local_sources = sources(flags, local, section.x - base, section.y - base);
            out.push(local_sources + base);
        }
    }
    out
}

/// The same sources as [`refine_slice`] by the plain walk of Yusov 2012 (Algorithm 3):
/// from each sample left and right to a depth break or the section's end.
pub fn refine_slice_naive(frame: &EpipolarFrame, depths: &[f32]) -> Vec<UVec2> {
    let samples = frame.samples;
    assert_eq!(depths.len(), samples as usize, "one depth per sample");
    let joined = |i: u32| {
        continuous(
            depths[i as usize],
            depths[i as usize + 1],
            frame.depth_threshold,
        )
    };
    (0..samples)
        .map(|k| {
            let ends = section(frame.initial_step, samples, k);
            let (a, b) = (ends.x, ends.y);
            if k == a || k == b {
                return UVec2::new(k, k);
            }
            let mut left = k;
            while left > a && joined(left - 1) {
                left -= 1;
            }
            let mut right = k;
            while right < b && joined(right) {
                right += 1;
            }
            if left == k || right == k {
                UVec2::new(k, k)
            } else {
                UVec2::new(left, right)
            }
        })
        .collect()
}

/// The coordinate texture of `epipolar_coords` (`samples` x `slices`, a row per slice):
/// `(ndc.xy, view depth (m, at most max_depth), 1)` per sample, `(INVALID, INVALID,
/// INVALID_DEPTH, 0)` off the screen; `view_depth(ndc)` is the scene's view depth there.
pub fn coordinates(frame: &EpipolarFrame, view_depth: impl Fn(Vec2) -> f32) -> Vec<Vec4> {
    let mut out = Vec::with_capacity((frame.samples * frame.slices) as usize);
    for slice in 0..frame.slices {
        let line = line(frame, slice);
        for k in 0..frame.samples {
            let p = sample_position(line, frame.samples, k);
            out.push(if p.x != INVALID {
                Vec4::new(p.x, p.y, view_depth(p).abs().min(frame.max_depth), 1.0)
            } else {
                Vec4::new(INVALID, INVALID, INVALID_DEPTH, 0.0)
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::height_fog::height_fog;
    use crate::uniforms::{EpipolarSampling, EpipolarView};

    /// Distance between two slice coordinates on a circle of circumference `n`.
    fn circular(a: f64, b: f64, n: f64) -> f64 {
        let d = (a - b).rem_euclid(n);
        d.min(n - d)
    }

    /// Liang-Barsky: the parameters `[t0, t1]` of the part of the segment `p0 -> p1`
    /// inside the square [-1, 1]^2 (f64), `None` when it misses.
    fn clip_segment(p0: [f64; 2], p1: [f64; 2]) -> Option<(f64, f64)> {
        let d = [p1[0] - p0[0], p1[1] - p0[1]];
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for axis in 0..2 {
            for (p, q) in [(-d[axis], p0[axis] + 1.0), (d[axis], 1.0 - p0[axis])] {
                if p == 0.0 {
                    if q < 0.0 {
                        return None;
                    }
                } else {
                    let r = q / p;
                    if p < 0.0 {
                        t0 = t0.max(r);
                    } else {
                        t1 = t1.min(r);
                    }
                }
            }
        }
        (t0 <= t1).then_some((t0, t1))
    }

    fn f64x2(v: Vec2) -> [f64; 2] {
        [f64::from(v.x), f64::from(v.y)]
    }

    #[test]
    fn exit_point_and_border_coord_round_trip() {
        let corners = [
            (0.0, Vec2::new(-1.0, 1.0)),
            (0.25, Vec2::new(-1.0, -1.0)),
            (0.5, Vec2::new(1.0, -1.0)),
            (0.75, Vec2::new(1.0, 1.0)),
            (1.0, Vec2::new(-1.0, 1.0)),
        ];
        for (s, corner) in corners {
            assert_eq!(exit_point(s), corner, "s = {s}");
            // Both edges meeting at the corner give its coordinate.
            let edge = ((s * 4.0) as u32) % 4;
            for e in [edge, (edge + 3) % 4] {
                let back = f64::from(border_coord(corner, e));
                assert!(
                    circular(back, f64::from(s), 1.0) < 1e-7,
                    "corner {s} edge {e}: {back}"
                );
            }
        }
        // Counter-clockwise: the polygon through the exit points has area +4 (y up).
        let n = 64;
        let area: f64 = (0..n)
            .map(|i| {
                let a = f64x2(exit_point(i as f32 / n as f32));
                let b = f64x2(exit_point(((i + 1) % n) as f32 / n as f32));
                0.5 * (a[0] * b[1] - a[1] * b[0])
            })
            .sum();
        assert!((area - 4.0).abs() < 1e-9, "area {area}");
        let mut rng = Rng(1);
        let mut count = 0;
        for i in 0..100_000u32 {
            let s = if i < 4096 {
                i as f32 / 4096.0
            } else {
                rng.unit()
            };
            let p = exit_point(s);
            assert_eq!(p.x.abs().max(p.y.abs()), 1.0, "s = {s}: {p}");
            assert!(p.abs().max_element() <= 1.0);
            let edge = ((f64::from(s) * 4.0).floor() as u32).min(3);
            let back = border_coord(p, edge);
            assert!((0.0..1.0).contains(&back));
            let err = circular(f64::from(back), f64::from(s), 1.0);
            assert!(err < 1e-6, "s = {s}: edge {edge} gives {back}");
            count += 1;
        }
        assert_eq!(count, 100_000);
    }

    #[test]
    fn entry_point_is_the_clipped_line() {
        let mut rng = Rng(2);
        let mut exits: Vec<f32> = (0..256).map(|j| (j as f32 + 0.5) / 256.0).collect();
        exits.extend((0..256).map(|_| rng.unit()));
        // Epipoles on the screen: the entry is the epipole.
        for _ in 0..200 {
            let e = Vec2::new(rng.range(-0.999, 0.999), rng.range(-0.999, 0.999));
            for &s in &exits {
                let entry = entry_point(e, exit_point(s));
                assert!((entry - e).abs().max_element() < 1e-5, "{e} {s}: {entry}");
            }
        }
        // Epipoles off the screen, up to the limit of EpipolarFrame.
        let mut epipoles = Vec::new();
        for r in [1.001f32, 1.01, 1.5, 3.0, 10.0, 100.0, 1e4, 1e6] {
            for d in [
                Vec2::X,
                -Vec2::X,
                Vec2::Y,
                -Vec2::Y,
                Vec2::ONE,
                Vec2::new(1.0, -0.3),
            ] {
                epipoles.push(d * r);
            }
            for _ in 0..20 {
                let a = rng.range(0.0, std::f32::consts::TAU);
                let d = Vec2::new(a.cos(), a.sin());
                epipoles.push(d * (r / d.abs().max_element()));
            }
        }
        let (mut crossing, mut missing) = (0, 0);
        for &e in &epipoles {
            assert!(e.abs().max_element() > 1.0 + 1e-4);
            for &s in &exits {
                let exit = exit_point(s);
                let entry = entry_point(e, exit);
                let (l, x, n) = (f64x2(e), f64x2(exit), f64x2(entry));
                // On the border.
                let m = n[0].abs().max(n[1].abs());
                assert!((m - 1.0).abs() < 1e-4, "{e} {s}: {entry} off the border");
                // On the line from the epipole to the exit.
                let (ux, uy) = (x[0] - l[0], x[1] - l[1]);
                let len = ux.hypot(uy);
                let off = ((n[0] - l[0]) * uy - (n[1] - l[1]) * ux).abs() / len;
                assert!(off < 1e-5, "{e} {s}: {entry} is {off} off the line");
                // The nearer intersection, from an independent clip of the segment.
                let t0 = clip_segment(l, x).map_or(1.0, |(t0, _)| t0);
                let want = [l[0] + t0 * ux, l[1] + t0 * uy];
                let err = (n[0] - want[0]).abs().max((n[1] - want[1]).abs());
                assert!(err < 1e-4, "{e} {s}: {entry} against {want:?}");
                let (dn, dw) = ((n[0] - l[0]).hypot(n[1] - l[1]), t0 * len);
                assert!(
                    (dn - dw).abs() < 1e-4 * len.max(1.0),
                    "{e} {s}: {dn} vs {dw}"
                );
                if t0 > 1.0 - 1e-9 {
                    // The segment only touches the screen at its exit.
                    assert!(
                        (entry - exit).abs().max_element() < 1e-5,
                        "{e} {s}: {entry} {exit}"
                    );
                    missing += 1;
                } else {
                    crossing += 1;
                }
            }
        }
        assert!(crossing > 10_000 && missing > 1_000, "{crossing} {missing}");
    }

    #[test]
    fn pixel_slice_inverts_the_lines() {
        let mut rng = Rng(3);
        let mut epipoles = vec![
            Vec2::ZERO,
            Vec2::new(1.0, 0.3),
            Vec2::new(-0.2, -1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, 0.999),
        ];
        epipoles.extend((0..8).map(|_| Vec2::new(rng.range(-0.99, 0.99), rng.range(-0.99, 0.99))));
        for r in [1.2f32, 3.0, 10.0, 1e4, 1e6] {
            for _ in 0..4 {
                let a = rng.range(0.0, std::f32::consts::TAU);
                let d = Vec2::new(a.cos(), a.sin());
                epipoles.push(d * (r / d.abs().max_element()));
            }
        }
        let mut checked = 0;
        let (mut worst, mut grazing, mut lines) = (0.0f64, 0usize, 0usize);
        for slices in [64u32, 512] {
            for &e in &epipoles {
                let frame = EpipolarFrame {
                    light_screen: e,
                    slices,
                    ..EpipolarFrame::default()
                };
                for j in 0..slices {
                    let exit = exit_point((j as f32 + 0.5) / slices as f32);
                    let entry = entry_point(e, exit);
                    // Lines shorter than 0.05 or running along the border (an epipole
                    // on an edge) cover no pixel.
                    let mid = 0.5 * (entry + exit);
                    if (exit - entry).length() < 0.05 || mid.abs().max_element() > 1.0 - 1e-6 {
                        continue;
                    }
                    // A line meeting its exit edge at a grazing angle (sine `across`)
                    // moves its exit by (position error) / across: the tolerance of
                    // 1e-3 slices holds from ~3 degrees and grows as 1 / across below.
                    let dir = (exit - entry).normalize();
                    let edge = ((j as f32 + 0.5) / slices as f32 * 4.0) as u32;
                    let across = if edge.is_multiple_of(2) {
                        dir.x.abs()
                    } else {
                        dir.y.abs()
                    };
                    let tol = 1e-3 * (0.05 / f64::from(across)).max(1.0);
                    grazing += usize::from(tol > 1e-3);
                    lines += 1;
                    for t in [0.1f32, 0.3, 0.5, 0.7, 0.9, 0.99] {
                        let p = entry.lerp(exit, t);
                        if (p - e).length() < 0.05 {
                            continue;
                        }
                        let got = f64::from(pixel_slice(&frame, p));
                        assert!((0.0..slices as f64).contains(&got));
                        let err = circular(got, j as f64 + 0.5, slices as f64);
                        assert!(err < tol, "{e} slice {j} at {t}: {got} (tolerance {tol})");
                        if tol == 1e-3 {
                            worst = worst.max(err);
                        }
                        checked += 1;
                    }
                }
            }
        }
        eprintln!("{checked} points on {lines} lines ({grazing} grazing), worst {worst:e} slices");
        assert!(
            checked > 20_000 && grazing * 20 < lines,
            "{checked} {lines} {grazing}"
        );
    }

    /// A scene: a camera looking along -Z-ish at 5 m, an orthographic light of 200 m x
    /// 200 m x 400 m around a point 60 m ahead, and a 256 x 256 shadow map.
    struct Scene {
        frame: EpipolarFrame,
        view_from_world: Mat4,
        shadow: Vec<f32>,
    }

    impl Scene {
        fn new(sun: Vec3, rng: &mut Rng, boxes: u32) -> Self {
            let size = 256;
            let eye = Vec3::new(0.0, 5.0, 0.0);
            let forward = Vec3::new(0.2, -0.05, -1.0).normalize();
            let view_from_world = glam::camera::rh::view::look_to_mat4(eye, forward, Vec3::Y);
            let up = if sun.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
            let center = eye + forward * 60.0;
            let light_from_world =
                glam::camera::rh::proj::directx::orthographic(
                    -100.0, 100.0, -100.0, 100.0, 0.0, 400.0,
                ) * glam::camera::rh::view::look_to_mat4(center + sun * 200.0, -sun, up);
            let view = EpipolarView {
                view_from_world,
                clip_from_view: glam::camera::rh::proj::directx::perspective(
                    1.0,
                    16.0 / 9.0,
                    0.1,
                    500.0,
                ),
                light_from_world,
                cascade: 0,
                rayleigh: Vec3::ZERO,
                phase: Default::default(),
                start_depth: 0.0,
                max_depth: 1000.0,
                depth_bias: 0.0,
            };
            let sampling = EpipolarSampling::new(1280, 720, size);
            let frame = EpipolarFrame::new(&sampling, &view, sun).unwrap();
            let mut shadow = vec![1.0f32; (size * size) as usize];
            for _ in 0..boxes {
                let (w, h) = (rng.int(2, 60), rng.int(2, 60));
                let (x0, y0) = (rng.int(0, size - 1), rng.int(0, size - 1));
                let depth = rng.range(0.35, 0.65);
                for y in y0..(y0 + h).min(size) {
                    for x in x0..(x0 + w).min(size) {
                        let d = &mut shadow[(y * size + x) as usize];
                        *d = d.min(depth);
                    }
                }
            }
            Self {
                frame,
                view_from_world,
                shadow,
            }
        }

        fn layer(&self) -> ShadowLayer<'_> {
            ShadowLayer {
                size: self.frame.shadow_size,
                depths: &self.shadow,
            }
        }

        /// A random valid sample `(slice, ndc)` of the frame.
        fn sample(&self, rng: &mut Rng) -> (u32, Vec2) {
            loop {
                let j = rng.int(0, self.frame.slices - 1);
                let line = line(&self.frame, j);
                // One in eight at the entry (the epipole when it is on the screen, where
                // rays run along the sun and project to less than a texel).
                let k = if rng.unit() < 0.125 {
                    0
                } else {
                    rng.int(0, self.frame.samples - 1)
                };
                let p = sample_position(line, self.frame.samples, k);
                if p.x != INVALID {
                    return (j, p);
                }
            }
        }
    }

    fn suns() -> Vec<Vec3> {
        [
            Vec3::new(0.3, 0.8, -0.5),  // ahead, the epipole on or near the screen
            Vec3::new(-0.4, 0.5, 0.75), // behind the camera
            Vec3::new(0.9, 0.3, 0.1),   // to the side, the epipole far off the screen
            Vec3::new(0.05, 0.99, -0.1),
            Vec3::new(0.2, 0.25, -0.95), // low, straight ahead
        ]
        .map(Vec3::normalize)
        .to_vec()
    }

    /// Algorithm 1 in f64 for uniform fog of extinction `sigma` (1/m): the sum over the
    /// sections of the height map (lit when the light depth at the middle is not behind
    /// h) of T(a) - T(b), the part beyond the map lit.
    fn algorithm_1(shadow: &ShadowLayer, map: Vec4, ray: &EpipolarRay, sigma: f64) -> f64 {
        let size = f64::from(shadow.size);
        let length = ray.segment.as_dvec3().length();
        let t_at = |t: f64| (-sigma * length * t).exp();
        let (s0, s1) = (f64::from(ray.start), f64::from(ray.end));
        let (l0, l1) = (f64::from(ray.light_start), f64::from(ray.light_end));
        let depth_at = |t: f64| l0 + (l1 - l0) * t;
        let h = |k: f64| {
            let qx = (f64::from(map.x) + (k + 0.5) * f64::from(map.z)).floor();
            let qy = (f64::from(map.y) + (k + 0.5) * f64::from(map.w)).floor();
            if qx < 0.0 || qy < 0.0 || qx >= size || qy >= size {
                f64::from(LIT_DEPTH)
            } else {
                f64::from(shadow.load(qx as u32, qy as u32))
            }
        };
        if s1 - s0 < 1.0 {
            let k = (0.5 * (s0 + s1)).floor().clamp(0.0, size);
            return if depth_at(0.5) <= h(k) {
                1.0 - t_at(1.0)
            } else {
                0.0
            };
        }
        let fraction = |i: f64| ((i - s0) / (s1 - s0)).clamp(0.0, 1.0);
        let stop = fraction(size);
        let first = s0.floor().max(0.0);
        let mut sum = 0.0;
        let mut k = first;
        while k < size {
            let ta = if k == first { 0.0 } else { fraction(k) };
            let tb = fraction(k + 1.0).min(stop);
            if ta >= stop {
                break;
            }
            if depth_at(0.5 * (ta + tb)) <= h(k) {
                sum += t_at(ta) - t_at(tb);
            }
            k += 1.0;
        }
        sum + t_at(stop) - t_at(1.0)
    }

    #[test]
    fn tree_march_equals_steps_and_algorithm_1() {
        let mut rng = Rng(4);
        let sigma = 0.02f32;
        let (mut rays, mut lit_some, mut dark_some) = (0, 0, 0);
        // S is a sum of differences of f32 transmittances: its error is absolute
        // (a few 1e-8), so the relative tolerance applies to S >= FLOOR (2e-7 below).
        const FLOOR: f64 = 2e-2;
        let (mut worst_tree, mut worst_ref) = ((0.0f64, String::new()), (0.0f64, String::new()));
        let mut worst_abs = 0.0f64;
        let mut short = 0usize;
        for (i, sun) in suns().into_iter().enumerate() {
            for boxes in [0, 40, 400] {
                let scene = Scene::new(sun, &mut rng, boxes);
                let frame = &scene.frame;
                let shadow = scene.layer();
                let tree = MinMaxTree::build(frame, &shadow);
                let medium = HeightFog::new(Vec3::splat(0.5), sigma, Vec3::Y, 0.0, 0.0).unwrap();
                let fog = EpipolarFrame::medium(&medium, scene.view_from_world);
                for _ in 0..300 {
                    let (j, p) = scene.sample(&mut rng);
                    let depth0 = if rng.unit() < 0.5 {
                        0.0
                    } else {
                        rng.range(0.0, 30.0)
                    };
                    let depth1 = depth0 + rng.range(0.5, 150.0);
                    let map = slice_map(frame, j);
                    let r = ray(frame, map, p, depth0, depth1);
                    let by_tree = f64::from(march_tree(&tree, j, &fog, &r, None).x);
                    let by_steps =
                        f64::from(march_steps(&shadow, map, frame.depth_bias, &fog, &r, None).x);
                    let reference = algorithm_1(&shadow, map, &r, f64::from(sigma));
                    let full = 1.0 - (-f64::from(sigma) * r.segment.as_dvec3().length()).exp();
                    let scale = by_steps.abs().max(reference.abs()).max(FLOOR);
                    let e_tree = (by_tree - by_steps).abs() / scale;
                    let e_ref = (by_steps - reference).abs() / scale;
                    if e_tree > worst_tree.0 {
                        worst_tree = (
                            e_tree,
                            format!(
                                "sun {i} boxes {boxes}: tree {by_tree} steps {by_steps} ({r:?})"
                            ),
                        );
                    }
                    if e_ref > worst_ref.0 {
                        worst_ref = (
                            e_ref,
                            format!(
                                "sun {i} boxes {boxes}: steps {by_steps} f64 {reference} ({r:?})"
                            ),
                        );
                    }
                    worst_abs = worst_abs
                        .max((by_tree - reference).abs())
                        .max((by_steps - reference).abs());
                    assert!(by_tree >= -1e-6 && by_tree <= full + 1e-5);
                    rays += 1;
                    short += usize::from(r.end - r.start < 1.0);
                    if reference > 0.99 * full {
                        lit_some += 1;
                    } else {
                        dark_some += 1;
                    }
                }
            }
        }
        eprintln!(
            "{rays} rays ({lit_some} lit, {dark_some} shadowed, {short} under a texel): \
             tree {:e}, f64 {:e}, abs {worst_abs:e}",
            worst_tree.0, worst_ref.0
        );
        assert!(worst_tree.0 < 1e-5, "{}", worst_tree.1);
        assert!(worst_ref.0 < 1e-5, "{}", worst_ref.1);
        assert!(lit_some > 500 && dark_some > 500, "{lit_some} {dark_some}");
        assert!(short > 20, "{short}");
    }

    #[test]
    fn unshadowed_march_is_the_closed_form() {
        let mut rng = Rng(5);
        let mut checked = 0;
        for sun in suns() {
            let scene = Scene::new(sun, &mut rng, 0);
            let frame = &scene.frame;
            let shadow = scene.layer();
            let tree = MinMaxTree::build(frame, &shadow);
            // Uniform fog and a height fog (view space) against their closed forms.
            let uniform = HeightFog::new(Vec3::ONE, 0.02, Vec3::Y, 0.0, 0.0).unwrap();
            let layered = HeightFog::new(Vec3::ONE, 0.05, Vec3::Y, 0.08, 2.0).unwrap();
            for medium in [uniform, layered] {
                let fog = EpipolarFrame::medium(&medium, scene.view_from_world);
                for _ in 0..200 {
                    let (j, p) = scene.sample(&mut rng);
                    let depth0 = if rng.unit() < 0.5 {
                        0.0
                    } else {
                        rng.range(0.0, 20.0)
                    };
                    let depth1 = depth0 + rng.range(0.5, 140.0);
                    let map = slice_map(frame, j);
                    let r = ray(frame, map, p, depth0, depth1);
                    assert!(
                        r.light_start.max(r.light_end) < 1.0
                            && r.light_start.min(r.light_end) > 0.0
                    );
                    // Closed form in f64: b |d| exp(-c (h - h0)) (1 - exp(-x)) / x.
                    let dir = view_ray(frame.view_from_clip, p).as_dvec3();
                    let (z0, z1) = (f64::from(depth0), f64::from(depth1));
                    let (o, d) = (dir * z0, dir * (z1 - z0));
                    let up = fog.up.as_dvec3();
                    let (b, c) = (f64::from(fog.density), f64::from(fog.falloff));
                    let x = c * d.dot(up);
                    let mean = if x.abs() < 1e-9 {
                        1.0
                    } else {
                        -(-x).exp_m1() / x
                    };
                    let od = b
                        * d.length()
                        * (-c * (o.dot(up) - f64::from(fog.base_height))).exp()
                        * mean;
                    let want = -(-od).exp_m1();
                    let by_tree = f64::from(march_tree(&tree, j, &fog, &r, None).x);
                    let by_steps =
                        f64::from(march_steps(&shadow, map, frame.depth_bias, &fog, &r, None).x);
                    // march_pixel gives the lit fraction: 1 without shadows.
                    let by_pixel = want
                        * f64::from(
                            march_pixel((&shadow, None), frame, &fog, p, (depth0, depth1), 64).x,
                        );
                    for (name, got) in [("tree", by_tree), ("steps", by_steps), ("pixel", by_pixel)]
                    {
                        assert!(
                            (got - want).abs() < 1e-5 * want.max(1.0),
                            "{name}: {got} against {want} ({r:?})"
                        );
                    }
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 2000);
    }

    #[test]
    fn tree_nodes_bound_their_entries() {
        let mut rng = Rng(6);
        let scene = Scene::new(suns()[0], &mut rng, 200);
        let frame = &scene.frame;
        let tree = MinMaxTree::build(frame, &scene.layer());
        let size = frame.shadow_size;
        assert_eq!(tree.nodes.len(), (2 * size * frame.slices) as usize);
        assert_eq!(level_offset(size, size.trailing_zeros()), 2 * size - 2);
        for slice in [0, 1, 77, frame.slices - 1] {
            let map = slice_map(frame, slice);
            let h: Vec<f32> = (0..size)
                .map(|k| height(&scene.layer(), map, k, 0.0))
                .collect();
            for level in 0..=size.trailing_zeros() {
                for (index, part) in h.chunks(1 << level).enumerate() {
                    let lo = part.iter().copied().fold(f32::INFINITY, f32::min);
                    let hi = part.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                    assert_eq!(tree.node(slice, level, index as u32), Vec2::new(lo, hi));
                }
            }
        }
    }

    /// Depths of one slice: runs of smooth depth (steps of at most 1 %) separated by
    /// jumps, some invalid runs and single-sample spikes.
    fn random_depths(rng: &mut Rng, samples: u32) -> Vec<f32> {
        let mut depths = Vec::with_capacity(samples as usize);
        while depths.len() < samples as usize {
            let run = rng.int(1, 48);
            let invalid = rng.unit() < 0.1;
            let mut z = rng.range(1.0, 200.0);
            for _ in 0..run {
                if invalid {
                    depths.push(INVALID_DEPTH);
                } else if rng.unit() < 0.02 {
                    depths.push(z * 3.0);
                } else {
                    z *= 1.0 + rng.range(-0.01, 0.01);
                    depths.push(z);
                }
            }
        }
        depths.truncate(samples as usize);
        depths
    }

    #[test]
    fn refine_matches_the_plain_walk() {
        let mut rng = Rng(7);
        let mut interpolated = 0;
        for initial_step in [8u32, 16, 32, 64] {
            for samples in [128u32, 256, 384, 512] {
                let frame = EpipolarFrame {
                    samples,
                    initial_step,
                    depth_threshold: 0.03,
                    ..EpipolarFrame::default()
                };
                for _ in 0..25 {
                    let depths = random_depths(&mut rng, samples);
                    let fast = refine_slice(&frame, &depths);
                    let naive = refine_slice_naive(&frame, &depths);
                    assert_eq!(
                        fast, naive,
                        "step {initial_step}, {samples} samples: {depths:?}"
                    );
                    let joined =
                        |i: u32| continuous(depths[i as usize], depths[i as usize + 1], 0.03);
                    for (k, src) in (0..samples).zip(&fast) {
                        let (l, r) = (src.x, src.y);
                        assert!(l <= k && k <= r, "{k}: {src}");
                        let ends = section(initial_step, samples, k);
                        assert!(ends.x <= l && r <= ends.y, "{k}: {src} outside {ends}");
                        if l == r {
                            assert_eq!(l, k);
                            continue;
                        }
                        // Interpolated between two ray-marching samples, no break between.
                        assert!((l..r).all(joined), "{k}: {src} straddles a break");
                        assert_eq!(fast[l as usize], UVec2::splat(l));
                        assert_eq!(fast[r as usize], UVec2::splat(r));
                        interpolated += 1;
                    }
                    // Section ends and both sides of every break are marched.
                    for i in 0..samples - 1 {
                        if !joined(i) {
                            assert_eq!(fast[i as usize], UVec2::splat(i));
                            assert_eq!(fast[i as usize + 1], UVec2::splat(i + 1));
                        }
                    }
                    assert_eq!(fast[samples as usize - 1], UVec2::splat(samples - 1));
                }
            }
        }
        assert!(interpolated > 50_000, "{interpolated}");
    }

    #[test]
    fn coordinates_follow_the_lines() {
        let mut rng = Rng(8);
        for sun in suns() {
            let scene = Scene::new(sun, &mut rng, 0);
            let frame = &scene.frame;
            let coords = coordinates(frame, |p| {
                10.0 + 5.0 * p.x + 1e4 * (p.y > 0.9) as u32 as f32
            });
            assert_eq!(coords.len(), (frame.samples * frame.slices) as usize);
            let (n, samples) = (frame.samples as usize, frame.samples);
            let mut valid = 0;
            for (j, row) in coords.chunks(n).enumerate() {
                let l = line(frame, j as u32);
                let pixels = ((l.zw() - l.xy()) * frame.screen_size * 0.5).length();
                assert!(
                    l.x == INVALID || pixels >= samples as f32 * (1.0 - 1e-5),
                    "{j}: {pixels}"
                );
                for (k, c) in row.iter().enumerate() {
                    if c.w == 0.0 {
                        assert_eq!(*c, Vec4::new(INVALID, INVALID, INVALID_DEPTH, 0.0));
                        continue;
                    }
                    valid += 1;
                    assert_eq!(c.w, 1.0);
                    assert!(c.x.abs().max(c.y.abs()) <= 1.0 + BORDER);
                    let want = if c.y > 0.9 {
                        frame.max_depth
                    } else {
                        10.0 + 5.0 * c.x
                    };
                    assert!((c.z - want).abs() < 1e-4, "{c}");
                    assert!((line_position(l, samples, c.xy()) - k as f32).abs() < 1e-2);
                    if k == 0 {
                        assert_eq!(c.xy(), l.xy());
                    }
                    if k > 0 && row[k - 1].w == 1.0 {
                        // At most a pixel apart (lines shorter than `samples` pixels
                        // are stretched to it, longer ones sampled sparser).
                        let step = ((c.xy() - row[k - 1].xy()) * frame.screen_size * 0.5).length();
                        assert!(step >= 1.0 - 1e-3, "{j} {k}: {step}");
                    }
                }
            }
            assert!(valid > 10_000, "{valid}");
        }
    }

    #[test]
    fn fog_without_shadows_is_the_height_fog() {
        let mut rng = Rng(9);
        let fog = HeightFog::new(Vec3::new(0.3, 0.4, 0.5), 0.03, Vec3::Y, 0.05, -1.0)
            .unwrap()
            .with_sun(
                Vec3::new(0.3, 0.8, -0.5).normalize(),
                Vec3::new(2.0, 1.8, 1.5),
                0.6,
            )
            .unwrap();
        let frame = EpipolarFrame {
            max_depth: 1e4,
            ..EpipolarFrame::default()
        };
        for phase_model in [0u32, 1] {
            let frame = EpipolarFrame {
                phase_model,
                ..frame
            };
            for _ in 0..500 {
                let view_pos = Vec3::new(
                    rng.range(-50.0, 50.0),
                    rng.range(-20.0, 20.0),
                    -rng.range(0.5, 300.0),
                );
                let t = (-height_fog_optical_depth(
                    fog.density,
                    fog.falloff,
                    fog.base_height,
                    fog.up,
                    Vec3::ZERO,
                    view_pos,
                ))
                .exp();
                let got = super::fog(&frame, &fog, view_pos, Vec3::ONE);
                assert!((got.w - t).abs() <= 1e-6 * t.max(1e-6), "{} {t}", got.w);
                if phase_model == 0 {
                    let want = height_fog(&fog, Vec3::ZERO, view_pos);
                    assert!((got - want).abs().max_element() < 1e-5, "{got} {want}");
                } else {
                    let c = (view_pos.normalize().dot(fog.sun_direction)) as f64;
                    assert!(phase(&frame, &fog, view_pos.normalize()).x > 0.0 && c.abs() <= 1.0);
                }
                // Shadowed everywhere: only the constant colour.
                let dark = super::fog(&frame, &fog, view_pos, Vec3::ZERO);
                assert!(
                    (dark.truncate() - fog.color * (1.0 - t))
                        .abs()
                        .max_element()
                        < 1e-5 * fog.color.max_element().max(1e-3)
                );
            }
        }
        // Before the start of the march: nothing.
        let near = EpipolarFrame {
            start_depth: 10.0,
            ..frame
        };
        assert_eq!(
            super::fog(&near, &fog, Vec3::new(0.0, 0.0, -5.0), Vec3::splat(0.5)),
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        );
    }
}

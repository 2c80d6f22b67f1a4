//! The closed room of the light-shadow test and the measures of its fog: per froxel the
//! light's in-scattering with shadows over the same without (the light's shadows off),
//! against the ESM leak bound behind the walls, and the unshadowed fog against the CPU
//! mirror (`volfog::cpu::lights::fog_light_inscatter` times sigma_s).

use std::fmt;

use volfog::cpu::local_shadow::local_shadow_cube;
use volfog::glam::{UVec3, Vec3, Vec4};
use volfog::uniforms::{CUBE_FACE_AXES, FogLight};
use volfog_bevy::ExtractedFroxelFog;

/// Inside of the room (m) and its wall thickness.
pub const ROOM_MIN: Vec3 = Vec3::new(-2.0, 0.0, -10.0);
pub const ROOM_MAX: Vec3 = Vec3::new(2.0, 3.0, -6.0);
pub const WALL: f32 = 0.2;

/// Froxels darker than this (the unshadowed in-scattering's largest channel) are not
/// measured.
const LIT: f32 = 1e-3;
/// Froxels this far (m) from the walls count as inside.
const MARGIN: f32 = 0.3;

/// The six walls, floor and ceiling of the room, closed: (min, max) of each box.
pub fn walls(min: Vec3, max: Vec3, wall: f32) -> Vec<(Vec3, Vec3)> {
    let (lo, hi) = (min - Vec3::splat(wall), max + Vec3::splat(wall));
    (0..3)
        .flat_map(|axis| {
            let mut a_max = hi;
            a_max[axis] = min[axis];
            let mut b_min = lo;
            b_min[axis] = max[axis];
            [(lo, a_max), (b_min, hi)]
        })
        .collect()
}

fn inside_room(p: Vec3) -> bool {
    p.cmpgt(ROOM_MIN).all() && p.cmplt(ROOM_MAX).all()
}

fn margin(p: Vec3) -> f32 {
    (p - ROOM_MIN).min(ROOM_MAX - p).min_element()
}

/// Where the ray from `origin` (inside the room) along `dir` leaves the room's inside.
fn exit(origin: Vec3, dir: Vec3) -> f32 {
    (0..3)
        .filter(|&i| dir[i] != 0.0)
        .map(|i| {
            let bound = if dir[i] > 0.0 {
                ROOM_MAX[i]
            } else {
                ROOM_MIN[i]
            };
            (bound - origin[i]) / dir[i]
        })
        .fold(f32::INFINITY, f32::min)
}

/// Bevy's cube space of a point light: `(p - light) * (1, 1, -1)`.
fn flip_z(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

/// The largest depth (along the face's axis) of the room's walls in the texels of a
/// point light's cube face within `reach` texels of uv (clamped to the face), as a map
/// of `size` texels renders them.
fn footprint_depth(lamp: Vec3, face: u32, uv: volfog::glam::Vec2, reach: i32, size: u32) -> f32 {
    let [right, up, forward] = CUBE_FACE_AXES[face as usize];
    let (cx, cy) = ((uv.x * size as f32) as i32, (uv.y * size as f32) as i32);
    let last = size as i32 - 1;
    let mut far = 0.0f32;
    for y in (cy - reach).max(0)..=(cy + reach).min(last) {
        for x in (cx - reach).max(0)..=(cx + reach).min(last) {
            let nx = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
            let ny = 1.0 - 2.0 * (y as f32 + 0.5) / size as f32;
            // Unit depth along the face's axis per unit of t.
            let dir = flip_z(forward + right * nx + up * ny);
            far = far.max(exit(lamp, dir));
        }
    }
    far
}

/// The froxels of a fog frame and what they are compared with.
pub struct Measure {
    fog: ExtractedFroxelFog,
    positions: Vec<Vec3>,
    sigma_s: f32,
}

/// The fog of a shadowed light in and around the room.
pub struct Leak {
    what: &'static str,
    band: f32,
    /// Froxels outside, beyond the band, and their largest fraction of the light.
    outside: usize,
    worst_outside: f32,
    in_band: usize,
    /// The light all the fog outside gets, over what it gets unshadowed.
    leaked: f64,
    /// Froxels inside (`MARGIN` from the walls) and their least fraction of the light.
    inside: usize,
    worst_inside: f32,
}

/// The unshadowed fog outside the room against the CPU mirror: froxels, the median
/// and 5th percentile of GPU / CPU.
pub struct AgainstCpu {
    pub count: usize,
    pub median: f32,
    pub low: f32,
}

impl Measure {
    /// The froxel centres (no jitter) of a frame's fog in homogeneous fog of
    /// extinction `density` and albedo 1.
    pub fn new(fog: &ExtractedFroxelFog, density: f32) -> Self {
        let c = &fog.config;
        let size = c.volume_size;
        let froxels =
            volfog::uniforms::Froxels::new(fog.clip_from_view, size, c.near, c.far, c.slice_curve)
                .expect("valid froxels");
        let world_from_view = fog.view_from_world.inverse();
        let mut positions = Vec::with_capacity((size.x * size.y * size.z) as usize);
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    let view = volfog::cpu::froxel::froxel_view_position(
                        UVec3::new(x, y, z),
                        Vec3::ZERO,
                        size,
                        froxels.view_from_clip,
                        c.near,
                        c.far,
                        c.slice_curve,
                    );
                    positions.push(world_from_view.transform_point3(view));
                }
            }
        }
        Self {
            fog: fog.clone(),
            positions,
            sigma_s: density,
        }
    }

    fn exponent(&self) -> f32 {
        self.fog
            .config
            .local_shadows
            .expect("local shadows")
            .exponent
    }

    /// Froxels lit unshadowed: (position, shadowed light, unshadowed light).
    fn lit<'a>(
        &'a self,
        on: &'a [Vec4],
        off: &'a [Vec4],
    ) -> impl Iterator<Item = (Vec3, f32, f32)> + 'a {
        self.positions
            .iter()
            .zip(on.iter().zip(off))
            .map(|(p, (g, u))| {
                assert!(g.is_finite() && u.is_finite(), "a non-finite froxel");
                (*p, g.truncate().max_element(), u.truncate().max_element())
            })
            .filter(|(_, _, u)| *u > LIT)
    }

    /// The point lamp in the room: outside, the fog beyond the band behind the farthest
    /// wall depth within the atlas texel's footprint (the blur radius and the bilinear
    /// look-up in atlas texels, times Bevy's map over the atlas, plus a texel for
    /// Bevy's rasterisation), against the ESM bound.
    pub fn point_lamp(
        &self,
        on: &[Vec4],
        off: &[Vec4],
        lamp: Vec3,
        range: f32,
        bias: f32,
        map: u32,
    ) -> Leak {
        let local = self.fog.config.local_shadows.expect("local shadows");
        let reach = ((self.fog.config.esm_blur_radius + 1) * (map / local.resolution) + 1) as i32;
        let mut leak = Leak::new("point lamp", bias + 3.0 * range / self.exponent());
        let (mut leaked, mut open) = (0.0f64, 0.0f64);
        for (p, g, u) in self.lit(on, off) {
            let visibility = g / u;
            if inside_room(p) {
                leak.inner(p, visibility);
                continue;
            }
            let c = local_shadow_cube(flip_z(p - lamp));
            let behind = c.depth - footprint_depth(lamp, c.face, c.uv, reach, map);
            leaked += f64::from(g);
            open += f64::from(u);
            leak.outer(behind, visibility);
        }
        leak.leaked = leaked / open;
        leak
    }

    /// The spot light in the room, pointing along +X at the wall x = `ROOM_MAX.x`,
    /// which fills its shadow camera: outside, the fog beyond the band behind that wall.
    pub fn spot_wall(&self, on: &[Vec4], off: &[Vec4], spot: Vec3, range: f32, bias: f32) -> Leak {
        let wall = ROOM_MAX.x - spot.x;
        let mut leak = Leak::new("spot light", bias + 3.0 * range / self.exponent());
        let (mut leaked, mut open) = (0.0f64, 0.0f64);
        for (p, g, u) in self.lit(on, off) {
            let visibility = g / u;
            if inside_room(p) {
                leak.inner(p, visibility);
            } else if p.x > ROOM_MAX.x {
                leaked += f64::from(g);
                open += f64::from(u);
                leak.outer(p.x - spot.x - wall, visibility);
            }
        }
        leak.leaked = leaked / open;
        leak
    }

    /// The fog outside the room's walls against the CPU mirror's unshadowed
    /// in-scattering of the light at `position` among a frame's `lights`, through the
    /// medium between the froxel and the light when the fog attenuates it
    /// (`FroxelFog::light_transmittance`).
    pub fn against_cpu(&self, texels: &[Vec4], lights: &[FogLight], position: Vec3) -> AgainstCpu {
        let light = lights
            .iter()
            .find(|l| (l.position - position).length() < 1e-4)
            .expect("the light in the fog");
        let (lo, hi) = (ROOM_MIN - Vec3::splat(WALL), ROOM_MAX + Vec3::splat(WALL));
        let mut ratios: Vec<f32> = self
            .positions
            .iter()
            .zip(texels)
            .filter(|(p, _)| !(p.cmpgt(lo).all() && p.cmplt(hi).all()))
            .filter_map(|(p, t)| {
                let through = if self.fog.config.light_transmittance {
                    volfog::cpu::density::medium_segment_transmittance(
                        &self.fog.medium,
                        *p,
                        light.position,
                    )
                } else {
                    1.0
                };
                let cpu = self.sigma_s
                    * through
                    * volfog::cpu::lights::fog_light_inscatter(light, *p, Vec3::Y, 0.0)
                        .max_element();
                (cpu > LIT).then(|| t.truncate().max_element() / cpu)
            })
            .collect();
        ratios.sort_by(f32::total_cmp);
        let n = ratios.len();
        AgainstCpu {
            count: n,
            median: ratios.get(n / 2).copied().unwrap_or(0.0),
            low: ratios.get(n / 20).copied().unwrap_or(0.0),
        }
    }
}

impl Leak {
    fn new(what: &'static str, band: f32) -> Self {
        Self {
            what,
            band,
            outside: 0,
            worst_outside: 0.0,
            in_band: 0,
            leaked: 0.0,
            inside: 0,
            worst_inside: 1.0,
        }
    }

    fn inner(&mut self, p: Vec3, visibility: f32) {
        if margin(p) > MARGIN {
            self.inside += 1;
            self.worst_inside = self.worst_inside.min(visibility);
        }
    }

    fn outer(&mut self, behind: f32, visibility: f32) {
        if behind >= self.band {
            self.outside += 1;
            self.worst_outside = self.worst_outside.max(visibility);
        } else {
            self.in_band += 1;
        }
    }

    /// Beyond the band outside: at most 5 % of the light; all the fog outside: under 5 %
    /// of its unshadowed light; inside: at least 95 %.
    pub fn assert_bounds(&self, outside: usize, inside: usize) {
        assert!(self.outside > outside && self.inside > inside, "{self}");
        assert!(self.worst_outside <= 0.05, "{self}");
        assert!(self.leaked < 0.05, "{self}");
        assert!(self.worst_inside >= 0.95, "{self}");
    }
}

impl fmt::Display for Leak {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} in a closed room with Bevy's shadow maps (leak band bias + 3 range / c = {:.3} m): \
             {} froxels outside, beyond the band behind the farthest wall depth within the blur footprint, \
             get at most {:.2} % of its light (bound 5 %), {} within the band; all the fog outside gets \
             {:.3} % of the light it gets unshadowed (bound 5 %); {} froxels inside ({MARGIN} m from the walls) \
             get at least {:.2} % (bound 95 %)",
            self.what,
            self.band,
            self.outside,
            100.0 * self.worst_outside,
            self.in_band,
            100.0 * self.leaked,
            self.inside,
            100.0 * self.worst_inside
        )
    }
}

impl fmt::Display for AgainstCpu {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} froxels, GPU / CPU median {:.4}, 5th percentile {:.4}",
            self.count, self.median, self.low
        )
    }
}

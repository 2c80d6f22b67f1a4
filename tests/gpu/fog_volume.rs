//! Analytic box and ellipsoid fog volumes (`volfog::fog_volume`, Wenzel 2007 "Fog
//! Volumes") on the GPU: ray entry/exit and fog against the CPU mirror and against an
//! independent f64 reference (the inside/outside boundary found by bisection of the
//! shape's distance function along the segment, the density integrated by Simpson's
//! rule), with the camera inside or outside and the segment clipped by the scene
//! depth; back-to-front compositing of several volumes; finiteness for adversarial
//! inputs.

use crate::common;

use common::Rng;

use common::{gpu, run_f32};
use glam::{Mat4, Vec2, Vec3, Vec4};
use volfog::cpu::fog_volume::*;
use volfog::uniforms::{FogVolume, VolumeShape};

/// Outputs per case: entry/exit (2), optical depth, fog rgba (4), ray_unit_box of the
/// raw local ray (2), ray_unit_sphere (2), padding.
const OUTPUTS: usize = 12;

const KERNEL: &str = r#"
#import volfog::types::FogVolume
#import volfog::fog_volume::{fog_volume, fog_volume_entry_exit, fog_volume_optical_depth,
    ray_unit_box, ray_unit_sphere}

struct Case { volume: FogVolume, eye: vec4<f32>, point: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let o = i * 12u;
    let t = fog_volume_entry_exit(c.volume, c.eye.xyz, c.point.xyz);
    output[o + 0u] = t.x;
    output[o + 1u] = t.y;
    output[o + 2u] = fog_volume_optical_depth(c.volume, c.eye.xyz, c.point.xyz);
    let f = fog_volume(c.volume, c.eye.xyz, c.point.xyz);
    output[o + 3u] = f.x;
    output[o + 4u] = f.y;
    output[o + 5u] = f.z;
    output[o + 6u] = f.w;
    // The raw intersections with the eye and point read as a local-space ray.
    let b = ray_unit_box(c.eye.xyz, c.point.xyz);
    let s = ray_unit_sphere(c.eye.xyz, c.point.xyz);
    output[o + 7u] = b.x;
    output[o + 8u] = b.y;
    output[o + 9u] = s.x;
    output[o + 10u] = s.y;
    output[o + 11u] = 0.0;
}
"#;

const COMPOSITE_KERNEL: &str = r#"
#import volfog::types::FogVolume
#import volfog::fog_volume::{fog_volume, fog_over, FOG_NONE}

struct Ray { volumes: array<FogVolume, 4>, eye: vec4<f32>, point: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Ray>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let r = input[i];
    // Volumes arrive sorted farthest first.
    var acc = FOG_NONE;
    for (var k = 0u; k < 4u; k++) {
        acc = fog_over(fog_volume(r.volumes[k], r.eye.xyz, r.point.xyz), acc);
    }
    output[i] = acc;
}
"#;

#[derive(Clone, Copy, Debug)]
struct Case {
    volume: FogVolume,
    eye: Vec3,
    point: Vec3,
}

fn volume_floats(v: &FogVolume) -> Vec<f32> {
    let bytes = v.to_bytes();
    assert_eq!(bytes.len(), 128, "FogVolume is 128 bytes");
    bytemuck::cast_slice(&bytes).to_vec()
}

impl Case {
    fn cpu(&self) -> [f32; OUTPUTS] {
        let t = fog_volume_entry_exit(&self.volume, self.eye, self.point);
        let f = fog_volume(&self.volume, self.eye, self.point);
        let b = ray_unit_box(self.eye, self.point);
        let s = ray_unit_sphere(self.eye, self.point);
        [
            t.x,
            t.y,
            fog_volume_optical_depth(&self.volume, self.eye, self.point),
            f.x,
            f.y,
            f.z,
            f.w,
            b.x,
            b.y,
            s.x,
            s.y,
            0.0,
        ]
    }
}

fn run_gpu(cases: &[Case]) -> Vec<[f32; OUTPUTS]> {
    let gpu = gpu();
    let mut input = Vec::new();
    for c in cases {
        input.extend(volume_floats(&c.volume));
        input.extend(c.eye.extend(0.0).to_array());
        input.extend(c.point.extend(0.0).to_array());
    }
    let out = run_f32(
        gpu,
        KERNEL,
        &input,
        cases.len() * OUTPUTS,
        cases.len() as u32,
    );
    out.chunks_exact(OUTPUTS)
        .map(|c| c.try_into().unwrap())
        .collect()
}

/// A general affine volume: translation * rotation * scale * rotation (any shear).
fn random_volume(rng: &mut Rng, shape: VolumeShape, center_range: f32) -> (FogVolume, Mat4) {
    let scale = Vec3::new(rng.log(0.5, 20.0), rng.log(0.5, 20.0), rng.log(0.5, 20.0));
    let world_from_local = Mat4::from_translation(rng.vec(center_range))
        * Mat4::from_quat(rng.quat())
        * Mat4::from_scale(scale)
        * Mat4::from_quat(rng.quat());
    let volume = FogVolume::new(
        world_from_local,
        shape,
        Vec3::new(rng.f(), rng.f(), rng.f()) * 3.0,
        rng.log(1e-3, 1.0),
    )
    .unwrap()
    .with_gradient(rng.unit(), rng.range(-0.2, 0.2), rng.range(-10.0, 10.0))
    .unwrap();
    (volume, world_from_local)
}

/// A local point inside the shape (within 0.9 of its extent).
fn inside(rng: &mut Rng, shape: VolumeShape) -> Vec3 {
    match shape {
        VolumeShape::Box => rng.vec(0.9),
        VolumeShape::Ellipsoid => rng.unit() * 0.9 * rng.f().cbrt(),
    }
}

// ---- f64 reference -------------------------------------------------------------------

type M64 = [[f64; 4]; 4];

fn m64(m: &Mat4) -> M64 {
    m.to_cols_array_2d().map(|c| c.map(|v| v as f64))
}

fn xform(m: &M64, p: [f64; 3], w: f64) -> [f64; 3] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r] * w)
}

fn v64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Distance-like function of the shape in local space: <= 0 inside.
fn phi(shape: u32, p: [f64; 3]) -> f64 {
    if shape == FOG_VOLUME_ELLIPSOID {
        norm(p) - 1.0
    } else {
        p[0].abs().max(p[1].abs()).max(p[2].abs()) - 1.0
    }
}

/// Magnitude of the terms summed into the local-space ray origin and direction: f32
/// rounding of the transform is a few ulp of this (local units).
fn local_magnitude(v: &FogVolume, eye: Vec3, point: Vec3) -> f64 {
    let m = m64(&v.local_from_world);
    let abs_m: M64 = m.map(|c| c.map(f64::abs));
    let e = v64(eye).map(f64::abs);
    let d = [0, 1, 2].map(|i| (point[i] as f64 - eye[i] as f64).abs());
    norm(xform(&abs_m, e, 1.0)) + norm(xform(&abs_m, d, 0.0))
}

struct Reference {
    /// Clipped interval [t0, t1] (t0 == t1 when empty).
    t: (f64, f64),
    /// The line passes within 1e-4 (local units) of tangency, or meets the surface at
    /// a cosine below 1e-3: its chord is ill-posed.
    grazing: bool,
    /// Length of the segment in local units.
    local_len: f64,
    /// Conditioning of t0 and t1: 1 / |cos| of the angle between the line and the
    /// surface normal where it enters / leaves (1 where the end is the camera or the
    /// point). A distance error e to the surface moves the end by e * amp along the line.
    amp: (f64, f64),
}

/// 1 / |cos| between the line direction and the shape's normal at local point p (the
/// worst face for a box point near an edge or corner).
fn incidence(shape: u32, p: [f64; 3], rd: [f64; 3]) -> f64 {
    let len = norm(rd);
    if shape == FOG_VOLUME_ELLIPSOID {
        let n = norm(p);
        len * n / (p[0] * rd[0] + p[1] * rd[1] + p[2] * rd[2]).abs()
    } else {
        let m = p[0].abs().max(p[1].abs()).max(p[2].abs());
        (0..3)
            .filter(|&k| p[k].abs() >= m - 1e-3)
            .map(|k| len / rd[k].abs())
            .fold(1.0, f64::max)
    }
}

/// Entry and exit by minimising the convex phi along the line (ternary search) and
/// bisecting phi = 0 on both sides of the minimum, all in f64.
fn reference(v: &FogVolume, eye: Vec3, point: Vec3) -> Reference {
    let m = m64(&v.local_from_world);
    let e = v64(eye);
    let seg = [0, 1, 2].map(|i| point[i] as f64 - e[i]);
    let ro = xform(&m, e, 1.0);
    let rd = xform(&m, seg, 0.0);
    let local_len = norm(rd);
    let empty = |grazing| Reference {
        t: (0.0, 0.0),
        grazing,
        local_len,
        amp: (1.0, 1.0),
    };
    if local_len == 0.0 {
        return empty(false);
    }
    let at = |t: f64| [0, 1, 2].map(|i| ro[i] + t * rd[i]);
    let f = |t: f64| phi(v.shape, at(t));
    let reach = (norm(ro) + 2.0) / local_len;
    let (mut lo, mut hi) = (-reach, reach);
    for _ in 0..400 {
        let a = lo + (hi - lo) / 3.0;
        let b = hi - (hi - lo) / 3.0;
        if f(a) <= f(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let tm = 0.5 * (lo + hi);
    let fm = f(tm);
    if fm > 0.0 {
        return empty(fm < 1e-4);
    }
    let bisect = |mut outside: f64, mut inside: f64| {
        for _ in 0..200 {
            let mid = 0.5 * (outside + inside);
            if f(mid) > 0.0 {
                outside = mid;
            } else {
                inside = mid;
            }
        }
        0.5 * (outside + inside)
    };
    let ta = bisect(-reach, tm);
    let tb = bisect(reach, tm);
    let t0 = ta.clamp(0.0, 1.0);
    let t1 = tb.clamp(t0, 1.0);
    if t1 <= t0 {
        return empty(fm > -1e-4);
    }
    let amp0 = if ta > 0.0 {
        incidence(v.shape, at(ta), rd)
    } else {
        1.0
    };
    let amp1 = if tb < 1.0 {
        incidence(v.shape, at(tb), rd)
    } else {
        1.0
    };
    Reference {
        t: (t0, t1),
        grazing: fm > -1e-4 || amp0.max(amp1) > 1e3,
        local_len,
        amp: (amp0, amp1),
    }
}

/// Extinction of a volume at a world point (f64), ignoring its shape.
fn density64(v: &FogVolume, p: [f64; 3]) -> f64 {
    let c = v64(v.center);
    let g = v64(v.gradient);
    let h = (0..3).map(|i| (p[i] - c[i]) * g[i]).sum::<f64>();
    v.density as f64 * (-(v.falloff as f64) * (h - v.offset as f64)).exp()
}

/// Optical depth over [t0, t1] of the segment by Simpson's rule (2048 intervals).
fn reference_od(v: &FogVolume, eye: Vec3, point: Vec3, t: (f64, f64)) -> f64 {
    let e = v64(eye);
    let seg = [0, 1, 2].map(|i| point[i] as f64 - e[i]);
    let len = norm(seg);
    if t.1 <= t.0 {
        return 0.0;
    }
    let n = 2048;
    let h = (t.1 - t.0) / n as f64;
    let at = |s: f64| density64(v, [0, 1, 2].map(|i| e[i] + s * seg[i]));
    let mut sum = at(t.0) + at(t.1);
    for i in 1..n {
        sum += at(t.0 + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0 * len
}

// ---- cases ---------------------------------------------------------------------------

fn cases() -> Vec<(&'static str, Case)> {
    let mut rng = Rng(0xf09_b0c5);
    let mut out = Vec::new();
    for i in 0..6000 {
        let shape = if i % 2 == 0 {
            VolumeShape::Box
        } else {
            VolumeShape::Ellipsoid
        };
        let (volume, w) = random_volume(&mut rng, shape, 100.0);
        let at = |p: Vec3| w.transform_point3(p);
        let (kind, eye, point) = match i % 6 {
            0 => (
                "camera outside, through",
                at(rng.vec(3.0)),
                at(rng.vec(3.0)),
            ),
            1 => (
                "camera inside",
                at(inside(&mut rng, shape)),
                at(rng.vec(3.0)),
            ),
            2 => (
                "point inside (scene depth)",
                at(rng.vec(3.0)),
                at(inside(&mut rng, shape)),
            ),
            3 => (
                "both inside",
                at(inside(&mut rng, shape)),
                at(inside(&mut rng, shape)),
            ),
            4 => {
                let eye = at(rng.vec(3.0));
                ("far point", eye, eye + rng.unit() * rng.log(50.0, 2000.0))
            }
            _ => {
                let eye = at(rng.vec(2.0));
                if rng.f() < 0.3 {
                    ("zero-length", eye, eye)
                } else {
                    ("short", eye, eye + rng.unit() * rng.log(1e-4, 1.0))
                }
            }
        };
        out.push((kind, Case { volume, eye, point }));
    }
    out
}

#[test]
fn fog_volumes_match_cpu_mirror() {
    let cases = cases();
    let plain: Vec<Case> = cases.iter().map(|(_, c)| *c).collect();
    let gpu = run_gpu(&plain);
    let mut worst = [0.0f64; 3];
    let mut compared = 0;
    for ((kind, c), g) in cases.iter().zip(&gpu) {
        let r = reference(&c.volume, c.eye, c.point);
        let cpu = c.cpu();
        if r.grazing {
            continue; // the chord of a tangent line is ill-posed; compared below anyway
        }
        compared += 1;
        // Ray parameters: within 1e-6 local units (t times the local segment length) plus
        // 8 ulp of the magnitude of the local-space ray's terms.
        let scale = r.local_len.max(1e-30);
        let base = 1e-6 + 8.0 * f32::EPSILON as f64 * local_magnitude(&c.volume, c.eye, c.point);
        let amp = r.amp.0.max(r.amp.1);
        let tol = base * amp;
        for k in 0..2 {
            // A miss may leave its empty interval anywhere: compare the lengths then.
            let e = if r.t.0 == r.t.1 {
                ((g[1] - g[0]) as f64).max((cpu[1] - cpu[0]) as f64) * scale
            } else {
                (g[k] as f64 - cpu[k] as f64).abs() * scale
            };
            worst[0] = worst[0].max(e / tol);
            assert!(
                e <= tol,
                "{kind}: t[{k}] gpu {:?} cpu {:?} ({e:e} local units, bound {tol:e}) for {c:?}",
                &g[..2],
                &cpu[..2]
            );
        }
        // Optical depth: relative 1e-4, or what that endpoint shift allows.
        let peak = c.volume.density as f64 * 1e4;
        let slack = peak * (tol / scale) * (c.point - c.eye).length() as f64;
        let e = (g[2] as f64 - cpu[2] as f64).abs();
        if amp <= 10.0 && (r.t.1 - r.t.0) * (c.point - c.eye).length() as f64 > 0.1 {
            worst[1] = worst[1].max(e / (cpu[2] as f64).max(1e-30));
        }
        assert!(
            e <= 1e-4 * cpu[2] as f64 + slack,
            "{kind}: OD gpu {} cpu {} for {c:?}",
            g[2],
            cpu[2]
        );
        for k in 3..7 {
            let e = (g[k] - cpu[k]).abs() as f64;
            worst[2] = worst[2].max(e);
            assert!(
                e <= 1e-4 * (1.0 + cpu[k].abs() as f64) + slack,
                "{kind}: fog[{}] gpu {} cpu {} for {c:?}",
                k - 3,
                g[k],
                cpu[k]
            );
        }
        // The raw unit-shape intersections agree where they are hits.
        for k in [7, 9] {
            if cpu[k] <= cpu[k + 1] && cpu[k].abs() < 1e6 {
                let e = (g[k] - cpu[k]).abs().max((g[k + 1] - cpu[k + 1]).abs());
                assert!(
                    e as f64 <= 1e-4 * (1.0 + cpu[k].abs().max(cpu[k + 1].abs()) as f64),
                    "raw intersection {k}: gpu {:?} cpu {:?}",
                    &g[k..k + 2],
                    &cpu[k..k + 2]
                );
            }
        }
    }
    eprintln!(
        "fog volume gpu vs cpu over {compared} non-grazing cases: worst |dt| {:.3} of its \
         bound ((1e-6 local units + 8 ulp of the local ray's terms) / |cos incidence|), \
         OD relative {:e} on chords > 10 cm with |cos| >= 0.1 (bound 1e-4 relative + the \
         endpoint shift), fog rgba abs {:e} (bound 1e-4 + the endpoint shift)",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn fog_volumes_match_f64_reference() {
    let cases = cases();
    let plain: Vec<Case> = cases.iter().map(|(_, c)| *c).collect();
    let gpu = run_gpu(&plain);
    let mut stats: std::collections::BTreeMap<&str, (usize, f64, f64)> = Default::default();
    let mut worst_t = 0.0f64;
    for ((kind, c), g) in cases.iter().zip(&gpu) {
        let r = reference(&c.volume, c.eye, c.point);
        let want_od = reference_od(&c.volume, c.eye, c.point, r.t);
        let cpu = c.cpu();
        for (side, out) in [("gpu", g), ("cpu", &cpu)] {
            assert!(
                out.iter().all(|v| v.is_finite()),
                "{side} {kind}: non-finite {out:?} for {c:?}"
            );
            assert!(
                (0.0..=1.0).contains(&out[6]),
                "{side} {kind}: T = {}",
                out[6]
            );
            if r.grazing {
                continue;
            }
            // Entry and exit within 1e-4 local units plus 8 ulp of the local ray's terms;
            // an empty interval may sit anywhere (t0 == t1).
            let base =
                1e-5 + 8.0 * f32::EPSILON as f64 * local_magnitude(&c.volume, c.eye, c.point);
            let tol = base * r.amp.0.max(r.amp.1);
            let dt = if r.t.0 == r.t.1 {
                (out[1] - out[0]) as f64 * r.local_len
            } else {
                (out[0] as f64 - r.t.0)
                    .abs()
                    .max((out[1] as f64 - r.t.1).abs())
                    * r.local_len
            };
            if side == "gpu" {
                worst_t = worst_t.max(dt / tol);
            }
            assert!(
                dt <= tol,
                "{side} {kind}: [t0, t1] = [{}, {}], reference [{}, {}] for {c:?}",
                out[0],
                out[1],
                r.t.0,
                r.t.1
            );
            // Optical depth within 1e-3 relative where the chord is longer than 10 cm;
            // shorter chords within the density times the endpoint tolerance.
            let seg_len = (c.point - c.eye).length() as f64;
            let chord = (r.t.1 - r.t.0) * seg_len;
            let chord_min = 0.1;
            let od = out[2] as f64;
            let rel = (od - want_od).abs() / want_od.max(1e-30);
            // Where the chord is longer than 10 cm and well conditioned (1 / |cos| <= 10),
            // the optical depth must be within 1e-3 relative; otherwise within that plus
            // the peak density times the endpoint tolerance (in metres) at both ends.
            let well_posed = chord > chord_min && r.amp.0.max(r.amp.1) <= 10.0;
            let peak = c.volume.density as f64 * 1e4;
            let slack = if well_posed {
                0.0
            } else {
                peak * 2.0 * tol / r.local_len.max(1e-30) * seg_len
            };
            assert!(
                (od - want_od).abs() <= 1e-3 * want_od + slack,
                "{side} {kind}: OD {od} reference {want_od} (rel {rel:e}, chord {chord} m) \
                 for {c:?}"
            );
            if side == "gpu" && well_posed {
                let s = stats.entry(kind).or_default();
                s.0 += 1;
                s.1 = s.1.max(rel);
            }
            // In-scatter: color * (1 - T), the fog lit by a constant radiance.
            let absorbed = -(-want_od).exp_m1();
            for k in 0..3 {
                let want = c.volume.color[k] as f64 * absorbed;
                let e = (out[3 + k] as f64 - want).abs() / want.max(1e-30);
                if well_posed {
                    assert!(
                        e <= 1e-3,
                        "{side} {kind}: in-scatter {} want {want} for {c:?}",
                        out[3 + k]
                    );
                    if side == "gpu" {
                        let s = stats.entry(kind).or_default();
                        s.2 = s.2.max(e);
                    }
                }
            }
        }
    }
    eprintln!(
        "fog volume entry/exit vs f64: worst {worst_t:.3} of the bound (1e-5 local units + \
         8 ulp of the local ray's terms) / |cos incidence|"
    );
    for (kind, (n, od, l)) in stats {
        eprintln!(
            "fog volume vs f64 ({kind:27}) {n:5} chords > 10 cm, |cos| >= 0.1: worst \
             relative error OD {od:e}, in-scatter {l:e} (bound 1e-3)"
        );
    }
}

/// A hand-checked case per shape: a 10 m cube / sphere of radius 5 at the origin,
/// camera inside, outside and the point clipping the segment.
#[test]
fn entry_exit_of_known_geometry() {
    let cube = FogVolume::new(
        Mat4::from_scale(Vec3::splat(5.0)),
        VolumeShape::Box,
        Vec3::ONE,
        0.1,
    )
    .unwrap();
    let ball = FogVolume {
        shape: FOG_VOLUME_ELLIPSOID,
        ..cube
    };
    let x = |v: f32| Vec3::new(v, 0.0, 0.0);
    // (volume, eye, point, expected t0, t1)
    let known: Vec<(&FogVolume, Vec3, Vec3, Vec2)> = vec![
        (&cube, x(-20.0), x(20.0), Vec2::new(0.375, 0.625)),
        (&cube, x(0.0), x(20.0), Vec2::new(0.0, 0.25)),
        (&cube, x(-20.0), x(0.0), Vec2::new(0.75, 1.0)),
        (&cube, x(-1.0), x(1.0), Vec2::new(0.0, 1.0)),
        (&cube, x(-20.0), x(-10.0), Vec2::new(1.0, 1.0)),
        (&cube, x(10.0), x(20.0), Vec2::new(0.0, 0.0)),
        (
            &cube,
            Vec3::new(-20.0, 6.0, 0.0),
            Vec3::new(20.0, 6.0, 0.0),
            Vec2::new(0.0, 0.0),
        ),
        (&ball, x(-20.0), x(20.0), Vec2::new(0.375, 0.625)),
        (&ball, x(0.0), x(-10.0), Vec2::new(0.0, 0.5)),
        (
            &ball,
            Vec3::new(-20.0, 3.0, 0.0),
            Vec3::new(20.0, 3.0, 0.0),
            Vec2::new(0.4, 0.6),
        ),
        (
            &ball,
            Vec3::new(-20.0, 4.0, 4.0),
            Vec3::new(20.0, 4.0, 4.0),
            Vec2::new(0.0, 0.0),
        ),
    ];
    let cases: Vec<Case> = known
        .iter()
        .map(|(v, e, p, _)| Case {
            volume: **v,
            eye: *e,
            point: *p,
        })
        .collect();
    let gpu = run_gpu(&cases);
    for ((c, (_, e, p, want)), g) in cases.iter().zip(&known).zip(&gpu) {
        let cpu = c.cpu();
        for (side, t) in [
            ("gpu", Vec2::new(g[0], g[1])),
            ("cpu", Vec2::new(cpu[0], cpu[1])),
        ] {
            let empty = want.x == want.y;
            let ok = if empty {
                (t.y - t.x).abs() < 1e-6
            } else {
                (t - *want).abs().max_element() < 1e-6
            };
            assert!(ok, "{side}: {e} -> {p}: t = {t}, expected {want}");
        }
        // 0.1 / m over the chord.
        let chord = (want.y - want.x) * (*p - *e).length();
        let t_want = (-0.1 * chord).exp();
        assert!(
            (g[6] - t_want).abs() < 1e-6,
            "{e} -> {p}: T = {}, expected {t_want}",
            g[6]
        );
    }
}

fn composite_input(rays: &[(Vec<FogVolume>, Vec3, Vec3)]) -> Vec<f32> {
    let mut input = Vec::new();
    for (volumes, eye, point) in rays {
        // Farthest centre first, as the CPU's fog_volumes sorts them.
        let mut sorted = volumes.clone();
        sorted.sort_by(|a, b| {
            b.center
                .distance_squared(*eye)
                .total_cmp(&a.center.distance_squared(*eye))
        });
        assert_eq!(sorted.len(), 4);
        for v in &sorted {
            input.extend(volume_floats(v));
        }
        input.extend(eye.extend(0.0).to_array());
        input.extend(point.extend(0.0).to_array());
    }
    input
}

#[test]
fn composited_volumes_match_cpu() {
    let mut rng = Rng(99);
    let mut rays = Vec::new();
    for i in 0..2000 {
        let volumes: Vec<FogVolume> = (0..4)
            .map(|k| {
                let shape = if (i + k) % 2 == 0 {
                    VolumeShape::Box
                } else {
                    VolumeShape::Ellipsoid
                };
                random_volume(&mut rng, shape, 20.0).0
            })
            .collect();
        let eye = rng.vec(30.0);
        let point = eye + rng.unit() * rng.log(1.0, 100.0);
        rays.push((volumes, eye, point));
    }
    let out = run_f32(
        gpu(),
        COMPOSITE_KERNEL,
        &composite_input(&rays),
        rays.len() * 4,
        rays.len() as u32,
    );
    let mut worst = 0.0f32;
    for (i, (volumes, eye, point)) in rays.iter().enumerate() {
        let want = fog_volumes(volumes, *eye, *point);
        let got = Vec4::from_slice(&out[i * 4..i * 4 + 4]);
        let e = (got - want).abs().max_element();
        worst = worst.max(e);
        assert!(
            e <= 1e-4,
            "ray {i}: gpu {got} cpu {want} for {volumes:?} {eye} {point}"
        );
        assert!(want.w >= 0.0 && want.w <= 1.0);
    }
    eprintln!(
        "4 overlapping volumes composited, gpu vs cpu: worst abs error {worst:e} (bound 1e-4)"
    );
}

/// Volumes that do not overlap along the ray, composited back to front, against the
/// radiative transfer through all of them marched in f64 (inside tests by the shapes'
/// distance functions, 2e5 steps): exact apart from the march.
#[test]
fn composited_volumes_match_radiative_transfer() {
    let mut rng = Rng(2024);
    let mut rays = Vec::new();
    for i in 0..100 {
        let volumes: Vec<FogVolume> = (0..4)
            .map(|k| {
                let shape = if (i + k) % 2 == 0 {
                    VolumeShape::Box
                } else {
                    VolumeShape::Ellipsoid
                };
                // Bounding spheres of radius <= 5 sqrt(3) < 10 around centres 20 m apart.
                let w = Mat4::from_translation(Vec3::new(10.0 + 20.0 * k as f32, 0.0, 0.0))
                    * Mat4::from_quat(rng.quat())
                    * Mat4::from_scale(Vec3::new(
                        rng.range(2.0, 5.0),
                        rng.range(2.0, 5.0),
                        rng.range(2.0, 5.0),
                    ));
                FogVolume::new(
                    w,
                    shape,
                    Vec3::new(rng.f(), rng.f(), rng.f()) * 2.0,
                    rng.log(0.01, 0.2),
                )
                .unwrap()
                .with_gradient(rng.unit(), rng.range(-0.1, 0.1), rng.range(-2.0, 2.0))
                .unwrap()
            })
            .collect();
        // Camera on the left of the row (sometimes inside the first volume), the scene
        // point anywhere along it (clipping some volumes).
        let eye = Vec3::new(
            rng.range(-10.0, 11.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let point = Vec3::new(
            rng.range(15.0, 100.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        rays.push((volumes, eye, point));
    }
    let out = run_f32(
        gpu(),
        COMPOSITE_KERNEL,
        &composite_input(&rays),
        rays.len() * 4,
        rays.len() as u32,
    );
    let mut worst = 0.0f64;
    for (i, (volumes, eye, point)) in rays.iter().enumerate() {
        let e = v64(*eye);
        let seg = [0, 1, 2].map(|k| point[k] as f64 - e[k]);
        let len = norm(seg);
        let n = 200_000;
        let ds = len / n as f64;
        let local: Vec<M64> = volumes.iter().map(|v| m64(&v.local_from_world)).collect();
        let (mut t, mut l) = (1.0f64, [0.0f64; 3]);
        for s in 0..n {
            let u = (s as f64 + 0.5) / n as f64;
            let p = [0, 1, 2].map(|k| e[k] + u * seg[k]);
            let (mut sigma, mut source) = (0.0, [0.0; 3]);
            for (v, m) in volumes.iter().zip(&local) {
                if phi(v.shape, xform(m, p, 1.0)) <= 0.0 {
                    let d = density64(v, p);
                    sigma += d;
                    for (acc, c) in source.iter_mut().zip(v.color.to_array()) {
                        *acc += d * c as f64;
                    }
                }
            }
            if sigma > 0.0 {
                let absorbed = -(-sigma * ds).exp_m1();
                for k in 0..3 {
                    l[k] += t * absorbed * source[k] / sigma;
                }
                t *= 1.0 - absorbed;
            }
        }
        let want = [l[0], l[1], l[2], t];
        let cpu = fog_volumes(volumes, *eye, *point);
        let got = Vec4::from_slice(&out[i * 4..i * 4 + 4]);
        for (side, v) in [("gpu", got), ("cpu", cpu)] {
            for k in 0..4 {
                let e = (v[k] as f64 - want[k]).abs() / want[k].abs().max(1e-2);
                worst = worst.max(e);
                assert!(
                    e <= 1e-3,
                    "{side} ray {i} channel {k}: {} radiative transfer {} ({eye} -> {point})",
                    v[k],
                    want[k]
                );
            }
        }
    }
    eprintln!(
        "4 disjoint volumes composited back to front vs f64 radiative transfer: worst \
         relative error {worst:e} (bound 1e-3, floor 1e-2)"
    );
}

#[test]
fn fog_volumes_are_finite_for_adversarial_inputs() {
    let points = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(1e-30, -1e-30, 0.0),
        Vec3::new(1e30, -1e30, 1e30),
        Vec3::splat(3.4e38),
        Vec3::new(-3.4e38, 0.0, 3.4e38),
        Vec3::new(1e9, 1.0, -1e9),
        Vec3::new(5.0, 1e-7, 0.0),
    ];
    let mut rng = Rng(3);
    let mut cases = Vec::new();
    for i in 0..20000 {
        let shape = if i % 2 == 0 {
            VolumeShape::Box
        } else {
            VolumeShape::Ellipsoid
        };
        // Valid volumes from a micrometre to a million kilometres, extreme gradients.
        let s = rng.log(2e-6, 1e9);
        let w = Mat4::from_translation(rng.vec(1e6))
            * Mat4::from_quat(rng.quat())
            * Mat4::from_scale(Vec3::new(s, s * rng.range(1.0, 2.0), s));
        let volume = FogVolume::new(w, shape, Vec3::splat(1e9), rng.log(1e-30, 1e3))
            .unwrap()
            .with_gradient(rng.unit(), rng.range(-1e3, 1e3), rng.range(-1e9, 1e9))
            .unwrap();
        let pick = |rng: &mut Rng| {
            if rng.f() < 0.5 {
                points[(rng.f() * points.len() as f32) as usize % points.len()]
            } else {
                w.transform_point3(rng.vec(1.5))
            }
        };
        let eye = pick(&mut rng);
        let point = if rng.f() < 0.1 { eye } else { pick(&mut rng) };
        cases.push(Case { volume, eye, point });
    }
    let gpu = run_gpu(&cases);
    for (c, g) in cases.iter().zip(&gpu) {
        for (side, out) in [("gpu", *g), ("cpu", c.cpu())] {
            assert!(
                out[..7].iter().all(|v| v.is_finite()),
                "{side}: non-finite {out:?} for {c:?}"
            );
            assert!(
                0.0 <= out[0] && out[0] <= out[1] && out[1] <= 1.0,
                "{side}: t = {:?}",
                &out[..2]
            );
            assert!(
                out[2] >= 0.0 && (0.0..=1.0).contains(&out[6]),
                "{side}: {out:?}"
            );
            assert!(out[3..6].iter().all(|v| *v >= 0.0), "{side}: {out:?}");
        }
    }
    eprintln!(
        "fog volumes: {} adversarial cases finite on gpu and cpu",
        cases.len()
    );
}

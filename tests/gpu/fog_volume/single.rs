//! One volume along a segment: entry/exit, optical depth and fog against the CPU
//! mirror, the f64 reference and hand-checked geometry; finite for adversarial inputs.

use super::reference::{local_magnitude, reference, reference_od};
use super::{Case, cases, run_gpu};
use crate::common::Rng;
use glam::{Mat4, Vec2, Vec3};
use volfog::cpu::fog_volume::*;
use volfog::uniforms::{FogVolume, VolumeShape};

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

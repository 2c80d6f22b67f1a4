//! The epipolar lines on the screen: exit and entry points on the border, each slice's
//! line and its sample positions, and the inverse map of a pixel onto them.

use glam::{Vec2, Vec4, Vec4Swizzles};

use super::{BORDER, INVALID, fract};
use crate::uniforms::EpipolarFrame;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;

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
}

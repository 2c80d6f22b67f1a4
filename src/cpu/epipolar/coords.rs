//! The coordinate texture of the `epipolar_coords` pass: each slice's sample positions
//! and their view depths.

use glam::{Vec2, Vec4};

use super::lines::{line, sample_position};
use super::{INVALID, INVALID_DEPTH};
use crate::uniforms::EpipolarFrame;

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
    use glam::Vec4Swizzles;

    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::epipolar::test_scene::{Scene, suns};
    use crate::cpu::epipolar::{BORDER, line_position};

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
}

//! Refinement of a slice's samples: sections, depth breaks and the interpolation
//! sources of every sample (the `epipolar_refine` pass).

use glam::UVec2;

use super::{GROUP, INVALID_DEPTH};
use crate::uniforms::EpipolarFrame;

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

/// Interpolation sources packed in one u32 (first in the low 16 bits); mirror of
/// `volfog::epipolar::epipolar_pack_sources`.
pub fn pack_sources(sources: UVec2) -> u32 {
    (sources.x & 0xffff) | (sources.y << 16)
}

/// The two sources of a packed u32; mirror of `volfog::epipolar::epipolar_unpack_sources`.
pub fn unpack_sources(packed: u32) -> UVec2 {
    UVec2::new(packed & 0xffff, packed >> 16)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;

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
}

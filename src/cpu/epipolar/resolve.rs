//! The full-resolution resolve of a pixel: its normalised device position and view
//! depth, the phase term and the fog with the pixel's lit fraction.

use glam::{Vec2, Vec3, Vec4};

use crate::cpu::froxel::view_from_ndc;
use crate::cpu::height_fog::{height_fog_optical_depth_below, height_fog_sun_share};
use crate::cpu::phase::{phase_cornette_shanks, phase_hg, phase_rayleigh};
use crate::uniforms::{EpipolarFrame, HeightFog};

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
/// view-space point `view_pos` (m, at most `frame.max_depth`) with lit fraction `shafts`
/// (per channel): `(color + P F R) (1 - T)`, `R` the share of the absorbed light the sun
/// reaches through the medium ([`height_fog_sun_share`]); mirror of `volfog::epipolar::epipolar_fog`.
pub fn fog(frame: &EpipolarFrame, fog: &HeightFog, view_pos: Vec3, shafts: Vec3) -> Vec4 {
    let depth = view_pos.z.abs();
    let end = depth.min(frame.max_depth);
    if end <= frame.start_depth || depth <= 0.0 {
        return Vec4::new(0.0, 0.0, 0.0, 1.0);
    }
    let origin = view_pos * (frame.start_depth / depth);
    let segment = view_pos * (end / depth) - origin;
    let od = height_fog_optical_depth_below(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        fog.top_height,
        origin,
        segment,
    );
    let view_dir = view_pos / view_pos.length();
    let lit = shafts.clamp(Vec3::ZERO, Vec3::ONE) * height_fog_sun_share(fog, origin, segment, od);
    let radiance = fog.color + phase(frame, fog, view_dir) * lit;
    crate::cpu::height_fog::fog_inscatter(radiance, od)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::height_fog::height_fog;

    #[test]
    fn fog_without_shadows_is_the_height_fog() {
        let mut rng = Rng(9);
        let base = HeightFog::new(Vec3::new(0.3, 0.4, 0.5), 0.03, Vec3::Y, 0.05, -1.0)
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
        // Without and with the sun's transmittance, without and with a top 12 m up.
        let media = [
            base,
            base.with_sun_transmittance(true),
            base.with_top(12.0).unwrap().with_sun_transmittance(true),
        ];
        for fog in media {
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
                    let t = (-height_fog_optical_depth_below(
                        fog.density,
                        fog.falloff,
                        fog.base_height,
                        fog.up,
                        fog.top_height,
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
                        assert!(
                            phase(&frame, &fog, view_pos.normalize()).x > 0.0 && c.abs() <= 1.0
                        );
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
        }
        let fog = base;
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

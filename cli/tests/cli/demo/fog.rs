//! The fog in the frame: the ground recedes into it at a rate the medium allows, its
//! shadow map agrees with the ground's shadows, and it shows light shafts.

use glam::{Vec3, Vec4};
use volfog::cpu::esm::{self, Layer};
use volfog::cpu::shadow;
use volfog::uniforms::ShadowCascades;

use super::{HEIGHT, Run, Volume, WIDTH, mat, median, num, read_f32, read_rgba, run, sum3, vec3};

/// One ground pixel: world position, distance from the camera (m), surface
/// radiance, fogged radiance, in-scattering (rgb sums), sun visibility of the surface.
#[derive(Debug, Clone, Copy)]
struct GroundPixel {
    world: Vec3,
    distance: f32,
    surface: f32,
    fogged: f32,
    inscatter: f32,
    sun: f32,
}

impl GroundPixel {
    fn transmittance(&self) -> f32 {
        (self.fogged - self.inscatter) / self.surface
    }
}

/// Ground pixels (world y = 0 by the depth buffer, off the sky), from the probe images.
fn ground_pixels(run: &Run) -> Vec<GroundPixel> {
    let camera = &run.probe["camera"];
    let world_from_clip = mat(&camera["world_from_clip"]);
    let eye = vec3(&camera["position"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let fogged = read_rgba(run, "fogged.f32");
    let inscatter = read_rgba(run, "inscatter.f32");
    let mut out = Vec::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = (y * WIDTH + x) as usize;
            if depth[i] >= 1.0 {
                continue;
            }
            let ndc = Vec3::new(
                (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / HEIGHT as f32 * 2.0,
                depth[i],
            );
            let world = world_from_clip.project_point3(ndc);
            if world.y.abs() > 0.02 {
                continue;
            }
            out.push(GroundPixel {
                world,
                distance: world.distance(eye),
                surface: sum3(surface[i]),
                fogged: sum3(fogged[i]),
                inscatter: sum3(inscatter[i]),
                sun: surface[i].w,
            });
        }
    }
    out
}

/// Fog on the ground: the per-pixel transmittance falls with distance, and the
/// extinction it implies lies within what the medium allows.
#[test]
fn ground_recedes_into_fog() {
    let run = run();
    let pixels = ground_pixels(run);
    let medium = &run.probe["medium"];
    let density = num(&medium["density"]) as f32;
    let noise = num(&medium["noise_strength"]) as f32;
    let falloff = num(&medium["height_falloff"]) as f32;
    let eye_height = num(&run.probe["camera"]["position"][1]) as f32;
    // Between the ground and the eye the extinction lies within these bounds, outside
    // the local fog pocket (the medians below are dominated by pixels off the pocket).
    let sigma_min = density * (1.0 - noise) * (-falloff * eye_height).exp();
    let sigma_max = density * (1.0 + noise);
    let bin = |lo: f32, hi: f32| {
        let t: Vec<f32> = pixels
            .iter()
            .filter(|p| p.distance >= lo && p.distance < hi && p.surface > 0.05)
            .map(GroundPixel::transmittance)
            .collect();
        let n = t.len();
        (median(t), n, 0.5 * (lo + hi))
    };
    let (t_near, n_near, d_near) = bin(3.0, 8.0);
    let (t_mid, n_mid, d_mid) = bin(10.0, 20.0);
    let (t_far, n_far, d_far) = bin(25.0, 60.0);
    eprintln!(
        "ground transmittance (median): {t_near:.3} at {d_near} m ({n_near} px), {t_mid:.3} at {d_mid} m ({n_mid} px), {t_far:.3} at {d_far} m ({n_far} px)"
    );
    for (t, d, n) in [
        (t_near, d_near, n_near),
        (t_mid, d_mid, n_mid),
        (t_far, d_far, n_far),
    ] {
        assert!(n >= 30, "{n} ground pixels near {d} m");
        let sigma = -t.ln() / d;
        eprintln!(
            "  implied extinction at {d} m: {sigma:.4} 1/m (medium allows {sigma_min:.4}..{sigma_max:.4})"
        );
        assert!(
            sigma >= sigma_min * 0.8 && sigma <= sigma_max * 1.25,
            "implied extinction {sigma} at {d} m outside {sigma_min}..{sigma_max}"
        );
    }
    assert!(t_near < 0.98, "fog attenuates even the nearest ground");
    assert!(
        t_mid < t_near - 0.05 && t_far < t_mid - 0.05,
        "transmittance falls with distance: {t_near} {t_mid} {t_far}"
    );
    // Farther ground is closer to the fog colour: the share of in-scattering in the
    // fogged radiance grows.
    let share = |lo: f32, hi: f32| {
        median(
            pixels
                .iter()
                .filter(|p| p.distance >= lo && p.distance < hi && p.fogged > 0.0)
                .map(|p| p.inscatter / p.fogged)
                .collect(),
        )
    };
    let (s_near, s_far) = (share(3.0, 8.0), share(25.0, 60.0));
    eprintln!(
        "in-scattering share of the ground's fogged radiance: {s_near:.3} near, {s_far:.3} far"
    );
    assert!(s_far > s_near + 0.1, "{s_near} -> {s_far}");
}

/// The sun's shadow in the fog as the probe recorded it: the cascades and the layers
/// the fog's filter reads (the shadow map itself for the compare filter, the ESM for
/// the ESM filter).
pub(super) struct SunShadow {
    cascades: ShadowCascades,
    layers: Vec<Layer>,
    compare: bool,
    log_space: bool,
}

impl SunShadow {
    /// The sun's visibility the fog's filter gives one point (one compare tap, or the
    /// ESM look-up).
    pub(super) fn visibility(&self, world: Vec3, view_depth: f32) -> f32 {
        let c = &self.cascades;
        if !self.compare {
            return esm::esm_shadow(&self.layers, c, world, view_depth, self.log_space);
        }
        let i = esm::esm_cascade(view_depth, c.splits, c.count);
        if i >= c.count {
            return 1.0;
        }
        shadow::shadow_cascade_compare(
            &self.layers[i as usize],
            c.light_from_world[i as usize],
            world,
            false,
        )
    }
}

/// The fog's shadow inputs as the probe recorded them.
pub(super) fn shadow_inputs(run: &Run) -> SunShadow {
    let c = &run.probe["cascades"];
    let mut cascades = ShadowCascades {
        splits: Vec4::from_slice(
            &c["splits"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| num(x) as f32)
                .collect::<Vec<_>>(),
        ),
        count: c["count"].as_u64().unwrap() as u32,
        exponent: num(&c["exponent"]) as f32,
        ..ShadowCascades::default()
    };
    for (i, m) in c["light_from_world"].as_array().unwrap().iter().enumerate() {
        cascades.light_from_world[i] = mat(m);
    }
    let fog = &run.probe["fog"];
    let compare = fog["shadow_filter"]
        .as_str()
        .unwrap()
        .starts_with("Compare");
    let (n, file) = if compare {
        (
            fog["sun_shadow_size"].as_u64().unwrap() as u32,
            "sun_shadow.f32",
        )
    } else {
        (fog["esm_resolution"].as_u64().unwrap() as u32, "esm.f32")
    };
    let texels = read_f32(run, file);
    assert_eq!(texels.len(), (n * n * cascades.count) as usize);
    let layers = texels
        .chunks_exact((n * n) as usize)
        .map(|c| Layer {
            width: n,
            height: n,
            texels: c.to_vec(),
        })
        .collect();
    SunShadow {
        cascades,
        layers,
        compare,
        log_space: fog["esm_log_space"] == true,
    }
}

/// The fog's shadow filter agrees with the demo's own shadow test of the ground (3x3
/// PCF on the raw shadow map): the shadows reach the fog where they are.
#[test]
fn fog_shadow_map_matches_the_ground_shadows() {
    let run = run();
    let sun = shadow_inputs(run);
    let view_from_world = mat(&run.probe["camera"]["view_from_world"]);
    let (mut agree, mut total, mut shadowed) = (0, 0, 0);
    for p in ground_pixels(run) {
        if p.sun > 0.05 && p.sun < 0.95 {
            continue;
        }
        // Just above the ground, which is itself in the shadow map.
        let world = p.world + Vec3::Y * 0.3;
        let depth = -view_from_world.transform_point3(world).z;
        let v = sun.visibility(world, depth);
        total += 1;
        shadowed += usize::from(p.sun < 0.05);
        agree += usize::from((v > 0.5) == (p.sun > 0.5));
    }
    let share = agree as f32 / total as f32;
    eprintln!(
        "fog's shadow filter vs ground shadow test: {:.1}% of {total} ground pixels agree ({shadowed} in shadow; bound 85%)",
        share * 100.0
    );
    assert!(shadowed >= 100 && total - shadowed >= 100);
    assert!(share >= 0.85, "{share}");
}

/// Light shafts in the fog: in the integrated volume, the radiance each froxel
/// scatters towards the eye, J = dL / (-dT) between consecutive slices (the source
/// function sigma_s L_in / sigma_t, independent of the density), is several times
/// larger in sunlit columns than in neighbouring columns in a pillar's shadow (same
/// slice and row, at most 4 columns apart, 3 to 13 m from the camera). Without the
/// sun in the fog the median ratio measures 0.98, with it 2.1 (the coloured lights
/// and the lamp add to both sides); the bound is 1.6.
#[test]
fn fog_shows_light_shafts() {
    let run = run();
    let volume = Volume::read(run);
    let size = volume.size;
    let sun = shadow_inputs(run);
    let (mut ratios, mut lit_count, mut shadow_count) = (Vec::new(), 0, 0);
    for z in 1..size.z {
        // (sun visibility, J) of every froxel of this slice with enough extinction.
        let mut row: Vec<Option<(f32, f32)>> = vec![None; size.x as usize];
        for y in 0..size.y {
            for x in 0..size.x {
                let (world, depth) = volume.world(x, y, z);
                row[x as usize] = volume
                    .scattered(x, y, z)
                    .filter(|_| (3.0..13.0).contains(&depth))
                    .map(|j| {
                        let v = sun.visibility(world, depth);
                        (v, j)
                    });
            }
            for x in 0..size.x as usize {
                let Some((v, j_shadow)) = row[x] else {
                    continue;
                };
                if v > 0.05 {
                    lit_count += usize::from(v > 0.95);
                    continue;
                }
                shadow_count += 1;
                let neighbours = &row[x.saturating_sub(4)..(x + 5).min(size.x as usize)];
                for (vn, j_lit) in neighbours.iter().flatten() {
                    if *vn > 0.95 && j_shadow > 0.0 {
                        ratios.push(j_lit / j_shadow);
                    }
                }
            }
        }
    }
    let n = ratios.len();
    eprintln!(
        "froxels 3..13 m from the camera: {lit_count} sunlit, {shadow_count} in shadow, {n} neighbour pairs"
    );
    assert!(n >= 200, "{n} lit/shadowed neighbour pairs");
    ratios.sort_by(|a, b| a.total_cmp(b));
    let (q25, q50, q75) = (ratios[n / 4], ratios[n / 2], ratios[3 * n / 4]);
    eprintln!(
        "scattered radiance J, sunlit / shadowed neighbouring columns: median {q50:.2} (quartiles {q25:.2}, {q75:.2}; bound: median >= 1.6)"
    );
    assert!(q50 >= 1.6, "shafts too weak: median ratio {q50}");
}

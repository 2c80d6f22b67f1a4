//! The phase, height-fog, lightning and fog-coordinate snippets compiled by compilers
//! that are not naga (Slang from HLSL, glslang from GLSL) into SPIR-V, dispatched on
//! lavapipe through `vkcheck` under the Khronos validation layer, and compared with
//! volfog's CPU mirror: 1e-5 relative for the phase, height-fog and lightning values
//! (transmittances exp(-OD): the optical depth's 1e-5 carried through exp, 1e-5 x
//! max(1, OD)); the
//! view position of a world position within the f32 error bound of its dot products,
//! which proves the matrix convention the README gives HLSL users (a transposed matrix
//! is metres off); fog coordinates from that view position within 1e-5.
//!
//! The hosts are `hosts/numbers.hlsl` and `hosts/numbers.comp`. A case is 26 vec4:
//! 0 (cos_theta, g, g2, w), 1 (dir, x_in), 2 (toward, -), 3 (away, -), 4..8 HeightFog,
//! 8 (origin, attenuation), 9 (segment, intensity), 10 (light, -), 11 (world, -),
//! 12..16 view_from_world rows, 16..20 clip_from_view rows, 20..24 view_from_clip rows,
//! 24 (froxel size, near), 25 (far, curve, -, -). Results are 9 vec4 per case.

use std::path::Path;

use glam::{Mat4, UVec3, Vec3, Vec4};
use vkcheck::Validator;
use volfog::cpu::{apply, height_fog, lightning, phase};
use volfog::uniforms::{Froxels, HeightFog};
use volfog_testkit::rng::{Rng, rel_err};

use crate::common::{exported, scratch};
use crate::tools::{glslang, output, slang_check, text};

const CASE_VEC4: usize = 26;
const OUT_VEC4: usize = 9;
/// Fog coordinates (from the world position).
const COORD_SLOTS: std::ops::Range<usize> = 28..32;
/// The view-space position of the world position.
const VIEW_SLOTS: std::ops::Range<usize> = 32..35;
/// Transmittances: height_fog_transmittance and height_fog's alpha (slot 11 is the
/// optical depth).
const TRANSMITTANCE_SLOTS: [usize; 2] = [7, 23];

struct Case {
    cos_theta: f32,
    g: f32,
    g2: f32,
    w: f32,
    dir: Vec3,
    x_in: f32,
    toward: Vec3,
    away: Vec3,
    fog: HeightFog,
    origin: Vec3,
    attenuation: f32,
    segment: Vec3,
    intensity: f32,
    light: Vec3,
    world: Vec3,
    view_from_world: Mat4,
    froxels: Froxels,
}

fn rows(m: Mat4) -> [Vec4; 4] {
    [m.row(0), m.row(1), m.row(2), m.row(3)]
}

impl Case {
    fn random(rng: &mut Rng) -> Case {
        let fog = HeightFog::new(
            Vec3::new(rng.f(), rng.f(), rng.f()) * 2.0,
            rng.log(1e-4, 1.0),
            rng.unit(),
            rng.range(-0.05, 0.3),
            rng.range(-20.0, 20.0),
        )
        .unwrap()
        .with_sun(
            rng.unit(),
            Vec3::new(rng.f(), rng.f(), rng.f()) * 20.0,
            rng.range(-0.9, 0.9),
        )
        .unwrap();
        let eye = rng.vec(50.0);
        let view_from_world = glam::camera::rh::view::look_to_mat4(eye, rng.unit(), Vec3::Y);
        let dir = view_from_world.inverse().transform_vector3(
            Vec3::new(rng.range(-0.5, 0.5), rng.range(-0.3, 0.3), -1.0).normalize(),
        );
        let projection =
            glam::camera::rh::proj::directx::perspective(rng.range(0.6, 1.4), 1.6, 0.1, 500.0);
        Case {
            cos_theta: rng.range(-1.0, 1.0),
            g: rng.range(-0.95, 0.95),
            g2: rng.range(-0.95, 0.95),
            w: rng.f(),
            dir: rng.unit(),
            x_in: rng.log(1e-6, 30.0),
            toward: Vec3::new(rng.f(), rng.f(), rng.f()),
            away: Vec3::new(rng.f(), rng.f(), rng.f()),
            fog,
            origin: rng.vec(30.0),
            attenuation: rng.log(1e-3, 1.0),
            segment: rng.unit() * rng.log(0.1, 100.0),
            intensity: rng.log(0.1, 10.0),
            light: rng.vec(20.0),
            world: eye + dir * rng.log(0.3, 300.0),
            view_from_world,
            froxels: Froxels::new(projection, UVec3::new(160, 90, 128), 0.5, 128.0, 4.0).unwrap(),
        }
    }

    fn input(&self) -> [Vec4; CASE_VEC4] {
        let f = &self.fog;
        let x = &self.froxels;
        let mut v = vec![
            Vec4::new(self.cos_theta, self.g, self.g2, self.w),
            self.dir.extend(self.x_in),
            self.toward.extend(0.0),
            self.away.extend(0.0),
            f.color.extend(f.density),
            f.up.extend(f.falloff),
            f.sun_direction.extend(f.base_height),
            f.sun_color.extend(f.sun_g),
            self.origin.extend(self.attenuation),
            self.segment.extend(self.intensity),
            self.light.extend(0.0),
            self.world.extend(0.0),
        ];
        v.extend(rows(self.view_from_world));
        v.extend(rows(x.clip_from_view));
        v.extend(rows(x.view_from_clip));
        v.push(x.size.as_vec3().extend(x.near));
        v.push(Vec4::new(x.far, x.curve, 0.0, 0.0));
        v.try_into().unwrap()
    }

    /// What the hosts write, from the CPU mirror.
    fn want(&self) -> [f32; OUT_VEC4 * 4] {
        let (c, g, f) = (self.cos_theta, self.g, &self.fog);
        let (o, s) = (self.origin, self.segment);
        let od =
            height_fog::height_fog_optical_depth(f.density, f.falloff, f.base_height, f.up, o, s);
        let t =
            height_fog::height_fog_transmittance(f.density, f.falloff, f.base_height, f.up, o, s);
        let (a, i) = (self.attenuation, self.intensity);
        let out = [
            Vec4::new(
                phase::phase_hg(c, g),
                phase::phase_schlick(c, phase::schlick_k(g)),
                phase::phase_cornette_shanks(c, g),
                phase::phase_rayleigh(c),
            ),
            Vec4::new(
                phase::phase_hg_two_lobe(c, g, self.g2, self.w),
                phase::phase_isotropic(),
                height_fog::exp_segment_average(self.x_in),
                t,
            ),
            phase::phase_hg_zonal_sh(g).extend(od),
            phase::phase_hg_sh_l1(self.dir, g),
            phase::phase_two_color(c, self.toward, self.away).extend(
                lightning::lightning_integral(a, self.light, self.origin, self.segment),
            ),
            height_fog::height_fog(f, self.origin, self.segment),
            Vec4::new(
                lightning::volumetric_lightning(i, a, self.light, self.origin, self.segment),
                lightning::lightning_density(i, a, self.light, self.origin + 0.5 * self.segment),
                0.0,
                0.0,
            ),
            apply::fog_coord_from_world(self.world, self.view_from_world, &self.froxels),
            apply::fog_view_position(self.world, self.view_from_world).extend(0.0),
        ];
        bytemuck::cast(out)
    }
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0xf0_4e16);
    (0..2048).map(|_| Case::random(&mut rng)).collect()
}

fn words(path: &Path) -> Vec<u32> {
    let bytes = std::fs::read(path).unwrap();
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Drops `OpSource` / `OpSourceContinued` (debug information): Slang writes its own
/// source-language value, which the validation layer of this Debian release predates.
fn strip_source(spirv: &[u32]) -> Vec<u32> {
    let mut out = spirv[..5].to_vec();
    let mut i = 5;
    while i < spirv.len() {
        let count = (spirv[i] >> 16) as usize;
        let opcode = spirv[i] & 0xffff;
        assert!(count > 0, "malformed SPIR-V at word {i}");
        if opcode != 3 && opcode != 4 {
            out.extend_from_slice(&spirv[i..i + count]);
        }
        i += count;
    }
    out
}

/// Runs the compiled host on every case and checks every value against the CPU.
fn check(compiler: &str, spirv: &[u32]) {
    let cases = cases();
    let input: Vec<Vec4> = cases.iter().flat_map(|c| c.input()).collect();
    let validator = Validator::new().unwrap_or_else(|e| panic!("{e}"));
    let (bytes, messages) = validator
        .run_compute(
            spirv,
            "main",
            bytemuck::cast_slice(&input),
            cases.len() * OUT_VEC4 * 16,
            cases.len() as u32,
        )
        .unwrap_or_else(|e| panic!("{compiler}: {e}"));
    assert!(messages.is_empty(), "{compiler}: {}", messages.join("\n"));
    let got: &[f32] = bytemuck::cast_slice(&bytes);
    let (mut worst_rel, mut worst_t) = (0.0f32, 0.0f32);
    let (mut worst_view, mut worst_coord) = (0.0f32, 0.0f32);
    for (n, c) in cases.iter().enumerate() {
        let want = c.want();
        let got = &got[n * OUT_VEC4 * 4..(n + 1) * OUT_VEC4 * 4];
        for k in 0..want.len() {
            assert!(
                got[k].is_finite(),
                "{compiler}: case {n} slot {k} is {}",
                got[k]
            );
            if VIEW_SLOTS.contains(&k) {
                // A 4-term dot product in f32 on each side: |error| <= 2 * 4 ulp of the
                // sum of the terms' magnitudes.
                let row = c.view_from_world.row(k - VIEW_SLOTS.start).abs();
                let bound = 8.0 * f32::EPSILON * row.dot(c.world.abs().extend(1.0));
                let e = (got[k] - want[k]).abs();
                worst_view = worst_view.max(e / bound);
                assert!(
                    e <= bound,
                    "{compiler}: case {n} view position {k}: {} vs cpu {} (abs {e:e}, bound {bound:e})",
                    got[k],
                    want[k]
                );
            } else if COORD_SLOTS.contains(&k) {
                // From the view position the host computed, so the world -> view
                // rounding above is not counted twice.
                let view = Vec3::from_slice(&got[VIEW_SLOTS]);
                let want = apply::fog_coord_from_view(view, &c.froxels)[k - COORD_SLOTS.start];
                let e = (got[k] - want).abs();
                worst_coord = worst_coord.max(e);
                assert!(
                    e <= 1e-5,
                    "{compiler}: case {n} fog coordinate {k}: {} vs cpu {want} (abs {e:e})",
                    got[k]
                );
            } else {
                // A transmittance exp(-OD) turns a relative error e of OD into e * OD:
                // the optical depth's 1e-5 carried through exp.
                let bound = if TRANSMITTANCE_SLOTS.contains(&k) {
                    1e-5 * want[11].max(1.0)
                } else {
                    1e-5
                };
                let e = rel_err(got[k], want[k], 1e-30);
                if TRANSMITTANCE_SLOTS.contains(&k) {
                    worst_t = worst_t.max(e / bound);
                } else {
                    worst_rel = worst_rel.max(e);
                }
                assert!(
                    e <= bound,
                    "{compiler}: case {n} slot {k}: {} vs cpu {} (rel {e:e}, bound {bound:e})",
                    got[k],
                    want[k]
                );
            }
        }
    }
    eprintln!(
        "{compiler} -> SPIR-V on {}: {} cases x 35 values; phase, height fog, lightning worst \
         relative error {worst_rel:e} (bound 1e-5), transmittances {worst_t:.3} of theirs; view \
         position worst {worst_view:.3} of its f32 dot-product bound; fog coordinates worst \
         absolute error {worst_coord:e} (bound 1e-5)",
        validator.device_name(),
        cases.len(),
    );
}

#[test]
fn hlsl_snippets_compiled_by_slang_match_the_cpu_mirror() {
    let spv = scratch("numbers-hlsl").with_extension("spv");
    let host = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/host/hosts/numbers.hlsl");
    let o = output(
        slang_check()
            .args([
                "--werror", "--target", "spirv", "--stage", "compute", "--entry", "main",
            ])
            .arg("-I")
            .arg(exported().join("hlsl/include"))
            .arg("-o")
            .arg(&spv)
            .arg(&host),
    );
    assert!(o.status.success(), "{}", text(&o));
    check("HLSL (Slang)", &strip_source(&words(&spv)));
}

#[test]
fn glsl_snippets_compiled_by_glslang_match_the_cpu_mirror() {
    let spv = scratch("numbers-glsl").with_extension("spv");
    let host = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/host/hosts/numbers.comp");
    let o = output(
        glslang()
            .args(["-V", "--target-env", "vulkan1.1"])
            .arg(format!("-I{}", exported().join("glsl/include").display()))
            .arg("-o")
            .arg(&spv)
            .arg(&host),
    );
    assert!(o.status.success(), "{}", text(&o));
    check("GLSL (glslang)", &words(&spv));
}

//! The demo through the `volfog` binary on the GPU at a small resolution: every pass
//! runs, the ground recedes into fog (transmittance measured per pixel falls with
//! distance, at a rate the medium allows), the fog's shadow map agrees with the
//! ground's shadows, the fog shows light shafts (sunlit columns of the froxel volume
//! scatter several times more than neighbouring columns in a pillar's shadow), the
//! semi-transparent sphere is drawn, the pool's water fogs what lies under it seen
//! from above and everything seen from the second camera under water (per pixel
//! equal to the CPU mirror of `volfog::water`), nothing is NaN, and the PNGs decode
//! at the requested size.
//!
//! The demo's `--probe` output gives linear float images of the last frame: the lit
//! surfaces before the fog (alpha: sun visibility), the image after the fullscreen
//! apply, the final image, and the same frame with every surface black (only the
//! fog's in-scattering L remains). With fogged = surface * T + L, the per-pixel
//! transmittance is T = (fogged - L) / surface.

mod clouds;
mod fog;
mod frame;
mod lamp;
mod sky;
mod water;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use glam::{Mat4, UVec3, Vec3, Vec4};
use serde_json::Value;
use volfog::cpu::inject::froxel_world_position;
use volfog::uniforms::{FogFrame, Froxels};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 108;
const FRAMES: u32 = 3;

struct Run {
    dir: PathBuf,
    stdout: String,
    probe: Value,
}

/// Runs the demo once for every test in these modules.
fn run() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("demo_test");
        let _ = std::fs::remove_dir_all(&dir);
        let output = Command::new(env!("CARGO_BIN_EXE_volfog"))
            .args(["demo", "--out"])
            .arg(&dir)
            .args([
                "--width",
                &WIDTH.to_string(),
                "--height",
                &HEIGHT.to_string(),
                "--frames",
                &FRAMES.to_string(),
                "--probe",
            ])
            .env("MESA_SHADER_CACHE_DISABLE", "true")
            .output()
            .expect("the volfog binary starts");
        let stdout = String::from_utf8_lossy(&output.stdout).to_string();
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        eprintln!("{stdout}");
        assert!(
            output.status.success(),
            "volfog demo failed ({}):\n{stdout}\n{stderr}",
            output.status
        );
        let text = std::fs::read_to_string(dir.join("probe/probe.json")).expect("probe.json");
        let probe = serde_json::from_str(&text).expect("probe.json parses");
        Run { dir, stdout, probe }
    })
}

fn read_f32(run: &Run, name: &str) -> Vec<f32> {
    let bytes = std::fs::read(run.dir.join("probe").join(name)).expect("probe image");
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn read_rgba(run: &Run, name: &str) -> Vec<Vec4> {
    let values = read_f32(run, name);
    assert_eq!(
        values.len(),
        (WIDTH * HEIGHT * 4) as usize,
        "{name} holds one rgba texel per pixel"
    );
    values.chunks_exact(4).map(Vec4::from_slice).collect()
}

fn mat(v: &Value) -> Mat4 {
    let cols: Vec<f32> = v
        .as_array()
        .expect("matrix array")
        .iter()
        .map(|x| x.as_f64().expect("number") as f32)
        .collect();
    Mat4::from_cols_slice(&cols)
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is a number"))
}

fn median(mut v: Vec<f32>) -> f32 {
    assert!(!v.is_empty(), "median of nothing");
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn sum3(v: Vec4) -> f32 {
    v.x + v.y + v.z
}

fn vec3(v: &Value) -> Vec3 {
    let a: Vec<f32> = v
        .as_array()
        .expect("vector array")
        .iter()
        .map(|x| num(x) as f32)
        .collect();
    Vec3::from_slice(&a)
}

/// The integrated froxel volume of the last frame (rgb in-scatter, a transmittance)
/// with the froxels' placement, from the probe.
struct Volume {
    size: UVec3,
    froxels: Froxels,
    frame: FogFrame,
    texels: Vec<Vec4>,
}

impl Volume {
    fn read(run: &Run) -> Self {
        let p = &run.probe;
        let fog = &p["fog"];
        let size = UVec3::from_slice(
            &fog["volume_size"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap() as u32)
                .collect::<Vec<_>>(),
        );
        let froxels = Froxels::new(
            mat(&p["camera"]["clip_from_view"]),
            size,
            num(&fog["near"]) as f32,
            num(&fog["far"]) as f32,
            num(&fog["slice_curve"]) as f32,
        )
        .expect("valid froxels");
        let frame = FogFrame {
            world_from_view: mat(&p["camera"]["view_from_world"]).inverse(),
            camera_position: vec3(&p["camera"]["position"]),
            ..FogFrame::default()
        };
        let texels: Vec<Vec4> = read_f32(run, "integrated.f32")
            .chunks_exact(4)
            .map(Vec4::from_slice)
            .collect();
        assert_eq!(texels.len() as u32, size.x * size.y * size.z);
        Self {
            size,
            froxels,
            frame,
            texels,
        }
    }

    fn at(&self, x: u32, y: u32, z: u32) -> Vec4 {
        let s = self.size;
        self.texels[((z * s.y + y) * s.x + x) as usize]
    }

    /// World position and view depth (m) of a froxel's centre.
    fn world(&self, x: u32, y: u32, z: u32) -> (Vec3, f32) {
        froxel_world_position(&self.froxels, &self.frame, UVec3::new(x, y, z), false)
    }

    /// The radiance froxel (x, y, z) scatters towards the eye, J = dL / (-dT) between
    /// slices z - 1 and z (the source function sigma_s L_in / sigma_t, independent of
    /// the density), where the slice has enough extinction to tell (culled froxels,
    /// behind the scene's surfaces, have none).
    fn scattered(&self, x: u32, y: u32, z: u32) -> Option<f32> {
        let (front, back) = (self.at(x, y, z - 1), self.at(x, y, z));
        let d_t = front.w - back.w;
        (d_t > 2e-3 * front.w).then(|| sum3(back - front) / d_t)
    }
}

/// World direction of each pixel (from the camera through the pixel's centre).
fn pixel_directions(run: &Run) -> Vec<Vec3> {
    let camera = &run.probe["camera"];
    let world_from_clip = mat(&camera["world_from_clip"]);
    (0..WIDTH * HEIGHT)
        .map(|i| {
            let ndc = glam::Vec2::new(
                ((i % WIDTH) as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                1.0 - ((i / WIDTH) as f32 + 0.5) / HEIGHT as f32 * 2.0,
            );
            let near = world_from_clip.project_point3(ndc.extend(0.0));
            let far = world_from_clip.project_point3(ndc.extend(1.0));
            (far - near).normalize()
        })
        .collect()
}

//! GPU self-check: runs the passes on the selected adapter and compares them with
//! independent answers (closed forms) and with the CPU mirror. `volfog selfcheck`
//! prints the report; the tests call the same runners with their own bounds.
//!
//! Shared here: the self-check's camera and froxels, f16 rounding, the report and
//! the list of checks it runs; each pass checked has its own module.

mod apply;
mod depth;
mod epipolar;
mod esm;
mod local_shadow;
mod scan;

use glam::{Mat4, UVec3, Vec4};
use wgpu::util::DeviceExt;

use volfog::options::{Filtering, ScanStep};
use volfog::uniforms::Froxels;

use crate::gpu::{Gpu, GpuError};

pub use apply::{ApplyCase, max_abs_diff, run_apply};
pub use depth::{depth_array_texture, depth_texture, write_f32_layer};
pub use epipolar::{EpipolarCheck, epipolar_check};
pub use esm::run_esm;
pub use local_shadow::{LocalShadowCheck, local_shadow_check};
pub use scan::{
    ScanError, cpu_scan, homogeneous, homogeneous_closed_form, live_slices_texture, run_scan,
    run_scan_culled, scan_vs_closed_form,
};

/// The camera used by the self-check: 60 degree vertical field of view, 16:9,
/// standard depth with near 0.1 m and far 1000 m.
pub fn test_projection() -> Mat4 {
    glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 0.1, 1000.0)
}

/// A froxel placement over `test_projection` with `slices` exponential slices from
/// 0.5 m to 128 m and `xy` froxels across the screen.
pub fn test_froxels(xy: [u32; 2], slices: u32) -> Froxels {
    Froxels::new(
        test_projection(),
        UVec3::new(xy[0], xy[1], slices),
        0.5,
        128.0,
        (128.0f32 / 0.5).ln(),
    )
    .expect("valid test froxels")
}

/// Rounds each component to the nearest f16, as an rgba16float texture stores it.
pub fn round_f16(v: Vec4) -> Vec4 {
    Vec4::from_array(v.to_array().map(|c| half::f16::from_f32(c).to_f32()))
}

fn uniform_buffer(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// The self-check report.
#[derive(Debug, Clone)]
pub struct Report {
    /// Adapter description.
    pub adapter: String,
    /// Scan errors against the closed form, per slice count and step.
    pub scan: Vec<ScanError>,
    /// Apply pass (sampler) vs CPU: largest absolute difference.
    pub apply_sampler: f32,
    /// Apply pass (manual filtering) vs CPU: largest absolute difference.
    pub apply_manual: f32,
    /// Epipolar sun shafts.
    pub epipolar: EpipolarCheck,
    /// The local-light shadow atlas.
    pub local_shadow: LocalShadowCheck,
}

/// Runs the self-check on an adapter.
pub fn run(gpu: &Gpu) -> Result<Report, GpuError> {
    let mut scan = Vec::new();
    for slices in [32, 64, 128] {
        for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
            scan.push(scan_vs_closed_form(gpu, step, slices, 0.03)?);
        }
    }
    let case = ApplyCase::synthetic(96, 54);
    let expected = case.expected();
    let apply_sampler = max_abs_diff(&run_apply(gpu, Filtering::Sampler, &case)?, &expected);
    let apply_manual = max_abs_diff(&run_apply(gpu, Filtering::Manual, &case)?, &expected);
    Ok(Report {
        adapter: gpu.describe(),
        scan,
        apply_sampler,
        apply_manual,
        epipolar: epipolar_check(gpu)?,
        local_shadow: local_shadow_check(gpu)?,
    })
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "adapter: {}", self.adapter)?;
        writeln!(
            f,
            "scan of homogeneous fog (sigma_t = 0.03/m, 0.5..128 m) vs closed form, max relative error:"
        )?;
        writeln!(f, "  slices  step               in-scatter   transmittance")?;
        for e in &self.scan {
            writeln!(
                f,
                "  {:>6}  {:<17}  {:>9.4}%  {:>12.4}%",
                e.slices,
                format!("{:?}", e.step),
                e.inscatter * 100.0,
                e.transmittance * 100.0
            )?;
        }
        writeln!(
            f,
            "apply pass vs CPU (color * T + L), max abs difference: sampler {:.2e}, manual filtering {:.2e}",
            self.apply_sampler, self.apply_manual
        )?;
        let e = &self.epipolar;
        writeln!(
            f,
            "epipolar shafts: unshadowed lit fraction vs 1, max {:.2e}; tree march vs every section, max {:.2e} over {} partly shadowed samples",
            e.unshadowed, e.tree_vs_steps, e.partly_shadowed
        )?;
        let l = &self.local_shadow;
        writeln!(
            f,
            "local-light shadow atlas (a point light in a closed room, c = {}): texels vs exp(c d / range), max relative {:.2e}; visibility 3 range / c behind the wall {:.4} (closed form exp(-3) = {:.4}), in front min {:.4} (1)",
            l.exponent,
            l.atlas,
            l.behind,
            (-3.0f32).exp(),
            l.in_front
        )
    }
}

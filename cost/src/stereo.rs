//! Stereo fog's frame (`volfog::pipeline::StereoFog`): the shared fog's passes once
//! (the shadows, inject and, where it runs apart, temporal), over one volume aligned
//! with a centre eye that encloses both eyes; then per eye the scan's
//! `VOLFOG_SCAN_RESAMPLE` variant, which reads the shared volume trilinearly at each of
//! the eye's froxel centres and writes the eye's integrated volume, and the eye's apply.
//! Stereo fog culls no froxels by depth and runs no transient lights, so its frame is
//! that of its configuration with both off ([`stereo_config`]).

use volfog::pipeline::FogConfig;
use volfog::pipeline::scan::resample_defines;

use crate::frame::{FramePass, RuntimeVariant, frame_passes, runtime_variants};
use crate::workload::Workload;

/// When the runtime runs the resampling scan.
pub const STEREO_WHEN: &str = "stereo fog (StereoFog): each eye's scan of the shared volume";

/// The eyes, in the order stereo fog records them.
pub const EYES: [&str; 2] = ["left eye", "right eye"];

/// The configuration `StereoFog::new` builds its shared fog with from `config`: no
/// depth culling, no transient lights.
pub fn stereo_config(config: &FogConfig) -> FogConfig {
    FogConfig {
        depth_cull: false,
        max_transient_lights: 0,
        ..config.clone()
    }
}

/// The resampling scan variant `StereoFog::new` builds for `config` (it never culls).
pub fn resample_variant(config: &FogConfig) -> RuntimeVariant {
    RuntimeVariant::new(
        "scan",
        resample_defines(config.scan_step, false),
        STEREO_WHEN,
    )
}

/// Every variant stereo fog builds pipelines from for `config`: the shared fog's
/// (that of [`stereo_config`], whose own scan is built but not run) and the eyes'
/// resampling scan.
pub fn stereo_variants(config: &FogConfig) -> Vec<RuntimeVariant> {
    let mut v = runtime_variants(&stereo_config(config));
    v.push(resample_variant(config));
    v
}

/// The passes of one stereo frame of `config` over `shared_work` (the frame as the
/// shared volume sees it, from the centre eye, without culling): the shared passes in
/// the order the runtime records them, then each eye's resampling scan, then each
/// eye's apply. The scans' shared volume (binding `scattering`) is sized explicitly:
/// one whole volume of `config.volume_size`, which both eyes' froxels cover.
pub fn stereo_frame_passes(config: &FogConfig, shared_work: &Workload) -> Vec<FramePass> {
    let config = stereo_config(config);
    let all = frame_passes(&config, shared_work);
    let v = config.volume_size;
    let volume = u64::from(v.x) * u64::from(v.y) * u64::from(v.z) * 8;
    let mut passes: Vec<FramePass> = all
        .iter()
        .filter(|p| p.name != "scan" && p.name != "apply")
        .cloned()
        .collect();
    let scan = all
        .iter()
        .find(|p| p.name == "scan")
        .expect("every frame scans");
    let apply = all
        .iter()
        .find(|p| p.name == "apply")
        .expect("every frame applies");
    for eye in EYES {
        let mut s = scan.clone();
        s.name = format!("scan, {eye}");
        s.ac4 = None;
        s.variant = resample_variant(&config);
        s.culled = false;
        s.binding_bytes = vec![("scattering".to_string(), volume)];
        passes.push(s);
    }
    for eye in EYES {
        let mut a = apply.clone();
        a.name = format!("apply, {eye}");
        a.ac4 = None;
        passes.push(a);
    }
    passes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loops::loops;

    /// Every loop of the resampling scan, counted through its calls, has a trip count
    /// in [`stereo_frame_passes`]; the frame runs the shared passes once and the scan
    /// and apply per eye.
    #[test]
    fn every_loop_of_the_resampling_scan_has_a_trip_count() {
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 100.0);
        let froxels =
            volfog::uniforms::Froxels::new(projection, glam::UVec3::new(16, 9, 32), 0.5, 64.0, 3.0)
                .unwrap();
        let work = Workload::of(
            &crate::workload::SceneFrame {
                froxels: &froxels,
                world_from_view: glam::Mat4::IDENTITY,
                lights: &[],
                shadowed_lights: &[],
                local_volumes: &[],
                cascades: (glam::Vec4::new(4.0, 8.0, 16.0, 64.0), 4),
                live_slices: None,
                screen: (160, 90),
                far_tail: false,
                shadow_taps: 1,
            },
            128,
        );
        let config = FogConfig::default();
        let passes = stereo_frame_passes(&config, &work);
        let names: Vec<&str> = passes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "inject",
                "scan, left eye",
                "scan, right eye",
                "apply, left eye",
                "apply, right eye"
            ]
        );
        let scan = &passes[1];
        assert!(scan.variant.name().contains("SCAN_RESAMPLE"));
        assert!(!scan.culled);
        // The shared volume has the configuration's grid.
        assert_eq!(
            scan.binding_bytes,
            [("scattering".to_string(), 160 * 90 * 128 * 8)]
        );
        assert!(
            stereo_variants(&config)
                .iter()
                .any(|v| v.name() == scan.variant.name())
        );
        let module = volfog::shaders::compose("scan", &scan.variant.defines).unwrap();
        for l in &loops(&module, "scan").unwrap() {
            assert!(
                scan.trips
                    .iter()
                    .any(|(k, _)| l.label.starts_with(k.as_str())),
                "{}: no trip count among {:?}",
                l.label,
                scan.trips
            );
        }
    }
}

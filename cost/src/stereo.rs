//! Stereo fog's frame (`volfog::pipeline::StereoFog`): the shared fog's passes once
//! (the shadows, inject and, where it runs apart, temporal), over one volume aligned
//! with a centre eye that encloses both eyes; then the scan's `VOLFOG_SCAN_RESAMPLE`
//! variant, one dispatch for both eyes, which reads the shared volume trilinearly at
//! each of an eye's froxel centres and writes that eye's integrated volume; then each
//! eye's apply.
//! Stereo fog culls no froxels by depth and runs no transient lights, so its frame is
//! that of its configuration with both off ([`stereo_config`]).

use volfog::pipeline::FogConfig;
use volfog::pipeline::scan::{RESAMPLE_WORKGROUP_Y, WORKGROUP, resample_defines};

use crate::frame::{FramePass, RuntimeVariant, frame_passes, runtime_variants};
use crate::workload::Workload;

/// When the runtime runs the resampling scan.
pub const STEREO_WHEN: &str = "stereo fog (StereoFog): both eyes' scan of the shared volume";

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
/// the order the runtime records them, then the resampling scan of both eyes, then
/// each eye's apply. The scan's textures are sized explicitly, each one whole volume of
/// `config.volume_size`: the shared volume (binding `scattering`), which both eyes'
/// froxels cover and whose texels a wave's two eyes read together (one fetch from
/// memory), and the eyes' integrated volumes (`integrated`, `right_integrated`). Its
/// invocations are its dispatch's: workgroups of 8 x 4 columns x 2 eyes.
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
    let mut s = scan.clone();
    s.name = "scan, both eyes".to_string();
    s.ac4 = None;
    s.variant = resample_variant(&config);
    s.culled = false;
    s.invocations = f64::from(v.x.div_ceil(WORKGROUP) * WORKGROUP)
        * f64::from(v.y.div_ceil(RESAMPLE_WORKGROUP_Y) * RESAMPLE_WORKGROUP_Y)
        * 2.0;
    s.binding_bytes = ["scattering", "integrated", "right_integrated"]
        .map(|name| (name.to_string(), volume))
        .to_vec();
    passes.push(s);
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
    /// of both eyes once and the apply per eye.
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
                "scan, both eyes",
                "apply, left eye",
                "apply, right eye"
            ]
        );
        let scan = &passes[1];
        assert!(scan.variant.name().contains("SCAN_RESAMPLE"));
        assert!(!scan.culled);
        // The shared volume and both eyes' volumes have the configuration's grid, and
        // they are every texture the scan touches: each is read or written once.
        let volume = 160 * 90 * 128 * 8;
        assert_eq!(
            scan.binding_bytes,
            ["scattering", "integrated", "right_integrated"].map(|n| (n.to_string(), volume))
        );
        let module = volfog::shaders::compose("scan", &scan.variant.defines).unwrap();
        let moved = crate::floor::traffic(
            &module,
            &["scan"],
            &|name| {
                scan.binding_bytes
                    .iter()
                    .find(|(n, _)| n == name)
                    .map_or(0, |(_, b)| *b)
            },
            (0, 0),
        );
        assert_eq!(
            (moved.bytes_read, moved.bytes_written),
            (volume, 2 * volume)
        );
        // Workgroups of 8 x 4 columns for both eyes: 160 x 92 columns, twice.
        assert_eq!(scan.invocations, 160.0 * 92.0 * 2.0);
        assert!(
            stereo_variants(&config)
                .iter()
                .any(|v| v.name() == scan.variant.name())
        );
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

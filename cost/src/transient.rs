//! The scan of a frame with transient lights (`FrameInputs::transient_lights`): the
//! runtime builds the scan's `VOLFOG_SCAN_TRANSIENT_LIGHTS` variant beside the plain one
//! (`FogConfig::max_transient_lights` > 0) and runs it on frames with transient lights.
//! Every live froxel evaluates every transient light (they are not culled), so the
//! light loop runs the frame's transient light count at each iteration of the slice
//! loop.

use volfog::pipeline::FogConfig;
use volfog::pipeline::scan::scan_defines;

use crate::frame::{FramePass, RuntimeVariant, frame_passes};
use crate::workload::Workload;

/// When the runtime runs the transient scan.
pub const TRANSIENT_WHEN: &str = "frames with transient lights";

/// The label of the transient light loop (`transient_inscatter` of `scan.wgsl`).
pub const TRANSIENT_LOOP: &str = "transient_inscatter: i < count";

/// The scan variant the runtime builds for frames with transient lights, if `config`
/// has room for any.
pub fn transient_variant(config: &FogConfig) -> Option<RuntimeVariant> {
    (config.max_transient_lights > 0).then(|| {
        RuntimeVariant::new(
            "scan",
            scan_defines(config.scan_step, config.depth_cull, true),
            TRANSIENT_WHEN,
        )
    })
}

/// The scan of `work`'s frame with `lights` transient lights: the plain scan's
/// dispatch, traffic and slice loops, the transient variant, and the light loop's trip
/// count. `None` when `config` builds no transient scan.
pub fn transient_scan(config: &FogConfig, work: &Workload, lights: u32) -> Option<FramePass> {
    let variant = transient_variant(config)?;
    let mut scan = frame_passes(config, work)
        .into_iter()
        .find(|p| p.name == "scan")
        .expect("every frame scans");
    scan.name = format!("scan, {lights} transient lights");
    scan.ac4 = None;
    scan.variant = variant;
    scan.trips
        .push((TRANSIENT_LOOP.to_string(), f64::from(lights)));
    Some(scan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loops::loops;

    /// Every loop of the transient scan, counted through its calls, has a trip count
    /// in [`transient_scan`]; the light loop runs inside the slice loop.
    #[test]
    fn every_loop_of_the_transient_scan_has_a_trip_count() {
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
        for config in [
            FogConfig::default(),
            FogConfig {
                depth_cull: false,
                ..FogConfig::default()
            },
        ] {
            let pass = transient_scan(&config, &work, 8).unwrap();
            assert!(pass.variant.name().contains("SCAN_TRANSIENT_LIGHTS"));
            let module = volfog::shaders::compose("scan", &pass.variant.defines).unwrap();
            let found = loops(&module, "scan").unwrap();
            for l in &found {
                assert!(
                    pass.trips
                        .iter()
                        .any(|(k, _)| l.label.starts_with(k.as_str())),
                    "{}: no trip count among {:?}",
                    l.label,
                    pass.trips
                );
            }
            let light = found
                .iter()
                .position(|l| l.label == TRANSIENT_LOOP)
                .unwrap();
            let parent = found[light].parent.expect("inside the slice loop");
            assert_eq!(found[parent].label, "scan: k < live");
            assert_eq!(pass.trips.last().unwrap().1, 8.0);
        }
        let none = FogConfig {
            max_transient_lights: 0,
            ..FogConfig::default()
        };
        assert!(transient_scan(&none, &work, 1).is_none());
    }
}

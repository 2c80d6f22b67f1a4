//! The medium's shadows of a frame (`FogConfig::medium_shadows`): the runtime builds
//! the `medium_shadow` pass, whose variant follows the medium defines of inject's, and
//! runs it every frame before inject, whose variant then reads its volume
//! (`VOLFOG_INJECT_MEDIUM_SHADOW`). One invocation per column of the volume walks its
//! slices, evaluating the medium at `MEDIUM_SHADOW_SUBSAMPLES` points a slice.

use volfog::pipeline::FogConfig;
use volfog::pipeline::medium_shadow::MediumShadowPass;

use crate::frame::{FramePass, RuntimeVariant};
use crate::workload::Workload;

/// When the runtime runs the pass.
pub const MEDIUM_SHADOW_WHEN: &str = "every frame (FogConfig::medium_shadows)";

/// Points per slice at which the pass evaluates the medium
/// (`volfog::cpu::medium_shadow::MEDIUM_SHADOW_SUBSAMPLES`).
const SUBSAMPLES: f64 = volfog::cpu::medium_shadow::MEDIUM_SHADOW_SUBSAMPLES as f64;

/// The pass's variant, if `config` has the medium's shadows.
pub fn medium_shadow_variant(config: &FogConfig) -> Option<RuntimeVariant> {
    config
        .medium_shadows
        .filter(|_| config.light_transmittance)
        .map(|_| {
            RuntimeVariant::new(
                "medium_shadow",
                MediumShadowPass::defines(&config.inject_options()),
                MEDIUM_SHADOW_WHEN,
            )
        })
}

/// The pass over `work`'s frame: a workgroup of 64 per column, the groups of 64 slices,
/// the six steps of the scan, the sub-sample loop, the local volumes evaluated at
/// every point (those that can reach the column: all of `work`'s, an upper bound) and
/// the four spheres a column's volume test takes; the volume it writes sized here.
pub fn medium_shadow_pass(config: &FogConfig, work: &Workload) -> Option<FramePass> {
    let variant = medium_shadow_variant(config)?;
    let m = config.medium_shadows.expect("the variant exists");
    let size = m.size;
    let volumes = f64::from(work.local_volumes);
    Some(FramePass {
        name: "medium shadow".to_string(),
        ac4: None,
        variant,
        entry: "medium_shadow_fill".to_string(),
        invocations: f64::from(size.x) * f64::from(size.y) * 64.0,
        culled: false,
        target: (0, 0),
        binding_bytes: vec![(MEDIUM_SHADOW_BINDING.to_string(), m.memory_bytes())],
        trips: vec![
            ("medium_shadow_fill: q < 4".to_string(), 4.0),
            (
                "medium_shadow_fill: base < size".to_string(),
                f64::from(size.z.div_ceil(64)),
            ),
            ("medium_shadow_fill: offset < ".to_string(), 6.0),
            ("medium_shadow_fill: j < ".to_string(), SUBSAMPLES),
            ("excess_extinction: i < volume_count".to_string(), volumes),
        ],
    })
}

/// The name of the volume's binding in the pass and in inject.
pub const MEDIUM_SHADOW_BINDING: &str = "medium_shadow_volume";

//! The pipelines of stereo fog's multiview path (`StereoFog::create_apply_multiview`):
//! the apply's `VOLFOG_APPLY_MULTIVIEW` variant, with and without the far-plane tail,
//! which draws both eyes in one multiview render pass. They are compiled with stereo
//! fog's other pipelines; the stereo frame's time model
//! ([`crate::stereo::stereo_frame_passes`]) draws the apply once per eye, as
//! `StereoFog::record_apply` does.

use volfog::pipeline::FogConfig;
use volfog::pipeline::apply::{MULTIVIEW_DEFINE, NO_TAIL_DEFINE};

use crate::frame::RuntimeVariant;

/// When the runtime builds the multiview apply.
pub const MULTIVIEW_WHEN: &str =
    "stereo fog's multiview apply, both eyes in one pass (create_apply_multiview)";

/// The multiview apply variants `StereoFog::create_apply_multiview` builds for
/// `config`: with the far-plane tail and without it.
pub fn multiview_apply_variants(config: &FogConfig) -> Vec<RuntimeVariant> {
    let mut with_tail = config.apply_filtering.defines();
    with_tail.push(MULTIVIEW_DEFINE.to_string());
    let mut no_tail = with_tail.clone();
    no_tail.push(NO_TAIL_DEFINE.to_string());
    vec![
        RuntimeVariant::new("apply", with_tail, MULTIVIEW_WHEN),
        RuntimeVariant::new("apply", no_tail, MULTIVIEW_WHEN),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multiview_apply_variants_are_prebuilt_and_compose() {
        for v in multiview_apply_variants(&FogConfig::default()) {
            assert!(
                volfog_codegen::manifest::variant(&v.name()).is_some(),
                "{} is a prebuilt variant",
                v.name()
            );
            volfog::shaders::compose(v.pass, &v.defines).unwrap();
        }
    }
}

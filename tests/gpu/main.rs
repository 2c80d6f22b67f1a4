//! The GPU tests: every module and pass dispatched on one shared device and compared
//! with the CPU mirror and with independent answers (closed forms, numerical
//! integration), and the `VolumetricFog` object run frame by frame. Without an adapter
//! every test fails with the command that installs Mesa's lavapipe.

mod apply;
mod area_lights;
mod clouds;
mod culling;
mod epipolar;
mod esm;
mod far_plane_seam;
mod fog_lit;
mod fog_volume;
mod forward_snippet;
mod frustum;
mod fused_temporal;
mod guide_example;
mod height_fog;
mod height_fog_lit;
mod hull;
mod inject;
mod js_host;
mod lightning;
mod local_shadow;
mod medium_shadow;
mod msaa;
mod noise;
mod particles;
mod phase;
mod pipeline;
mod properties;
mod scan;
mod shadow_filter;
mod shared_fog;
mod sky;
mod soft_particles;
mod stereo;
mod temporal;
mod transient;
mod transparent;
mod truth;
mod truth_area;
mod truth_volfog;
mod water;

/// What the test modules share: the device, kernels, inputs and the small scene.
mod common {
    pub use volfog_testkit::kernel::{compose, run_f32};
    pub use volfog_testkit::rng::{Rng, rel_err};
    pub use volfog_testkit::scene;

    /// The shared device (the test fails with the install command without one).
    pub fn gpu() -> &'static volfog_testkit::Gpu {
        volfog_testkit::Gpu::shared()
    }
}

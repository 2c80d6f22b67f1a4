//! `vkcheck`: raw Vulkan (through [`ash`]) with the Khronos validation layer, for volfog's tests.
//!
//! Three uses:
//!
//! * **Layout checks** — [`Validator::compute_pipeline`] and [`Validator::graphics_pipeline`]
//!   build a pipeline from SPIR-V plus the descriptor set layouts the caller says it will use,
//!   destroy it again, and return every WARNING / ERROR message the validation layer produced
//!   meanwhile. An empty vector means the layer found nothing to complain about; a shader that
//!   uses a binding the layout lacks, or declares it with another descriptor type or stage,
//!   yields messages such as `VUID-VkComputePipelineCreateInfo-layout-00703` (VUIDs and wording
//!   differ between layer versions, so tests should assert that messages exist, not their text).
//! * **Running compute shaders** from other compilers (Slang, glslang, naga) —
//!   [`Validator::run_compute`] binds an input and an output storage buffer, dispatches, and
//!   returns the output bytes so that numbers can be compared across compilers.
//! * **A driver's compiler statistics** — [`StatsDevice`] builds the same pipelines without
//!   the layer on a device with `VK_KHR_pipeline_executable_properties` and returns what the
//!   driver reports per shader (for Mesa's RADV: registers, spills, occupancy, instruction
//!   count, ACO's cycle estimates, and its IR on request). RADV's null device
//!   (`RADV_FORCE_FAMILY=<chip>`) compiles for an AMD GPU that is not there.
//!
//! It is meant for lavapipe (Mesa's CPU Vulkan driver) on CI machines without a GPU, but works
//! on any Vulkan 1.3 device (or 1.2 with `VK_KHR_dynamic_rendering`). Requirements (Debian):
//!
//! ```text
//! apt-get install -y mesa-vulkan-drivers libvulkan1 vulkan-validationlayers
//! ```
//!
//! The loader `libvulkan.so.1` is opened at run time (`ash`'s `loaded` feature), so building
//! needs none of these; [`Validator::new`] reports what is missing with the command that installs it.
//!
//! # Validation errors stop the call
//!
//! The debug-utils callback returns `VK_TRUE` for ERROR-severity *validation* messages. The
//! layer then skips the offending call and returns `VK_ERROR_VALIDATION_FAILED_EXT` instead of
//! passing invalid input to the driver (lavapipe 22.3.6 segfaults on, e.g., a compute pipeline
//! whose layout lacks a binding the shader uses). The pipeline checks treat such a skipped call as
//! the expected outcome and return the messages; [`Validator::run_compute`] returns an error
//! holding them. While the device is being destroyed nothing is refused, so a leak report cannot
//! stop `vkDestroyDevice` itself.
//!
//! # Environment
//!
//! * `WGPU_ADAPTER_NAME` — case-insensitive substring of the device name to use (same variable
//!   as volfog's wgpu tests); unset or empty: the first device.
//! * `MESA_SHADER_CACHE_DISABLE=true` — what CI sets; recommended so lavapipe compiles every
//!   pipeline afresh and writes no cache under `$HOME`.

#![warn(missing_docs)]

mod desc;
mod error;
mod scratch;
mod spirv;
mod stats;
mod validator;

pub use ash::vk;
pub use desc::*;
pub use error::*;
pub use spirv::local_size;
pub use stats::*;
pub use validator::*;

pub(crate) use scratch::*;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_selection() {
        let names = vec![
            "NVIDIA GeForce RTX 4090".to_owned(),
            "llvmpipe (LLVM 15.0.6, 256 bits)".to_owned(),
        ];
        assert_eq!(select_device(&names, None), Some(0));
        assert_eq!(select_device(&names, Some("LLVMpipe")), Some(1));
        assert_eq!(select_device(&names, Some("rtx")), Some(0));
        assert_eq!(select_device(&names, Some("radv")), None);
        assert_eq!(select_device(&[], None), None);
    }

    #[test]
    fn stages_and_kinds_map_to_vulkan() {
        let s = Stages::VERTEX | Stages::FRAGMENT;
        assert_eq!(s, Stages::VERTEX_FRAGMENT);
        assert!(s.contains(Stages::FRAGMENT) && !s.contains(Stages::COMPUTE));
        assert_eq!(
            s.to_vk(),
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT
        );
        assert_eq!(Stages::NONE.to_vk(), vk::ShaderStageFlags::empty());
        assert_eq!(
            DescriptorKind::CombinedImageSampler.to_vk(),
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER
        );
    }

    #[test]
    fn validator_is_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<Validator>();
    }

    #[test]
    fn errors_name_the_install_command() {
        let e = VkError::NoDevice {
            requested: None,
            available: vec![],
        };
        assert!(e.to_string().contains(INSTALL_LAVAPIPE), "{e}");
        assert!(
            VkError::MissingLayer
                .to_string()
                .contains(INSTALL_VALIDATION_LAYER)
        );
    }
}

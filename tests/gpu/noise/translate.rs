//! The noise kernels, procedural and textured, translated to every target and checked
//! by the independent validators.

use super::EVAL_KERNEL;
use super::texture::TEXTURE_KERNEL;
use crate::common;

#[test]
fn noise_kernel_translates_to_every_target() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gpu_noise_translate");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, kernel) in [("noise", EVAL_KERNEL), ("noise_texture", TEXTURE_KERNEL)] {
        let module = common::compose(kernel, &[]);
        let entries = volfog_codegen::translate::translate(
            &format!("{name}_test"),
            module,
            &Default::default(),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(entries.len(), 1);
        let entry = &entries[0];
        for (target, text) in [
            ("wgsl", &entry.wgsl),
            ("glsl", &entry.glsl),
            ("hlsl", &entry.hlsl),
            ("msl", &entry.msl),
        ] {
            // The permutation travels as a table in the shader (first word 0x5b89a097).
            assert!(
                text.contains("1535746199") || text.contains("0x5b89a097"),
                "{name} {target}: no permutation table"
            );
        }
        let spv = dir.join(format!("{name}.spv"));
        std::fs::write(&spv, entry.bytes(volfog_codegen::Target::Spirv)).unwrap();
        let glsl = dir.join(format!("{name}.comp"));
        std::fs::write(&glsl, &entry.glsl).unwrap();
        // Kept beside them for review: there is no HLSL or MSL compiler here.
        std::fs::write(dir.join(format!("{name}.hlsl")), &entry.hlsl).unwrap();
        std::fs::write(dir.join(format!("{name}.metal")), &entry.msl).unwrap();
        const HINT: &str = "apt-get update && apt-get install -y spirv-tools glslang-tools";
        for (tool, args) in [
            (
                "spirv-val",
                vec!["--target-env", "vulkan1.1", spv.to_str().unwrap()],
            ),
            ("glslangValidator", vec![glsl.to_str().unwrap()]),
        ] {
            let o = std::process::Command::new(tool)
                .args(&args)
                .output()
                .unwrap_or_else(|_| panic!("{tool} is not installed; install it with: {HINT}"));
            assert!(
                o.status.success(),
                "{name}: {tool}: {}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
        }
    }
}

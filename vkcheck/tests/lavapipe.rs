//! vkcheck on the real Vulkan stack (lavapipe + Khronos validation layer), with shaders compiled
//! from GLSL by `glslangValidator` at test time.
//!
//! Needs: `apt-get install -y mesa-vulkan-drivers libvulkan1 glslang-tools spirv-tools vulkan-validationlayers`.
//! A missing tool or layer fails the test with that command; nothing is skipped.
//! CI runs with `MESA_SHADER_CACHE_DISABLE=true`; [`setup`] sets it when it is unset so local
//! runs behave the same.

use std::path::PathBuf;
use std::process::Command;
use std::sync::Once;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use vkcheck::{
    Blend, DescriptorBinding, DescriptorKind, GraphicsDesc, ShaderEntry, Stages, Validator,
    VertexAttribute, VertexBuffer, vk,
};

const INSTALL: &str = "apt-get install -y glslang-tools spirv-tools vulkan-validationlayers";

/// Sets `MESA_SHADER_CACHE_DISABLE=true` (as CI does) once, before any test touches Vulkan.
fn setup() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("MESA_SHADER_CACHE_DISABLE").is_none() {
            // SAFETY: every test calls `setup()` before anything else, and `Once` blocks the
            // other test threads until this returns, so no thread reads the environment now.
            unsafe { std::env::set_var("MESA_SHADER_CACHE_DISABLE", "true") };
        }
    });
}

/// A validator on the default (or `WGPU_ADAPTER_NAME`) device; fails with the install command.
fn validator() -> Validator {
    setup();
    let v = Validator::new().unwrap_or_else(|e| panic!("{e}"));
    assert!(
        v.creation_messages().is_empty(),
        "messages while creating the device: {:#?}",
        v.creation_messages()
    );
    v
}

/// Compiles GLSL `source` for `stage` (`comp`, `vert`, `frag`) with `glslangValidator -V`.
fn glsl(stage: &str, source: &str) -> Vec<u32> {
    setup();
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("vkcheck-glsl");
    std::fs::create_dir_all(&dir).unwrap();
    let stem = format!(
        "{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    );
    let src = dir.join(format!("{stem}.{stage}"));
    let out = dir.join(format!("{stem}.{stage}.spv"));
    std::fs::write(&src, source).unwrap();
    let result = Command::new("glslangValidator")
        .arg("-V")
        .arg("-o")
        .arg(&out)
        .arg(&src)
        .output()
        .unwrap_or_else(|e| panic!("cannot run glslangValidator ({e}); install it: {INSTALL}"));
    assert!(
        result.status.success(),
        "glslangValidator failed on {}:\n{}{}",
        src.display(),
        String::from_utf8_lossy(&result.stdout),
        String::from_utf8_lossy(&result.stderr)
    );
    let bytes = std::fs::read(&out).unwrap();
    let _ = std::fs::remove_file(&src);
    let _ = std::fs::remove_file(&out);
    assert_eq!(bytes.len() % 4, 0);
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Reads `src` into set 0 binding 0, writes `2 * src` to set 0 binding 1.
const DOUBLE: &str = r#"#version 450
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) readonly buffer Src { float v[]; } src;
layout(set = 0, binding = 1) buffer Dst { float v[]; } dst;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < src.v.length()) {
        dst.v[i] = 2.0 * src.v[i];
    }
}
"#;

fn storage(binding: u32) -> DescriptorBinding {
    DescriptorBinding::new(binding, DescriptorKind::StorageBuffer, Stages::COMPUTE)
}

fn report(label: &str, messages: &[String]) {
    eprintln!("--- {label}: {} message(s)", messages.len());
    for m in messages {
        eprintln!("  {m}");
    }
}

#[test]
fn run_compute_doubles_floats() {
    let spirv = glsl("comp", DOUBLE);
    assert_eq!(vkcheck::local_size(&spirv, "main").unwrap(), [64, 1, 1]);
    let v = validator();
    eprintln!("device: {}", v.device_name());

    // 100 invocations: two workgroups of 64, the shader guards the last 28.
    let input: Vec<f32> = (0..100).map(|i| i as f32 * 0.5 - 7.25).collect();
    let bytes: Vec<u8> = input.iter().flat_map(|f| f.to_le_bytes()).collect();
    let started = Instant::now();
    let (out, messages) = v
        .run_compute(&spirv, "main", &bytes, bytes.len() + 16, 100)
        .unwrap();
    eprintln!("run_compute: {:?}", started.elapsed());
    assert_eq!(messages, Vec::<String>::new());
    assert_eq!(out.len(), bytes.len() + 16);
    let got: Vec<f32> = out
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let want: Vec<f32> = input.iter().map(|x| 2.0 * x).collect();
    assert_eq!(&got[..100], &want[..]);
    assert_eq!(&got[100..], &[0.0; 4], "bytes past the input stay zero");

    // A second run on the same validator starts from fresh, zeroed buffers.
    let (out, messages) = v.run_compute(&spirv, "main", &bytes[..8], 8, 64).unwrap();
    assert!(messages.is_empty(), "{messages:#?}");
    let want: Vec<u8> = input[..2]
        .iter()
        .flat_map(|x| (2.0 * x).to_le_bytes())
        .collect();
    assert_eq!(out, want);

    let leaks = v.close();
    assert!(leaks.is_empty(), "teardown messages: {leaks:#?}");
}

#[test]
fn run_compute_with_specialised_workgroup_size() {
    // `local_size_x_id` makes glslang emit a WorkgroupSize built-in made of a spec constant
    // (default 32, the value given alongside); it takes precedence over `LocalSize`.
    let source = DOUBLE.replace(
        "local_size_x = 64",
        "local_size_x_id = 0, local_size_x = 32",
    );
    let spirv = glsl("comp", &source);
    assert_eq!(vkcheck::local_size(&spirv, "main").unwrap(), [32, 1, 1]);
    let v = validator();
    let input: Vec<u8> = (0..33u32).flat_map(|i| (i as f32).to_le_bytes()).collect();
    let (out, messages) = v
        .run_compute(&spirv, "main", &input, input.len(), 33)
        .unwrap();
    assert!(messages.is_empty(), "{messages:#?}");
    let last = f32::from_le_bytes(out[128..132].try_into().unwrap());
    assert_eq!(last, 64.0);
}

#[test]
fn wrong_compute_layout_is_reported() {
    let spirv = glsl("comp", DOUBLE);
    let v = validator();

    let correct = v
        .compute_pipeline(&spirv, "main", &[vec![storage(0), storage(1)]])
        .unwrap();
    assert_eq!(correct, Vec::<String>::new(), "the correct layout is clean");

    let uniform_at_1 = v
        .compute_pipeline(
            &spirv,
            "main",
            &[vec![
                storage(0),
                DescriptorBinding::new(1, DescriptorKind::UniformBuffer, Stages::COMPUTE),
            ]],
        )
        .unwrap();
    report("uniform buffer declared at binding 1", &uniform_at_1);
    assert!(!uniform_at_1.is_empty());

    let missing_1 = v
        .compute_pipeline(&spirv, "main", &[vec![storage(0)]])
        .unwrap();
    report("binding 1 omitted", &missing_1);
    assert!(!missing_1.is_empty());

    let wrong_stage = v
        .compute_pipeline(
            &spirv,
            "main",
            &[vec![
                storage(0),
                DescriptorBinding::new(1, DescriptorKind::StorageBuffer, Stages::FRAGMENT),
            ]],
        )
        .unwrap();
    report("binding 1 visible to the fragment stage only", &wrong_stage);
    assert!(!wrong_stage.is_empty());

    let no_sets = v.compute_pipeline(&spirv, "main", &[]).unwrap();
    report("no descriptor sets at all", &no_sets);
    assert!(!no_sets.is_empty());

    // After the failures the same validator still reports the correct layout as clean.
    assert!(
        v.compute_pipeline(&spirv, "main", &[vec![storage(0), storage(1)]])
            .unwrap()
            .is_empty()
    );

    // run_compute refuses a shader whose bindings do not match its fixed layout.
    let elsewhere = glsl("comp", &DOUBLE.replace("binding = 1", "binding = 2"));
    let err = v
        .run_compute(&elsewhere, "main", &[0; 16], 16, 4)
        .unwrap_err();
    eprintln!("--- run_compute with the output at binding 2: {err}");
    assert!(
        matches!(
            err,
            vkcheck::VkError::Vulkan {
                result: vk::Result::ERROR_VALIDATION_FAILED_EXT,
                ..
            }
        ),
        "{err}"
    );

    let leaks = v.close();
    assert!(leaks.is_empty(), "teardown messages: {leaks:#?}");
}

#[test]
fn empty_sets_before_the_used_one() {
    let spirv = glsl("comp", &DOUBLE.replace("set = 0", "set = 2"));
    let v = validator();
    let messages = v
        .compute_pipeline(
            &spirv,
            "main",
            &[vec![], vec![], vec![storage(0), storage(1)]],
        )
        .unwrap();
    assert_eq!(messages, Vec::<String>::new());
}

#[test]
fn invalid_spirv_and_entry_are_reported() {
    let spirv = glsl("comp", DOUBLE);
    let v = validator();
    let set = [vec![storage(0), storage(1)]];

    let wrong_entry = v.compute_pipeline(&spirv, "not_main", &set).unwrap();
    report("entry point that does not exist", &wrong_entry);
    assert!(!wrong_entry.is_empty());

    let mut corrupt = spirv.clone();
    corrupt.truncate(corrupt.len() - 3);
    let corrupt_messages = v.compute_pipeline(&corrupt, "main", &set).unwrap();
    report("truncated SPIR-V", &corrupt_messages);
    assert!(!corrupt_messages.is_empty());

    assert!(v.run_compute(&spirv, "not_main", &[], 4, 1).is_err());
    assert!(v.compute_pipeline(&spirv, "ma\0in", &set).is_err());
}

const VERT: &str = r#"#version 450
layout(set = 0, binding = 0) uniform Globals { mat4 view_proj; vec4 tint; } globals;
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 uv;
layout(location = 0) out vec2 v_uv;
void main() {
    v_uv = uv;
    gl_Position = globals.view_proj * vec4(position, 1.0);
}
"#;

const FRAG: &str = r#"#version 450
layout(set = 0, binding = 0) uniform Globals { mat4 view_proj; vec4 tint; } globals;
layout(set = 0, binding = 1) uniform sampler2D tex;
layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 color;
void main() {
    color = texture(tex, v_uv) * globals.tint;
}
"#;

#[test]
fn graphics_pipeline_layouts() {
    let vert = glsl("vert", VERT);
    let frag = glsl("frag", FRAG);
    let v = validator();
    let vertex_buffers = [VertexBuffer {
        stride: 20,
        per_instance: false,
        attributes: vec![
            VertexAttribute {
                location: 0,
                format: vk::Format::R32G32B32_SFLOAT,
                offset: 0,
            },
            VertexAttribute {
                location: 1,
                format: vk::Format::R32G32_SFLOAT,
                offset: 12,
            },
        ],
    }];
    let good_sets = [vec![
        DescriptorBinding::new(0, DescriptorKind::UniformBuffer, Stages::VERTEX_FRAGMENT),
        DescriptorBinding::new(1, DescriptorKind::CombinedImageSampler, Stages::FRAGMENT),
    ]];
    let desc = GraphicsDesc {
        vertex: ShaderEntry {
            spirv: &vert,
            entry: "main",
        },
        fragment: ShaderEntry {
            spirv: &frag,
            entry: "main",
        },
        sets: &good_sets,
        vertex_buffers: &vertex_buffers,
        color_format: vk::Format::R8G8B8A8_UNORM,
        blend: Some(Blend::PREMULTIPLIED_ALPHA),
    };
    let started = Instant::now();
    let clean = v.graphics_pipeline(&desc).unwrap();
    eprintln!("graphics_pipeline: {:?}", started.elapsed());
    assert_eq!(clean, Vec::<String>::new());
    assert!(
        v.graphics_pipeline(&GraphicsDesc {
            blend: None,
            color_format: vk::Format::R16G16B16A16_SFLOAT,
            ..desc.clone()
        })
        .unwrap()
        .is_empty()
    );

    let sampled_not_combined = [vec![
        good_sets[0][0],
        DescriptorBinding::new(1, DescriptorKind::SampledImage, Stages::FRAGMENT),
    ]];
    let wrong_type = v
        .graphics_pipeline(&GraphicsDesc {
            sets: &sampled_not_combined,
            ..desc.clone()
        })
        .unwrap();
    report(
        "sampled image instead of combined image sampler",
        &wrong_type,
    );
    assert!(!wrong_type.is_empty());

    let vertex_only_uniform = [vec![
        DescriptorBinding::new(0, DescriptorKind::UniformBuffer, Stages::VERTEX),
        good_sets[0][1],
    ]];
    let wrong_stage = v
        .graphics_pipeline(&GraphicsDesc {
            sets: &vertex_only_uniform,
            ..desc.clone()
        })
        .unwrap();
    report(
        "uniform block not visible to the fragment stage",
        &wrong_stage,
    );
    assert!(!wrong_stage.is_empty());

    let missing_attribute = [VertexBuffer {
        attributes: vertex_buffers[0].attributes[..1].to_vec(),
        ..vertex_buffers[0].clone()
    }];
    let attr = v
        .graphics_pipeline(&GraphicsDesc {
            vertex_buffers: &missing_attribute,
            ..desc.clone()
        })
        .unwrap();
    report("vertex attribute at location 1 missing", &attr);

    let leaks = v.close();
    assert!(leaks.is_empty(), "teardown messages: {leaks:#?}");
}

#[test]
fn adapter_selection_by_name() {
    setup();
    let v = Validator::with_adapter(Some("LLVMPIPE")).unwrap_or_else(|e| panic!("{e}"));
    assert!(v.device_name().to_lowercase().contains("llvmpipe"));
    drop(v);
    let err = Validator::with_adapter(Some("no such adapter")).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("no such adapter") && text.contains("llvmpipe"),
        "{text}"
    );
}

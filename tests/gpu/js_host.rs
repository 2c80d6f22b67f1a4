//! A renderer in another language succeeds with the export alone: the JavaScript host in
//! `examples/webgpu-node` (Node + Dawn through the npm package `webgpu`, its OpenGL
//! backend on Mesa) runs inject, scan and apply from the exported WGSL and
//! `manifest.json`, packing every uniform and storage buffer from the manifest's struct
//! offsets and the uniform values serialized by member name. Its scattering volume,
//! integrated volume and fogged image match `VolumetricFog`'s on lavapipe for the same
//! inputs within fp16 tolerance.

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::{Vec3, Vec4};
use serde_json::json;
use volfog::cpu::ambient::AmbientSh;
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, HeightFog};
use volfog_codegen::Target;
use volfog_codegen::export::{ExportRequest, export};
use volfog_codegen::reflect::HlslSamplers;
use volfog_testkit::scene::{
    SLAB, lights, local_volumes, medium, overhead_sun, projection, read_esm, read_volume,
    shadow_map, small_config, view,
};

use crate::common::gpu;

const INSTALL: &str = "cargo xtask tools";

fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/webgpu-node")
}

fn f32_file(path: &Path, values: &[f32]) {
    std::fs::write(path, bytemuck::cast_slice::<f32, u8>(values)).unwrap();
}

fn read_f32(path: &Path) -> Vec<Vec4> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    bytemuck::cast_slice::<u8, f32>(&bytes)
        .chunks_exact(4)
        .map(Vec4::from_slice)
        .collect()
}

/// Worst |got - want| over `scale(want)`, where fp16 storage gives each value 2^-11
/// relative rounding: the error is measured against max(|want|, floor) per channel.
fn worst_relative(got: &[Vec4], want: &[Vec4], floor: f32) -> f32 {
    assert_eq!(got.len(), want.len());
    got.iter()
        .zip(want)
        .map(|(g, w)| {
            assert!(g.is_finite(), "non-finite value from the JS host: {g}");
            ((*g - *w).abs() / w.abs().max(Vec4::splat(floor))).max_element()
        })
        .fold(0.0, f32::max)
}

#[test]
fn the_js_host_runs_the_export_and_matches_the_rust_pipeline() {
    assert!(
        example_dir().join("node_modules/webgpu").is_dir(),
        "the example's npm package webgpu is not installed; install it with `{INSTALL}`"
    );
    let gpu = gpu();
    // The host runs the exported defaults: the ESM filter's passes.
    let config = FogConfig {
        shadow_filter: volfog::options::ShadowFilter::Esm,
        esm_log_space: false,
        depth_cull: false,
        local_shadows: None,
        ..small_config()
    };
    // The variants this configuration composes are the exported defaults.
    assert!(config.inject_options().defines().is_empty());
    assert!(config.scan_step.defines().is_empty());
    assert!(config.apply_filtering.defines().is_empty());

    let (cascades, depth_layers) = overhead_sun(&config, Some(SLAB));
    let lights = lights();
    let volumes = local_volumes();
    let medium = medium();
    let inputs = FrameInputs {
        medium,
        sun: DirectionalLight {
            direction: Vec3::new(0.2, 1.0, 0.1).normalize(),
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::sky_ground(
            Vec3::new(0.2, 0.3, 0.5),
            Vec3::new(0.05, 0.04, 0.03),
            Vec3::Y,
        ),
        lights: &lights,
        local_volumes: &volumes,
        cascades,
        tail: HeightFog::from_medium(&medium, Vec3::splat(0.2)),
        ..FrameInputs::new(view(3.0, -0.1), projection(), 1.5)
    };

    // The Rust pipeline.
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let shadow = shadow_map(gpu, &depth_layers);
    fog.set_shadow_map(&gpu.device, &shadow).unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let rust_scattering = read_volume(gpu, fog.scattering_texture());
    let rust_integrated = read_volume(gpu, fog.integrated_texture());
    let esm = read_esm(gpu, &fog);

    let (w, h) = (64u32, 36u32);
    let depths: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            // Sky in the top rows, then surfaces from 2 m to beyond the far plane.
            if y < 6 {
                1.0
            } else {
                0.95 + 0.05 * (x as f32 / w as f32) * (y as f32 / h as f32)
            }
        })
        .collect();
    let clear = Vec4::new(0.6, 0.3, 0.1, 1.0);
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depths).unwrap();
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let apply = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let target = gpu.texture_2d_rgba16f("lit image", [w, h], &vec![clear; (w * h) as usize]);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.record_apply(
        &mut encoder,
        &apply,
        &target.create_view(&Default::default()),
        &apply.depth_bind_group(&gpu.device, &depth_view),
    )
    .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let rust_image = gpu.read_texture_rgba16f(&target).unwrap();

    // The export and the scene file the JS host reads.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("js-host");
    let _ = std::fs::remove_dir_all(&dir);
    let export_dir = dir.join("export");
    export(&ExportRequest {
        out: export_dir.clone(),
        targets: vec![Target::Wgsl],
        variants: vec![],
        defines: vec![],
        hlsl_samplers: HlslSamplers::Classic,
        snippets: None,
        custom_density: None,
    })
    .unwrap();
    let u = inputs
        .uniforms(&config, fog.frame_index().unwrap())
        .unwrap();
    let esm_texels: Vec<f32> = esm.iter().flat_map(|l| l.texels.clone()).collect();
    f32_file(&dir.join("esm_array.f32"), &esm_texels);
    f32_file(&dir.join("scene_depth.f32"), &depths);
    let scene = json!({
        "variants": { "inject": "inject@default", "scan": "scan@default", "apply": "apply@default" },
        "volume_size": config.volume_size.to_array(),
        "image": { "size": [w, h], "format": "rgba16float", "clear": clear.to_array() },
        "values": {
            "froxels": u.froxels,
            "fog_froxels": u.froxels,
            "frame": u.frame,
            "fog_medium": u.medium,
            "fog_lighting": u.lighting,
            "shadow_cascades": u.cascades,
            "lights": lights,
            "local_volumes": volumes,
            "fog_far_tail": u.tail,
        },
        "textures": {
            "esm_array": {
                "format": "r32float",
                "size": [esm[0].width, esm[0].height, esm.len()],
                "view_dimension": "2d-array",
                "file": "esm_array.f32",
            },
            "scene_depth": {
                "format": "r32float",
                "size": [w, h, 1],
                "view_dimension": "2d",
                "file": "scene_depth.f32",
            },
        },
    });
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();

    let out = dir.join("out");
    let run = Command::new("node")
        .current_dir(example_dir())
        .arg("main.mjs")
        .arg("--export")
        .arg(&export_dir)
        .arg("--scene")
        .arg(&scene_path)
        .arg("--out")
        .arg(&out)
        .env("EGL_PLATFORM", "surfaceless")
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run node ({e}); install the test tools with `{INSTALL}`")
        });
    assert!(
        run.status.success(),
        "the JS host failed:\n{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();

    // fp16 volumes and image: 2^-11 relative per stored value; the two compilers
    // (naga -> SPIR-V -> lavapipe, Tint -> GLSL -> Mesa GL) round differently inside,
    // and the scan carries one pass's rounding into the next: bound 2e-3 relative (four
    // half-ulps) above a floor of 1e-3 of the largest value.
    let checks = [
        (
            "scattering",
            read_f32(&out.join("scattering.f32")),
            &rust_scattering,
        ),
        (
            "integrated",
            read_f32(&out.join("integrated.f32")),
            &rust_integrated,
        ),
        ("image", read_f32(&out.join("image.f32")), &rust_image),
    ];
    for (name, got, want) in &checks {
        let peak = want
            .iter()
            .map(|v| v.abs().max_element())
            .fold(0.0, f32::max);
        assert!(peak > 0.0, "{name}: the Rust pipeline wrote something");
        let worst = worst_relative(got, want, 1e-3 * peak);
        eprintln!(
            "JS host ({}) vs VolumetricFog on {}: {name}, {} values, worst relative error {worst:e} (bound 2e-3)",
            report["adapter"].as_str().unwrap_or("?"),
            gpu.adapter.get_info().name,
            want.len() * 4
        );
        assert!(worst <= 2e-3, "{name}: {worst}");
    }
    // The fog is visible in the image the JS host drew.
    let (_, image, _) = &checks[2];
    assert!(
        image
            .iter()
            .any(|p| (*p - clear).abs().max_element() > 0.05),
        "the JS host's apply changed the image"
    );
}

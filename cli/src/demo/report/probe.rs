//! The probe files (`--probe`): linear float images, the depth buffer, the sun's
//! shadow map (or, with the ESM filter, its ESM and the lamp's shadow atlas) and the integrated volume of the last frame with `probe.json`, and the images of the
//! camera under water with `underwater.json`.

use serde_json::json;

use super::{flat, median, write_error, write_f32};
use crate::demo::DemoError;
use crate::demo::passes::{Demo, FrameSetup, PASS_COUNT, PASS_NAMES, SceneUniform};
use crate::demo::scene;

/// The pool's water and footprint for the probe files.
fn water_json(water: &volfog::uniforms::Water) -> serde_json::Value {
    json!({
        "uniform": water,
        "pool_min": scene::POOL_MIN.to_array(),
        "pool_max": scene::POOL_MAX.to_array(),
    })
}

/// The lamp house, the lamp, its shadow camera and what the fog's local shadows got.
fn lamp_json(
    scene: &scene::Scene,
    camera: &volfog::uniforms::LightCamera,
    fog: &volfog::pipeline::VolumetricFog,
) -> serde_json::Value {
    let house = &scene.lamp;
    let light = &scene.lights[house.light as usize];
    let stats = fog.local_shadow_stats();
    let local = fog.config().local_shadows;
    json!({
        "light": house.light,
        "position": light.position.to_array(),
        "color": light.color.to_array(),
        "range": light.range,
        "fog_intensity": light.fog_intensity,
        "wall_min": house.wall_min.to_array(),
        "wall_max": house.wall_max.to_array(),
        "yard_min": house.yard_min.to_array(),
        "yard_max": house.yard_max.to_array(),
        "doorway_min": house.doorway_min.to_array(),
        "doorway_max": house.doorway_max.to_array(),
        "light_from_world": camera.light_from_world().to_cols_array().to_vec(),
        "clip_from_view": camera.clip_from_view().to_cols_array().to_vec(),
        "atlas_resolution": local.map_or(0, |l| l.resolution),
        "atlas_exponent": local.map_or(0.0, |l| l.exponent),
        "point_shadows": stats.point_shadows,
        "spot_shadows": stats.spot_shadows,
        "unshadowed": stats.unshadowed,
        "atlas_layers": stats.layers,
    })
}

pub fn write_probe(
    demo: &mut Demo<'_>,
    setup: &FrameSetup,
    times: &[[f64; PASS_COUNT]],
) -> Result<(), DemoError> {
    let final_hdr = demo.gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    let dry_hdr = demo.dry_surface(setup)?;
    let Demo {
        args,
        gpu,
        renderer,
        fog,
        apply,
        depth_group,
        clip_from_view,
        scene,
        probe_textures,
        sky,
        lamp_camera: demo_lamp_camera,
        ..
    } = demo;
    let [surface, clouded, fogged] = probe_textures.as_ref().expect("called with --probe");
    let (uniform, cascades, clip_from_view, medium) = (
        &setup.uniform,
        &setup.cascades,
        *clip_from_view,
        &scene.medium,
    );
    let dir = args.out.join("probe");
    std::fs::create_dir_all(&dir).map_err(|e| write_error(&dir, e))?;
    let surface_hdr = gpu.read_texture_rgba16f(surface)?;
    let fogged_hdr = gpu.read_texture_rgba16f(fogged)?;
    let clouded_hdr = gpu.read_texture_rgba16f(clouded)?;
    let depth_raw = gpu.read_texture_raw(&renderer.depth, 4)?;
    let depth: Vec<f32> = bytemuck::cast_slice(&depth_raw).to_vec();

    // Black surfaces under the same fog volume: what remains is the in-scattering.
    let black = SceneUniform {
        surface_scale: 0.0,
        ..*uniform
    };
    renderer.upload(&gpu.queue, &black, cascades, args.exposure);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode_opaque(&mut encoder, false);
    gpu.queue.submit([encoder.finish()]);
    // Before the air's fog: only the pool's underwater in-scattering remains.
    let water_hdr = gpu.read_texture_rgba16f(&renderer.hdr)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.record_apply(&mut encoder, apply, renderer.hdr_view(), depth_group)?;
    gpu.queue.submit([encoder.finish()]);
    let inscatter_hdr = gpu.read_texture_rgba16f(&renderer.hdr)?;

    let integrated = gpu.read_texture_rgba16f(fog.integrated_texture())?;
    let size = fog.config().volume_size;
    let last_slice = &integrated[((size.z - 1) * size.x * size.y) as usize..];
    let mean_far_t =
        last_slice.iter().map(|t| f64::from(t.w)).sum::<f64>() / last_slice.len() as f64;
    let finite_volume = integrated.iter().all(|t| t.is_finite());
    let atlas_raw = match fog.local_shadow_atlas() {
        Some(t) => gpu.read_texture_raw(t, 4)?,
        None => Vec::new(),
    };
    // The sun's shadow map as the compare filter reads it (Depth32Float).
    let sun_shadow_raw = gpu.read_texture_raw(renderer.shadow_map(), 4)?;
    let esm_raw = gpu.read_texture_raw(fog.esm_texture(), 4)?;
    let esm: &[f32] = bytemuck::cast_slice(&esm_raw);
    let (esm_min, esm_max) = esm
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });

    for (name, data) in [
        ("surface.f32", flat(&surface_hdr)),
        ("surface_dry.f32", flat(&dry_hdr)),
        ("clouded.f32", flat(&clouded_hdr)),
        ("cloud_map.f32", scene.cloud_map.clone()),
        ("fogged.f32", flat(&fogged_hdr)),
        ("final.f32", flat(&final_hdr)),
        ("inscatter.f32", flat(&inscatter_hdr)),
        ("water.f32", flat(&water_hdr)),
        ("depth.f32", depth),
        ("integrated.f32", flat(&integrated)),
        ("esm.f32", esm.to_vec()),
        (
            "sun_shadow.f32",
            bytemuck::pod_collect_to_vec(&sun_shadow_raw),
        ),
        ("lamp_atlas.f32", bytemuck::pod_collect_to_vec(&atlas_raw)),
    ] {
        write_f32(&dir.join(name), &data)?;
    }
    let measured = if times.len() > 1 { &times[1..] } else { times };
    let passes: Vec<serde_json::Value> = PASS_NAMES
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let mut v: Vec<f64> = measured.iter().map(|t| t[i]).collect();
            json!({
                "name": name,
                "frames_with_gpu_time": times.iter().filter(|t| t[i] > 0.0).count(),
                "gpu_ms_median": if v.is_empty() { None } else { Some(median(&mut v)) },
                "gpu_ms_min": v.iter().copied().reduce(f64::min),
            })
        })
        .collect();
    let mat = |m: glam::Mat4| m.to_cols_array().to_vec();
    let info = json!({
        "width": args.width,
        "height": args.height,
        "frames": args.frames,
        "adapter": gpu.describe(),
        "timestamps": !times.is_empty(),
        "images": {
            "layout": "rgba f32 little-endian, rows top to bottom; depth.f32: one f32 per pixel (depth buffer, 0 near .. 1 far)",
            "surface": "surface.f32: lit opaque pass and sky before the fog (alpha: sun visibility of the surface, 1 for the sky), seen through the pool's water",
            "surface_dry": "surface_dry.f32: the same with the pool dry",
            "clouded": "clouded.f32: after the clouds' shadow and the distance clouds, before the fog",
            "cloud_map": "cloud_map.f32: the cloud density map, one f32 per texel, rows of cloud_map_size",
            "fogged": "fogged.f32: after the fullscreen fog apply (alpha kept)",
            "final": "final.f32: after the semi-transparent pass, before the tonemap",
            "inscatter": "inscatter.f32: every surface and the sky black, then the fog applied: the in-scattered radiance",
            "water": "water.f32: every surface and the sky black, before the fog: the pool's underwater in-scattering",
            "integrated": "integrated.f32: the integrated froxel volume (rgb in-scatter, a transmittance), x fastest, then y, then z",
            "esm": "esm.f32: the filtered ESM, one esm_resolution^2 layer per cascade (1 x 1 with the compare filter)",
            "sun_shadow": "sun_shadow.f32: the sun's shadow map (standard depth), one sun_shadow_size^2 layer per cascade",
            "lamp_atlas": "lamp_atlas.f32: the local-light ESM atlas, one resolution^2 layer per cube face of the lamp (+X, -X, +Y, -Y, +Z, -Z)",
        },
        "camera": {
            "position": uniform.camera_position.to_array(),
            "view_from_world": mat(uniform.view_from_world),
            "clip_from_view": mat(clip_from_view),
            "world_from_clip": mat(uniform.world_from_clip),
        },
        "sun_direction": uniform.sun_direction.to_array(),
        "water": water_json(&scene.water),
        "sky": {
            "atmosphere": scene.atmosphere,
            "memory_bytes": sky.memory_bytes(),
        },
        "clouds": {
            "layer": setup.clouds,
            "map_size": scene::CLOUD_MAP_SIZE,
        },
        "medium": {
            "density": medium.density,
            "height_falloff": medium.height_falloff,
            "base_height": medium.base_height,
            "noise_strength": medium.noise_strength,
            "albedo": medium.albedo.to_array(),
            "phase_g": medium.phase_g,
        },
        "fog": {
            "volume_size": fog.config().volume_size.to_array(),
            "near": fog.config().near,
            "far": fog.config().far,
            "slice_curve": fog.config().slice_curve,
            "memory_bytes": fog.memory_bytes(),
            "frames_prepared": fog.frame_index().map_or(0, |i| i + 1),
            "integrated_finite": finite_volume,
            "mean_transmittance_far": mean_far_t,
            "esm_min": esm_min,
            "esm_max": esm_max,
            "esm_resolution": fog.config().esm_resolution,
            "shadow_filter": format!("{:?}", fog.config().shadow_filter),
            "sun_shadow_size": renderer.shadow_map().width(),
            "esm_log_space": fog.config().esm_log_space,
            "live_fraction": volfog_testkit::scene::live_fraction(gpu, fog)?,
        },
        "cascades": {
            "light_from_world": cascades.light_from_world.iter().map(|m| mat(*m)).collect::<Vec<_>>(),
            "splits": cascades.splits.to_array(),
            "count": cascades.count,
            "exponent": cascades.exponent,
        },
        "lamp": lamp_json(scene, demo_lamp_camera, fog),
        "passes": passes,
    });
    let path = dir.join("probe.json");
    let text = serde_json::to_string_pretty(&info).map_err(|e| write_error(&path, e))?;
    std::fs::write(&path, text).map_err(|e| write_error(&path, e))?;
    println!("wrote probe images and {}", path.display());
    Ok(())
}

/// With `--probe`, the linear images of the camera under water and
/// `underwater.json` (see `render_underwater`).
pub fn write_underwater_probe(demo: &Demo<'_>, setup: &FrameSetup) -> Result<(), DemoError> {
    let (args, gpu) = (demo.args, &demo.gpu);
    let Some([surface, _, _]) = demo.probe_textures.as_ref() else {
        return Ok(());
    };
    let dir = args.out.join("probe");
    let surface_hdr = gpu.read_texture_rgba16f(surface)?;
    let final_hdr = gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    let depth_raw = gpu.read_texture_raw(&demo.renderer.depth, 4)?;
    let dry = demo.dry_surface(setup)?;
    let black = SceneUniform {
        surface_scale: 0.0,
        ..setup.uniform
    };
    demo.renderer
        .upload(&gpu.queue, &black, &setup.cascades, args.exposure);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    demo.renderer.encode_opaque(&mut encoder, false);
    gpu.queue.submit([encoder.finish()]);
    let water_hdr = gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    for (name, data) in [
        ("underwater_water.f32", flat(&water_hdr)),
        ("underwater_surface.f32", flat(&surface_hdr)),
        ("underwater_dry.f32", flat(&dry)),
        ("underwater_final.f32", flat(&final_hdr)),
        (
            "underwater_depth.f32",
            bytemuck::cast_slice(&depth_raw).to_vec(),
        ),
    ] {
        write_f32(&dir.join(name), &data)?;
    }
    let info = json!({
        "camera": {
            "position": setup.uniform.camera_position.to_array(),
            "world_from_clip": setup.uniform.world_from_clip.to_cols_array().to_vec(),
        },
        "water": water_json(&demo.scene.water),
    });
    let path = dir.join("underwater.json");
    let text = serde_json::to_string_pretty(&info).map_err(|e| write_error(&path, e))?;
    std::fs::write(&path, text).map_err(|e| write_error(&path, e))?;
    Ok(())
}

//! The wgpu code of the README and of `docs/wgpu.md`, run on a device: the README's
//! `VolumetricFog` in ten lines, the guide's frame with a shadow map, depth culling, a
//! light and the far-plane tail, shadowed lamps with a cookie, epipolar sun shafts,
//! short-lived lights (a muzzle flash, a lightning strike), local volumes that clear
//! fog and add smoke, a density of your own in WGSL, and smoke rising from a vent as
//! particles. Each function sets up what
//! the guide's lines take from the renderer around them (textures, camera, sun), then
//! runs those lines as the guide shows them; the host tests check that every `rust`
//! block of the guides appears here line for line.
//!
//! `cargo run --example wgpu_fog` (any Vulkan adapter, Mesa's lavapipe included;
//! `WGPU_ADAPTER_NAME` picks one).

use std::error::Error;

use glam::{Mat4, Vec3};
use volfog::pipeline::{FogConfig, cascade_projection, cascade_splits};
use volfog::uniforms::ShadowCascades;
use volfog_testkit::Gpu;

/// The screen the guides' code renders.
const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;

type Result<T = ()> = std::result::Result<T, Box<dyn Error>>;

fn main() -> Result {
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.describe());
    run(&gpu, "README: VolumetricFog", quick_start)?;
    run(
        &gpu,
        "docs/wgpu.md: VolumetricFog with shadows, culling, a light and the tail",
        shadowed_frame,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: shadowed lamps and a cookie",
        shadowed_lamps,
    )?;
    run(&gpu, "docs/wgpu.md: epipolar sun shafts", epipolar_shafts)?;
    run(
        &gpu,
        "docs/wgpu.md: a muzzle flash and a lightning strike",
        short_lived_lights,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: a ceiling panel and a round lamp",
        area_lights,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: a column of smoke shadows the fog",
        medium_shadows,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: a house that clears the fog, and smoke inside it",
        cleared_house,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: your own density (examples/portal_swirl.wgsl)",
        custom_density,
    )?;
    run(
        &gpu,
        "docs/wgpu.md: smoke rising from a vent, as particles",
        smoke_particles,
    )?;
    Ok(())
}

/// Runs one guide's code, waits for the GPU and fails on any validation error.
fn run(gpu: &Gpu, what: &str, guide: fn(&Gpu) -> Result) -> Result {
    gpu.checked(|| guide(gpu))??;
    gpu.device.poll(wgpu::PollType::wait_indefinitely())?;
    println!("{what}: ran");
    Ok(())
}

/// The README's use of `VolumetricFog`.
#[rustfmt::skip]
fn quick_start(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let Screen { lit_color_view, scene_depth_view, .. } = Screen::new(&device, &queue);
    let (view_from_world, clip_from_view, time) = camera();

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};

    let mut fog = VolumetricFog::new(&device, &FogConfig::default())?;        // 160x90x128, 4 cascades
    let apply = fog.create_apply(&device, wgpu::TextureFormat::Rgba16Float)?;  // one per colour format
    let depth_group = apply.depth_bind_group(&device, &scene_depth_view);     // one per depth texture
    // every frame, once the lit colour and its depth are drawn:
    fog.prepare(&queue, &FrameInputs::new(view_from_world, clip_from_view, time))?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    fog.record_apply(&mut encoder, &apply, &lit_color_view, &depth_group)?;   // colour * T + L
    queue.submit([encoder.finish()]);

    Ok(())
}

/// The wgpu guide's frame: shadows, depth culling, a point light and the tail.
#[rustfmt::skip]
fn shadowed_frame(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let Screen { lit_color_view, scene_depth_texture, scene_depth_view } = Screen::new(&device, &queue);
    let config = FogConfig::default();
    let sun = Sun::new(&device, &queue, &config, config.esm_resolution * 4);
    let Sun { cascades, sun_cascade_depth_array, .. } = sun;
    let (view_from_world, clip_from_view, time) = camera();
    let (lamp_position, fog_color) = (Vec3::new(-2.0, 2.0, -12.0), Vec3::new(0.6, 0.65, 0.7));
    let lit_pass_descriptor = wgpu::RenderPassDescriptor {
        label: Some("lit pass"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &lit_color_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    };

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::{FogLight, FogMedium, HeightFog};

    // once:
    let mut fog = VolumetricFog::new(&device, &FogConfig::default())?;   // 160x90x128, 4 cascades
    fog.set_shadow_map(&device, &sun_cascade_depth_array)?;   // checked: square, a layer per cascade
    fog.set_scene_depth(&device, &scene_depth_texture, 0)?;   // skip froxels behind opaque surfaces
    let apply = fog.create_apply(&device, wgpu::TextureFormat::Rgba16Float)?;  // one per colour format
    let depth_group = apply.depth_bind_group(&device, &scene_depth_view);     // one per depth texture
    // every frame:
    let lights = [FogLight::point(lamp_position, glam::Vec3::new(40.0, 25.0, 10.0), 12.0)];
    let medium = FogMedium { density: 0.03, height_falloff: 0.08, ..FogMedium::default() };
    fog.prepare(&queue, &FrameInputs {
        medium,
        lights: &lights,
        cascades,                                          // your sun's cascade matrices and splits
        tail: HeightFog::from_medium(&medium, fog_color),  // fog continues beyond the far plane
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    // ... lay out this frame's depth (opaque pass or depth prepass) first ...
    fog.encode(&mut encoder)?;
    {
        let mut pass = encoder.begin_render_pass(&lit_pass_descriptor);  // loads the lit HDR colour
        // ... your own draws ...
        fog.draw_apply(&mut pass, &apply, &depth_group)?;             // colour * T + L
    }
    queue.submit([encoder.finish()]);

    Ok(())
}

/// The wgpu guide's shadowed lamps: a spot light with a shadow map and a cookie, a
/// point light with a cube shadow map.
#[rustfmt::skip]
fn shadowed_lamps(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();
    // The lamps' depth maps as a renderer draws them (here cleared to the far plane),
    // 4 x the atlas resolution, and one white cookie.
    let spot_depth_array = texture(&device, "spot shadows", (1024, 1024, 1), wgpu::TextureFormat::Depth32Float);
    let cube_depth_array = texture(&device, "point shadows", (1024, 1024, 6), wgpu::TextureFormat::Depth32Float);
    let cookie_array = texture(&device, "cookies", (64, 64, 1), wgpu::TextureFormat::Rgba8Unorm);
    let mut encoder = device.create_command_encoder(&Default::default());
    for layer in 0..6 {
        let face = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        });
        clear(&mut encoder, None, &face(&cube_depth_array));
    }
    clear(&mut encoder, None, &spot_depth_array.create_view(&Default::default()));
    let cookie_depth = texture(&device, "cookie depth", (64, 64, 1), wgpu::TextureFormat::Depth32Float);
    clear(&mut encoder, Some(&cookie_array.create_view(&Default::default())), &cookie_depth.create_view(&Default::default()));
    queue.submit([encoder.finish()]);
    let desk_lamp = volfog::uniforms::FogLight::spot(
        Vec3::new(1.0, 3.0, -8.0), Vec3::new(0.0, -1.0, -0.3).normalize(), Vec3::splat(30.0), 10.0, 0.4, 0.6);
    let torch = volfog::uniforms::FogLight::point(Vec3::new(-2.0, 1.5, -10.0), Vec3::new(40.0, 25.0, 10.0), 8.0);
    let volfog::uniforms::LightCamera::Spot { view_from_world: lamp_view, clip_from_view: lamp_projection } =
        volfog::uniforms::LightCamera::spot(&desk_lamp, 0.1)? else { unreachable!() };
    let volfog::uniforms::LightCamera::Point { cube_from_world: torch_cube, clip_from_view: face_projection } =
        volfog::uniforms::LightCamera::point(&torch, 0.1)? else { unreachable!() };

    use volfog::pipeline::{FogConfig, FrameInputs, ShadowedLight, VolumetricFog};
    use volfog::uniforms::LightCamera;

    // once: the lamps' depth maps as your renderer draws them (any perspective depth)
    let mut fog = VolumetricFog::new(&device, &FogConfig::default())?;  // 4 spot + 2 point shadows
    fog.set_spot_shadow_maps(&device, &spot_depth_array)?;    // a layer per spot light, square
    fog.set_point_shadow_maps(&device, &cube_depth_array)?;   // six layers (+X, -X, +Y, -Y, +Z, -Z) a light
    fog.set_cookies(&device, &cookie_array)?;                 // optional: what spot lights project
    // every frame:
    let lights = [desk_lamp, torch];
    let shadowed = [
        ShadowedLight::new(0, LightCamera::Spot { view_from_world: lamp_view, clip_from_view: lamp_projection })
            .with_shadow(0).with_cookie(0),                   // spot map 0, cookie 0
        ShadowedLight::new(1, LightCamera::Point { cube_from_world: torch_cube, clip_from_view: face_projection })
            .with_shadow(0),                                  // cube 0 of the point maps
    ];
    fog.prepare(&queue, &FrameInputs {
        lights: &lights,
        shadowed_lights: &shadowed,   // in priority order: lights past the budget are unshadowed
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;                                // inject (and the atlas pass with the ESM)
    queue.submit([encoder.finish()]);

    let stats = fog.local_shadow_stats();
    assert_eq!((stats.spot_shadows, stats.point_shadows, stats.unshadowed), (1, 1, 0));
    Ok(())
}

/// The wgpu guide's epipolar sun shafts, alone as a post-process.
#[rustfmt::skip]
fn epipolar_shafts(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let Screen { lit_color_view, scene_depth_texture, .. } = Screen::new(&device, &queue);
    let sun = Sun::new(&device, &queue, &FogConfig::default(), 2048);
    let Sun { cascades, sun_cascade_depth_array, sun_direction, sun_color } = sun;
    let (view_from_world, clip_from_view, _) = camera();
    let fog_color = Vec3::new(0.6, 0.65, 0.7);
    let mut encoder = device.create_command_encoder(&Default::default());

    use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
    use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};

    let mut shafts = EpipolarShafts::new(&device, EpipolarSampling::new(1920, 1080, 2048))?;
    shafts.set_inputs(&device, &scene_depth_texture, &sun_cascade_depth_array)?;
    let composite = shafts.create_apply(&device, wgpu::TextureFormat::Rgba16Float)?;
    // every frame:
    let medium = HeightFog::new(fog_color, 0.02, glam::Vec3::Y, 0.05, 0.0)?
        .with_sun(sun_direction, sun_color, 0.6)?;
    shafts.prepare(&queue, &EpipolarView {
        view_from_world, clip_from_view,
        light_from_world: cascades.light_from_world[3], cascade: 3,   // the cascade to march in
        rayleigh: glam::Vec3::ZERO, phase: EpipolarPhase::HenyeyGreenstein,
        start_depth: 0.0, max_depth: 1000.0, depth_bias: 0.002,
    }, &medium)?;
    shafts.encode(&mut encoder, EpipolarMode::Tree)?;
    shafts.record_apply(&mut encoder, &composite, &lit_color_view);   // colour * T + L

    queue.submit([encoder.finish()]);
    Ok(())
}

/// The wgpu guide's short-lived lights: a muzzle flash and a lightning strike that
/// light one frame each, and leave nothing in the fog's history.
#[rustfmt::skip]
fn short_lived_lights(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let Screen { lit_color_view, scene_depth_view, .. } = Screen::new(&device, &queue);
    let (view_from_world, clip_from_view, time) = camera();
    let muzzle_position = Vec3::new(0.3, 1.7, -1.0);

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::FogLight;

    let mut fog = VolumetricFog::new(&device, &FogConfig::default())?;  // room for 8 transient lights
    let apply = fog.create_apply(&device, wgpu::TextureFormat::Rgba16Float)?;
    let depth_group = apply.depth_bind_group(&device, &scene_depth_view);
    // the frame the gun fires: the flash lights this frame's fog, all of it, at once
    let flash = [FogLight::point(muzzle_position, glam::Vec3::new(400.0, 260.0, 90.0), 12.0)];
    fog.prepare(&queue, &FrameInputs {
        transient_lights: &flash,
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;              // the scan adds the flash after the temporal blend
    fog.record_apply(&mut encoder, &apply, &lit_color_view, &depth_group)?;
    queue.submit([encoder.finish()]);
    // a lightning strike: a directional light (toward the light, illuminance) for a frame
    let strike = [FogLight::directional(glam::Vec3::new(0.2, 1.0, -0.5).normalize(), glam::Vec3::splat(3.0))];
    fog.prepare(&queue, &FrameInputs {
        transient_lights: &strike,
        ..FrameInputs::new(view_from_world, clip_from_view, time + 1.0 / 60.0)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;              // no trace of the flash: it never reached the history
    fog.record_apply(&mut encoder, &apply, &lit_color_view, &depth_group)?;
    queue.submit([encoder.finish()]);

    Ok(())
}

/// The wgpu guide's area lights: a rectangle and a disk emitter lighting the fog.
#[rustfmt::skip]
fn area_lights(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::AreaLight;

    let mut fog = VolumetricFog::new(&device, &FogConfig {
        max_area_lights: 4,                 // builds inject@...INJECT_AREA_LIGHTS
        ..FogConfig::default()
    })?;
    // a 2 m x 1 m ceiling panel facing down (it emits towards axis_x x axis_y = -Y) and a
    // round lamp of radius 0.3 m facing +X; radiance in W / (m^2 sr) per channel
    let lights = [
        AreaLight::rect(glam::Vec3::new(0.0, 3.0, -6.0), glam::Vec3::X, glam::Vec3::Z, 1.0, 0.5,
            glam::Vec3::new(60.0, 55.0, 45.0), 15.0),
        AreaLight::disk(glam::Vec3::new(-3.0, 2.0, -4.0), glam::Vec3::X, 0.3,
            glam::Vec3::splat(200.0), 10.0),
    ];
    fog.prepare(&queue, &FrameInputs {
        area_lights: &lights,
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    queue.submit([encoder.finish()]);

    Ok(())
}

/// The wgpu guide's medium shadows: a column of smoke whose shadow falls through the
/// fog around it.
#[rustfmt::skip]
fn medium_shadows(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::{LocalVolume, MediumShadowConfig, VolumeShape};

    let mut fog = VolumetricFog::new(&device, &FogConfig {
        // 64^3 texels over the view's first 64 m, reaching 32 m further towards the sun,
        // 8 samples towards each point, spot and directional light
        medium_shadows: Some(MediumShadowConfig::default()),
        ..FogConfig::default()
    })?;
    // a column of smoke 12 m tall and 2.4 m across, 1 / m: its shadow falls through the
    // thinner fog around it
    let column = [LocalVolume::new(
        glam::Mat4::from_scale_rotation_translation(glam::Vec3::new(1.2, 6.0, 1.2),
            glam::Quat::IDENTITY, glam::Vec3::new(-4.0, 6.0, -15.0)),
        VolumeShape::Cylinder, 1.0, 0.1)?];
    fog.prepare(&queue, &FrameInputs {
        local_volumes: &column,
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    queue.submit([encoder.finish()]);

    Ok(())
}

/// The wgpu guide's local volumes: a subtractive box clears the fog inside a house,
/// then a cylinder of smoke is added inside it. Checked on the integrated volume: along
/// the column through the middle of the house the transmittance holds between 17 and
/// 23 m (no fog there), while along a column beside the house it falls.
#[rustfmt::skip]
fn cleared_house(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();

    use glam::{Quat, Vec3};
    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::{BlendMode, FogMedium, LocalVolume, VolumeShape};

    let mut fog = VolumetricFog::new(&device, &FogConfig::default())?;   // up to 16 volumes
    let house = Mat4::from_scale_rotation_translation(Vec3::new(6.0, 2.5, 5.0), Quat::IDENTITY, Vec3::new(0.0, 2.5, -20.0));
    let hearth = Mat4::from_scale_rotation_translation(Vec3::new(0.8, 2.0, 0.8), Quat::IDENTITY, Vec3::new(3.0, 2.0, -22.0));
    // every frame: the volumes blend into the fog in this order
    let volumes = [
        LocalVolume::new(house, VolumeShape::Box, 1.0, 0.05)?.with_blend(BlendMode::Subtract)?,  // no fog indoors
        LocalVolume::new(hearth, VolumeShape::Cylinder, 0.3, 0.5)?,                             // then smoke, added
    ];
    fog.prepare(&queue, &FrameInputs {
        medium: FogMedium { density: 0.03, ..FogMedium::default() },
        local_volumes: &volumes,
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    queue.submit([encoder.finish()]);

    let config = FogConfig::default();
    let integrated = gpu.read_texture_rgba16f(fog.integrated_texture())?;
    let size = config.volume_size;
    let slice = |depth: f32| {
        let t = volfog::cpu::froxel::slice_coord(depth, config.near, config.far, config.slice_curve);
        (t * size.z as f32) as u32
    };
    let transmittance = |x: u32, depth: f32| {
        integrated[((slice(depth) * size.y + size.y / 2) * size.x + x) as usize].w
    };
    // The middle column runs through the house, the first column (9 m left of the
    // house's wall at 17 m) beside it.
    let indoors = transmittance(size.x / 2, 23.0) / transmittance(size.x / 2, 17.0);
    let outdoors = transmittance(0, 23.0) / transmittance(0, 17.0);
    println!("  transmittance across 17..23 m: {indoors:.4} through the house, {outdoors:.4} beside it");
    assert!(indoors > 0.998 && outdoors < 0.9, "{indoors} {outdoors}");
    Ok(())
}

/// The wgpu guide's particles: a column of smoke rising from a vent, written each frame
/// as the application's particle system would. Checked on the integrated volume:
/// between 15 and 25 m the column through the smoke keeps less than half the share of
/// light the first column (beside it) keeps.
#[rustfmt::skip]
fn smoke_particles(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::uniforms::FogParticle;

    let mut fog = VolumetricFog::new(&device, &FogConfig {
        max_particles: 4096,                // builds inject@...INJECT_PARTICLES
        ..FogConfig::default()
    })?;
    // every frame, from your particle system: smoke rising from a vent 20 m ahead, the
    // puffs widening and thinning as they rise, swaying with time
    let particles: Vec<FogParticle> = (0..64)
        .map(|i| {
            let h = i as f32 * 0.15;
            let at = glam::Vec3::new(0.3 * (h + time).sin(), h, -20.0);
            FogParticle::smoke(at, 0.4 + 0.12 * h, 1.5 / (1.0 + h), glam::Vec3::splat(0.4))
        })
        .collect();
    fog.prepare(&queue, &FrameInputs {
        particles: &particles,
        ..FrameInputs::new(view_from_world, clip_from_view, time)
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    queue.submit([encoder.finish()]);

    let config = FogConfig::default();
    let integrated = gpu.read_texture_rgba16f(fog.integrated_texture())?;
    let size = config.volume_size;
    let slice = |depth: f32| {
        let t = volfog::cpu::froxel::slice_coord(depth, config.near, config.far, config.slice_curve);
        (t * size.z as f32) as u32
    };
    let kept = |x: u32| {
        let at = |depth: f32| integrated[((slice(depth) * size.y + size.y / 2) * size.x + x) as usize].w;
        at(25.0) / at(15.0)
    };
    let (smoke, beside) = (kept(size.x / 2), kept(0));
    println!("  transmittance across 15..25 m: {smoke:.4} through the smoke, {beside:.4} beside it");
    assert!(smoke < 0.5 * beside, "{smoke} {beside}");
    Ok(())
}

/// The wgpu guide's own density: `examples/portal_swirl.wgsl` composed into the inject
/// pass, its parameters set each frame. Checked on the integrated volume: between 15
/// and 35 m the column through the portal keeps less than half the share of light the
/// first column (beside the portal) keeps.
#[rustfmt::skip]
fn custom_density(gpu: &Gpu) -> Result {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let (view_from_world, clip_from_view, time) = camera();

    use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
    use volfog::shaders::CustomModule;
    use volfog::uniforms::FogCustomParams;

    // once: your module, composed into the inject pass (an error names its line and column)
    let swirl = CustomModule::new("examples/portal_swirl.wgsl", include_str!("portal_swirl.wgsl"));
    let mut fog = VolumetricFog::new(&device, &FogConfig { custom_density: Some(swirl), ..FogConfig::default() })?;
    // every frame: what its `params` argument holds
    let custom_params = FogCustomParams::new(&[
        glam::Vec4::new(0.0, 2.0, -25.0, 4.0),   // the portal's centre and radius (m)
        glam::Vec4::new(0.5, 1.5, 3.0, 0.0),     // peak extinction (1/m), swirl speed (rad/s), arms
        glam::Vec4::new(0.6, 0.2, 1.4, 0.0),     // its glow at the peak
    ])?;
    fog.prepare(&queue, &FrameInputs { custom_params, ..FrameInputs::new(view_from_world, clip_from_view, time) })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    queue.submit([encoder.finish()]);

    let config = FogConfig::default();
    let integrated = gpu.read_texture_rgba16f(fog.integrated_texture())?;
    let size = config.volume_size;
    let slice = |depth: f32| {
        let t = volfog::cpu::froxel::slice_coord(depth, config.near, config.far, config.slice_curve);
        (t * size.z as f32) as u32
    };
    let kept = |x: u32| {
        let at = |depth: f32| integrated[((slice(depth) * size.y + size.y / 2) * size.x + x) as usize].w;
        at(35.0) / at(15.0)
    };
    let (portal, beside) = (kept(size.x / 2), kept(0));
    println!("  transmittance across 15..35 m: {portal:.4} through the portal, {beside:.4} beside it");
    assert!(portal < 0.5 * beside, "{portal} {beside}");
    Ok(())
}

/// The camera: 60 degrees vertical, 16:9, 0.1..500 m, 2 m above the ground looking
/// along -Z; and the time in seconds.
fn camera() -> (Mat4, Mat4, f32) {
    let view = glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, 2.0, 0.0), -Vec3::Z, Vec3::Y);
    let projection = glam::camera::rh::proj::directx::perspective(
        60f32.to_radians(),
        WIDTH as f32 / HEIGHT as f32,
        0.1,
        500.0,
    );
    (view, projection, 1.5)
}

/// The renderer's screen: the lit HDR colour and the scene depth, cleared (a grey
/// colour, depth 1 everywhere: nothing drawn).
struct Screen {
    lit_color_view: wgpu::TextureView,
    scene_depth_texture: wgpu::Texture,
    scene_depth_view: wgpu::TextureView,
}

impl Screen {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let color = texture(
            device,
            "lit colour",
            (WIDTH, HEIGHT, 1),
            wgpu::TextureFormat::Rgba16Float,
        );
        let depth = texture(
            device,
            "scene depth",
            (WIDTH, HEIGHT, 1),
            wgpu::TextureFormat::Depth32Float,
        );
        let lit_color_view = color.create_view(&Default::default());
        let scene_depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        clear(&mut encoder, Some(&lit_color_view), &scene_depth_view);
        queue.submit([encoder.finish()]);
        Self {
            lit_color_view,
            scene_depth_texture: depth,
            scene_depth_view,
        }
    }
}

/// The sun: its direction and colour, four cascades around the camera and their
/// shadow map (`size` texels square, a layer per cascade, cleared to depth 1: no
/// occluder).
struct Sun {
    cascades: ShadowCascades,
    sun_cascade_depth_array: wgpu::Texture,
    sun_direction: Vec3,
    sun_color: Vec3,
}

impl Sun {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue, config: &FogConfig, size: u32) -> Self {
        let sun_direction = Vec3::new(0.3, 0.5, -0.8).normalize();
        let mut cascades = ShadowCascades {
            splits: cascade_splits(config.cascades, config.near, config.far, 0.5),
            count: config.cascades,
            exponent: config.esm_exponent,
            ..Default::default()
        };
        for (i, m) in cascades.light_from_world.iter_mut().enumerate() {
            let half = 16.0 * (i as f32 + 1.0);
            *m = cascade_projection(sun_direction, Vec3::new(0.0, 0.0, -half), half, 400.0);
        }
        let layers = cascades.light_from_world.len() as u32;
        let shadow = texture(
            device,
            "sun cascades",
            (size, size, layers),
            wgpu::TextureFormat::Depth32Float,
        );
        let mut encoder = device.create_command_encoder(&Default::default());
        for layer in 0..layers {
            let view = shadow.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            });
            clear(&mut encoder, None, &view);
        }
        queue.submit([encoder.finish()]);
        Self {
            cascades,
            sun_cascade_depth_array: shadow,
            sun_direction,
            sun_color: Vec3::new(8.0, 7.5, 6.5),
        }
    }
}

/// A 2D texture (array) that passes render to and shaders read.
fn texture(
    device: &wgpu::Device,
    label: &str,
    (width, height, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// Clears a depth view to 1 and a colour view, if any, to grey.
fn clear(
    encoder: &mut wgpu::CommandEncoder,
    color: Option<&wgpu::TextureView>,
    depth: &wgpu::TextureView,
) {
    let grey = wgpu::Color {
        r: 0.2,
        g: 0.2,
        b: 0.2,
        a: 1.0,
    };
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear"),
        color_attachments: &[color.map(|view| wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(grey),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
}

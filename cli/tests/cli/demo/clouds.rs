//! The clouds: distance clouds over the sky and their shadows moving over the lit
//! scene, against the CPU mirror of `volfog::clouds`.

use glam::Vec3;

use super::{HEIGHT, Run, WIDTH, mat, pixel_directions, read_f32, read_rgba, run, vec3};

/// The cloud layer and its map as the probe recorded them.
fn cloud_layer(run: &Run) -> (volfog::cpu::clouds::CloudMap, volfog::uniforms::CloudLayer) {
    let layer = serde_json::from_value(run.probe["clouds"]["layer"].clone()).expect("CloudLayer");
    let size = run.probe["clouds"]["map_size"].as_u64().unwrap() as u32;
    let map = volfog::cpu::clouds::CloudMap {
        width: size,
        height: size,
        texels: read_f32(run, "cloud_map.f32"),
    };
    (map, layer)
}

/// Distance clouds over the sky: each sky pixel after the clouds pass equals the sky
/// attenuated and lit by `cpu::clouds::distance_clouds` along its ray, for rays more
/// than 2 degrees above the horizon (nearer to it the slab lies tens of kilometres
/// away and a 1e-6 change of the ray's direction moves its samples by metres, across
/// the map's texels: the ray, not the formula, is then ill-conditioned).
#[test]
fn distance_clouds_cover_the_sky() {
    let run = run();
    let (map, layer) = cloud_layer(run);
    let eye = vec3(&run.probe["camera"]["position"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let clouded = read_rgba(run, "clouded.f32");
    let dirs = pixel_directions(run);
    let (mut n, mut covered, mut worst) = (0, 0, 0.0f32);
    for i in 0..(WIDTH * HEIGHT) as usize {
        if depth[i] < 1.0 || dirs[i].y < 2f32.to_radians().sin() {
            continue;
        }
        let c = volfog::cpu::clouds::distance_clouds(&map, &layer, eye, dirs[i], 1e30);
        let want = surface[i].truncate() * c.w + c.truncate();
        let got = clouded[i].truncate();
        let e = ((got - want).abs() / want.max(Vec3::splat(0.01))).max_element();
        worst = worst.max(e);
        assert!(e <= 0.02, "pixel {i}: {got} vs {want} (clouds {c})");
        n += 1;
        covered += (c.w < 0.8) as usize;
    }
    eprintln!(
        "distance clouds: {n} sky pixels above 2 degrees vs cpu::clouds worst rel {worst:.4} (bound 0.02); {covered} under cloud (T < 0.8)"
    );
    assert!(covered > 50, "clouds in the sky: {covered}");
}

/// The clouds' shadow on the lit scene: each geometry pixel after the clouds pass is
/// its lit colour times `cpu::clouds::cloud_shadow` at its position, at the frame's
/// time; one second earlier the wind had the shadows elsewhere.
#[test]
fn cloud_shadows_move_over_the_scene() {
    use volfog::cpu::clouds::cloud_shadow;
    let run = run();
    let (map, layer) = cloud_layer(run);
    let world_from_clip = mat(&run.probe["camera"]["world_from_clip"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let clouded = read_rgba(run, "clouded.f32");
    let earlier = volfog::uniforms::CloudLayer {
        time: layer.time - 1.0,
        ..layer
    };
    let (mut n, mut shadowed, mut moved, mut worst) = (0, 0, 0, 0.0f32);
    for i in 0..(WIDTH * HEIGHT) as usize {
        if depth[i] >= 1.0 || surface[i].truncate().max_element() < 1e-3 {
            continue;
        }
        let ndc = glam::Vec2::new(
            ((i as u32 % WIDTH) as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
            1.0 - ((i as u32 / WIDTH) as f32 + 0.5) / HEIGHT as f32 * 2.0,
        );
        let p = world_from_clip.project_point3(ndc.extend(depth[i]));
        let t = cloud_shadow(&map, &layer, p);
        let want = surface[i].truncate() * t;
        let got = clouded[i].truncate();
        let e = ((got - want).abs() / surface[i].truncate().max(Vec3::splat(1e-3))).max_element();
        worst = worst.max(e);
        assert!(e <= 0.02, "pixel {i} at {p}: {got} vs {want} (shadow {t})");
        n += 1;
        shadowed += (t < 0.5) as usize;
        moved += ((cloud_shadow(&map, &earlier, p) - t).abs() > 0.05) as usize;
    }
    eprintln!(
        "cloud shadows: {n} geometry pixels vs cpu::clouds worst {worst:.4} of the lit colour \
         (bound 0.02); {shadowed} in shadow (T < 0.5); {moved} change by more than 0.05 in 1 s of wind"
    );
    assert!(shadowed > 50 && shadowed < n, "shadows and light");
    assert!(moved > 50, "the shadows move with the wind");
}

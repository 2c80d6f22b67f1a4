//! The pool's water seen from above and from the camera under water: its
//! in-scattering per pixel against the CPU mirror of `volfog::water`.

use glam::{Mat4, Vec3, Vec4};
use serde_json::Value;

use super::{HEIGHT, Run, WIDTH, mat, read_f32, read_rgba, run, vec3};

/// The pool's water as the probe recorded it, and the demo's test for "in the water"
/// (the footprint with 1 cm of slack, below the surface).
fn pool(run: &Run) -> (volfog::uniforms::Water, impl Fn(Vec3) -> bool) {
    let w = &run.probe["water"];
    let water: volfog::uniforms::Water =
        serde_json::from_value(w["uniform"].clone()).expect("Water deserializes");
    let (lo, hi) = (vec3(&w["pool_min"]), vec3(&w["pool_max"]));
    let inside = move |p: Vec3| {
        p.x >= lo.x - 0.01
            && p.x <= hi.x + 0.01
            && p.z >= lo.z - 0.01
            && p.z <= hi.z + 0.01
            && p.dot(water.normal) <= water.height
    };
    (water, inside)
}

/// World positions of the pixels off the sky, from a depth image.
fn world_positions(depth: &[f32], world_from_clip: Mat4) -> Vec<Option<Vec3>> {
    (0..(WIDTH * HEIGHT) as usize)
        .map(|i| {
            let (x, y) = ((i as u32 % WIDTH) as f32, (i as u32 / WIDTH) as f32);
            (depth[i] < 1.0).then(|| {
                world_from_clip.project_point3(Vec3::new(
                    (x + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                    1.0 - (y + 0.5) / HEIGHT as f32 * 2.0,
                    depth[i],
                ))
            })
        })
        .collect()
}

/// Per pixel of the pool's water: the demo's underwater in-scattering (every surface
/// black, before the air's fog) against `cpu::water::water_fog` for the same eye and
/// point. Returns the pixel count and the worst error.
fn check_water_inscatter(
    water: &volfog::uniforms::Water,
    inside: &impl Fn(Vec3) -> bool,
    eye: Vec3,
    world: &[Option<Vec3>],
    black: &[Vec4],
) -> (usize, f32) {
    let (mut n, mut worst) = (0, 0.0f32);
    for (i, p) in world.iter().enumerate() {
        let Some(p) = *p else { continue };
        if !inside(p) {
            continue;
        }
        let want = volfog::cpu::water::water_fog(water, eye, p).truncate();
        let got = black[i].truncate();
        // rgba16float storage (2^-11) and the depth buffer's reconstruction.
        let e = ((got - want).abs() / (want.abs() + Vec3::splat(0.02))).max_element();
        worst = worst.max(e);
        assert!(e <= 5e-3, "pixel {i} at {p}: demo {got} cpu {want}");
        n += 1;
    }
    (n, worst)
}

/// Seen from above: the water's in-scattering in the pool equals the CPU mirror, and
/// the submerged surfaces, lit through the water, turn bluer than the dry pool.
#[test]
fn pool_water_seen_from_above() {
    let run = run();
    let (water, inside) = pool(run);
    let camera = &run.probe["camera"];
    let eye = vec3(&camera["position"]);
    let world = world_positions(&read_f32(run, "depth.f32"), mat(&camera["world_from_clip"]));
    let (n, worst) =
        check_water_inscatter(&water, &inside, eye, &world, &read_rgba(run, "water.f32"));
    let wet = read_rgba(run, "surface.f32");
    let dry = read_rgba(run, "surface_dry.f32");
    let (mut wet_sum, mut dry_sum) = (Vec3::ZERO, Vec3::ZERO);
    for (i, p) in world.iter().enumerate() {
        if p.is_some_and(&inside) {
            wet_sum += wet[i].truncate();
            dry_sum += dry[i].truncate();
        }
    }
    let ratio = |v: Vec3| v.z / v.x.max(1e-6);
    eprintln!(
        "pool from above: {n} pixels under water, in-scatter vs cpu::water worst rel {worst:.2e} \
         (bound 5e-3); blue/red of the submerged surfaces wet {:.2}, dry {:.2}",
        ratio(wet_sum),
        ratio(dry_sum)
    );
    assert!(n > 300, "the pool is in view: {n} pixels");
    assert!(ratio(wet_sum) > 1.2 * ratio(dry_sum));
}

/// The second camera, under water: everything in the pool carries the water's
/// in-scattering (equal to the CPU mirror), what lies beyond the surface is seen
/// through the water (darker and bluer than dry), and the PNG is written.
#[test]
fn pool_water_seen_from_below() {
    let run = run();
    let text =
        std::fs::read_to_string(run.dir.join("probe/underwater.json")).expect("underwater.json");
    let info: Value = serde_json::from_str(&text).expect("parses");
    let (water, inside) = pool(run);
    let eye = vec3(&info["camera"]["position"]);
    assert!(inside(eye), "the second camera is under water");
    let world = world_positions(
        &read_f32(run, "underwater_depth.f32"),
        mat(&info["camera"]["world_from_clip"]),
    );
    let (n, worst) = check_water_inscatter(
        &water,
        &inside,
        eye,
        &world,
        &read_rgba(run, "underwater_water.f32"),
    );
    let wet = read_rgba(run, "underwater_surface.f32");
    let dry = read_rgba(run, "underwater_dry.f32");
    // Beyond the surface (the sky and the scene above the water).
    let (mut wet_above, mut dry_above, mut above) = (Vec3::ZERO, Vec3::ZERO, 0);
    for (i, p) in world.iter().enumerate() {
        if p.is_none_or(|p| !inside(p)) {
            wet_above += wet[i].truncate();
            dry_above += dry[i].truncate();
            above += 1;
        }
    }
    eprintln!(
        "pool from below: {n} pixels in the water, in-scatter vs cpu::water worst rel {worst:.2e} \
         (bound 5e-3); {above} pixels beyond the surface, mean wet {:?} vs dry {:?}",
        wet_above / above.max(1) as f32,
        dry_above / above.max(1) as f32
    );
    assert!(n > 1000, "the pool fills most of the view: {n}");
    assert!(above > 100, "the surface shows the world above: {above}");
    assert!(wet_above.z / wet_above.x > dry_above.z / dry_above.x);
    let file = std::fs::File::open(run.dir.join("underwater.png")).expect("underwater.png exists");
    let info = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("decodes")
        .info()
        .clone();
    assert_eq!((info.width, info.height), (WIDTH, HEIGHT));
}

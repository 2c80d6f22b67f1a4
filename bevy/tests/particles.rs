//! `FroxelFogParticles` reach the fog of a camera with `FroxelFog::max_particles`: on
//! the `fog_scene` scene, a dense smoke particle 6 m ahead of the camera darkens the
//! transmittance through the volume along the rays that cross it and nowhere else,
//! against the same scene without it; more particles than the camera's room switch
//! its fog off with one warning naming `FrameInputs.particles`.

#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "support/warnings.rs"]
mod warnings;

use bevy::prelude::*;
use bevy::render::RenderApp;
use scene::{FogKind, SceneCamera, SceneOptions, read_volume};
use volfog_bevy::volfog::glam as vg;
use volfog_bevy::{FogParticle, FogViews, FroxelFog, FroxelFogParticles};
use warnings::{volfog_warnings, warnings};

/// The particle: 6 m straight ahead, 0.8 m wide, 4 /m at its centre (a chord through
/// the centre has optical depth 3.4).
const DEPTH: f32 = 6.0;
const RADIUS: f32 = 0.8;
const EXTINCTION: f32 = 4.0;

fn frames(app: &mut App, n: u32) {
    for _ in 0..n {
        app.update();
    }
}

fn fog_views(app: &App) -> usize {
    app.sub_app(RenderApp).world().resource::<FogViews>().len()
}

/// The transmittance through the whole volume per froxel column (the last slice).
fn far_transmittance(texels: &[Vec4], size: vg::UVec3) -> Vec<f32> {
    let last = ((size.z - 1) * size.y * size.x) as usize;
    texels[last..].iter().map(|t| t.w).collect()
}

#[test]
fn particles_reach_the_fog_where_they_are() {
    warnings();
    let mut app = scene::app(&SceneOptions::still(96, 54, FogKind::Froxel));
    frames(&mut app, 1);
    let camera = {
        let world = app.world_mut();
        let mut q = world.query_filtered::<Entity, With<SceneCamera>>();
        q.single(world).unwrap()
    };
    app.world_mut()
        .get_mut::<FroxelFog>(camera)
        .unwrap()
        .max_particles = 4;
    frames(&mut app, 4);
    let without = read_volume(&app);
    let fog = &without.fog;
    assert_eq!(fog.config.max_particles, 4);
    assert!(fog.particles.is_empty());
    let size = fog.config.volume_size;
    let before = far_transmittance(&without.texels, size);

    // Straight ahead of the camera: it projects to the middle of the screen.
    let at = fog.view_from_world.inverse() * vg::Vec4::new(0.0, 0.0, -DEPTH, 1.0);
    let particle = FogParticle::smoke(at.truncate(), RADIUS, EXTINCTION, vg::Vec3::splat(0.6));
    let smoke = app
        .world_mut()
        .spawn(FroxelFogParticles(vec![particle]))
        .id();
    frames(&mut app, 4);
    let with = read_volume(&app);
    assert_eq!(with.fog.particles, [particle]);
    let after = far_transmittance(&with.texels, size);

    // The particle's extent on the grid (froxels from the middle), plus a froxel and a
    // half either way for where the grid's middle falls and the froxels' own width.
    let p = fog.clip_from_view;
    let reach = vg::Vec2::new(
        p.x_axis.x * RADIUS / DEPTH * size.x as f32 / 2.0,
        p.y_axis.y * RADIUS / DEPTH * size.y as f32 / 2.0,
    ) + 1.5;
    let middle = vg::Vec2::new(size.x as f32, size.y as f32) / 2.0;
    let (mut least_ratio, mut outside, mut near) = (f32::MAX, 0.0f32, 0);
    for y in 0..size.y {
        for x in 0..size.x {
            let i = (y * size.x + x) as usize;
            let centre = vg::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let d = (centre - middle).abs();
            if d.x <= reach.x && d.y <= reach.y {
                near += 1;
                least_ratio = least_ratio.min(after[i] / before[i]);
            } else {
                outside = outside.max((after[i] - before[i]).abs());
            }
        }
    }
    eprintln!(
        "{}x{} columns, {near} around the particle: transmittance through the volume down \
         to {least_ratio:.3} of the scene's without it there (bound 0.5), elsewhere within \
         {outside:.1e} (bound 1e-3)",
        size.x, size.y
    );
    assert!(
        least_ratio < 0.5,
        "the particle darkens its rays: {least_ratio}"
    );
    assert!(outside <= 1e-3, "nothing changes elsewhere: {outside}");
    assert!(volfog_warnings().is_empty(), "{:?}", volfog_warnings());

    // Five particles in a fog with room for four: the fog goes off with one warning.
    let more = app
        .world_mut()
        .spawn(FroxelFogParticles(vec![particle; 4]))
        .id();
    frames(&mut app, 3);
    let warned = volfog_warnings();
    assert_eq!(fog_views(&app), 0, "the fog is off");
    assert_eq!(warned.len(), 1, "one warning: {warned:?}");
    assert!(warned[0].contains("FrameInputs.particles"), "{}", warned[0]);
    // Back within its room, the fog comes back.
    app.world_mut().despawn(more);
    app.world_mut().despawn(smoke);
    frames(&mut app, 3);
    assert_eq!(fog_views(&app), 1, "the fog is back");
}

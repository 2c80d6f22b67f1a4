//! The cameras: their projection, the main camera's path above the ground, the
//! camera under water, and the shadow cascades fitted to a camera's frustum.

use glam::{Mat4, Vec3};
use volfog::pipeline::cascade_projection;
use volfog::uniforms::ShadowCascades;

/// The cameras' vertical field of view (degrees).
pub const FOV_Y: f32 = 55.0;
/// The cameras' near plane (m).
pub const NEAR: f32 = 0.1;
/// The cameras' far plane (m).
pub const FAR: f32 = 500.0;

/// Camera pose at `t` in [0, 1] along the path (the final frame is t = 1): a slow
/// sideways dolly towards the colonnade, in the shadows of its pillars.
pub fn camera(t: f32) -> (Vec3, Mat4) {
    let eye = Vec3::new(-2.0 + 2.5 * t, 1.8 - 0.1 * t, -8.0 - 3.0 * t);
    let target = Vec3::new(0.5, 2.8, -25.0);
    (
        eye,
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
    )
}

/// The second camera: under water in the pool's near half, looking along it towards
/// the far wall and up through the surface.
pub fn underwater_camera() -> (Vec3, Mat4) {
    let eye = Vec3::new(-1.5, -1.3, -15.0);
    let target = Vec3::new(-1.2, -0.5, -19.0);
    (
        eye,
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
    )
}

/// Fits shadow cascades to the camera frustum: one bounding sphere per split
/// interval, snapped to the shadow-map texel grid so the maps do not shimmer as the
/// camera moves. Returns the cascades and the world size of a texel per cascade.
#[allow(clippy::too_many_arguments)]
pub fn fit_cascades(
    world_from_view: Mat4,
    fov_y: f32,
    aspect: f32,
    near: f32,
    splits: glam::Vec4,
    count: u32,
    sun: Vec3,
    map_size: u32,
    exponent: f32,
) -> (ShadowCascades, [f32; 4]) {
    let tan_y = (fov_y * 0.5).tan();
    let lateral = |depth: f32| depth * tan_y * (1.0 + aspect * aspect).sqrt();
    // Occluders up to this height (m) must fall inside each cascade's depth range.
    let caster_height = 12.0;
    let reach = caster_height / sun.y.max(0.05);
    let light_rotation = glam::camera::rh::view::look_at_mat4(sun, Vec3::ZERO, Vec3::Y);
    let mut cascades = ShadowCascades {
        splits,
        count,
        exponent,
        ..ShadowCascades::default()
    };
    let mut texels = [0.0; 4];
    let mut front = near;
    for i in 0..count as usize {
        let back = splits[i];
        let (a0, a1) = (lateral(front), lateral(back));
        // Centre on the view axis equidistant from the front and back corner rings.
        let z = ((back * back - front * front + a1 * a1 - a0 * a0) / (2.0 * (back - front)))
            .clamp(front, back);
        let radius = ((z - front).powi(2) + a0 * a0)
            .max((back - z).powi(2) + a1 * a1)
            .sqrt();
        // A fixed radius per cascade (rounded up) keeps the texel size constant.
        let radius = (radius * 2.0).ceil() * 0.5;
        let center = world_from_view.transform_point3(Vec3::new(0.0, 0.0, -z));
        let texel = 2.0 * radius / map_size as f32;
        let mut ls = light_rotation.transform_point3(center);
        ls.x = (ls.x / texel).round() * texel;
        ls.y = (ls.y / texel).round() * texel;
        let center = light_rotation.inverse().transform_point3(ls);
        // Shift the depth range towards the sun so casters outside the sphere count.
        let range = 2.0 * radius + reach;
        cascades.light_from_world[i] =
            cascade_projection(sun, center + sun * (reach * 0.5), radius, range);
        texels[i] = texel;
        front = back;
    }
    (cascades, texels)
}

// Demo shadow maps: depth-only rendering of the scene into one cascade layer of the
// sun's shadow map or one cube face of the lamp's.
//
// Bindings (group 0): 0 the cascade's (or the face's) world -> light clip transform.

@group(0) @binding(0) var<uniform> light_from_world: mat4x4<f32>;

@vertex
fn shadow_vs(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light_from_world * vec4<f32>(position, 1.0);
}

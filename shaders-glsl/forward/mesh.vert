#version 460
// The one vertex shader of the forward passes. `invariant` keeps depth bit-identical between
// the depth/ambient pass and the per-light passes, which test with EQUAL.
#include "common/scene.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) flat out vec3 albedo;

invariant gl_Position;

void main() {
    Object o = objects[push.object];
    // `precise` (no FMA contraction) in this shader and in shadow_volume/extrude.vert: the
    // shadow volume's front cap must land on exactly these depths, and `invariant` alone only
    // covers identical shader code.
    precise vec4 wp = o.model * vec4(in_position, 1.0);
    world_position = wp.xyz;
    world_normal = mat3(o.normal_matrix) * in_normal;
    albedo = o.albedo.rgb;
    precise vec4 clip = frame.view_proj * wp;
    gl_Position = clip;
}

#version 460
// Shadow-volume vertices (Everitt–Kilgard §2.2): w = 1 keeps the caster's vertex A, w = 0
// extrudes it to the point at infinity (A·Lw − L·Aw, 0) away from the light, in world space.
// With P_inf (or depth clamp) such points land on the far depth, never clipped.
// `invariant` keeps the front cap's depths bit-identical to the forward passes', so the cap
// fails a LESS depth test against the caster's own surface, as z-fail needs.
#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;

invariant gl_Position;

void main() {
    // `precise` as in forward/mesh.vert, so front-cap depths equal the scene's exactly.
    precise vec4 world = objects[push.object].model * vec4(in_position.xyz, 1.0);
    if (in_position.w == 0.0) {
        vec4 l = lights[push.view].position;
        world = vec4(world.xyz * l.w - l.xyz, 0.0);
    }
    precise vec4 clip = frame.view_proj * world;
    gl_Position = clip;
}

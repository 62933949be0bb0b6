// Shadow-volume vertices (Everitt–Kilgard §2.2) to clip space: w = 1 keeps the caster's vertex
// A, w = 0 extrudes it to the point at infinity (A·Lw − L·Aw, 0) away from the light, in world
// space. `precise` as in forward/mesh.vert, so front-cap depths equal the scene's exactly.
#ifndef UMBRA_SHADOW_VOLUME_EXTRUDE_GLSL
#define UMBRA_SHADOW_VOLUME_EXTRUDE_GLSL

#include "common/scene.glsl"

vec4 volume_clip_position(vec4 p) {
    precise vec4 world = objects[push.object].model * vec4(p.xyz, 1.0);
    if (p.w == 0.0) {
        vec4 l = lights[push.view].position;
        world = vec4(world.xyz * l.w - l.xyz, 0.0);
    }
    precise vec4 clip = frame.view_proj * world;
    return clip;
}

#endif

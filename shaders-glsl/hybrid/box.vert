#version 460
// Blocker culling (Chan–Durand §6.3): a caster's world-space bounding box, drawn from the
// light's view (`push.view` indexes shadow_views) against the shadow map's depth under an
// occlusion query. No fragment shader, no writes.
#include "common/scene.glsl"

layout(location = 0) in vec4 in_position;

void main() {
    gl_Position = shadow_views[push.view] * in_position;
}

#version 460
// Williams' first pass: depth from the light, positions only, no colour.
// `push.view` selects the light-space view-projection (one per spot/directional light, six
// per point light).
#include "common/scene.glsl"

layout(location = 0) in vec3 in_position;

void main() {
    gl_Position = shadow_views[push.view] * (objects[push.object].model * vec4(in_position, 1.0));
}

#version 460
// Forward pass 1: lays down depth and the ambient term.
#include "common/scene.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(albedo * frame.ambient.rgb, 1.0);
}

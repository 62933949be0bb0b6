#version 460
// The G-buffer the exact reference reads (umbra_shadows::GBuffer), drawn over the frame's depth
// (EQUAL) with forward/mesh.vert, so it holds the very points the lighting passes shaded.
// Location 0: world position, w = object index + 1 (0, the clear value: no surface).
// Location 1: the geometric normal, from the screen-space derivatives of the position (both
// lie in the triangle's plane, helper pixels included), turned towards the camera.
#include "common/scene.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;

void main() {
    vec3 n = cross(dFdxFine(world_position), dFdyFine(world_position));
    float len = length(n);
    n = len > 0.0 ? n / len : vec3(0.0);
    if (dot(n, frame.camera_position.xyz - world_position) < 0.0) {
        n = -n;
    }
    out_position = vec4(world_position, float(push.object + 1u));
    out_normal = vec4(n, 0.0);
}

#version 460
// Shadow-volume vertices clipped to the view on the host (`umbra_shadows::HostClip`, for
// drivers whose own clipping is not watertight): t = 0, the volume vertex `a` itself (as
// shadow_volume/extrude.vert places it, bit for bit); t < 0, `b` is already a clip-space
// position (a cut point, on the clipped region's boundary, computed on the host in f64).
#include "shadow_volume/extrude.glsl"

layout(location = 0) in vec4 in_a;
layout(location = 1) in vec4 in_b;
layout(location = 2) in float in_t;

invariant gl_Position;

void main() {
    if (in_t < 0.0) {
        gl_Position = in_b;
        return;
    }
    gl_Position = volume_clip_position(in_a);
}

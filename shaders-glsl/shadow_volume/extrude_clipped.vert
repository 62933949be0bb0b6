#version 460
// Shadow-volume vertices clipped to the view on the host (`umbra_shadows::HostClip`, for
// drivers whose own clipping is not watertight): t = 0, the volume vertex `a` itself (as
// shadow_volume/extrude.vert places it, bit for bit); 0 < t < 1, the point a + t·(b − a) of the
// edge between volume vertices a and b, in clip space; t < 0, `b` is already a clip-space
// position (a corner of the clipped region, on its boundary).
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
    vec4 a = volume_clip_position(in_a);
    if (in_t == 0.0) {
        gl_Position = a;
        return;
    }
    vec4 b = volume_clip_position(in_b);
    precise vec4 p = a + in_t * (b - a);
    gl_Position = p;
}

#version 460
// Shadow-volume vertices (shadow_volume/extrude.glsl). With P_inf (or depth clamp) points at
// infinity land on the far depth, never clipped.
// `invariant` keeps the front cap's depths bit-identical to the forward passes', so the cap
// fails a LESS depth test against the caster's own surface, as z-fail needs.
#include "shadow_volume/extrude.glsl"

layout(location = 0) in vec4 in_position;

invariant gl_Position;

void main() {
    gl_Position = volume_clip_position(in_position);
}

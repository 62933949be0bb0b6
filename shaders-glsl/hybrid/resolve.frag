#version 460
// Chan–Durand §3 step 4: the silhouette pixels' visibility from their stencil count, written
// into the light's visibility image by a full-screen triangle (fullscreen/triangle.vert) drawn
// twice: through a stencil test for count 0 (LIT, visibility 1) and for any other count
// (visibility 0). Every other pixel's visibility came from the map in classify.frag.
#include "hybrid/classes.glsl"
#include "visibility/image.glsl"

layout(constant_id = 1) const bool LIT = false; // (id 0 is fullscreen/triangle.vert's depth)

layout(location = 0) out vec2 out_visibility;

void main() {
    if (!is_silhouette_pixel(ivec2(gl_FragCoord.xy))) {
        discard;
    }
    out_visibility = visibility_decided(LIT ? 1.0 : 0.0);
}

#version 460
// Chan–Durand §4, the computation mask: a full-screen triangle (fullscreen/triangle.vert) that
// keeps either the silhouette pixels or the others (KEEP_SILHOUETTE) and discards the rest.
// The pipeline decides what a kept fragment does:
//   depth-bounds  keeps non-silhouette pixels and writes depth 0 there (outside [eps, 1]);
//   stencil       keeps silhouette pixels and sets the stencil's high bit there;
//   none          keeps silhouette pixels and writes nothing (an occlusion query counts them).
#include "hybrid/classes.glsl"

layout(constant_id = 1) const bool KEEP_SILHOUETTE = false;

void main() {
    if (is_silhouette_pixel(ivec2(gl_FragCoord.xy)) != KEEP_SILHOUETTE) {
        discard;
    }
}

// The hybrid's silhouette-pixel classes (Chan–Durand §3 step 2), written by classify.frag in
// the colours of debug/classes.glsl and read by the later full-screen and surface passes
// through set 1, binding 3 (the light's per-technique image). A pixel is a silhouette pixel,
// one the shadow volumes decide, while it holds CLASS_SILHOUETTE_LIT. The target is cleared to
// 0: black where no surface was drawn (the readback turns it into the background grey).
#ifndef UMBRA_HYBRID_CLASSES_GLSL
#define UMBRA_HYBRID_CLASSES_GLSL

#include "debug/classes.glsl"

layout(set = 1, binding = 3) uniform sampler2D silhouette_classes;

bool is_silhouette_pixel(ivec2 pixel) {
    vec4 c = texelFetch(silhouette_classes, pixel, 0);
    // Green alone: every other class has red or blue, or green below 0.8 (greys).
    return c.g > 0.9 && c.r < 0.1 && c.b < 0.1;
}

#endif

#version 460
// Chan–Durand §3 step 2 (Fig. 4): the eye pass of a hybrid light, drawn over the frame's depth
// (EQUAL). One hardware 2x2 PCF fetch (SHADOW_FILTER is specialized to pcf2x2 and the shadow
// set binds a LINEAR comparison sampler): a result strictly between 0 and 1 on a surface facing
// the light marks a silhouette pixel, left for the shadow volumes; anywhere else the map
// decides. Surfaces facing away from the light are never silhouette pixels.
// Location 0: the light's visibility image (visibility/image.glsl), written here where the map
// decides (hybrid/resolve.frag writes the silhouette pixels' from their stencil count).
// Location 1: the pixel's class (hybrid/classes.glsl).
#include "shadow_map/lookup.glsl"
#include "debug/classes.glsl"
#include "visibility/surface.glsl"

layout(location = 1) out vec4 out_class;

void main() {
    Light l = lights[push.view];
    vec3 n = viewer_normal();
    // The class of every fragment is written, so unreached ones write their visibility too
    // (the last of two fragments at one depth decides the pixel).
    if (!shadow_in_question(l, n, false)) {
        // Not a receiver, or back-facing: never a silhouette (Fig. 4's diffuse > 0).
        out_class = out_visibility == VISIBILITY_NOT_RECEIVER ? CLASS_NOT_RECEIVER : CLASS_UNREACHED;
        return;
    }
    float v = shadow_visibility(l, world_position, n);
    if (v > 0.0 && v < 1.0) {
        out_class = CLASS_SILHOUETTE_LIT; // the volumes decide (hybrid/resolve.frag)
        out_visibility = VISIBILITY_UNREACHED; // until resolved
        return;
    }
    out_class = v > 0.5 ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
    out_visibility = visibility_decided(v);
}

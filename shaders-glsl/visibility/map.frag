#version 460
// The visibility of a shadow-map or silhouette-map light, over the frame's depth (EQUAL):
// Williams' second pass (shadow_map/lookup.glsl, with the renderer's filter) or the silhouette
// map's pass 3 (Sen et al. §3.2, silhouette_map/lookup.glsl), at the interpolated world
// position, into the visibility image (visibility/image.glsl).
#include "silhouette_map/lookup.glsl"
#include "visibility/surface.glsl"

void main() {
    Light l = lights[push.view];
    vec3 n = viewer_normal();
    if (!shadow_in_question(l, n, true)) {
        return;
    }
    float v;
    if (silhouette_light(l)) {
        bool reconstructed;
        v = silhouette_visibility(l, world_position, n, reconstructed);
    } else {
        v = shadow_visibility(l, world_position, n);
    }
    out_visibility = visibility_decided(v);
}

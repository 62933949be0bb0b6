#version 460
// The ray-traced hybrid's classification: the hybrid's (hybrid/classify.glsl), and at each
// silhouette pixel the exact reference's shadow ray (ray/shadow_ray.glsl) appended to the ray
// list (hybrid/ray_list.glsl), cast by hybrid/rays.comp. Early fragment tests: only fragments
// that pass the depth test (EQUAL) append.
// Location 2: the index + 1 of the pixel's ray in the list (0: none). Where two fragments
// cover a pixel at one depth both append, but the attachment keeps the later one in primitive
// order, as every visibility pass keeps it: only that ray writes the pixel, so the image does
// not depend on the order the rays run in.
layout(early_fragment_tests) in;

#include "hybrid/classify.glsl"
#include "ray/shadow_ray.glsl"
#include "hybrid/ray_list.glsl"

layout(location = 2) out uint out_ray;

void main() {
    vec3 g = geometric_normal();
    out_ray = 0u;
    if (!classify()) {
        return;
    }
    ShadowRay r = shadow_ray(lights[push.view], world_position, g);
    uint i = atomicAdd(header.count, 1u);
    if (i >= uint(entries.length())) {
        return;
    }
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    entries[i] = RayEntry(r.origin, pixel.x | (pixel.y << 16), r.dir, r.t_max);
    out_ray = i + 1u;
    if (i % RAY_GROUP == 0u) {
        atomicAdd(header.groups_x, 1u);
    }
}

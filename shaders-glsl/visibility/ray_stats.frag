#version 460
// Diagnostics (`ray stats N`): visibility/ray.frag's shadow rays cast again, each counting the
// BVH nodes and triangles it visits (ray/stats.glsl, set 2). It writes the visibility ray.frag
// wrote. Early fragment tests: only the fragments that passed the depth test count.
#define RAY_STATS
layout(early_fragment_tests) in;
#include "visibility/ray.glsl"
#include "ray/stats.glsl"

void main() {
    if (cast_visibility_ray()) {
        count_ray(push.view, ray_nodes, ray_triangles);
    }
}

// The ray-traced hybrid's step 3 (hybrid/rays.comp): the shadow rays of the silhouette pixels
// (hybrid/ray_list.glsl), one per invocation, dispatched indirectly with the workgroup count
// the classification wrote; each walks the scene's BVH (ray/bvh.glsl) and writes its pixel's
// visibility (visibility/image.glsl) into the light's visibility image. With RAY_STATS
// (hybrid/rays_stats.comp, the diagnostics' `ray stats N`) each ray counts the BVH nodes and
// triangles it visits (ray/stats.glsl, set 3, the light in the push constants) instead.
#ifndef UMBRA_HYBRID_RAYS_GLSL
#define UMBRA_HYBRID_RAYS_GLSL

#define BVH_SET 0
#define RAY_LIST_SET 1
#include "ray/bvh.glsl"
#include "hybrid/ray_list.glsl"
#include "visibility/image.glsl"

layout(local_size_x = 64) in; // RAY_GROUP

layout(set = 2, binding = 0, rg32f) uniform writeonly image2D visibility;
// Per pixel the index + 1 of the ray that decides it (hybrid/classify_rays.frag).
layout(set = 2, binding = 1, r32ui) uniform readonly uimage2D pixel_rays;

#ifdef RAY_STATS
#define RAY_STATS_SET 3
#include "ray/stats.glsl"
layout(push_constant) uniform StatsPush {
    uint light;
} stats_push;
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(header.count, uint(entries.length()))) {
        return;
    }
    RayEntry e = entries[i];
    ivec2 pixel = ivec2(e.pixel & 0xffffu, e.pixel >> 16);
    if (imageLoad(pixel_rays, pixel).r != i + 1u) {
        return; // another fragment of this pixel, later in primitive order, decides it
    }
    bool blocked = ray_occluded(e.origin, e.dir, e.t_max);
#ifdef RAY_STATS
    count_ray(stats_push.light, ray_nodes, ray_triangles);
#else
    imageStore(visibility, pixel, vec4(visibility_decided(blocked ? 0.0 : 1.0), 0.0, 0.0));
#endif
}

#endif

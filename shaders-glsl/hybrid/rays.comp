#version 460
// The ray-traced hybrid's step 3: the shadow rays of the silhouette pixels
// (hybrid/ray_list.glsl), one per invocation, dispatched indirectly with the workgroup count
// the classification wrote; each walks the scene's BVH (ray/bvh.glsl) and writes its pixel's
// visibility (visibility/image.glsl) into the light's visibility image.
#define BVH_SET 0
#define RAY_LIST_SET 1
#include "ray/bvh.glsl"
#include "hybrid/ray_list.glsl"
#include "visibility/image.glsl"

layout(local_size_x = 64) in; // RAY_GROUP

layout(set = 2, binding = 0, rg32f) uniform writeonly image2D visibility;
// Per pixel the index + 1 of the ray that decides it (hybrid/classify_rays.frag).
layout(set = 2, binding = 1, r32ui) uniform readonly uimage2D pixel_rays;

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
    imageStore(visibility, pixel, vec4(visibility_decided(blocked ? 0.0 : 1.0), 0.0, 0.0));
}

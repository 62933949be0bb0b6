// The visibility of a ray-traced light at one receiver fragment, over the frame's depth
// (EQUAL): the exact reference's shadow ray (ray/shadow_ray.glsl) walked through the scene's
// BVH (ray/bvh.glsl), into the visibility image. Shared by visibility/ray.frag and its counted
// twin visibility/ray_stats.frag.
#ifndef UMBRA_VISIBILITY_RAY_GLSL
#define UMBRA_VISIBILITY_RAY_GLSL

#include "visibility/surface.glsl"
#include "ray/shadow_ray.glsl"
#include "ray/bvh.glsl"

// Writes the fragment's visibility; false when the light's shadow is not in question here (no
// ray cast).
bool cast_visibility_ray() {
    vec3 g = geometric_normal();
    Light l = lights[push.view];
    if (!shadow_in_question(l, viewer_normal(), true)) {
        return false;
    }
    ShadowRay r = shadow_ray(l, world_position, g);
    bool blocked = ray_occluded(r.origin, r.dir, r.t_max);
    out_visibility = visibility_decided(blocked ? 0.0 : 1.0);
    return true;
}

#endif

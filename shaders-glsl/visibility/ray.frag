#version 460
// The visibility of a ray-traced light, over the frame's depth (EQUAL): one shadow ray per
// receiver pixel (ray/shadow_ray.glsl: the exact reference's ray) walked through the scene's
// BVH (ray/bvh.glsl), into the visibility image.
#include "visibility/surface.glsl"
#include "ray/shadow_ray.glsl"
#include "ray/bvh.glsl"

void main() {
    vec3 g = geometric_normal();
    Light l = lights[push.view];
    if (!shadow_in_question(l, viewer_normal(), true)) {
        return;
    }
    ShadowRay r = shadow_ray(l, world_position, g);
    bool blocked = ray_occluded(r.origin, r.dir, r.t_max);
    out_visibility = visibility_decided(blocked ? 0.0 : 1.0);
}

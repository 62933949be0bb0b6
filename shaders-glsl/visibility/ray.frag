#version 460
// The visibility of a ray-traced light, over the frame's depth (EQUAL): one shadow ray per
// receiver pixel, from the interpolated world position offset along the geometric normal by
// RAY_OFFSET_SCALE * max(|p|, 1) towards the light (to infinity for a directional light, to the
// light less the offset for a point or spot), walked through the scene's BVH (ray/bvh.glsl):
// the exact reference's ray (umbra_reference::shadow_ray), into the visibility image.
#include "visibility/surface.glsl"
#include "ray/bvh.glsl"

// umbra_reference::RAY_OFFSET_SCALE.
const float RAY_OFFSET_SCALE = 1e-5;

void main() {
    // The geometric normal from the position's derivatives, as the G-buffer the reference reads
    // (taken first: derivatives are undefined once a neighbour of the quad has left).
    vec3 g = cross(dFdxFine(world_position), dFdyFine(world_position));
    float len = length(g);
    g = len > 0.0 ? g / len : vec3(0.0);
    if (dot(g, frame.camera_position.xyz - world_position) < 0.0) {
        g = -g;
    }
    Light l = lights[push.view];
    if (!shadow_in_question(l, viewer_normal(), true)) {
        return;
    }
    vec3 p = world_position;
    vec3 a = abs(p);
    float offset = RAY_OFFSET_SCALE * max(max(max(a.x, a.y), a.z), 1.0);
    vec3 dir;
    float t_max;
    if (l.position.w == 0.0) {
        dir = normalize(l.position.xyz);
        t_max = uintBitsToFloat(0x7f800000u);
    } else {
        vec3 to_light = l.position.xyz / l.position.w - p;
        float d = length(to_light);
        dir = to_light / d;
        t_max = d - offset;
    }
    bool blocked = ray_occluded(p + g * offset, dir, t_max);
    out_visibility = visibility_decided(blocked ? 0.0 : 1.0);
}

// The shadow ray of a receiver fragment, as the exact reference casts it
// (`umbra_reference::shadow_ray`): from the interpolated world position offset along the
// geometric normal by RAY_OFFSET_SCALE * max(|p|, 1) towards the viewer's side, to infinity for
// a directional light, to the light less the offset for a point or spot. Shared by the
// ray-traced technique (visibility/ray.frag) and the ray-traced hybrid (hybrid/classify_rays.frag).
// Include after visibility/surface.glsl.
#ifndef UMBRA_RAY_SHADOW_RAY_GLSL
#define UMBRA_RAY_SHADOW_RAY_GLSL

// umbra_reference::RAY_OFFSET_SCALE.
const float RAY_OFFSET_SCALE = 1e-5;

struct ShadowRay {
    vec3 origin;
    vec3 dir;
    float t_max;
};

// The geometric normal from the position's derivatives, as the G-buffer the reference reads,
// turned towards the camera. Call it before any branch: derivatives are undefined once a
// neighbour of the quad has left.
vec3 geometric_normal() {
    vec3 g = cross(dFdxFine(world_position), dFdyFine(world_position));
    float len = length(g);
    g = len > 0.0 ? g / len : vec3(0.0);
    if (dot(g, frame.camera_position.xyz - world_position) < 0.0) {
        g = -g;
    }
    return g;
}

// The ray from `p` (geometric normal `g`) towards light `l`.
ShadowRay shadow_ray(Light l, vec3 p, vec3 g) {
    vec3 a = abs(p);
    float offset = RAY_OFFSET_SCALE * max(max(max(a.x, a.y), a.z), 1.0);
    ShadowRay r;
    r.origin = p + g * offset;
    if (l.position.w == 0.0) {
        r.dir = normalize(l.position.xyz);
        r.t_max = uintBitsToFloat(0x7f800000u);
    } else {
        vec3 to_light = l.position.xyz / l.position.w - p;
        float d = length(to_light);
        r.dir = to_light / d;
        r.t_max = d - offset;
    }
    return r;
}

#endif

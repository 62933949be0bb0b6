// The hybrid's conservative classification (Chan–Durand §3 step 2, made exact): a receiver is
// decided by the light's depth bounds (hybrid/bounds.frag) only where they cannot be wrong.
// Certainly lit: the receiver lies nearer the light than the least depth any occluder can have
// in its texel. Certainly shadowed: one occluder triangle covers the whole texel nearer than
// it. Anything else is a silhouette pixel, for the shadow volumes. `margin` keeps contact
// (an occluder within it of the receiver) in question.
#ifndef UMBRA_HYBRID_BOUNDS_LOOKUP_GLSL
#define UMBRA_HYBRID_BOUNDS_LOOKUP_GLSL

#include "common/cube.glsl"
#include "hybrid/bounds.glsl"

layout(constant_id = 1) const bool OUTSIDE_LIT = true;

// Layer f holds face f's nearest (R) and covering (G) bounds.
layout(set = 1, binding = 4) uniform sampler2DArray hybrid_bounds;

const float CERTAINLY_SHADOWED = 0.0;
const float CERTAINLY_LIT = 1.0;
const float IN_QUESTION = -1.0;

// CERTAINLY_LIT, CERTAINLY_SHADOWED or IN_QUESTION for receiver p of light l.
float bounded_visibility(Light l, vec3 p) {
    bool cube = uint(l.spot_params.z) == SHADOW_CUBE;
    float major;
    uint face = cube ? cube_face(p - l.position.xyz, major) : 0u;
    vec4 clip = shadow_views[uint(l.spot_params.w) + face] * vec4(p, 1.0);
    if (clip.w <= 0.0) {
        return IN_QUESTION;
    }
    vec2 ndc = clip.xy / clip.w;
    if (!cube && any(greaterThan(abs(ndc), vec2(1.0)))) {
        // Outside the frustum fitted to every caster that can shadow a visible receiver.
        return OUTSIDE_LIT ? CERTAINLY_LIT : CERTAINLY_SHADOWED;
    }
    float size = 1.0 / l.shadow_params.y;
    vec2 texel = floor(vec2(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y) * size);
    ivec2 t = clamp(ivec2(texel), ivec2(0), ivec2(int(size) - 1));
    float depth = light_depth(l, clip);
    float margin = l.position.w == 0.0 ? 2e-5 : 1e-4 * depth;
    vec2 bounds = texelFetch(hybrid_bounds, ivec3(t, int(face)), 0).rg;
    float nearest = bounds.r;
    float covering = bounds.g;
    if (depth + margin < nearest) {
        return CERTAINLY_LIT;
    }
    if (covering < 1.0 && covering + margin < depth) {
        return CERTAINLY_SHADOWED;
    }
    return IN_QUESTION;
}

#endif

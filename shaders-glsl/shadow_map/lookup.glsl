// Shadow-map lookup in the lighting pass (Williams' second pass; Chan–Durand §3 step 1).
//
// Filters, chosen by the specialization constant SHADOW_FILTER:
//   0 nearest  one comparison (the sampler filters NEAREST)
//   1 pcf2x2   hardware 2x2 PCF: one fetch through a LINEAR comparison sampler
//   2 pcf3x3   3x3 nearest comparisons averaged
//   3 pcf5x5   5x5 nearest comparisons averaged
// A point outside a 2D shadow map's frustum is lit (OUTSIDE_LIT) or shadowed, explicitly: the
// clamped border texel is never consulted for it (Arneson Fig. 1's artifact).
#ifndef UMBRA_SHADOW_MAP_LOOKUP_GLSL
#define UMBRA_SHADOW_MAP_LOOKUP_GLSL

#include "common/scene.glsl"

layout(constant_id = 0) const uint SHADOW_FILTER = 1u;
layout(constant_id = 1) const bool OUTSIDE_LIT = true;

layout(set = 1, binding = 0) uniform sampler2DShadow shadow_map;
layout(set = 1, binding = 1) uniform samplerCubeShadow shadow_cube;

int pcf_radius() {
    return SHADOW_FILTER == 3u ? 2 : (SHADOW_FILTER == 2u ? 1 : 0);
}

float lookup_2d(Light l, vec3 p) {
    vec4 clip = shadow_views[uint(l.spot_params.w)] * vec4(p, 1.0);
    if (clip.w <= 0.0) {
        return OUTSIDE_LIT ? 1.0 : 0.0;
    }
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) {
        return OUTSIDE_LIT ? 1.0 : 0.0;
    }
    // The shadow pass used umbra's y-up viewport: row 0 is ndc.y = +1.
    vec2 uv = vec2(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    // Beyond the far plane (a receiver behind every caster) compares as depth 1.
    float depth = clamp(ndc.z, 0.0, 1.0);
    int r = pcf_radius();
    if (r == 0) {
        return texture(shadow_map, vec3(uv, depth));
    }
    float texel = l.shadow_params.y;
    float sum = 0.0;
    for (int j = -r; j <= r; ++j) {
        for (int i = -r; i <= r; ++i) {
            sum += texture(shadow_map, vec3(uv + vec2(i, j) * texel, depth));
        }
    }
    return sum / float((2 * r + 1) * (2 * r + 1));
}

float lookup_cube(Light l, vec3 p) {
    vec3 v = p - l.position.xyz;
    vec3 a = abs(v);
    float major = max(a.x, max(a.y, a.z));
    float near = l.shadow_params.z;
    float far = l.shadow_params.w;
    // The face's perspective depth of a point `major` away along the face axis.
    float depth = clamp(far / (far - near) * (1.0 - near / max(major, 1e-20)), 0.0, 1.0);
    int r = pcf_radius();
    if (r == 0) {
        return texture(shadow_cube, vec4(v, depth));
    }
    // Step one texel across the face: 2 * major / size in the two face-plane axes.
    vec3 t1 = a.x >= a.y && a.x >= a.z ? vec3(0, 1, 0) : vec3(1, 0, 0);
    vec3 t2 = a.z >= a.x && a.z >= a.y ? vec3(0, 1, 0) : vec3(0, 0, 1);
    float step = 2.0 * major * l.shadow_params.y;
    float sum = 0.0;
    for (int j = -r; j <= r; ++j) {
        for (int i = -r; i <= r; ++i) {
            sum += texture(shadow_cube, vec4(v + (float(i) * t1 + float(j) * t2) * step, depth));
        }
    }
    return sum / float((2 * r + 1) * (2 * r + 1));
}

// 1 = lit, 0 = shadowed, in between on filtered edges. `n` is the unit geometric normal
// facing the light's side; the normal offset moves the lookup point along it.
float shadow_visibility(Light l, vec3 p, vec3 n) {
    uint kind = uint(l.spot_params.z);
    if (kind == SHADOW_NONE) {
        return 1.0;
    }
    vec3 q = p + n * l.shadow_params.x;
    return kind == SHADOW_CUBE ? lookup_cube(l, q) : lookup_2d(l, q);
}

#endif

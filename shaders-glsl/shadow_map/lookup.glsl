// Shadow-map lookup in the lighting pass (Williams' second pass; Chan–Durand §3 step 1).
//
// Filters, chosen by the specialization constant SHADOW_FILTER:
//   0 nearest  one comparison (the sampler filters NEAREST)
//   1 pcf2x2   hardware 2x2 PCF: one fetch through a LINEAR comparison sampler
//   2 pcf3x3   3x3 nearest comparisons averaged
//   3 pcf5x5   5x5 nearest comparisons averaged
// Lookups use explicit LOD 0 (textureLod / zero-gradient textureGrad): they run in
// non-uniform control flow (after `discard`, per-light branches), where implicit derivatives
// are undefined.
// A point outside a 2D shadow map's frustum is lit (OUTSIDE_LIT) or shadowed, explicitly: the
// clamped border texel is never consulted for it (Arneson Fig. 1's artifact).
#ifndef UMBRA_SHADOW_MAP_LOOKUP_GLSL
#define UMBRA_SHADOW_MAP_LOOKUP_GLSL

#include "common/scene.glsl"

layout(constant_id = 0) const uint SHADOW_FILTER = 1u;
layout(constant_id = 1) const bool OUTSIDE_LIT = true;

layout(set = 1, binding = 0) uniform sampler2DShadow shadow_map;
layout(set = 1, binding = 1) uniform samplerCubeShadow shadow_cube;

// Perspective maps (spot, cube) store f/(f-n) * (1 - n/z): for a surface that faces the light
// head-on, z is constant across the map, the slope-scaled bias is zero, and the cancellation in
// (1 - n/z) (in the rasterizer's matrix path and in this lookup alike) leaves the receiver
// compared against itself within a few ulps: per-pixel acne independent of the map's
// resolution. The receiver is compared as if RECEIVER_SHRINK (relative) nearer the light along
// the view axis: ~1000 ulps of depth, 10^-4 of the distance in world units.
const float RECEIVER_SHRINK = 1e-4;

float perspective_depth(float z, float near, float far) {
    return clamp(far / (far - near) * (1.0 - near / max(z * (1.0 - RECEIVER_SHRINK), 1e-20)), 0.0, 1.0);
}

int pcf_radius() {
    return SHADOW_FILTER == 3u ? 2 : (SHADOW_FILTER == 2u ? 1 : 0);
}

// Projects p into light l's 2D map: its texture coordinates and the depth it compares with.
// False when p lies outside the map's frustum (the caller applies OUTSIDE_LIT).
bool project_2d(Light l, vec3 p, out vec2 uv, out float depth) {
    uv = vec2(0.0);
    depth = 1.0;
    vec4 clip = shadow_views[uint(l.spot_params.w)] * vec4(p, 1.0);
    if (clip.w <= 0.0) {
        return false;
    }
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) {
        return false;
    }
    // The shadow pass used umbra's y-up viewport: row 0 is ndc.y = +1.
    uv = vec2(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    // Beyond the far plane (a receiver behind every caster) compares as depth 1.
    depth = clamp(ndc.z, 0.0, 1.0);
    if (l.position.w != 0.0) {
        // Spot: depth along the axis, through the same formula as the cube faces.
        float z = dot(p - l.position.xyz, normalize(l.spot_direction.xyz));
        depth = perspective_depth(z, l.shadow_params.z, l.shadow_params.w);
    }
    return true;
}

float lookup_2d(Light l, vec3 p) {
    vec2 uv;
    float depth;
    if (!project_2d(l, p, uv, depth)) {
        return OUTSIDE_LIT ? 1.0 : 0.0;
    }
    int r = pcf_radius();
    if (r == 0) {
        return textureLod(shadow_map, vec3(uv, depth), 0.0);
    }
    float texel = l.shadow_params.y;
    float sum = 0.0;
    for (int j = -r; j <= r; ++j) {
        for (int i = -r; i <= r; ++i) {
            sum += textureLod(shadow_map, vec3(uv + vec2(i, j) * texel, depth), 0.0);
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
    float depth = perspective_depth(major, near, far);
    int r = pcf_radius();
    if (r == 0) {
        return textureGrad(shadow_cube, vec4(v, depth), vec3(0.0), vec3(0.0));
    }
    // Step one texel across the face: 2 * major / size in the two face-plane axes.
    vec3 t1 = a.x >= a.y && a.x >= a.z ? vec3(0, 1, 0) : vec3(1, 0, 0);
    vec3 t2 = a.z >= a.x && a.z >= a.y ? vec3(0, 1, 0) : vec3(0, 0, 1);
    float step = 2.0 * major * l.shadow_params.y;
    float sum = 0.0;
    for (int j = -r; j <= r; ++j) {
        for (int i = -r; i <= r; ++i) {
            vec3 w = v + (float(i) * t1 + float(j) * t2) * step;
            sum += textureGrad(shadow_cube, vec4(w, depth), vec3(0.0), vec3(0.0));
        }
    }
    return sum / float((2 * r + 1) * (2 * r + 1));
}

// 1 = lit, 0 = shadowed, in between on filtered edges. `n` is the unit geometric normal
// facing the light's side; the normal offset moves the lookup point along it. Silhouette-map
// lights (SHADOW_SILHOUETTE, SHADOW_SILHOUETTE_CUBE) are looked up by silhouette_visibility
// (silhouette_map/lookup.glsl), never here.
float shadow_visibility(Light l, vec3 p, vec3 n) {
    uint kind = uint(l.spot_params.z);
    if (kind == SHADOW_NONE) {
        return 1.0;
    }
    vec3 q = p + n * l.shadow_params.x;
    return kind == SHADOW_CUBE ? lookup_cube(l, q) : lookup_2d(l, q);
}

#endif

// Pass 3 of the silhouette map (§3.2): four depth comparisons at the corners of the
// silhouette texel holding the point; where they agree, that is the answer (one branch for
// most pixels). Where they disagree a silhouette crosses the texel: fetch its point and its
// four neighbours', find the skewed quadrant holding the point (eight wedge tests, Fig. 5) and
// use that corner's comparison.
#ifndef UMBRA_SILHOUETTE_LOOKUP_GLSL
#define UMBRA_SILHOUETTE_LOOKUP_GLSL

#include "shadow_map/lookup.glsl"
#include "silhouette_map/geometry.glsl"
#include "silhouette_map/bindings.glsl"

// Where p falls in light l's silhouette map: the silhouette texel and the texel-local point.
// False outside the map's frustum.
bool silhouette_cell(Light l, vec3 p, out ivec2 cell, out vec2 local, out float depth) {
    vec2 uv;
    cell = ivec2(0);
    local = DEFAULT_POINT;
    if (!project_2d(l, p, uv, depth)) {
        return false;
    }
    // Silhouette texel i spans map coordinates [i + 0.5, i + 1.5].
    vec2 m = uv / l.shadow_params.y - 0.5;
    vec2 c = floor(m);
    cell = ivec2(c);
    local = m - c;
    return true;
}

// The stored point of silhouette texel `t` (the default point beyond the map's edge).
vec2 silhouette_point(ivec2 t, int res) {
    if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, ivec2(res)))) {
        return DEFAULT_POINT;
    }
    return texelFetch(silhouette_map, t, 0).xy;
}

// 1 = lit, 0 = shadowed. `reconstructed` tells whether the comparisons disagreed and the
// silhouette points decided (a silhouette pixel).
float silhouette_visibility(Light l, vec3 p, vec3 n, out bool reconstructed) {
    reconstructed = false;
    ivec2 cell;
    vec2 s;
    float depth;
    if (!silhouette_cell(l, p + n * l.shadow_params.x, cell, s, depth)) {
        return OUTSIDE_LIT ? 1.0 : 0.0;
    }
    float texel = l.shadow_params.y;
    // One gather at the middle of the texel: its four corner samples compared with `depth`,
    // x = corner (0, 1), y = (1, 1), z = (1, 0), w = (0, 0).
    vec4 lit = textureGather(shadow_map, (vec2(cell) + 1.0) * texel, depth);
    float sum = lit.x + lit.y + lit.z + lit.w;
    if (sum == 0.0 || sum == 4.0) {
        return lit.x;
    }
    reconstructed = true;
    int res = int(round(1.0 / texel));
    vec2 centre = silhouette_point(cell, res);
    vec2 left = silhouette_point(cell + ivec2(-1, 0), res) + vec2(-1.0, 0.0);
    vec2 down = silhouette_point(cell + ivec2(0, -1), res) + vec2(0.0, -1.0);
    vec2 right = silhouette_point(cell + ivec2(1, 0), res) + vec2(1.0, 0.0);
    vec2 up = silhouette_point(cell + ivec2(0, 1), res) + vec2(0.0, 1.0);
    uint corner = quadrant(centre, left, down, right, up, s);
    return corner == CORNER_00 ? lit.w : (corner == CORNER_10 ? lit.z : (corner == CORNER_11 ? lit.y : lit.x));
}

#endif

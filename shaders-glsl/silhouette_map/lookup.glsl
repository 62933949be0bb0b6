// Pass 3 of the silhouette map (§3.2): four depth comparisons at the corners of the
// silhouette texel holding the point; where they agree, that is the answer (one branch for
// most pixels). Where they disagree a silhouette crosses the texel: fetch its point and its
// four neighbours', find the skewed quadrant holding the point (eight wedge tests, Fig. 5) and
// use that corner's comparison. A point light's maps are face atlases: the lookup runs in the
// face the direction picks.
#ifndef UMBRA_SILHOUETTE_LOOKUP_GLSL
#define UMBRA_SILHOUETTE_LOOKUP_GLSL

#include "shadow_map/atlas.glsl"
#include "shadow_map/lookup.glsl"
#include "silhouette_map/geometry.glsl"
#include "silhouette_map/bindings.glsl"

// Whether light l casts silhouette-map shadows (a 2D map or a face atlas).
bool silhouette_light(Light l) {
    uint kind = uint(l.spot_params.z);
    return kind == SHADOW_SILHOUETTE || kind == SHADOW_SILHOUETTE_CUBE;
}

// Where a point falls in a light's silhouette map: the silhouette texel in its face, the
// texel-local point and the depth it compares with; and where that face lies in the map.
struct SilhouetteCell {
    ivec2 cell;
    vec2 local;
    float depth;
    ivec2 origin; // the face's first texel (0 for a 2D map)
    int side;     // texels per side of the face
    vec2 to_uv;   // map texels to texture coordinates
};

// Where p falls in light l's silhouette map. A face atlas (a point light) uses the face the
// direction's major axis picks: p lies within its 90° interior, so the texels the lookup reads
// lie in that face and its border (shadow_map/atlas.glsl). False outside a 2D map's frustum.
bool silhouette_cell(Light l, vec3 p, out SilhouetteCell c) {
    vec2 uv;
    c.cell = ivec2(0);
    c.local = DEFAULT_POINT;
    c.depth = 1.0;
    uint face = 0u;
    if (uint(l.spot_params.z) == SHADOW_SILHOUETTE_CUBE) {
        float major;
        face = cube_face(p - l.position.xyz, major);
        vec4 clip = shadow_views[uint(l.spot_params.w) + face] * vec4(p, 1.0);
        if (clip.w <= 0.0) {
            return false;
        }
        vec2 ndc = clip.xy / clip.w;
        uv = vec2(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
        c.depth = perspective_depth(major, l.shadow_params.z, l.shadow_params.w);
    } else if (!project_2d(l, p, uv, c.depth)) {
        return false;
    }
    map_face(l, face, c.origin, c.side, c.to_uv);
    // Silhouette texel i spans map coordinates [i + 0.5, i + 1.5].
    vec2 m = uv / l.shadow_params.y - 0.5;
    vec2 f = floor(m);
    c.cell = ivec2(f);
    c.local = m - f;
    return true;
}

// The stored point of silhouette texel `t` of c's face (the default point beyond the face).
vec2 silhouette_point(SilhouetteCell c, ivec2 t) {
    if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, ivec2(c.side)))) {
        return DEFAULT_POINT;
    }
    return texelFetch(silhouette_map, c.origin + t, 0).xy;
}

// 1 = lit, 0 = shadowed. `reconstructed` tells whether the comparisons disagreed and the
// silhouette points decided (a silhouette pixel).
float silhouette_visibility(Light l, vec3 p, vec3 n, out bool reconstructed) {
    reconstructed = false;
    SilhouetteCell c;
    if (!silhouette_cell(l, p + n * l.shadow_params.x, c)) {
        return OUTSIDE_LIT ? 1.0 : 0.0;
    }
    // One gather at the middle of the texel: its four corner samples compared with the depth,
    // x = corner (0, 1), y = (1, 1), z = (1, 0), w = (0, 0).
    vec4 lit = textureGather(shadow_map, (vec2(c.origin + c.cell) + 1.0) * c.to_uv, c.depth);
    float sum = lit.x + lit.y + lit.z + lit.w;
    if (sum == 0.0 || sum == 4.0) {
        return lit.x;
    }
    reconstructed = true;
    vec2 centre = silhouette_point(c, c.cell);
    vec2 left = silhouette_point(c, c.cell + ivec2(-1, 0)) + vec2(-1.0, 0.0);
    vec2 down = silhouette_point(c, c.cell + ivec2(0, -1)) + vec2(0.0, -1.0);
    vec2 right = silhouette_point(c, c.cell + ivec2(1, 0)) + vec2(1.0, 0.0);
    vec2 up = silhouette_point(c, c.cell + ivec2(0, 1)) + vec2(0.0, 1.0);
    uint corner = quadrant(centre, left, down, right, up, c.local);
    return corner == CORNER_00 ? lit.w : (corner == CORNER_10 ? lit.z : (corner == CORNER_11 ? lit.y : lit.x));
}

#endif

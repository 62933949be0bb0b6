#version 460
// Pass 2 of the silhouette map (§3.1, Fig. 3): each silhouette edge (one instance, world-space
// endpoints) becomes a thin quad in the silhouette map, widened and lengthened by GROW texels
// so that every texel the segment touches gets a fragment (a texel the segment crosses has its
// centre within sqrt(2)/2 of it): conservative rasterization without the extension.
//
// The silhouette map is the depth map's grid shifted by half a texel in x and y (the dual
// grid): silhouette texel (i, j) spans map coordinates [i + 0.5, i + 1.5] x [j + 0.5, j + 1.5],
// its corners the depth samples (i, j) .. (i + 1, j + 1). Map coordinates are texels of the
// depth map along u and v; the fragment shader gets both endpoints in them, with their depth.
#include "common/scene.glsl"

// The device's subPixelPrecisionBits: the depth pass rasterized the casters with their
// vertices snapped to 1/2^bits of a texel, so a depth sample within that distance of an edge
// may fall on either side of the exact line. Endpoints snapped the same way keep the stored
// points on the edge the depth map actually holds, so the corner comparisons agree with them.
layout(constant_id = 2) const uint SUBPIXEL_BITS = 8u;

layout(location = 0) in vec3 edge_a;
layout(location = 1) in vec3 edge_b;

layout(location = 0) flat out vec3 out_a; // map x, map y, depth-map depth
layout(location = 1) flat out vec3 out_b;

const float GROW = 1.0;  // texels: > sqrt(2)/2, with a margin for the rasterizer's tie rules
const float GUARD = 2.0; // texels beyond the map the segment is clipped to (keeps coordinates small)
// Quad corners over two triangles: 0 = (a, -), 1 = (b, -), 2 = (b, +), 3 = (a, +).
const uint VERTICES_PER_EDGE = 6u;
const uint QUAD[6] = uint[6](0u, 1u, 2u, 0u, 2u, 3u);

vec3 to_map(vec4 clip, float res) {
    vec3 ndc = clip.xyz / clip.w;
    // umbra's y-up viewport stores ndc.y = +1 in row 0 (as shadow_map/lookup.glsl reads it).
    return vec3((0.5 + 0.5 * ndc.x) * res, (0.5 - 0.5 * ndc.y) * res, ndc.z);
}

void main() {
    Light l = lights[push.view];
    // `push.object` is the face of a face atlas (0 for a 2D map); the viewport is its tile.
    mat4 view_proj = shadow_views[uint(l.spot_params.w) + push.object];
    float res = 1.0 / l.shadow_params.y;
    vec4 ca = view_proj * vec4(edge_a, 1.0);
    vec4 cb = view_proj * vec4(edge_b, 1.0);
    // Clip to the map's near plane (w = near for a spot or a cube face; an orthographic map
    // has w = 1):
    // nothing nearer is in the depth map, and w <= 0 would not project.
    float w_min = l.position.w == 0.0 ? 0.0 : l.shadow_params.z;
    bool keep = ca.w >= w_min || cb.w >= w_min;
    if (keep && ca.w < w_min) {
        ca = mix(ca, cb, (w_min - ca.w) / (cb.w - ca.w));
    } else if (keep && cb.w < w_min) {
        cb = mix(cb, ca, (w_min - cb.w) / (ca.w - cb.w));
    }
    vec3 a = to_map(ca, res);
    vec3 b = to_map(cb, res);
    float grid = float(1u << SUBPIXEL_BITS);
    a.xy = round(a.xy * grid) / grid;
    b.xy = round(b.xy * grid) / grid;
    // Liang–Barsky clip of a -> b to the map plus a guard band; depth is affine in map space
    // for orthographic and perspective maps alike, so it follows the same parameter.
    vec3 d = b - a;
    float t0 = 0.0;
    float t1 = 1.0;
    for (int i = 0; i < 2; ++i) {
        float lo = -GUARD;
        float hi = res + GUARD;
        if (d[i] == 0.0) {
            keep = keep && a[i] >= lo && a[i] <= hi;
        } else {
            float ta = (lo - a[i]) / d[i];
            float tb = (hi - a[i]) / d[i];
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        }
    }
    keep = keep && t0 <= t1 && !any(isnan(a)) && !any(isnan(b)) && !any(isinf(a)) && !any(isinf(b));
    vec3 a2 = a + d * t0;
    vec3 b2 = a + d * t1;
    out_a = a2;
    out_b = b2;
    if (!keep) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0); // all six corners equal: no area, no fragment
        return;
    }
    vec2 e = b2.xy - a2.xy;
    float len = length(e);
    vec2 dir = len > 1e-6 ? e / len : vec2(1.0, 0.0);
    vec2 normal = vec2(-dir.y, dir.x);
    uint corner = QUAD[uint(gl_VertexIndex) % VERTICES_PER_EDGE];
    bool at_b = corner == 1u || corner == 2u;
    float side = corner >= 2u ? 1.0 : -1.0;
    vec2 p = (at_b ? b2.xy + dir * GROW : a2.xy - dir * GROW) + normal * (side * GROW);
    // Framebuffer position of the shifted grid: map coordinate minus half a texel.
    vec2 f = p - 0.5;
    gl_Position = vec4(2.0 * f.x / res - 1.0, 1.0 - 2.0 * f.y / res, 0.5, 1.0);
}

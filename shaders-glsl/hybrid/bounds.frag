#version 460
// The hybrid's conservative depth bounds, fragment stage (hybrid/bounds.glsl): this texel's
// square (grown by 1/64 of a texel, for the classification's own rounding) against the real
// triangle, in homogeneous 2D coordinates (x, y, w). With the corners c0, c1, c2 and
// e_k = c_i x c_j over det [c0 c1 c2], u_k(p) = e_k . (p, 1) are the barycentric coordinates,
// scaled by the ray parameter, of where the ray through NDC point p meets the triangle's plane;
// the ray meets the triangle in front of the light exactly where all three are >= 0, and their
// sum q(p) is 1 / w there (1 for orthographic views). Each is affine in p, so its extremes over
// the square lie at the corners: value at the centre plus or minus |gradient| . half-size.
//
// Both bounds at once, into an RG32F layer per map face blended with MIN (cleared to 1, which
// bounds nothing). R, nearest: where the square may touch the triangle (no u_k below 0 at every
// corner) and its centre lies in the triangle's grown box (bounds.vert), a lower bound of the
// triangle's depth over the square (the plane's least value at a corner, and never below its
// nearest corner). G, covering: where the square lies inside the triangle (every u_k above 0 at
// every corner), an upper bound of its depth there; 1 elsewhere. A square the triangle may not
// touch writes neither (it lies inside no triangle either).
#include "hybrid/bounds.glsl"

layout(location = 0) flat in vec4 corner[3];
layout(location = 3) flat in vec4 box;
layout(location = 4) flat in uint covers;

layout(location = 0) out vec2 out_bounds;

void main() {
    Light l = lights[bounds_light()];
    float texel = l.shadow_params.y;
    // umbra's y-up viewport: row 0 is NDC y = +1.
    vec2 centre = vec2(gl_FragCoord.x * 2.0 * texel - 1.0, 1.0 - gl_FragCoord.y * 2.0 * texel);
    if (any(lessThan(centre, box.xy)) || any(greaterThan(centre, box.zw))) {
        discard;
    }
    vec2 half_size = vec2(texel * (1.0 + 1.0 / 64.0));
    vec3 c0 = corner[0].xyz;
    vec3 c1 = corner[1].xyz;
    vec3 c2 = corner[2].xyz;
    vec3 e[3] = vec3[3](cross(c1, c2), cross(c2, c0), cross(c0, c1));
    float det = dot(c0, e[0]);
    vec3 depth = vec3(corner[0].w, corner[1].w, corner[2].w);
    bool perspective = l.position.w != 0.0;
    float scale = length(c0) * length(c1) * length(c2);
    bool degenerate = abs(det) <= 1e-6 * scale;
    if (degenerate) {
        // Edge-on to the light (or nearly): it covers no texel; its box, drawn by the vertex
        // stage, bounds it at its nearest corner.
        float w_min = min(c0.z, min(c1.z, c2.z));
        float nearest = perspective && w_min <= 0.0 ? 0.0 : clamp(min(depth.x, min(depth.y, depth.z)), 0.0, 1.0);
        out_bounds = vec2(nearest, 1.0);
        return;
    }
    vec3 p = vec3(centre, 1.0);
    vec3 q = vec3(0.0); // gradient (xy) and constant (z) of the sum of the u_k
    vec3 z = vec3(0.0); // of the orthographic depth, sum of u_k * depth_k
    bool inside = covers != 0u;
    for (int k = 0; k < 3; ++k) {
        vec3 u = e[k] / det;
        float at_centre = dot(u, p);
        float spread = dot(abs(u.xy), half_size);
        if (at_centre + spread < 0.0) {
            discard;
        }
        inside = inside && at_centre - spread > 0.0;
        q += u;
        z += u * depth[k];
    }
    float q_centre = dot(q, p);
    float q_spread = dot(abs(q.xy), half_size);
    float z_centre = dot(z, p);
    float z_spread = dot(abs(z.xy), half_size);
    float nearest;
    float covering = 1.0;
    float nearest_corner = min(depth.x, min(depth.y, depth.z));
    float farthest_corner = max(depth.x, max(depth.y, depth.z));
    if (perspective) {
        float q_max = q_centre + q_spread;
        if (q_max <= 0.0) {
            discard; // only behind the light (and so inside no square's triangle either)
        }
        float w_min = min(c0.z, min(c1.z, c2.z));
        float w = max(1.0 / q_max, w_min);
        nearest = w / l.shadow_params.w;
        float q_min = q_centre - q_spread;
        if (inside) {
            covering = q_min > 0.0 ? min(1.0 / q_min / l.shadow_params.w, farthest_corner) : 1.0;
        }
    } else {
        nearest = max(z_centre - z_spread, nearest_corner);
        if (inside) {
            covering = min(z_centre + z_spread, farthest_corner);
        }
    }
    out_bounds = clamp(vec2(nearest, covering), 0.0, 1.0);
}

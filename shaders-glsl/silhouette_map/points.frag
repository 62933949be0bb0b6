#version 460
// Pass 2 of the silhouette map (§3.1): pick the point this texel stores on the edge, in
// texel-local coordinates, or discard: the segment misses the texel, or the edge lies farther
// from the light than all four depth samples at the texel's corners (a hidden silhouette).
// Drawn once per face into a face atlas, each face's edges clipped to its tile.
#include "common/scene.glsl"
#include "shadow_map/atlas.glsl"
#include "silhouette_map/geometry.glsl"
#include "silhouette_map/bindings.glsl"

layout(location = 0) flat in vec3 in_a;
layout(location = 1) flat in vec3 in_b;

layout(location = 0) out vec2 out_point;

// Depth-map units an edge may lie behind the farthest corner sample and still count as seen.
const float HIDDEN_TOLERANCE = 1e-6;

void main() {
    // Silhouette texel (i, j) of the face has fragment centre (i + 0.5, j + 0.5) in its tile:
    // exactly the map coordinates of its (0, 0) corner, depth sample (i, j). `push.object` is
    // the face being drawn (0 for a 2D map).
    Light l = lights[push.view];
    ivec2 face_origin;
    int side;
    vec2 to_uv;
    map_face(l, push.object, face_origin, side, to_uv);
    vec2 origin = gl_FragCoord.xy - vec2(face_origin);
    vec2 a = in_a.xy - origin;
    vec2 b = in_b.xy - origin;
    vec2 p;
    if (!pick_point(a, b, p)) {
        discard;
    }
    vec2 e = b - a;
    float len2 = dot(e, e);
    float t = len2 > 0.0 ? clamp(dot(p - a, e) / len2, 0.0, 1.0) : 0.0;
    float depth = mix(in_a.z, in_b.z, t);
    // The 2x2 footprint centred on the texel's middle: its four corner samples.
    vec4 corners = textureGather(shadow_depth_raw, (gl_FragCoord.xy + 0.5) * to_uv, 0);
    if (depth > max(max(corners.x, corners.y), max(corners.z, corners.w)) + HIDDEN_TOLERANCE) {
        discard;
    }
    out_point = p;
}

// The hybrid's conservative depth bounds (hybrid/bounds.vert, hybrid/bounds.frag): per texel of
// a light's map, a lower bound on the depth of every occluder that touches the texel's square
// ("nearest") or an upper bound on the depth of an occluder triangle that covers all of it
// ("covering"). docs/techniques/hybrid.md, "A classification that cannot be wrong", argues why
// the classification that reads them (hybrid/bounds_lookup.glsl) is conservative.
//
// Depth here is the light's own measure along its rays: the orthographic map's z for a
// directional light, the distance along the axis over `far` (clip w / far) for perspective
// views (spot, cube faces). Along one ray through the light both grow with distance, so they
// order an occluder and a receiver on that ray exactly.
#ifndef UMBRA_HYBRID_BOUNDS_GLSL
#define UMBRA_HYBRID_BOUNDS_GLSL

#include "common/scene.glsl"

// push.view packs the light (bits 4..), the map face (cube face, bits 1..3) and whether the
// object's mesh is closed (bit 0).
uint bounds_light() {
    return push.view >> 4;
}

uint bounds_face() {
    return (push.view >> 1) & 7u;
}

bool bounds_closed() {
    return (push.view & 1u) != 0u;
}

// Whether the triangle of homogeneous corners c0, c1, c2 (clip x, y, w) is edge-on to the light
// (or nearly): its determinant at most `tolerance` of its scale.
bool bounds_edge_on(vec3 c0, vec3 c1, vec3 c2, float tolerance) {
    float det = dot(c0, cross(c1, c2));
    return abs(det) <= tolerance * length(c0) * length(c1) * length(c2);
}

// The light's depth measure of a clip-space position of view `l`.
float light_depth(Light l, vec4 clip) {
    return l.position.w == 0.0 ? clip.z : clip.w / l.shadow_params.w;
}

#endif

#version 460
// Diagnostic: a shadow-map, silhouette-map or shadow-volume light's per-pixel class
// (debug/classes.glsl) over the frame's depth (EQUAL), decided by the same lookups as its
// visibility pass (visibility/map.frag): the technique's per-light shadow mask in the colours of
// Chan–Durand Fig. 6b. A shadow-volume light's shader sees no map: its stencil, copied out with
// the classes, decides the pixels classed as lit here (`umbra_shadows::diagnostics`).
#include "common/scene.glsl"
#include "forward/lambert.glsl"
#include "silhouette_map/lookup.glsl"
#include "debug/classes.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_class;

void main() {
    Light l = lights[push.view];
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    float lambert = lambert_attenuated(l, world_position, n);
    bool receiver = objects[push.object].albedo.a > 0.5;
    if (!receiver) {
        out_class = CLASS_NOT_RECEIVER;
        return;
    }
    if (lambert <= 0.0) {
        out_class = CLASS_UNREACHED;
        return;
    }
    bool reconstructed = false;
    float visibility;
    if (silhouette_light(l)) {
        visibility = silhouette_visibility(l, world_position, n, reconstructed);
    } else {
        visibility = shadow_visibility(l, world_position, n);
    }
    // Filtered maps give fractions: the pixel counts as lit from one half up.
    bool lit = visibility > 0.5;
    if (reconstructed) {
        out_class = lit ? CLASS_SILHOUETTE_LIT : CLASS_SILHOUETTE_SHADOWED;
    } else {
        out_class = lit ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
    }
}

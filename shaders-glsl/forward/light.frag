#version 460
// Forward pass per light, blended additively: Lambert's law, albedo * radiance * max(N.L, 0),
// with inverse-square falloff for point and spot lights, a smooth spot cone
// (forward/lambert.glsl), and the light's shadow test: a shadow-map lookup
// (shadow_map/lookup.glsl), a silhouette-map lookup (silhouette_map/lookup.glsl), or
// visibility 1 when the light casts no shadows here.
// Surfaces are lit on both sides (open meshes show their inside through holes).
// With OUTPUT_CLASSES (a diagnostic pipeline) the same decisions are written as the pixel's
// class (debug/classes.glsl) instead of light: the technique's per-light shadow mask.
#include "common/scene.glsl"
#include "forward/lambert.glsl"
#include "silhouette_map/lookup.glsl"
#include "debug/classes.glsl"

layout(constant_id = 2) const bool OUTPUT_CLASSES = false;

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_color;

void main() {
    Light l = lights[push.view];
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    float lambert = lambert_attenuated(l, world_position, n);
    bool receiver = objects[push.object].albedo.a > 0.5;
    if (lambert <= 0.0) {
        if (OUTPUT_CLASSES) {
            out_color = receiver ? CLASS_UNREACHED : CLASS_NOT_RECEIVER;
            return;
        }
        discard; // adds nothing; skips the shadow lookup
    }
    float visibility = 1.0;
    bool reconstructed = false;
    if (receiver) {
        if (uint(l.spot_params.z) == SHADOW_SILHOUETTE) {
            visibility = silhouette_visibility(l, world_position, n, reconstructed);
        } else {
            visibility = shadow_visibility(l, world_position, n);
        }
    }
    if (OUTPUT_CLASSES) {
        // Filtered maps give fractions: the pixel counts as lit from one half up.
        bool lit = visibility > 0.5;
        if (!receiver) {
            out_color = CLASS_NOT_RECEIVER;
        } else if (reconstructed) {
            out_color = lit ? CLASS_SILHOUETTE_LIT : CLASS_SILHOUETTE_SHADOWED;
        } else {
            out_color = lit ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
        }
        return;
    }
    out_color = vec4(albedo * l.radiance.rgb * (lambert * visibility), 0.0);
}

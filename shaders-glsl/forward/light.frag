#version 460
// Forward pass per light, blended additively: Lambert's law, albedo * radiance * max(N.L, 0),
// with inverse-square falloff for point and spot lights, a smooth spot cone
// (forward/lambert.glsl), and the light's shadow test: a shadow-map lookup
// (shadow_map/lookup.glsl), a silhouette-map lookup (silhouette_map/lookup.glsl), or
// visibility 1 when the light casts no shadows here.
// Surfaces are lit on both sides (open meshes show their inside through holes).
#include "common/scene.glsl"
#include "forward/lambert.glsl"
#include "silhouette_map/lookup.glsl"

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
    if (lambert <= 0.0) {
        discard; // adds nothing; skips the shadow lookup
    }
    float visibility = 1.0;
    if (objects[push.object].albedo.a > 0.5) {
        if (uint(l.spot_params.z) == SHADOW_SILHOUETTE) {
            bool reconstructed;
            visibility = silhouette_visibility(l, world_position, n, reconstructed);
        } else {
            visibility = shadow_visibility(l, world_position, n);
        }
    }
    out_color = vec4(albedo * l.radiance.rgb * (lambert * visibility), 0.0);
}

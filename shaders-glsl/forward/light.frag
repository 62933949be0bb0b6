#version 460
// Forward pass per light, blended additively: Lambert's law, albedo * radiance * max(N.L, 0),
// with inverse-square falloff for point and spot lights, a smooth spot cone, and the light's
// shadow test (shadow_map/lookup.glsl; visibility 1 when the light casts no shadows).
// Surfaces are lit on both sides (open meshes show their inside through holes).
#include "common/scene.glsl"
#include "shadow_map/lookup.glsl"

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
    // Homogeneous light vector: for w = 0 it is the direction itself.
    vec3 to_light = l.position.xyz - world_position * l.position.w;
    float dist2 = max(dot(to_light, to_light), 1e-12);
    vec3 dir = to_light * inversesqrt(dist2);
    float attenuation = l.position.w == 0.0 ? 1.0 : 1.0 / dist2;
    if (l.spot_params.y > 0.5) {
        float c = dot(-dir, normalize(l.spot_direction.xyz));
        attenuation *= smoothstep(l.spot_direction.w, l.spot_params.x, c);
    }
    float lambert = max(dot(n, dir), 0.0);
    if (lambert * attenuation <= 0.0) {
        discard; // adds nothing; skips the shadow lookup
    }
    bool receives = objects[push.object].albedo.a > 0.5;
    float visibility = receives ? shadow_visibility(l, world_position, n) : 1.0;
    out_color = vec4(albedo * l.radiance.rgb * (lambert * attenuation * visibility), 0.0);
}

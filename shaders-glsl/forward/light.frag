#version 460
// Forward pass per light, blended additively: Lambert's law, albedo * radiance * max(N.L, 0),
// with inverse-square falloff for point and spot lights and a smooth spot cone
// (forward/lambert.glsl), times the light's visibility. Every shadow technique wrote that
// visibility into the light's visibility image before this pass (visibility/image.glsl, set 2);
// a light without one (it casts no shadow here) is specialized with SHADOWED = false.
// Surfaces are lit on both sides (open meshes show their inside through holes).
#include "common/scene.glsl"
#include "forward/lambert.glsl"

layout(constant_id = 0) const bool SHADOWED = true;

layout(set = 2, binding = 0) uniform sampler2D visibility_image;

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
        discard; // adds nothing; skips the visibility fetch
    }
    float visibility = SHADOWED ? texelFetch(visibility_image, ivec2(gl_FragCoord.xy), 0).r : 1.0;
    out_color = vec4(albedo * l.radiance.rgb * (lambert * visibility), 0.0);
}

#version 460
// Chan–Durand §3 step 4: the silhouette pixels' share of a hybrid light, drawn over the frame's
// depth (EQUAL) where the stencil count is zero. Only silhouette pixels add light here: every
// other pixel got its light, or its shadow, from classify.frag.
#include "common/scene.glsl"
#include "forward/lambert.glsl"
#include "hybrid/classes.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_color;

void main() {
    if (!is_silhouette_pixel(ivec2(gl_FragCoord.xy))) {
        discard;
    }
    Light l = lights[push.view];
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    out_color = vec4(albedo * l.radiance.rgb * lambert_attenuated(l, world_position, n), 0.0);
}

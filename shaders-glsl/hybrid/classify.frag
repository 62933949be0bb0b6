#version 460
// Chan–Durand §3 step 2 (Fig. 4): the eye pass of a hybrid light, drawn over the frame's depth
// (EQUAL). One hardware 2x2 PCF fetch (SHADOW_FILTER is specialized to pcf2x2 and the shadow
// set binds a LINEAR comparison sampler): a result strictly between 0 and 1 on a surface facing
// the light marks a silhouette pixel, left for the shadow volumes; anywhere else the map
// decides, and this pass adds the light's contribution. Surfaces facing away from the light are
// shadowed, never silhouette pixels.
// Location 0: the frame's colour (additive). Location 1: the pixel's class (hybrid/classes.glsl).
#include "common/scene.glsl"
#include "debug/classes.glsl"
#include "forward/lambert.glsl"
#include "shadow_map/lookup.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_class;

void main() {
    Light l = lights[push.view];
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    float lambert = lambert_attenuated(l, world_position, n);
    out_color = vec4(0.0);
    if (objects[push.object].albedo.a <= 0.5) {
        out_class = CLASS_NOT_RECEIVER;
        out_color = vec4(albedo * l.radiance.rgb * lambert, 0.0);
        return;
    }
    if (lambert <= 0.0) {
        out_class = CLASS_UNREACHED; // back-facing: never lit, never a silhouette (Fig. 4's diffuse > 0)
        return;
    }
    float v = shadow_visibility(l, world_position, n);
    if (v > 0.0 && v < 1.0) {
        out_class = CLASS_SILHOUETTE_LIT; // the volumes decide (lit.frag adds it where lit)
        return;
    }
    out_class = v > 0.5 ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
    out_color = vec4(albedo * l.radiance.rgb * (lambert * v), 0.0);
}

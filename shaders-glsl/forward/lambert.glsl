// Lambert's law with the light's falloff: max(N.L, 0) times inverse-square attenuation for
// point and spot lights, the glTF range window clamp(1 - (d/range)^4, 0, 1)^2 (exactly 0 from
// the range on, which the planner's culling relies on) and the spot's smooth cone. Shared by the lighting pass and the
// per-light diagnostic views, so both agree on which surfaces a light reaches.
#ifndef UMBRA_LAMBERT_GLSL
#define UMBRA_LAMBERT_GLSL

#include "common/scene.glsl"

// `n` is the unit normal on the viewer's side. Zero where the light adds nothing.
float lambert_attenuated(Light l, vec3 p, vec3 n) {
    // Homogeneous light vector: for w = 0 it is the direction itself.
    vec3 to_light = l.position.xyz - p * l.position.w;
    float dist2 = max(dot(to_light, to_light), 1e-12);
    vec3 dir = to_light * inversesqrt(dist2);
    float attenuation = l.position.w == 0.0 ? 1.0 : 1.0 / dist2;
    if (l.position.w != 0.0 && l.radiance.w > 0.0) {
        float q = dist2 / (l.radiance.w * l.radiance.w); // (d / range)^2
        float window = clamp(1.0 - q * q, 0.0, 1.0);
        attenuation *= window * window;
    }
    if (l.spot_params.y > 0.5) {
        float c = dot(-dir, normalize(l.spot_direction.xyz));
        attenuation *= smoothstep(l.spot_direction.w, l.spot_params.x, c);
    }
    return max(dot(n, dir), 0.0) * attenuation;
}

#endif

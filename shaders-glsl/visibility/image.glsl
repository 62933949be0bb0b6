// The per-light visibility image (`umbra_shadows::visibility`, RG32F, one texel per frame pixel):
// R is the light's visibility, what the lighting multiplies its contribution by (1 lit, 0
// shadowed, in between only on a filtered shadow map's edges); G is 1 where the light's shadow is
// in question (a receiver the light reaches) and 0 elsewhere. A surface that does not receive
// shadows is lit (R = 1); one the light does not reach (facing away from it, outside its range or
// a spot's cone) and pixels without a surface (the clear value) hold 0, 0.
// Every technique writes it; forward/light.frag reads it (set 2, binding 0).
#ifndef UMBRA_VISIBILITY_IMAGE_GLSL
#define UMBRA_VISIBILITY_IMAGE_GLSL

const vec2 VISIBILITY_NOT_RECEIVER = vec2(1.0, 0.0);
const vec2 VISIBILITY_UNREACHED = vec2(0.0, 0.0);

// The texel of a receiver the light reaches, with visibility `v`.
vec2 visibility_decided(float v) {
    return vec2(v, 1.0);
}

#endif

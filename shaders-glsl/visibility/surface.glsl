// What the visibility passes over the frame's surfaces (depth EQUAL, forward/mesh.vert) share:
// the interpolated inputs, and the decision of whether the light's shadow is in question here.
// The world position is the rasterizer's interpolation of the surface, not one rebuilt from the
// depth buffer (see docs/architecture.md, "Visibility images").
#ifndef UMBRA_VISIBILITY_SURFACE_GLSL
#define UMBRA_VISIBILITY_SURFACE_GLSL

#include "common/scene.glsl"
#include "forward/lambert.glsl"
#include "visibility/image.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec2 out_visibility;

// The unit normal on the viewer's side.
vec3 viewer_normal() {
    vec3 n = normalize(world_normal);
    return gl_FrontFacing ? n : -n;
}

// True for a receiver light `l` reaches (the caller decides its visibility). Else false, with
// the texel of a surface that does not receive shadows written; a fragment the light does not
// reach writes nothing when `discard_unreached`, leaving the clear value (0, 0), so that where two
// fragments cover one pixel at the same depth (a shared edge, coincident faces) the one the light
// reaches keeps its decision whichever comes last, as each fragment's own lookup did before the
// visibility image.
bool shadow_in_question(Light l, vec3 n, bool discard_unreached) {
    if (objects[push.object].albedo.a <= 0.5) {
        out_visibility = VISIBILITY_NOT_RECEIVER;
        return false;
    }
    if (lambert_attenuated(l, world_position, n) <= 0.0) {
        if (discard_unreached) {
            discard;
        }
        out_visibility = VISIBILITY_UNREACHED;
        return false;
    }
    return true;
}

#endif

// Chan–Durand §3 step 2 (Fig. 4), made conservative: the eye pass of a hybrid light, drawn over
// the frame's depth (EQUAL). The light's depth bounds (hybrid/bounds_lookup.glsl) decide a
// receiver only where they cannot be wrong; every other receiver facing the light is a
// silhouette pixel, left for the shadow volumes (hybrid/classify.frag) or the shadow rays
// (hybrid/classify_rays.frag). Surfaces facing away from the light are never silhouette pixels.
// Location 0: the light's visibility image (visibility/image.glsl), written here where the
// bounds decide (the volumes or the rays write the silhouette pixels').
// Location 1: the pixel's class (hybrid/classes.glsl).
#ifndef UMBRA_HYBRID_CLASSIFY_GLSL
#define UMBRA_HYBRID_CLASSIFY_GLSL

#include "hybrid/bounds_lookup.glsl"
#include "debug/classes.glsl"
#include "visibility/surface.glsl"

layout(location = 1) out vec4 out_class;

// Classifies this fragment; true at a silhouette pixel, whose visibility is left undecided.
bool classify() {
    Light l = lights[push.view];
    vec3 n = viewer_normal();
    // A fragment the light does not reach (back-facing: never a silhouette, Fig. 4's
    // diffuse > 0) writes nothing, as in the other visibility passes: where two fragments cover
    // one pixel at one depth, the one the light reaches keeps its decision.
    if (!shadow_in_question(l, n, true)) {
        out_class = CLASS_NOT_RECEIVER;
        return false;
    }
    float v = bounded_visibility(l, world_position);
    if (v == IN_QUESTION) {
        out_class = CLASS_SILHOUETTE_LIT; // the volumes or the rays decide
        out_visibility = VISIBILITY_UNREACHED; // until decided
        return true;
    }
    out_class = v == CERTAINLY_LIT ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
    out_visibility = visibility_decided(v);
    return false;
}

#endif

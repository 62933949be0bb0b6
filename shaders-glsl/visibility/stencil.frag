#version 460
// The visibility of a shadow-volume light, resolved from its stencil counts (Everitt–Kilgard):
// drawn over the frame's depth (EQUAL) twice, once through a stencil test for count 0 (LIT,
// visibility 1) and once for any other count (visibility 0), so that every pixel is written once.
#include "visibility/surface.glsl"

layout(constant_id = 0) const bool LIT = false;

void main() {
    Light l = lights[push.view];
    if (shadow_in_question(l, viewer_normal(), true)) {
        out_visibility = visibility_decided(LIT ? 1.0 : 0.0);
    }
}

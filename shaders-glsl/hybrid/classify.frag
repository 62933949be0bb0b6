#version 460
// The hybrid's classification (hybrid/classify.glsl); its silhouette pixels are resolved from
// the volumes' stencil counts (hybrid/resolve.frag).
#include "hybrid/classify.glsl"

void main() {
    classify();
}

#version 460
// The visibility of a ray-traced light, over the frame's depth (EQUAL): one shadow ray per
// receiver pixel (visibility/ray.glsl) into the visibility image.
#include "visibility/ray.glsl"

void main() {
    cast_visibility_ray();
}

#version 460
// The ray-traced hybrid's step 3, `hybrid rays N`: hybrid/rays.glsl.
#include "hybrid/rays.glsl"

#version 460
// Diagnostics, `ray stats N` of a ray-traced hybrid light: hybrid/rays.glsl's rays cast again,
// counted (ray/stats.glsl) and not stored.
#define RAY_STATS
#include "hybrid/rays.glsl"

// Set 1 bindings the silhouette map adds to the shadow set (binding 0 and 1 are in
// shadow_map/lookup.glsl): the light's depth map read raw (no comparison) and its silhouette
// map (RG32F texel-local points; (0.5, 0.5) where no silhouette passes).
#ifndef UMBRA_SILHOUETTE_BINDINGS_GLSL
#define UMBRA_SILHOUETTE_BINDINGS_GLSL

layout(set = 1, binding = 2) uniform sampler2D shadow_depth_raw;
layout(set = 1, binding = 3) uniform sampler2D silhouette_map;

#endif

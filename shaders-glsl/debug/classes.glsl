// Colours of the per-pixel classification views (Chan–Durand 2004, Fig. 6b): pixels the
// depth comparisons decide alone are red (shadowed) or blue (lit); silhouette pixels, decided
// by the accurate technique (silhouette map, shadow volumes), are black (shadowed) or green
// (lit). Surfaces that do not receive shadows are light grey, surfaces the light does not reach
// (facing away from it, outside a spot's cone) dark grey; the background is mid grey.
// `umbra_shadows::diagnostics::PixelClass` decodes them; change both together.
#ifndef UMBRA_DEBUG_CLASSES_GLSL
#define UMBRA_DEBUG_CLASSES_GLSL

const vec4 CLASS_MAP_SHADOWED = vec4(1.0, 0.0, 0.0, 1.0);
const vec4 CLASS_MAP_LIT = vec4(0.0, 0.0, 1.0, 1.0);
const vec4 CLASS_SILHOUETTE_SHADOWED = vec4(0.0, 0.0, 0.0, 1.0);
const vec4 CLASS_SILHOUETTE_LIT = vec4(0.0, 1.0, 0.0, 1.0);
const vec4 CLASS_NOT_RECEIVER = vec4(0.75, 0.75, 0.75, 1.0);
const vec4 CLASS_UNREACHED = vec4(0.25, 0.25, 0.25, 1.0);

#endif

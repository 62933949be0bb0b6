#version 460
// Diagnostic views of one silhouette-map light, drawn over the frame's depth (EQUAL):
// location 0, the per-pixel classification (debug/classes.glsl): decided by the four depth
// comparisons, or reconstructed from the silhouette points; surfaces the light does not reach
// are classed so without a lookup. Location 1, a mask of the silhouette points as seen from the
// camera (Sen et al. Fig. 9, middle): red where the pixel's map position lies within
// POINT_RADIUS texels of a stored (non-default) point.
#include "common/scene.glsl"
#include "debug/classes.glsl"
#include "forward/lambert.glsl"
#include "silhouette_map/lookup.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) flat in vec3 albedo;

layout(location = 0) out vec4 out_class;
layout(location = 1) out vec4 out_points;

const float POINT_RADIUS = 0.15;

void main() {
    Light l = lights[push.view];
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    out_points = vec4(0.0);
    if (objects[push.object].albedo.a <= 0.5) {
        out_class = CLASS_NOT_RECEIVER;
        return;
    }
    if (lambert_attenuated(l, world_position, n) <= 0.0) {
        out_class = CLASS_UNREACHED;
        return;
    }
    bool reconstructed;
    float v = silhouette_visibility(l, world_position, n, reconstructed);
    if (reconstructed) {
        out_class = v > 0.5 ? CLASS_SILHOUETTE_LIT : CLASS_SILHOUETTE_SHADOWED;
    } else {
        out_class = v > 0.5 ? CLASS_MAP_LIT : CLASS_MAP_SHADOWED;
    }
    SilhouetteCell c;
    if (silhouette_cell(l, world_position, c)) {
        vec2 stored = silhouette_point(c, c.cell);
        if (stored != DEFAULT_POINT && distance(stored, c.local) < POINT_RADIUS) {
            out_points = vec4(1.0, 0.0, 0.0, 1.0);
        }
    }
}

// The face atlas (`umbra_shadows::shadow_map::atlas`; change both together): a point light's
// six cube faces, each `side` texels with a border beyond its 90° interior, three across and
// two down in one 2D map. The faces' view-projections (widened) place each point; a lookup
// picks the face by the direction's major axis, as a cube map would.
#ifndef UMBRA_SHADOW_MAP_ATLAS_GLSL
#define UMBRA_SHADOW_MAP_ATLAS_GLSL

#include "common/cube.glsl"
#include "common/scene.glsl"

const int ATLAS_COLUMNS = 3;
const int ATLAS_ROWS = 2;

// Where face `face` of light l's map lies: its first texel, its side in texels, and the scale
// from map texels to texture coordinates. A 2D map is one face at the origin.
void map_face(Light l, uint face, out ivec2 origin, out int side, out vec2 to_uv) {
    side = int(round(1.0 / l.shadow_params.y));
    if (uint(l.spot_params.z) == SHADOW_SILHOUETTE_CUBE) {
        origin = ivec2(int(face) % ATLAS_COLUMNS, int(face) / ATLAS_COLUMNS) * side;
        to_uv = 1.0 / (vec2(ATLAS_COLUMNS, ATLAS_ROWS) * float(side));
    } else {
        origin = ivec2(0);
        to_uv = vec2(l.shadow_params.y);
    }
}

#endif

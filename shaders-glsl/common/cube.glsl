// Cube-face selection, as Vulkan's cube-map sampling picks faces: the shadow map's cube
// (hybrid/bounds_lookup.glsl) and the silhouette map's face atlas (shadow_map/atlas.glsl).
#ifndef UMBRA_COMMON_CUBE_GLSL
#define UMBRA_COMMON_CUBE_GLSL

// The face for direction v, in layer order (+X, -X, +Y, -Y, +Z, -Z; `frustum::CUBE_FACES`):
// its view holds v's ray. `major` is v's distance along that face's axis.
uint cube_face(vec3 v, out float major) {
    vec3 a = abs(v);
    if (a.x >= a.y && a.x >= a.z) {
        major = a.x;
        return v.x >= 0.0 ? 0u : 1u;
    }
    if (a.y >= a.z) {
        major = a.y;
        return v.y >= 0.0 ? 2u : 3u;
    }
    major = a.z;
    return v.z >= 0.0 ? 4u : 5u;
}

#endif

// The ray-traced hybrid's list of shadow rays (`umbra_shadows::hybrid::rays`): the
// classification (hybrid/classify_rays.frag) appends one entry per silhouette pixel, and
// counts the workgroups of the indirect dispatch that casts them (hybrid/rays.comp) as it goes,
// so no pass sits between the two. Set RAY_LIST_SET (2 unless the including shader defines it).
#ifndef UMBRA_HYBRID_RAY_LIST_GLSL
#define UMBRA_HYBRID_RAY_LIST_GLSL

#ifndef RAY_LIST_SET
#define RAY_LIST_SET 2
#endif

// Rays per workgroup of hybrid/rays.comp (`hybrid::rays::RAY_GROUP`).
const uint RAY_GROUP = 64u;

// A `VkDispatchIndirectCommand` (reset to 0, 1, 1 before the classification) and the rays
// appended, which may exceed the list's length (the excess is not cast; the report says so).
layout(set = RAY_LIST_SET, binding = 0, std430) buffer RayListHeader {
    uint groups_x;
    uint groups_y;
    uint groups_z;
    uint count;
} header;

// One shadow ray: its origin, its frame pixel (x | y << 16), direction and extent.
struct RayEntry {
    vec3 origin;
    uint pixel;
    vec3 dir;
    float t_max;
};

layout(set = RAY_LIST_SET, binding = 1, std430) buffer RayList {
    RayEntry entries[];
};

#endif

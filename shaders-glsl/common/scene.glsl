// Scene data shared by every pass: set 0 holds the frame (camera), the objects, the lights and
// the light-space view-projections of the shadow maps.
// Layouts mirror `umbra_shadows::gpu_scene` (std140 / std430); change both together.
#ifndef UMBRA_SCENE_GLSL
#define UMBRA_SCENE_GLSL

struct Object {
    mat4 model;
    mat4 normal_matrix; // inverse-transpose of `model` (upper 3x3 used)
    vec4 albedo;        // rgb; a = 1 if the object receives shadows, 0 if not
};

// A light as a homogeneous position: w = 0 directional (xyz points towards the light),
// w = 1 point or spot.
struct Light {
    vec4 position;
    vec4 radiance;       // rgb = colour * intensity, w = range (0: unbounded)
    vec4 spot_direction; // xyz = axis the spot shines along, w = cos(outer angle)
    vec4 spot_params;    // x = cos(inner angle), y = 1 for a spot light,
                         // z = shadow kind (SHADOW_NONE, SHADOW_2D, SHADOW_CUBE,
                         //      SHADOW_SILHOUETTE, SHADOW_SILHOUETTE_CUBE),
                         // w = index of its first view in `shadow_views`
    vec4 shadow_params;  // x = normal offset (world units), y = shadow-map texel size (1/res;
                         //     a face atlas: 1 / a face's side, border included),
                         // z = near, w = far of perspective maps (spot, cube faces)
};

const uint SHADOW_NONE = 0u;
const uint SHADOW_2D = 1u;
const uint SHADOW_CUBE = 2u;
const uint SHADOW_SILHOUETTE = 3u; // a 2D depth map plus its silhouette map
const uint SHADOW_SILHOUETTE_CUBE = 4u; // both as face atlases (shadow_map/atlas.glsl)

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_proj;
    vec4 camera_position;
    vec4 ambient; // rgb
} frame;

layout(set = 0, binding = 1, std430) readonly buffer Objects {
    Object objects[];
};

layout(set = 0, binding = 2, std430) readonly buffer Lights {
    Light lights[];
};

layout(set = 0, binding = 3, std430) readonly buffer ShadowViews {
    mat4 shadow_views[];
};

// `view` indexes the lights (forward passes) or `shadow_views` (shadow-map passes); `job`, in
// shaders that define UMBRA_PUSH_JOB, a caster's job of the volumes built on the GPU
// (shadow_volume/gpu_volume.glsl).
layout(push_constant) uniform Push {
    uint object;
    uint view;
#ifdef UMBRA_PUSH_JOB
    uint job;
#endif
} push;

#endif

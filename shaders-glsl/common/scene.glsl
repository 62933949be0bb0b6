// Scene data shared by every pass: set 0 holds the frame (camera), the objects and the lights.
// Layouts mirror `umbra_shadows::gpu_scene` (std140 / std430); change both together.
#ifndef UMBRA_SCENE_GLSL
#define UMBRA_SCENE_GLSL

struct Object {
    mat4 model;
    mat4 normal_matrix; // inverse-transpose of `model` (upper 3x3 used)
    vec4 albedo;        // rgb, a unused
};

// A light as a homogeneous position: w = 0 directional (xyz points towards the light),
// w = 1 point or spot.
struct Light {
    vec4 position;
    vec4 radiance;       // rgb = colour * intensity
    vec4 spot_direction; // xyz = axis the spot shines along, w = cos(outer angle)
    vec4 spot_params;    // x = cos(inner angle), y = 1 for a spot light
};

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

layout(push_constant) uniform Push {
    uint object;
    uint light;
} push;

#endif

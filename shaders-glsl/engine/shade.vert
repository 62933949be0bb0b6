#version 460
// The example engine's (examples/embed) vertex shader, for its depth pre-pass (no fragment
// shader) and its shading pass: an engine's shader, not umbra's. umbra's passes test the
// engine's depth with EQUAL, so positions reach clip space the way umbra's own do
// (docs/embedding.md): world = model * p, then clip = view_proj * world, both `precise`,
// `gl_Position` invariant, view_proj the single matrix proj * view computed on the CPU.

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 light_position[4]; // w = 0: direction towards a directional light
    vec4 light_radiance[4]; // rgb; w = 1 where umbra handed a visibility image
    vec4 spot[4];           // xyz = axis, w = cos(outer angle); 2 where not a spot
    vec4 ambient;           // rgb; w = light count
} frame;

layout(push_constant) uniform Push {
    mat4 model;
    vec4 albedo;
} push;

invariant gl_Position;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;

void main() {
    precise vec4 world = push.model * vec4(in_position, 1.0);
    precise vec4 clip = frame.view_proj * world;
    gl_Position = clip;
    world_position = world.xyz;
    world_normal = mat3(push.model) * in_normal;
}

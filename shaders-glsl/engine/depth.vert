#version 460
// The example engine's own depth pre-pass (examples and tests/embed.rs): an engine's shader,
// not umbra's. umbra's passes test the engine's depth with EQUAL, so positions reach clip
// space the way umbra's own do (docs/embedding.md): world = model * p, then clip = view_proj *
// world, both `precise` (no fused multiply-add), `gl_Position` invariant, with view_proj the
// single matrix proj * view computed on the CPU.

layout(location = 0) in vec3 in_position;

layout(push_constant) uniform Push {
    mat4 view_proj;
    mat4 model;
} push;

invariant gl_Position;

void main() {
    precise vec4 world = push.model * vec4(in_position, 1.0);
    precise vec4 clip = push.view_proj * world;
    gl_Position = clip;
}

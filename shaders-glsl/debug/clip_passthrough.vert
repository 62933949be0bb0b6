#version 460
// Positions already in clip space (computed on the CPU): for tests of rasterization alone.
layout(location = 0) in vec4 in_clip;

void main() {
    gl_Position = in_clip;
}

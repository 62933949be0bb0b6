#version 460
// One triangle covering the whole viewport, from gl_VertexIndex alone (draw 3 vertices, no
// vertex buffer). Depth comes from the specialization constant DEPTH (as float bits).
layout(constant_id = 0) const uint DEPTH_BITS = 0x3f000000u; // 0.5

void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(uv * 2.0 - 1.0, uintBitsToFloat(DEPTH_BITS), 1.0);
}

#version 460
// The example engine's own deformation (examples/embed --deform), not umbra's: every vertex of
// a mesh moved sideways by a wave travelling up it, written over the positions of its
// interleaved vertices (position, normal; the normals are left as they were). A function of
// the rest position alone, so vertices that share a position keep sharing it, as umbra's
// deforming meshes require.
layout(local_size_x = 64) in;

// The rest pose, interleaved as the vertices: 6 floats a vertex.
layout(set = 0, binding = 0, std430) readonly buffer Rest {
    float rest[];
};

layout(set = 0, binding = 1, std430) buffer Vertices {
    float vertices[];
};

layout(push_constant) uniform Push {
    float time;       // radians of phase
    float amplitude;  // object-space units
    float frequency;  // radians per object-space unit of height
    uint count;       // vertices
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    vec3 p = vec3(rest[6u * i], rest[6u * i + 1u], rest[6u * i + 2u]);
    vertices[6u * i] = p.x + push.amplitude * sin(push.frequency * p.y + push.time);
    vertices[6u * i + 1u] = p.y;
    vertices[6u * i + 2u] = p.z;
}

#version 460
// Shadow volumes built on the GPU: a caster's side quads from its silhouette list
// (shadow_volume/silhouettes.comp), drawn indirectly, 6 vertices per listed edge. A listed edge
// a -> b (as its casting faces walk it) is closed by the triangles b, a, a_inf and b, a_inf,
// b_inf: the vertices `umbra_scene::Volume::build` makes, through the same extrusion.
#define UMBRA_PUSH_JOB
#define VOLUME_SET 1
#include "shadow_volume/extrude.glsl"
#include "shadow_volume/gpu_volume.glsl"

invariant gl_Position;

void main() {
    uint entry = silhouettes[gl_VertexIndex / 6];
    uint corner = gl_VertexIndex % 6;
    uvec4 edge = volume_edges[jobs[push.job].edges + (entry >> 1)];
    bool reversed = (entry & 1u) != 0u;
    uint a = reversed ? edge.y : edge.x;
    uint b = reversed ? edge.x : edge.y;
    // Corners 0..5: b, a, a_inf, b, a_inf, b_inf.
    uint vertex = (corner == 1u || corner == 2u || corner == 4u) ? a : b;
    bool far = corner == 2u || corner == 4u || corner == 5u;
    gl_Position = volume_clip_position(vec4(volume_positions[vertex].xyz, far ? 0.0 : 1.0));
}

#version 460
// Shadow volumes on the GPU, stage 2: every edge of a caster with the net count of its casting
// faces (`umbra_scene::silhouette_edges`): a closed mesh's light-facing faces, an open
// or non-manifold mesh's faces not edge-on (oriented towards the light), each +1 walking the
// edge one way and −1 the other. An edge whose count is not 0 is appended to the job's list
// as many times, directed as its casting faces walk it, and its side quads (6 vertices each)
// are added to the indirect draw of the mode classify.comp decided.
#define VOLUME_WRITES
#include "shadow_volume/gpu_volume.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Push {
    uint job;
} push;

void main() {
    VolumeJob j = jobs[push.job];
    uint e = gl_GlobalInvocationID.x;
    if (e >= j.edge_count) {
        return;
    }
    uvec4 edge = volume_edges[j.edges + e];
    bool closed = j.closed != 0u;
    int net = 0;
    for (uint k = 0u; k < edge.w; ++k) {
        uint use = edge_faces[edge.z + k];
        uint f = facing[j.facing + (use >> 1)];
        bool forward = (use & 1u) != 0u;
        bool towards = f == FACING_TOWARDS;
        if (closed ? !towards : f == FACING_EDGE_ON) {
            continue;
        }
        net += forward == (towards || closed) ? 1 : -1;
    }
    if (net == 0) {
        return;
    }
    uint count = uint(abs(net));
    uint at = JOB_DRAWS * push.job;
    uint draw = volume_draws[at + DRAW_COUNTS].y == MODE_ZPASS ? DRAW_ZPASS_SIDES : DRAW_ZFAIL_SIDES;
    uint first = atomicAdd(volume_draws[at + draw].x, 6u * count) / 6u;
    uint entry = (e << 1) | (net > 0 ? 0u : 1u);
    for (uint k = 0u; k < count; ++k) {
        silhouettes[j.list + first + k] = entry;
    }
}

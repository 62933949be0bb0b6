#version 460
// Shadow volumes built on the GPU: a caster's caps (z-fail), straight from its mesh's triangles
// and their facing (shadow_volume/classify.comp), 3 vertices per triangle, as
// `umbra_scene::Volume::build` makes them. A closed caster: a light-facing triangle as it is
// (front cap), any other at infinity (back cap). An open or non-manifold caster (drawn as two
// instances): every triangle not edge-on, oriented towards the light, as it is (instance 0)
// and reversed at infinity (instance 1). A triangle that makes no cap (degenerate, or edge-on
// on an open caster) is moved wholly outside the view, where it covers nothing.
#define UMBRA_PUSH_JOB
#define VOLUME_SET 1
#include "shadow_volume/extrude.glsl"
#include "shadow_volume/gpu_volume.glsl"

invariant gl_Position;

void main() {
    VolumeJob j = jobs[push.job];
    uint t = gl_VertexIndex / 3;
    uint corner = gl_VertexIndex % 3;
    uvec4 tri = volume_triangles[j.triangles + t];
    uint f = facing[j.facing + t];
    bool degenerate = tri.x == tri.y || tri.y == tri.z || tri.x == tri.z;
    bool closed = j.closed != 0u;
    if (degenerate || (!closed && f == FACING_EDGE_ON)) {
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        return;
    }
    bool lit = f == FACING_TOWARDS;
    bool far;
    uvec3 order = tri.xyz;
    if (closed) {
        far = !lit;
    } else {
        // Oriented towards the light, then reversed at infinity for the far copy.
        if (!lit) {
            order = order.xzy;
        }
        far = gl_InstanceIndex == 1;
        if (far) {
            order = order.xzy;
        }
    }
    uint vertex = corner == 0u ? order.x : (corner == 1u ? order.y : order.z);
    gl_Position = volume_clip_position(vec4(volume_positions[vertex].xyz, far ? 0.0 : 1.0));
}

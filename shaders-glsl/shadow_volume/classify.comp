#version 460
// Shadow volumes on the GPU, stage 1 (Everitt–Kilgard §2): how each triangle of a caster faces
// its light, from the triangle's plane evaluated at the homogeneous light position,
// d = n·L.xyz − (n·a)·L.w with n = (b − a) × (c − a), in the caster's object space. Every
// operation in the order `umbra_scene::facing` does it in f32, and `precise` (no
// contraction into fused multiply-adds), so a light in the plane of a face classifies alike.
// An open caster's faces edge-on to the light are counted into its job's counts.
//
// Its first invocation also decides the job's counting mode (§3.4): z-pass unless the caster's
// box may touch the near-plane clip region, whose planes the host gives, tested in f32 as
// `NearRegion::may_touch` in build.rs does (same operations, `precise`); a z-fail caster's
// caps draw gets its triangles.
#define VOLUME_WRITES
#include "shadow_volume/gpu_volume.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Push {
    uint job;
} push;

// Whether the job's box may touch its near-plane clip region (false: certainly not).
bool may_touch_near_region(VolumeJob j) {
    if (j.near_count == 0u) {
        return true;
    }
    for (uint k = 0u; k < j.near_count; ++k) {
        vec4 pl = j.near[k];
        // The box corner farthest against the outward normal: if even it is outside, all is.
        vec3 nearest = vec3(pl.x >= 0.0 ? j.box_min.x : j.box_max.x,
                            pl.y >= 0.0 ? j.box_min.y : j.box_max.y,
                            pl.z >= 0.0 ? j.box_min.z : j.box_max.z);
        precise float outside = pl.x * nearest.x + pl.y * nearest.y + pl.z * nearest.z + pl.w;
        if (outside > 0.0) {
            return false;
        }
    }
    return true;
}

// The job's counting mode, its caps draw set for z-fail.
void decide_mode(VolumeJob j) {
    uint mode = j.mode;
    if (mode == MODE_AUTO) {
        mode = may_touch_near_region(j) ? MODE_ZFAIL : MODE_ZPASS;
    }
    uint at = JOB_DRAWS * push.job;
    volume_draws[at + DRAW_COUNTS].y = mode;
    if (mode == MODE_ZFAIL) {
        volume_draws[at + DRAW_CAPS].xy = uvec2(3u * j.triangle_count, j.closed != 0u ? 1u : 2u);
    }
}

void main() {
    VolumeJob j = jobs[push.job];
    uint t = gl_GlobalInvocationID.x;
    if (t == 0u) {
        decide_mode(j);
    }
    if (t >= j.triangle_count) {
        return;
    }
    uvec4 tri = volume_triangles[j.triangles + t];
    vec3 a = volume_positions[tri.x].xyz;
    vec3 b = volume_positions[tri.y].xyz;
    vec3 c = volume_positions[tri.z].xyz;
    precise vec3 e1 = b - a;
    precise vec3 e2 = c - a;
    precise vec3 n = vec3(e1.y * e2.z - e2.y * e1.z, e1.z * e2.x - e2.z * e1.x, e1.x * e2.y - e2.x * e1.y);
    vec4 l = j.light;
    precise float towards_light = n.x * l.x + n.y * l.y + n.z * l.z;
    precise float towards_vertex = n.x * a.x + n.y * a.y + n.z * a.z;
    precise float d = towards_light - towards_vertex * l.w;
    facing[j.facing + t] = d > 0.0 ? FACING_TOWARDS : (d < 0.0 ? FACING_AWAY : FACING_EDGE_ON);
    // An open caster's edge-on face makes no cap: counted for the report (rare, so one atomic
    // each costs nothing).
    bool degenerate = tri.x == tri.y || tri.y == tri.z || tri.x == tri.z;
    if (d == 0.0 && j.closed == 0u && !degenerate) {
        atomicAdd(volume_draws[JOB_DRAWS * push.job + DRAW_COUNTS].x, 1u);
    }
}

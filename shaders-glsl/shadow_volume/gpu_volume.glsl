// Shadow volumes built on the GPU (crates/umbra-shadows/src/shadow_volume/gpu.rs): every
// mesh's welded adjacency (umbra_scene::Adjacency), concatenated, and per caster and light a
// job. Layouts mirror `gpu.rs`; change both together.
#ifndef UMBRA_SHADOW_VOLUME_GPU_VOLUME_GLSL
#define UMBRA_SHADOW_VOLUME_GPU_VOLUME_GLSL

#ifndef VOLUME_SET
#define VOLUME_SET 0
#endif

// The stages that write (compute) define VOLUME_WRITES; the vertex shaders read only, as
// devices without vertexPipelineStoresAndAtomics require.
#ifdef VOLUME_WRITES
#define VOLUME_WRITTEN
#else
#define VOLUME_WRITTEN readonly
#endif

// One caster's volume for one light.
struct VolumeJob {
    vec4 light;          // the light in the caster's object space, as the host computes it
    vec4 box_min;        // the caster's world bounds (xyz; w unused), for the mode test
    vec4 box_max;
    vec4 near[5];        // the light's near-plane clip region (Everitt–Kilgard §3.4): outward
                         // planes, a point p outside when dot(n, p) + d > 0
    uint triangles;      // its mesh's first triangle
    uint triangle_count;
    uint edges;          // its mesh's first edge
    uint edge_count;
    uint facing;         // its first entry in `facing` (one per triangle)
    uint list;           // its first entry in `silhouettes`
    uint closed;         // 1: a closed 2-manifold mesh (umbra_scene::TopologyReport::closed)
    uint faces;          // its mesh's triangles with three distinct vertices (the caps' source)
    uint near_count;     // planes in `near`: 0 when none is known (then z-fail)
    uint mode;           // MODE_AUTO, or the mode the light's settings force
    uint pad0;
    uint pad1;
};

// A job's counting mode: asked for (VolumeJob::mode), and decided (the counts' y).
const uint MODE_AUTO = 0u;
const uint MODE_ZPASS = 1u;
const uint MODE_ZFAIL = 2u;

// How a triangle faces the light (umbra_scene::Facing).
const uint FACING_AWAY = 0u;
const uint FACING_TOWARDS = 1u;
const uint FACING_EDGE_ON = 2u;

// Welded positions (w = 1) of every mesh.
layout(set = VOLUME_SET, binding = 0, std430) readonly buffer VolumePositions {
    vec4 volume_positions[];
};

// Triangles over the welded positions (indices already offset to the mesh's first vertex).
layout(set = VOLUME_SET, binding = 1, std430) readonly buffer VolumeTriangles {
    uvec4 volume_triangles[];
};

// Edges: x, y the welded vertices (smaller first, offset), z the first of its faces in
// `edge_faces`, w how many faces use it.
layout(set = VOLUME_SET, binding = 2, std430) readonly buffer VolumeEdges {
    uvec4 volume_edges[];
};

// A face's use of an edge: the face (within its mesh) << 1 | 1 when it walks x -> y.
layout(set = VOLUME_SET, binding = 3, std430) readonly buffer VolumeEdgeFaces {
    uint edge_faces[];
};

layout(set = VOLUME_SET, binding = 4, std430) readonly buffer VolumeJobs {
    VolumeJob jobs[];
};

layout(set = VOLUME_SET, binding = 5, std430) VOLUME_WRITTEN buffer VolumeFacing {
    uint facing[];
};

// A silhouette edge: the edge (within its mesh) << 1 | 1 when its casting faces walk y -> x;
// repeated with its multiplicity.
layout(set = VOLUME_SET, binding = 6, std430) VOLUME_WRITTEN buffer VolumeSilhouettes {
    uint silhouettes[];
};

// Per job JOB_DRAWS entries, from JOB_DRAWS * job: three VkDrawIndirectCommands, its z-fail
// sides (DRAW_ZFAIL_SIDES), its z-pass sides (DRAW_ZPASS_SIDES), each x vertices (6 per
// silhouette edge), y instances (1), z first vertex (6 * job.list), w first instance (0), of
// which only its mode's gets vertices; its caps (DRAW_CAPS, z-fail only): x 3 per triangle,
// y instances (1 for a closed caster, 2 for an open one), z, w 0; then its counts
// (DRAW_COUNTS): x its faces edge-on to the light (an open caster's, which make no cap;
// counted by classify.comp), y the mode classify.comp decided, z, w 0.
const uint JOB_DRAWS = 4u;
const uint DRAW_ZFAIL_SIDES = 0u;
const uint DRAW_ZPASS_SIDES = 1u;
const uint DRAW_CAPS = 2u;
const uint DRAW_COUNTS = 3u;
layout(set = VOLUME_SET, binding = 7, std430) VOLUME_WRITTEN buffer VolumeDraws {
    uvec4 volume_draws[];
};

#endif

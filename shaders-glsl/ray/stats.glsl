// Diagnostics (`umbra_shadows::ray_traced::stats`): per light, the shadow rays cast and the BVH
// nodes and triangles each one visited (ray/bvh.glsl with RAY_STATS), as 64-bit sums and as
// histograms for the 95th percentile. Set RAY_STATS_SET (2 unless the including shader defines
// it), one storage buffer of STATS_WORDS words per light. The layout mirrors `stats.rs`.
#ifndef UMBRA_RAY_STATS_GLSL
#define UMBRA_RAY_STATS_GLSL

#ifndef RAY_STATS_SET
#define RAY_STATS_SET 2
#endif

// Bins of each histogram (`stats::BINS`): one per count below 64, then eight per power of two.
const uint STATS_BINS = 272u;
// Per light: rays, nodes (low, high word), triangles (low, high word), three unused, then the
// node and the triangle histograms.
const uint STATS_WORDS = 8u + 2u * STATS_BINS;

layout(set = RAY_STATS_SET, binding = 0, std430) buffer RayStats {
    uint stats[];
};

// The histogram bin of count `n` (`stats::bin`): `n` itself below 64, else its power of two
// and the three bits below its leading one.
uint stats_bin(uint n) {
    if (n < 64u) {
        return n;
    }
    uint e = uint(findMSB(n));
    return 64u + 8u * (e - 6u) + ((n >> (e - 3u)) & 7u);
}

// Adds `v` to the 64-bit sum at words `at` (low) and `at` + 1 (high): the add that wraps the
// low word carries.
void add_wide(uint at, uint v) {
    uint old = atomicAdd(stats[at], v);
    if (old + v < old) {
        atomicAdd(stats[at + 1u], 1u);
    }
}

// Counts one ray of light `light` that visited `nodes` nodes and `triangles` triangles.
void count_ray(uint light, uint nodes, uint triangles) {
    uint base = light * STATS_WORDS;
    atomicAdd(stats[base], 1u);
    add_wide(base + 1u, nodes);
    add_wide(base + 3u, triangles);
    atomicAdd(stats[base + 8u + stats_bin(nodes)], 1u);
    atomicAdd(stats[base + 8u + STATS_BINS + stats_bin(triangles)], 1u);
}

#endif

// Ray-traced shadows' two-level BVH (`umbra_shadows::ray_traced`; set BVH_SET, 1 unless the
// including shader defines it: 1 in the ray pass, 0 in the ray-traced hybrid's rays) and the
// walk of one shadow ray through it: the same steps as `RayScene::occluded` (ray_traced/walk.rs),
// which tests them on the host against the exact reference.
// Layouts mirror `BvhNode`, `WideNode`, `BvhInstance` and `BvhTriangle` (std430); change both
// together. The meshes' nodes are binary or compressed wide (CWBVH, `BvhLayout`), chosen by the
// specialization constant WIDE_BVH (`BvhLayout::specialization`); the top level is binary.
#ifndef UMBRA_RAY_BVH_GLSL
#define UMBRA_RAY_BVH_GLSL

#ifndef BVH_SET
#define BVH_SET 1
#endif

// An inner node (count == 0) has its children at first and first + 1; a leaf holds `count`
// primitives from `first` on.
struct BvhNode {
    vec3 lo;
    uint first;
    vec3 hi;
    uint count;
};

struct BvhInstance {
    vec4 world_to_object[3]; // rows 0 to 2 (row 3 is 0 0 0 1)
    uint node_offset;
    uint triangle_offset;
    uint object;
    uint pad;
};

struct BvhTriangle {
    vec4 v[3];
};

layout(set = BVH_SET, binding = 0, std430) readonly buffer TopNodes {
    BvhNode top_nodes[];
};
layout(set = BVH_SET, binding = 1, std430) readonly buffer Instances {
    BvhInstance instances[];
};
// The meshes' nodes as uvec4s: two a binary node, five a wide one.
layout(set = BVH_SET, binding = 2, std430) readonly buffer MeshNodes {
    uvec4 mesh_words[];
};

layout(constant_id = 9) const bool WIDE_BVH = false;

BvhNode mesh_node(uint i) {
    uvec4 a = mesh_words[2u * i];
    uvec4 b = mesh_words[2u * i + 1u];
    return BvhNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}
layout(set = BVH_SET, binding = 3, std430) readonly buffer Triangles {
    BvhTriangle triangles[];
};

// The deepest BVH walked (`ray_traced::MAX_STACK`): both children are pushed, so one entry per
// level is enough.
const uint MAX_STACK = 64u;

// With RAY_STATS defined (the diagnostics' `ray stats N` passes, ray/stats.glsl), the nodes and
// triangles this invocation's walk visited; otherwise RAY_COUNT compiles to nothing.
#ifdef RAY_STATS
uint ray_nodes = 0u;
uint ray_triangles = 0u;
#define RAY_COUNT(counter) ++counter
#else
#define RAY_COUNT(counter)
#endif

// 1 + 2 gamma_3 (gamma_n = n eps / (1 - n eps), eps = 2^-24): the far slab distance widened so
// rounding never drops a box the ray touches (Ize 2013).
const float WIDEN = 1.0 + 2.0 * (3.0 * 5.9604645e-8) / (1.0 - 3.0 * 5.9604645e-8);

// The inverse direction for the slab test, a zero component replaced by a tiny one of its sign
// so that no 0 * inf makes a NaN.
vec3 slab_inverse(vec3 d) {
    vec3 safe = mix(d, mix(vec3(1e-20), vec3(-1e-20), lessThan(d, vec3(0.0))), lessThan(abs(d), vec3(1e-20)));
    return 1.0 / safe;
}

bool slab_hits(BvhNode n, vec3 o, vec3 inv, float t_max) {
    precise vec3 t0 = (n.lo - o) * inv;
    precise vec3 t1 = (n.hi - o) * inv;
    vec3 lo = min(t0, t1);
    vec3 hi = max(t0, t1);
    float near = max(max(max(lo.x, lo.y), lo.z), 0.0);
    precise float far = min(min(min(hi.x, hi.y), hi.z) * WIDEN, t_max);
    return near <= far;
}

// The watertight ray-triangle test (Woop, Benthin, Wald 2013) in f32: the direction's dominant
// axis becomes z and a shear maps the direction onto +z, so each edge is a signed area at the
// origin. `precise` keeps every product and difference apart (no fused multiply-add), so an
// edge two triangles share gets the same area, negated, from both: no ray passes between them.
struct Watertight {
    vec3 o;
    int kx;
    int ky;
    int kz;
    vec3 shear;
};

Watertight watertight(vec3 o, vec3 d) {
    vec3 a = abs(d);
    int kz = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
    int kx = (kz + 1) % 3;
    int ky = (kz + 2) % 3;
    if (d[kz] < 0.0) {
        int t = kx;
        kx = ky;
        ky = t;
    }
    precise vec3 shear = vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
    return Watertight(o, kx, ky, kz, shear);
}

vec3 sheared(Watertight r, vec3 v) {
    precise vec3 p = v - r.o;
    precise vec3 s = vec3(p[r.kx] - r.shear.x * p[r.kz], p[r.ky] - r.shear.y * p[r.kz], r.shear.z * p[r.kz]);
    return s;
}

bool triangle_hits(Watertight r, BvhTriangle t, float t_max) {
    vec3 a = sheared(r, t.v[0].xyz);
    vec3 b = sheared(r, t.v[1].xyz);
    vec3 c = sheared(r, t.v[2].xyz);
    precise float u = c.x * b.y - c.y * b.x;
    precise float v = a.x * c.y - a.y * c.x;
    precise float w = b.x * a.y - b.y * a.x;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return false;
    }
    precise float det = u + v + w;
    if (det == 0.0) {
        return false;
    }
    precise float t_hit = (u * a.z + v * b.z + w * c.z) / det;
    return t_hit > 0.0 && t_hit <= t_max;
}

// Byte `slot` (0 to 7) of the eight in `w`.
uint slot_byte(uvec2 w, uint slot) {
    return ((slot < 4u ? w.x : w.y) >> (8u * (slot & 3u))) & 0xffu;
}

// The walk of one instance's compressed wide BVH (`WideNode`'s walk in ray_traced/walk.rs): a popped
// node's children tested against the ray, each box one grid step wider than its quantized one
// (`WideNode::child_box`), inner children hit pushed, leaves hit tested.
bool occluded_in_wide(BvhInstance inst, vec3 o, vec3 inv, Watertight r, float t_max) {
    uint stack[MAX_STACK];
    uint sp = 0u;
    stack[sp++] = 0u;
    while (sp > 0u) {
        uint base = 5u * (inst.node_offset + stack[--sp]);
        RAY_COUNT(ray_nodes);
        uvec4 w0 = mesh_words[base];
        uvec4 w1 = mesh_words[base + 1u];
        uvec4 w2 = mesh_words[base + 2u];
        uvec4 w3 = mesh_words[base + 3u];
        uvec4 w4 = mesh_words[base + 4u];
        vec3 p = uintBitsToFloat(w0.xyz);
        vec3 step = uintBitsToFloat((uvec3(w0.w, w0.w >> 8u, w0.w >> 16u) & 0xffu) << 23u);
        uint inner = w0.w >> 24u;
        for (uint slot = 0u; slot < 8u; ++slot) {
            uint meta = slot_byte(w1.zw, slot);
            if (meta == 0u) {
                continue;
            }
            vec3 q_lo = vec3(slot_byte(w2.xy, slot), slot_byte(w3.xy, slot), slot_byte(w4.xy, slot));
            vec3 q_hi = vec3(slot_byte(w2.zw, slot), slot_byte(w3.zw, slot), slot_byte(w4.zw, slot));
            precise vec3 lo = p + step * (q_lo - 1.0);
            precise vec3 hi = p + step * (q_hi + 1.0);
            if (!slab_hits(BvhNode(lo, 0u, hi, 0u), o, inv, t_max)) {
                continue;
            }
            if (((inner >> slot) & 1u) != 0u) {
                if (sp < MAX_STACK) {
                    stack[sp++] = w1.x + bitCount(inner & ((1u << slot) - 1u));
                }
            } else {
                uint first = w1.y + (meta & 31u);
                uint count = uint(bitCount(meta >> 5u));
                for (uint k = 0u; k < count; ++k) {
                    RAY_COUNT(ray_triangles);
                    if (triangle_hits(r, triangles[inst.triangle_offset + first + k], t_max)) {
                        return true;
                    }
                }
            }
        }
    }
    return false;
}

// The ray against one instance's mesh, carried into the mesh's space (t unchanged).
bool occluded_in(BvhInstance inst, vec3 origin, vec3 dir, float t_max) {
    mat3x4 m = mat3x4(inst.world_to_object[0], inst.world_to_object[1], inst.world_to_object[2]);
    vec3 o = vec4(origin, 1.0) * m;
    vec3 d = vec4(dir, 0.0) * m;
    vec3 inv = slab_inverse(d);
    Watertight r = watertight(o, d);
    if (WIDE_BVH) {
        return occluded_in_wide(inst, o, inv, r, t_max);
    }
    uint stack[MAX_STACK];
    uint sp = 0u;
    stack[sp++] = 0u;
    while (sp > 0u) {
        BvhNode n = mesh_node(inst.node_offset + stack[--sp]);
        RAY_COUNT(ray_nodes);
        if (!slab_hits(n, o, inv, t_max)) {
            continue;
        }
        if (n.count > 0u) {
            for (uint k = 0u; k < n.count; ++k) {
                RAY_COUNT(ray_triangles);
                if (triangle_hits(r, triangles[inst.triangle_offset + n.first + k], t_max)) {
                    return true;
                }
            }
        } else if (sp + 2u <= MAX_STACK) {
            stack[sp++] = n.first;
            stack[sp++] = n.first + 1u;
        }
    }
    return false;
}

// Whether a shadow-casting triangle lies on origin + t dir, t in (0, t_max].
bool ray_occluded(vec3 origin, vec3 dir, float t_max) {
    vec3 inv = slab_inverse(dir);
    uint stack[MAX_STACK];
    uint sp = 0u;
    stack[sp++] = 0u;
    while (sp > 0u) {
        BvhNode n = top_nodes[stack[--sp]];
        RAY_COUNT(ray_nodes);
        if (!slab_hits(n, origin, inv, t_max)) {
            continue;
        }
        if (n.count > 0u) {
            for (uint k = 0u; k < n.count; ++k) {
                if (occluded_in(instances[n.first + k], origin, dir, t_max)) {
                    return true;
                }
            }
        } else if (sp + 2u <= MAX_STACK) {
            stack[sp++] = n.first;
            stack[sp++] = n.first + 1u;
        }
    }
    return false;
}

#endif

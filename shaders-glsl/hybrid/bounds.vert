#version 460
// The hybrid's conservative depth bounds, vertex stage (hybrid/bounds.glsl). Neither CPU driver
// has VK_EXT_conservative_rasterization (nor SwiftShader geometry shaders), so each triangle is
// pulled whole from the scene's vertex and index buffers (set 1) by every one of its three
// vertices, and drawn as one triangle that holds the centre of every texel whose square it may
// touch: the triangle itself with each edge moved out by as much as the fragment stage's test
// lets a square's centre lie beyond it (and a sixteenth of a texel more, for rounding), or,
// for a triangle reaching behind the light's plane or seen edge-on, a triangle around the box
// of its part in front of the light, grown by a texel. The fragment stage keeps only centres
// inside that grown box, whichever was drawn, and tests each texel's square
// against the real triangle exactly (Hasselgren et al., GPU Gems 2 ch. 42, in homogeneous
// 2D coordinates, so that corners behind the light need no clipping).
//
// Which triangles: every one of an open mesh; only those of a closed mesh that do not face the
// light (a ray from a receiver outside the solid to the light is blocked by the solid exactly
// when it enters it, through a face turned away from the light), so that a lit surface never
// bounds itself.
// Drawn without an index buffer: gl_VertexIndex / 3 is the triangle (firstVertex = the mesh's
// first index, three vertices per three indices) and gl_InstanceIndex is its vertex offset
// (firstInstance).
#include "hybrid/bounds.glsl"

layout(set = 1, binding = 0, std430) readonly buffer Vertices {
    float vertex_data[]; // position xyz, normal xyz (gpu_scene::Vertex)
};
layout(set = 1, binding = 1, std430) readonly buffer Indices {
    uint index_data[];
};

// The triangle's corners as clip x, y, w and light depth (bounds.frag reads them).
layout(location = 0) flat out vec4 corner[3];
// The grown box (lo.xy, hi.xy in NDC) no touched square's centre lies outside.
layout(location = 3) flat out vec4 box;
// Whether the box is at least a texel wide both ways (else the triangle covers no square).
layout(location = 4) flat out uint covers;

vec3 pulled_position(uint index) {
    uint v = (index_data[index] + uint(gl_InstanceIndex)) * 6u;
    return vec3(vertex_data[v], vertex_data[v + 1u], vertex_data[v + 2u]);
}

// A corner outside every view: the three of a dropped triangle coincide and draw nothing.
const vec4 DROPPED = vec4(-4.0, -4.0, 0.5, 1.0);

// Corner k of triangle c (homogeneous corners, all in front of the light, not edge-on) grown
// so that it holds every NDC point where bounds.frag's nearest test passes: each edge k
// moved out to where its function u_k (c_i x c_j over det, affine in the point) reaches minus
// the test's spread over a square of half-size `texel` (grown by 1/64), plus 1/16 texel.
vec2 grown_corner(vec3 c[3], uint k, float texel) {
    vec3 e[3] = vec3[3](cross(c[1], c[2]), cross(c[2], c[0]), cross(c[0], c[1]));
    float det = dot(c[0], e[0]);
    vec2 half_size = vec2(texel * (1.0 + 1.0 / 64.0));
    // The two edges through corner k: those opposite the other two corners.
    uint i = (k + 1u) % 3u;
    uint j = (k + 2u) % 3u;
    vec3 ui = e[i] / det;
    vec3 uj = e[j] / det;
    // Line g . p = -(u.z + spread + margin), for each of the two.
    float ri = -(ui.z + dot(abs(ui.xy), half_size) + length(ui.xy) * texel / 8.0);
    float rj = -(uj.z + dot(abs(uj.xy), half_size) + length(uj.xy) * texel / 8.0);
    float m = ui.x * uj.y - ui.y * uj.x;
    return vec2(ri * uj.y - rj * ui.y, ui.x * rj - uj.x * ri) / m;
}

// The box (NDC) of the part of triangle c (homogeneous corners, a perspective view) in front
// of w = w_min and inside the view grown to |x|, |y| <= grow w; false where nothing is.
// Sutherland–Hodgman in homogeneous coordinates: a triangle reaching behind the light's plane
// is boxed by the part of it the view can see, not by its corners' projections, which reach
// arbitrarily far out (a floor's underside, beside a point light, fills a strip of a side face,
// not all of it).
bool seen_box(vec3 c[3], float w_min, float grow, out vec2 lo, out vec2 hi) {
    // Each plane keeps dot(plane.xyz, v) + plane.w >= 0.
    const int PLANES = 5;
    vec4 planes[PLANES] = vec4[PLANES](vec4(0.0, 0.0, 1.0, -w_min), vec4(-1.0, 0.0, grow, 0.0),
        vec4(1.0, 0.0, grow, 0.0), vec4(0.0, -1.0, grow, 0.0), vec4(0.0, 1.0, grow, 0.0));
    vec3 poly[8];
    poly[0] = c[0];
    poly[1] = c[1];
    poly[2] = c[2];
    int n = 3;
    for (int p = 0; p < PLANES; ++p) {
        vec3 kept[8];
        int m = 0;
        for (int i = 0; i < n; ++i) {
            vec3 a = poly[i];
            vec3 b = poly[(i + 1) % n];
            float da = dot(planes[p].xyz, a) + planes[p].w;
            float db = dot(planes[p].xyz, b) + planes[p].w;
            if (da >= 0.0) {
                kept[m++] = a;
            }
            if ((da >= 0.0) != (db >= 0.0) && m < 8) {
                kept[m++] = mix(a, b, da / (da - db));
            }
        }
        n = m;
        for (int i = 0; i < n; ++i) {
            poly[i] = kept[i];
        }
        if (n == 0) {
            return false;
        }
    }
    lo = vec2(1e30);
    hi = vec2(-1e30);
    for (int i = 0; i < n; ++i) {
        vec2 v = poly[i].xy / max(poly[i].z, w_min);
        lo = min(lo, v);
        hi = max(hi, v);
    }
    return true;
}

void main() {
    Light l = lights[bounds_light()];
    mat4 view = shadow_views[uint(l.spot_params.w) + bounds_face()];
    mat4 model = objects[push.object].model;
    uint first = uint(gl_VertexIndex) / 3u * 3u;
    vec3 world[3];
    vec4 clip[3];
    for (uint k = 0u; k < 3u; ++k) {
        world[k] = (model * vec4(pulled_position(first + k), 1.0)).xyz;
        clip[k] = view * vec4(world[k], 1.0);
        corner[k] = vec4(clip[k].xyw, light_depth(l, clip[k]));
    }
    // umbra_scene::facing in world space: a mirroring transform turns the winding over.
    vec3 n = cross(world[1] - world[0], world[2] - world[0]) * sign(determinant(mat3(model)));
    float towards = dot(n, l.position.xyz) - dot(n, world[0]) * l.position.w;
    bool perspective = l.position.w != 0.0;
    bool behind = perspective && clip[0].w <= 0.0 && clip[1].w <= 0.0 && clip[2].w <= 0.0;
    if ((bounds_closed() && towards > 0.0) || behind) {
        gl_Position = DROPPED;
        return;
    }
    // The box of the triangle's part in front of the light: its corners there and, for a
    // perspective light, where its edges cross w = w_min (a hair in front of the light's plane,
    // relative to the triangle's own depth: only occluders within 10^-6 of the light itself,
    // which project outside the view anyway, are left out of the box).
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    float w_min = perspective ? 1e-6 * max(clip[0].w, max(clip[1].w, clip[2].w)) : 0.0;
    bool in_front = true;
    for (uint k = 0u; k < 3u; ++k) {
        vec4 a = clip[k];
        vec4 b = clip[(k + 1u) % 3u];
        if (!perspective || a.w > w_min) {
            lo = min(lo, a.xy / a.w);
            hi = max(hi, a.xy / a.w);
        } else {
            in_front = false;
        }
        if (perspective && (a.w > w_min) != (b.w > w_min)) {
            vec4 cut = mix(a, b, (w_min - a.w) / (b.w - a.w));
            lo = min(lo, cut.xy / w_min);
            hi = max(hi, cut.xy / w_min);
        }
    }
    // A triangle whose box is narrower than a texel (2 / size) covers no texel square.
    covers = any(lessThan(hi - lo, vec2(2.0 * l.shadow_params.y))) ? 0u : 1u;
    // One texel (2 / size in NDC) around the box, clamped just outside the view.
    float pad = 2.0 * l.shadow_params.y * 1.05;
    vec3 c[3] = vec3[3](clip[0].xyw, clip[1].xyw, clip[2].xyw);
    // Reaching behind the light's plane: the box of what the view, grown by two such texels,
    // can see of it (a texel square touching the triangle lies in the view grown by one).
    if (!in_front && !seen_box(c, w_min, 1.0 + 2.0 * pad, lo, hi)) {
        gl_Position = DROPPED;
        return;
    }
    lo = max(lo - pad, vec2(-1.0 - pad));
    hi = min(hi + pad, vec2(1.0 + pad));
    if (any(greaterThan(lo, hi))) {
        gl_Position = DROPPED;
        return;
    }
    box = vec4(lo, hi);
    uint k = uint(gl_VertexIndex) % 3u;
    if (in_front && !bounds_edge_on(c[0], c[1], c[2], 2e-6)) {
        gl_Position = vec4(grown_corner(c, k, l.shadow_params.y), 0.5, 1.0);
        return;
    }
    // A triangle around the box: the corner lo and the corners 2.5 times the box's size from it
    // along each axis (its hypotenuse passes well beyond the corner hi; what it holds beyond the
    // box, the fragment stage leaves).
    vec2 size = 2.5 * (hi - lo);
    gl_Position = vec4(lo + vec2(k == 1u ? size.x : 0.0, k == 2u ? size.y : 0.0), 0.5, 1.0);
}

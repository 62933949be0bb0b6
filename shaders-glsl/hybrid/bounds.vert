#version 460
// The hybrid's conservative depth bounds, vertex stage (hybrid/bounds.glsl). Neither CPU driver
// has VK_EXT_conservative_rasterization (nor SwiftShader geometry shaders), so each triangle is
// pulled whole from the scene's vertex and index buffers (set 1) by every one of its three
// vertices, and drawn as a rectangle (two triangles, six vertices) that holds the centre of
// every texel whose square it may touch (the box of its part in front of the light, grown by a
// texel). The fragment stage then tests each texel's square
// against the real triangle exactly (Hasselgren et al., GPU Gems 2 ch. 42, in homogeneous
// 2D coordinates, so that corners behind the light need no clipping).
//
// Which triangles: every one of an open mesh; only those of a closed mesh that do not face the
// light (a ray from a receiver outside the solid to the light is blocked by the solid exactly
// when it enters it, through a face turned away from the light), so that a lit surface never
// bounds itself.
// Drawn without an index buffer: gl_VertexIndex / 6 is the triangle (firstVertex = twice the
// mesh's first index, six vertices per three indices) and gl_InstanceIndex is its vertex offset
// (firstInstance).
#include "hybrid/bounds.glsl"

layout(set = 1, binding = 0, std430) readonly buffer Vertices {
    float vertex_data[]; // position xyz, normal xyz (gpu_scene::Vertex)
};
layout(set = 1, binding = 1, std430) readonly buffer Indices {
    uint index_data[];
};

// 0 nearest, 1 covering (bounds.frag).
layout(constant_id = 0) const uint BOUND = 0u;

// The triangle's corners as clip x, y, w and light depth (bounds.frag reads them).
layout(location = 0) flat out vec4 corner[3];

vec3 pulled_position(uint index) {
    uint v = (index_data[index] + uint(gl_InstanceIndex)) * 6u;
    return vec3(vertex_data[v], vertex_data[v + 1u], vertex_data[v + 2u]);
}

// A corner outside every view: the three of a dropped triangle coincide and draw nothing.
const vec4 DROPPED = vec4(-4.0, -4.0, 0.5, 1.0);

void main() {
    Light l = lights[bounds_light()];
    mat4 view = shadow_views[uint(l.spot_params.w) + bounds_face()];
    mat4 model = objects[push.object].model;
    uint first = uint(gl_VertexIndex) / 6u * 3u;
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
    for (uint k = 0u; k < 3u; ++k) {
        vec4 a = clip[k];
        vec4 b = clip[(k + 1u) % 3u];
        if (!perspective || a.w > w_min) {
            lo = min(lo, a.xy / a.w);
            hi = max(hi, a.xy / a.w);
        }
        if (perspective && (a.w > w_min) != (b.w > w_min)) {
            vec4 cut = mix(a, b, (w_min - a.w) / (b.w - a.w));
            lo = min(lo, cut.xy / w_min);
            hi = max(hi, cut.xy / w_min);
        }
    }
    // A triangle whose box is narrower than a texel (2 / size) covers no texel square.
    if (BOUND == 1u && any(lessThan(hi - lo, vec2(2.0 * l.shadow_params.y)))) {
        gl_Position = DROPPED;
        return;
    }
    // One texel (2 / size in NDC) around the box, clamped just outside the view.
    float pad = 2.0 * l.shadow_params.y * 1.05;
    lo = max(lo - pad, vec2(-1.0 - pad));
    hi = min(hi + pad, vec2(1.0 + pad));
    if (any(greaterThan(lo, hi))) {
        gl_Position = DROPPED;
        return;
    }
    // Corners lo, (hi.x, lo.y), (lo.x, hi.y), then (hi.x, lo.y), hi, (lo.x, hi.y).
    const uvec2 CORNERS[6] = uvec2[6](uvec2(0, 0), uvec2(1, 0), uvec2(0, 1), uvec2(1, 0), uvec2(1, 1), uvec2(0, 1));
    uvec2 c = CORNERS[uint(gl_VertexIndex) % 6u];
    gl_Position = vec4(c.x == 0u ? lo.x : hi.x, c.y == 0u ? lo.y : hi.y, 0.5, 1.0);
}

#version 460
// The example engine's (examples/embed) forward shading: its own Lambert with inverse-square
// falloff and a hard spot cone, each light multiplied by the visibility umbra wrote into that
// light's visibility image (R channel), read at this pixel. An engine's shader, not umbra's.

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 light_position[4];
    vec4 light_radiance[4];
    vec4 spot[4];
    vec4 ambient;
} frame;

layout(set = 1, binding = 0) uniform sampler2D visibility0;
layout(set = 1, binding = 1) uniform sampler2D visibility1;
layout(set = 1, binding = 2) uniform sampler2D visibility2;
layout(set = 1, binding = 3) uniform sampler2D visibility3;

layout(push_constant) uniform Push {
    mat4 model;
    vec4 albedo;
} push;

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;

layout(location = 0) out vec4 out_color;

float visibility(int light) {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    switch (light) {
        case 0: return texelFetch(visibility0, pixel, 0).r;
        case 1: return texelFetch(visibility1, pixel, 0).r;
        case 2: return texelFetch(visibility2, pixel, 0).r;
        default: return texelFetch(visibility3, pixel, 0).r;
    }
}

void main() {
    vec3 n = normalize(world_normal);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 color = frame.ambient.rgb * push.albedo.rgb;
    for (int i = 0; i < int(frame.ambient.w); ++i) {
        vec4 p = frame.light_position[i];
        vec3 to_light = p.xyz - world_position * p.w;
        float d2 = max(dot(to_light, to_light), 1e-8);
        vec3 l = to_light * inversesqrt(d2);
        float falloff = p.w == 0.0 ? 1.0 : 1.0 / d2;
        if (frame.spot[i].w <= 1.0 && dot(-l, frame.spot[i].xyz) < frame.spot[i].w) {
            falloff = 0.0;
        }
        float lit = max(dot(n, l), 0.0) * falloff;
        if (lit > 0.0) {
            float v = frame.light_radiance[i].w > 0.5 ? visibility(i) : 1.0;
            color += push.albedo.rgb * frame.light_radiance[i].rgb * (lit * v);
        }
    }
    // The engine's tone curve: clamp, then sRGB-ish gamma.
    out_color = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}

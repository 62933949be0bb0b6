// The silhouette map's geometry (Sen, Cammarano, Hanrahan 2003, §3.1–3.2), mirrored on the CPU
// by `umbra_shadows::silhouette_map::geometry` (its unit tests are this file's tests: change
// both together).
//
// Coordinates are texel-local on the dual grid: a silhouette texel is the square whose corners
// are four depth samples, (0, 0) at the sample with the smallest map coordinates and (1, 1) at
// the largest; x runs along the map's columns and y along its rows (texture u and v).
#ifndef UMBRA_SILHOUETTE_GEOMETRY_GLSL
#define UMBRA_SILHOUETTE_GEOMETRY_GLSL

// How far outside the texel an intersection still counts (§3.1: the clipping square is
// enlarged slightly), so a line through a corner is stored in all four neighbours.
const float CORNER_SLACK = 1e-3;
// The point of a texel without a silhouette: its centre (a plain shadow map's behaviour).
const vec2 DEFAULT_POINT = vec2(0.5);

// Corners of a texel, as `quadrant` returns them.
const uint CORNER_00 = 0u;
const uint CORNER_10 = 1u;
const uint CORNER_11 = 2u;
const uint CORNER_01 = 3u;

bool silhouette_inside(vec2 p, float slack) {
    return all(greaterThanEqual(p, vec2(-slack))) && all(lessThanEqual(p, vec2(1.0 + slack)));
}

float perp_dot(vec2 u, vec2 v) {
    return u.x * v.y - u.y * v.x;
}

// Where segment a -> b crosses segment c -> d, both parameters within [-slack, 1 + slack].
bool silhouette_cross(vec2 a, vec2 b, vec2 c, vec2 d, float slack, out vec2 hit) {
    vec2 r = b - a;
    vec2 s = d - c;
    float denom = perp_dot(r, s);
    hit = vec2(0.0);
    if (abs(denom) < 1e-12) {
        return false;
    }
    float t = perp_dot(c - a, s) / denom;
    float u = perp_dot(c - a, r) / denom;
    bool ok = t >= -slack && t <= 1.0 + slack && u >= -slack && u <= 1.0 + slack;
    hit = a + r * t;
    return ok;
}

// §3.1, Fig. 4: an endpoint inside the texel; otherwise the one diagonal crossing, or the
// midpoint of both; false when the segment misses the texel. The point is clamped into it.
bool pick_point(vec2 a, vec2 b, out vec2 p) {
    p = DEFAULT_POINT;
    if (any(isnan(a)) || any(isinf(a)) || any(isnan(b)) || any(isinf(b))) {
        return false;
    }
    if (silhouette_inside(a, CORNER_SLACK)) {
        p = clamp(a, 0.0, 1.0);
        return true;
    }
    if (silhouette_inside(b, CORNER_SLACK)) {
        p = clamp(b, 0.0, 1.0);
        return true;
    }
    vec2 h1, h2;
    bool main_diagonal = silhouette_cross(a, b, vec2(0.0), vec2(1.0), CORNER_SLACK, h1);
    bool other_diagonal = silhouette_cross(a, b, vec2(0.0, 1.0), vec2(1.0, 0.0), CORNER_SLACK, h2);
    if (main_diagonal && other_diagonal) {
        p = clamp(0.5 * (h1 + h2), 0.0, 1.0);
    } else if (main_diagonal) {
        p = clamp(h1, 0.0, 1.0);
    } else if (other_diagonal) {
        p = clamp(h2, 0.0, 1.0);
    } else {
        return false;
    }
    return true;
}

// Whether `s` lies in the wedge swept counter-clockwise from ray r1 to ray r2 (both from the
// texel's point; the wedge is at most a half-plane).
bool in_wedge(vec2 r1, vec2 s, vec2 r2) {
    return perp_dot(r1, s) >= 0.0 && perp_dot(s, r2) >= 0.0;
}

// §3.2, Fig. 5: the skewed quadrant holding `sample`. The segments from the texel's point `c`
// to its neighbours' points (in this texel's frame) and to the four corners cut the texel into
// eight wedges, two per corner; the first wedge containing the sample names the corner whose
// depth comparison shades it.
uint quadrant(vec2 c, vec2 left, vec2 down, vec2 right, vec2 up, vec2 sample_point) {
    vec2 s = sample_point - c;
    vec2 l = left - c;
    vec2 d = down - c;
    vec2 r = right - c;
    vec2 u = up - c;
    vec2 c00 = vec2(0.0, 0.0) - c;
    vec2 c10 = vec2(1.0, 0.0) - c;
    vec2 c11 = vec2(1.0, 1.0) - c;
    vec2 c01 = vec2(0.0, 1.0) - c;
    if (in_wedge(l, s, c00) || in_wedge(c00, s, d)) {
        return CORNER_00;
    }
    if (in_wedge(d, s, c10) || in_wedge(c10, s, r)) {
        return CORNER_10;
    }
    if (in_wedge(r, s, c11) || in_wedge(c11, s, u)) {
        return CORNER_11;
    }
    if (in_wedge(u, s, c01) || in_wedge(c01, s, l)) {
        return CORNER_01;
    }
    // Only reachable through degenerate (zero-length) rays: the nearest corner.
    return sample_point.x < 0.5 ? (sample_point.y < 0.5 ? CORNER_00 : CORNER_01)
                                : (sample_point.y < 0.5 ? CORNER_10 : CORNER_11);
}

#endif

//! Shadow volumes clipped to the view on the host ([`crate::HostClip`]): the workaround for
//! drivers whose frustum clipping is not watertight. SwiftShader, clipping a closed mesh's long
//! triangles against the view's x and y planes, leaves pixels along shared edges to neither
//! triangle (`tests/shadow_volume.rs` reproduces it with three triangles), which a stencil count
//! reads as a shadow edge. Cut on the host to just inside the view, the triangles leave the
//! driver nothing to clip, and the same volumes count exactly on both drivers.
//!
//! Every volume triangle is clipped in f64 against z ≥ 0 and |x|, |y| ≤ [`INSIDE`]·w
//! (Sutherland–Hodgman). A cut point on an original edge is expressed from that edge's two
//! endpoints alone, in one order, so the two triangles sharing the edge emit the same vertex:
//! as the edge and a parameter, which the vertex shader (`shadow_volume/extrude_clipped.vert`)
//! turns into the point between the endpoints it transforms exactly as `extrude.vert` does, so
//! the point lies on the edge the unclipped path rasterizes and the vertices a triangle keeps
//! (the front cap's, on its caster) stay bit-identical to the caster's own. Where the
//! endpoints' f32 rounding could move the point by a quarter of the 10⁻⁴ w margin left to the
//! view's edge ([`gpu_placement_is_exact_enough`]: endpoints 10⁵ units away, hard case 32,
//! where a column of pixels at the frame's border was left to one volume piece), the point is
//! sent in clip space instead, rounded from f64 once, as the points where two clip planes
//! meet always are: those lie on the boundary of the clipped region, where no pixel centre is.

//! A front cap that leaves the view is cut too: left to the driver, two cap triangles sharing
//! an edge (a floor's two top triangles) leave pixels along it to neither or both, counted
//! wrong behind whatever hides the floor. Cut, its interpolated depth is no longer the
//! caster's own, which z-fail needs where the caster is the visible surface (the cap must
//! fail LESS there), so the cut caps go last in the caster's range (`CasterVolume::cut_caps`)
//! and are drawn with no depth test, each fragment counted as behind
//! ([`super::pass::CUT_CAP_COMPARE`]: nothing visible lies behind a cap on its caster). Caps
//! inside the view keep their vertices, bit-identical to the caster's, and test `LESS`.

use super::build::CasterVolume;
use glam::{DMat4, DVec4, Mat4, Vec4};
use umbra_scene::Scene;
use umbra_vk::{vk, VertexAttribute};

/// The clipped region's half-extent in x and y, in units of w: just inside the view, so the
/// driver's clipper never runs, and far enough inside (10⁻⁴ w) that the vertex shader's f32
/// rounding cannot push a vertex back out.
pub(crate) const INSIDE: f64 = 0.9999;

/// One vertex of a host-clipped volume: `t = 0`, the volume vertex `a` (object space, w = 0 at
/// infinity); `0 < t < 1`, the point `a + t (b − a)` of the edge between volume vertices `a` and
/// `b`, in clip space; `t < 0`, `b` is a clip-space position.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ClippedVertex {
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub t: f32,
}

/// Vertex layout of [`ClippedVertex`].
pub(crate) const CLIPPED_ATTRIBUTES: [VertexAttribute; 3] = [
    VertexAttribute { location: 0, format: vk::Format::R32G32B32A32_SFLOAT, offset: 0 },
    VertexAttribute { location: 1, format: vk::Format::R32G32B32A32_SFLOAT, offset: 16 },
    VertexAttribute { location: 2, format: vk::Format::R32_SFLOAT, offset: 32 },
];
pub(crate) const CLIPPED_STRIDE: u32 = std::mem::size_of::<ClippedVertex>() as u32;

/// The clip planes as signed distances, inside where ≥ 0.
const PLANES: [fn(DVec4) -> f64; 5] =
    [|p| p.z, |p| INSIDE * p.w - p.x, |p| INSIDE * p.w + p.x, |p| INSIDE * p.w - p.y, |p| INSIDE * p.w + p.y];

/// A vertex of a triangle being clipped: one of its three vertices, a point on the edge
/// between two of them (`i` before `j` in the canonical order), or a corner of the region.
#[derive(Clone, Copy)]
enum Point {
    Vertex(usize),
    Edge { i: usize, j: usize, t: f64 },
    Corner(DVec4),
}

/// The volume vertices of one light (`vertices`, object space, as `build::build_light` made
/// them) clipped for the camera `view_proj`: every caster's range is rewritten to its range in
/// the returned vertices.
pub(crate) fn clip_light(
    scene: &Scene,
    light: Vec4,
    view_proj: Mat4,
    vertices: &[Vec4],
    casters: &mut [CasterVolume],
    out: &mut Vec<ClippedVertex>,
    cut_caps: &mut Vec<ClippedVertex>,
) {
    let (vp, l) = (view_proj.as_dmat4(), light.as_dvec4());
    for c in casters.iter_mut() {
        let model = scene.objects.get(c.object).map_or(DMat4::IDENTITY, |o| o.transform.as_dmat4());
        let first = out.len() as u32;
        let range = c.first as usize..(c.first + c.count) as usize;
        cut_caps.clear();
        for t in vertices.get(range).unwrap_or_default().chunks_exact(3) {
            clip_triangle([t[0], t[1], t[2]], |v| clip_position(vp, model, l, v), out, cut_caps);
        }
        out.extend_from_slice(cut_caps);
        c.first = first;
        c.count = out.len() as u32 - first;
        c.cut_caps = cut_caps.len() as u32;
    }
}

/// `extrude.glsl`'s `volume_clip_position` in f64.
fn clip_position(vp: DMat4, model: DMat4, light: DVec4, v: Vec4) -> DVec4 {
    let world = model * v.truncate().as_dvec3().extend(1.0);
    let world = match v.w == 0.0 {
        true => (world.truncate() * light.w - light.truncate()).extend(0.0),
        false => world,
    };
    vp * world
}

/// Clips one triangle and fans what is left into `out`, or into `cut_caps` for a front cap
/// (every vertex finite) that had to be cut; nothing when it lies outside.
fn clip_triangle(
    v: [Vec4; 3],
    project: impl Fn(Vec4) -> DVec4,
    out: &mut Vec<ClippedVertex>,
    cut_caps: &mut Vec<ClippedVertex>,
) {
    let clip = v.map(&project);
    let inside = |p: DVec4| PLANES.iter().all(|d| d(p) >= 0.0);
    if clip.iter().all(|&p| inside(p)) {
        out.extend(v.map(|a| ClippedVertex { a: a.to_array(), b: [0.0; 4], t: 0.0 }));
        return;
    }
    let out = if v.iter().all(|p| p.w != 0.0) { cut_caps } else { out };
    // The canonical order of two vertices: by their bits, so a shared edge is seen alike.
    let before = |i: usize, j: usize| v[i].to_array().map(f32::to_bits) <= v[j].to_array().map(f32::to_bits);
    let position = |p: Point| match p {
        Point::Vertex(k) => clip[k],
        Point::Edge { i, j, t } => clip[i] + (clip[j] - clip[i]) * t,
        Point::Corner(c) => c,
    };
    // The original edge a point lies on, if any (a vertex lies on two; either will do).
    let edge_of = |a: Point, b: Point| -> Option<(usize, usize)> {
        let ends = |p: Point| match p {
            Point::Vertex(k) => Some([k, k]),
            Point::Edge { i, j, .. } => Some([i, j]),
            Point::Corner(_) => None,
        };
        let (ea, eb) = (ends(a)?, ends(b)?);
        // On an original edge exactly when the two points touch two of the three vertices.
        let mut touched = (0..3).filter(|k| ea.contains(k) || eb.contains(k));
        let (i, j) = (touched.next()?, touched.next()?);
        match touched.next() {
            Some(_) => None,
            None => Some(if before(i, j) { (i, j) } else { (j, i) }),
        }
    };
    // At most 3 + 5 vertices after five planes; the two buffers are swapped plane by plane.
    let mut poly: Vec<Point> = Vec::with_capacity(8);
    poly.extend((0..3).map(Point::Vertex));
    let mut next = Vec::with_capacity(8);
    for plane in PLANES {
        next.clear();
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (plane(position(a)), plane(position(b)));
            if da >= 0.0 {
                next.push(a);
            }
            if (da >= 0.0) == (db >= 0.0) {
                continue;
            }
            next.push(match edge_of(a, b) {
                // On an original edge: from its endpoints alone.
                Some((i, j)) => {
                    let (di, dj) = (plane(clip[i]), plane(clip[j]));
                    Point::Edge { i, j, t: di / (di - dj) }
                }
                None => {
                    let (pa, pb) = (position(a), position(b));
                    Point::Corner(pa + (pb - pa) * (da / (da - db)))
                }
            });
        }
        std::mem::swap(&mut poly, &mut next);
        if poly.len() < 3 {
            return;
        }
    }
    let vertex = |p: Point| match p {
        Point::Vertex(k) => ClippedVertex { a: v[k].to_array(), b: [0.0; 4], t: 0.0 },
        Point::Edge { i, j, t } if gpu_placement_is_exact_enough(clip[i], clip[j], position(p)) => {
            ClippedVertex { a: v[i].to_array(), b: v[j].to_array(), t: t as f32 }
        }
        Point::Edge { .. } | Point::Corner(_) => {
            ClippedVertex { a: [0.0; 4], b: position(p).as_vec4().to_array(), t: -1.0 }
        }
    };
    for k in 1..poly.len() - 1 {
        out.extend([vertex(poly[0]), vertex(poly[k]), vertex(poly[k + 1])]);
    }
}

/// Whether the cut point `p` of the edge between clip positions `a` and `b`, placed by the
/// vertex shader from the endpoints it transforms in f32, stays within a quarter of the margin
/// [`INSIDE`] leaves to the view's edge: the endpoints' rounding and the interpolation's move it
/// by a few units in the last place of the larger endpoint (bounded here by 2⁻²⁰ of it).
fn gpu_placement_is_exact_enough(a: DVec4, b: DVec4, p: DVec4) -> bool {
    let rounding = a.abs().max(b.abs()).max_element() * f64::powi(2.0, -20);
    rounding < 0.25 * (1.0 - INSIDE) * p.w.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Clips the triangle whose clip-space corners are `clip`, its volume vertices standing for
    /// side or back-cap vertices (w = 0, so not a front cap) that carry their index in x.
    fn clip_at(clip: [Vec4; 3], out: &mut Vec<ClippedVertex>) {
        let v = [0.0, 1.0, 2.0].map(|i| Vec4::new(i, 0.0, 0.0, 0.0));
        clip_triangle(v, |p| clip[p.x as usize].as_dvec4(), out, &mut Vec::new());
    }

    /// The clip position a clipped vertex stands for, given the clip positions of the volume
    /// vertices by index (as the vertex shader places it).
    fn placed(v: &ClippedVertex, clip: &[Vec4; 3]) -> DVec4 {
        let at = |p: [f32; 4]| clip[p[0] as usize].as_dvec4();
        if v.t < 0.0 {
            Vec4::from_array(v.b).as_dvec4()
        } else if v.t == 0.0 {
            at(v.a)
        } else {
            at(v.a) + (at(v.b) - at(v.a)) * f64::from(v.t)
        }
    }

    #[test]
    fn a_triangle_inside_the_view_is_kept_and_a_front_cap_leaving_it_is_cut_apart() {
        let (mut out, mut caps) = (Vec::new(), Vec::new());
        let inside = [Vec4::new(-0.5, -0.5, 0.5, 1.0), Vec4::new(0.5, -0.5, 0.5, 1.0), Vec4::new(0.0, 0.5, 0.5, 1.0)];
        clip_triangle(inside, |p| p.as_dvec4(), &mut out, &mut caps);
        assert_eq!(out.len(), 3);
        assert!(out.iter().all(|v| v.t == 0.0) && caps.is_empty());
        // A front cap (finite vertices) reaching far outside the view: cut, into `caps`.
        let cap = [Vec4::new(-5.0, -0.5, 0.5, 1.0), Vec4::new(5.0, -0.5, 0.5, 1.0), Vec4::new(0.0, 5.0, 0.5, 1.0)];
        clip_triangle(cap, |p| p.as_dvec4(), &mut out, &mut caps);
        assert_eq!(out.len(), 3);
        assert!(caps.len() >= 3 && caps.iter().any(|v| v.t != 0.0));
    }

    #[test]
    fn a_triangle_outside_the_view_is_dropped() {
        let mut out = Vec::new();
        clip_at(
            [Vec4::new(2.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.0, 0.5, 1.0), Vec4::new(2.5, 1.0, 0.5, 1.0)],
            &mut out,
        );
        assert!(out.is_empty());
    }

    #[test]
    fn triangles_sharing_an_edge_share_its_cut_points() {
        // Two triangles on either side of the edge between volume vertices 0 and 1, which
        // leaves the view on the right; seen from either triangle in either direction.
        let (a, b) = (Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.3, 0.5, 1.0));
        let (c, d) = (Vec4::new(0.2, 0.5, 0.5, 1.0), Vec4::new(0.2, -0.5, 0.5, 1.0));
        let clip_one = [a, b, c];
        let (mut one, mut two) = (Vec::new(), Vec::new());
        clip_at(clip_one, &mut one);
        // The second triangle lists the shared vertices the other way round: volume vertex 1
        // first (index 1 → clip b), then 0 (→ a).
        let v = [Vec4::new(1.0, 0.0, 0.0, 0.0), Vec4::new(0.0, 0.0, 0.0, 0.0), Vec4::new(2.0, 0.0, 0.0, 0.0)];
        let clip_two = [a, b, d];
        clip_triangle(v, |p| clip_two[p.x as usize].as_dvec4(), &mut two, &mut Vec::new());
        // Endpoints near the view: the cut point is sent as the edge and a parameter, the same
        // from either triangle.
        let on_edge = |vs: &[ClippedVertex]| -> Vec<ClippedVertex> {
            vs.iter().filter(|v| v.t > 0.0 && v.a[0] < 2.0 && v.b[0] < 2.0).copied().collect()
        };
        let (e1, e2) = (on_edge(&one), on_edge(&two));
        assert!(!e1.is_empty() && !e2.is_empty());
        assert_eq!(e1[0], e2[0], "the same cut point, expressed the same way");
        let p = placed(&e1[0], &clip_one);
        assert!((p.x - INSIDE * p.w).abs() < 1e-6, "{p}");
    }

    /// Far from its edge's endpoints (10⁶ clip units away) a cut point is sent in clip space and
    /// lies on the clip plane to f32 precision: within the margin `INSIDE` leaves to the view's
    /// edge, which the endpoints' rounding on the GPU would exceed.
    #[test]
    fn cut_points_far_from_their_endpoints_stay_inside_the_margin() {
        // An edge from a point 1e6 to the left of the view to one just inside it.
        let a = Vec4::new(-1.0e6, 0.0, 5.0, 10.0);
        let b = Vec4::new(0.5, 0.3, 5.0, 10.0);
        let c = Vec4::new(0.5, -0.3, 5.0, 10.0);
        let mut out = Vec::new();
        clip_at([a, b, c], &mut out);
        let clip = [a, b, c];
        assert!(out.iter().all(|v| v.t <= 0.0), "a cut point left to the GPU: {out:?}");
        let cut: Vec<_> = out.iter().filter(|v| v.t < 0.0).collect();
        assert!(!cut.is_empty());
        for v in cut {
            // As the GPU receives it: f32 clip coordinates, divided once.
            let p = Vec4::from_array(v.b);
            let ndc = p.x / p.w;
            assert!((f64::from(ndc) + INSIDE).abs() < 1e-6, "{ndc} for {:?}", placed(v, &clip));
        }
    }

    /// Signed coverage of the NDC point `p` by clipped triangles: +1 counter-clockwise.
    fn winding(tris: &[ClippedVertex], clip: &[Vec4; 3], p: (f64, f64)) -> i32 {
        tris.chunks_exact(3)
            .map(|t| {
                let q: Vec<(f64, f64)> = t.iter().map(|v| placed(v, clip)).map(|c| (c.x / c.w, c.y / c.w)).collect();
                let e = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
                let (e0, e1, e2) = (e(q[0], q[1]), e(q[1], q[2]), e(q[2], q[0]));
                match (e0 > 0.0 && e1 > 0.0 && e2 > 0.0, e0 < 0.0 && e1 < 0.0 && e2 < 0.0) {
                    (true, _) => 1,
                    (_, true) => -1,
                    _ => 0,
                }
            })
            .sum()
    }

    #[test]
    fn what_is_left_covers_the_view_as_the_triangle_did() {
        // Triangles with a vertex far outside the view or behind the eye: inside the view the
        // clipped pieces cover every point exactly as the whole triangle does.
        let mut seed = 7u64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 1_000_000) as f32 / 1e6
        };
        for _ in 0..300 {
            let p = |x: f32, y: f32, w: f32| Vec4::new(x * w, y * w, 0.5 * w, w);
            let (cx, cy) = (rnd() * 1.6 - 0.8, rnd() * 1.6 - 0.8);
            let a = p(cx + 0.2 * rnd(), cy + 0.2 * rnd(), 2.0 + rnd());
            let b = p(cx - 0.2 * rnd(), cy + 0.2 * rnd(), 2.0 + rnd());
            let ang = rnd() * std::f32::consts::TAU;
            let w = 0.05 + rnd();
            let c = Vec4::new(30.0 * ang.cos() * w, 30.0 * ang.sin() * w, 0.5 * w, w);
            let clip = [a, b, c];
            let mut out = Vec::new();
            clip_at(clip, &mut out);
            let whole: Vec<ClippedVertex> =
                [0.0, 1.0, 2.0].map(|i| ClippedVertex { a: [i, 0.0, 0.0, 0.0], b: [0.0; 4], t: 0.0 }).to_vec();
            for _ in 0..50 {
                let q = (f64::from(rnd()) * 1.9 - 0.95, f64::from(rnd()) * 1.9 - 0.95);
                assert_eq!(winding(&out, &clip, q), winding(&whole, &clip, q), "{clip:?} at {q:?}");
            }
        }
    }
}

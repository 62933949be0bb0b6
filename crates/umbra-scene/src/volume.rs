//! Shadow volumes on the CPU (Everitt–Kilgard 2002 §2–3), per caster and per light:
//! triangle facing from each plane evaluated at the homogeneous light position, silhouette
//! edges, the extruded side quads, and the caps.
//!
//! The volume is a list of triangles over [`VolumeVertex`]es: a welded mesh vertex, either as
//! is or extruded to infinity away from the light. The vertex shader makes the far vertex
//! `(A·Lw − L·Aw, 0)` (w = 0), so no geometry shader is needed.
//!
//! - Closed 2-manifold casters: front cap = the light-facing triangles, back cap = the
//!   back-facing triangles at infinity, sides = the silhouette edges (one light-facing and one
//!   back-facing face) extruded — the paper's construction.
//! - Open or non-manifold casters (Bergeron; Arneson §4): a surface with holes blocks light
//!   with its back-facing triangles too (light entering a teapot's opening stops at the inside
//!   of the far wall), so **every** triangle casts, oriented towards the light (back-facing
//!   ones flipped), and each is closed on its own: front cap = the oriented triangles, back
//!   cap = the same reversed at infinity, and an edge is extruded as many times as the net
//!   count of oriented faces that walk it one way minus the other. Boundary edges and edges of
//!   3+ faces then close the volume; every triangle a shadow ray crosses adds one to the count,
//!   so any occluder shadows, and no crack or inverted region appears.
//!
//! Either way every directed edge of the volume has a reverse twin (the closed-volume
//! invariant the tests check), so the stencil count along any ray is its winding number.

use crate::Adjacency;
use glam::{Vec3, Vec4};
use serde::Serialize;

/// A volume vertex: welded mesh vertex `vertex`, extruded to infinity when `far`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VolumeVertex {
    /// Index into [`Adjacency::positions`].
    pub vertex: u32,
    /// Projected to infinity away from the light.
    pub far: bool,
}

/// How many of each part a volume has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct VolumeStats {
    /// Edges extruded into side quads (with multiplicity).
    pub silhouette_edges: usize,
    /// Side triangles (two per extruded edge).
    pub side_triangles: usize,
    /// Front and back cap triangles.
    pub cap_triangles: usize,
    /// Triangles facing the light.
    pub light_facing: usize,
}

/// One caster's shadow volume for one light.
#[derive(Clone, Debug, Default)]
pub struct Volume {
    /// Side triangles (all z-pass needs).
    pub sides: Vec<[VolumeVertex; 3]>,
    /// Front and back caps (z-fail needs them too).
    pub caps: Vec<[VolumeVertex; 3]>,
    /// Counts.
    pub stats: VolumeStats,
}

const fn near(vertex: u32) -> VolumeVertex {
    VolumeVertex { vertex, far: false }
}

const fn far(vertex: u32) -> VolumeVertex {
    VolumeVertex { vertex, far: true }
}

fn degenerate(t: &[u32; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[0] == t[2]
}

/// How a triangle faces a light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Facing {
    /// Its plane evaluated at the light is positive: the light sees its front.
    Towards,
    /// Negative: the light sees its back.
    Away,
    /// Exactly zero: its plane contains the light, which sees it edge-on. It blocks no light
    /// ray (every one runs in its plane), so an open caster's construction leaves it out:
    /// closed on its own it would be a flat sheet whose two sides cancel only where the
    /// rasterizer happens to interpolate them alike. A closed caster counts it as
    /// [`Facing::Away`] (part of the back cap), as the paper does.
    EdgeOn,
}

/// How each triangle of `adj` faces the homogeneous light position `light` (in the mesh's
/// object space), from its plane evaluated at the light, `d = A·Lx + B·Ly + C·Lz + D·Lw`, so
/// directional lights (w = 0) need no special case.
pub fn facing(adj: &Adjacency, light: Vec4) -> Vec<Facing> {
    adj.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| adj.positions[i as usize]);
            let n = (b - a).cross(c - a);
            let d = n.dot(light.truncate()) - n.dot(a) * light.w;
            if d > 0.0 {
                Facing::Towards
            } else if d < 0.0 {
                Facing::Away
            } else {
                Facing::EdgeOn
            }
        })
        .collect()
}

/// The silhouette edges of `adj` for the facing `facing` (from [`facing`]), directed as a casting
/// face walks them and repeated with their multiplicity: the one source of silhouettes for
/// shadow volumes and silhouette maps.
///
/// Closed meshes: edges between a light-facing and a back-facing face. Open or non-manifold
/// meshes: every face not edge-on to the light casts, oriented towards the light, and an edge
/// counts the net number of oriented faces walking it one way minus the other (boundary edges
/// and edges of 3+ faces included).
pub fn silhouette_edges(adj: &Adjacency, facing: &[Facing]) -> Vec<[u32; 2]> {
    let closed = adj.report.closed;
    let mut out = Vec::new();
    for e in &adj.edges {
        let net: i32 = e
            .faces
            .iter()
            .map(|f| (f, facing[f.face as usize]))
            .filter(|&(_, fa)| if closed { fa == Facing::Towards } else { fa != Facing::EdgeOn })
            .map(|(f, fa)| if f.forward == (fa == Facing::Towards || closed) { 1 } else { -1 })
            .sum();
        let edge = if net > 0 { [e.v[0], e.v[1]] } else { [e.v[1], e.v[0]] };
        out.extend(std::iter::repeat_n(edge, net.unsigned_abs() as usize));
    }
    out
}

impl Volume {
    /// Builds the volume of a caster whose welded connectivity is `adj`, for a light at the
    /// homogeneous position `light` **in the caster's object space** (w = 0 directional).
    /// A triangle faces the light when its plane evaluated at `light` is positive.
    pub fn build(adj: &Adjacency, light: Vec4) -> Self {
        let facings = facing(adj, light);
        let closed = adj.report.closed;
        let mut v = Volume::default();
        for (t, &f) in adj.triangles.iter().zip(&facings) {
            if degenerate(t) || (!closed && f == Facing::EdgeOn) {
                continue;
            }
            let lit = f == Facing::Towards;
            let [a, b, c] = *t;
            v.stats.light_facing += usize::from(lit);
            if closed {
                if lit {
                    v.caps.push([near(a), near(b), near(c)]);
                } else {
                    v.caps.push([far(a), far(b), far(c)]);
                }
            } else {
                // Oriented towards the light: back-facing triangles flipped.
                let (b, c) = if lit { (b, c) } else { (c, b) };
                v.caps.push([near(a), near(b), near(c)]);
                v.caps.push([far(a), far(c), far(b)]);
            }
        }
        for [a, b] in silhouette_edges(adj, &facings) {
            // A casting face walking a -> b is closed by the side b -> a -> a_inf -> b_inf.
            v.sides.push([near(b), near(a), far(a)]);
            v.sides.push([near(b), far(a), far(b)]);
            v.stats.silhouette_edges += 1;
        }
        v.stats.side_triangles = v.sides.len();
        v.stats.cap_triangles = v.caps.len();
        v
    }

    /// Vertices for the GPU: object-space position with w = 1, or w = 0 for far vertices
    /// (the vertex shader extrudes those). Sides first, then caps.
    pub fn vertices(&self, adj: &Adjacency, with_caps: bool) -> Vec<Vec4> {
        let tris = self.sides.iter().chain(if with_caps { &self.caps[..] } else { &[] });
        tris.flat_map(|t| t.map(|v| adj.positions[v.vertex as usize].extend(if v.far { 0.0 } else { 1.0 }))).collect()
    }

    /// Every directed edge of every triangle, for the closed-volume check.
    pub fn directed_edges(&self) -> impl Iterator<Item = (VolumeVertex, VolumeVertex)> + '_ {
        self.sides.iter().chain(&self.caps).flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
    }

    /// Whether every directed edge has exactly as many reverse twins as copies (a closed
    /// surface, counted with multiplicity).
    pub fn is_closed(&self) -> bool {
        let mut count: std::collections::HashMap<(VolumeVertex, VolumeVertex), i64> = Default::default();
        for (a, b) in self.directed_edges() {
            *count.entry((a, b)).or_default() += 1;
            *count.entry((b, a)).or_default() -= 1;
        }
        count.values().all(|&c| c == 0)
    }
}

/// The point a far vertex stands for, for a world- or object-space light: the direction
/// `A·Lw − L·Aw` (w = 0). Exposed for CPU-side tests of the vertex shader's formula.
pub fn extrude(a: Vec3, light: Vec4) -> Vec4 {
    (a * light.w - light.truncate()).extend(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;
    use proptest::prelude::*;

    fn light_strategy() -> impl Strategy<Value = Vec4> {
        (-4.0f32..4.0, -4.0f32..4.0, -4.0f32..4.0, prop::bool::ANY).prop_map(|(x, y, z, directional)| {
            if directional {
                Vec3::new(x, y, z).normalize_or(Vec3::Y).extend(0.0)
            } else {
                Vec4::new(x, y, z, 1.0)
            }
        })
    }

    /// Random closed, non-convex meshes: spheres with random bumps.
    fn closed_mesh() -> impl Strategy<Value = crate::Mesh> {
        (3u32..14, 2u32..9, prop::collection::vec(0.5f32..1.5, 8)).prop_map(|(segments, rings, bumps)| {
            primitives::displaced_sphere(1.0, segments, rings, |t, p| {
                bumps[((t * 3.0) as usize + (p * 5.0) as usize) % bumps.len()]
            })
        })
    }

    proptest! {
        #[test]
        fn volumes_of_closed_meshes_are_closed(mesh in closed_mesh(), light in light_strategy()) {
            let adj = Adjacency::build(&mesh);
            prop_assert!(adj.report.closed);
            let v = Volume::build(&adj, light);
            prop_assert!(v.is_closed(), "{:?}", v.stats);
            // Closed manifold: front cap + back cap cover every triangle once.
            prop_assert_eq!(v.stats.cap_triangles, adj.report.triangles - adj.report.degenerate_triangles);
        }

        #[test]
        fn volumes_of_open_meshes_are_closed_too(mesh in closed_mesh(), light in light_strategy(), keep in prop::collection::vec(prop::bool::weighted(0.7), 64)) {
            // Punch random holes: drop triangles.
            let mut open = mesh.clone();
            open.indices = mesh.indices.chunks_exact(3).enumerate().filter(|(i, _)| keep[i % keep.len()]).flat_map(|(_, t)| t.to_vec()).collect();
            let adj = Adjacency::build(&open);
            let v = Volume::build(&adj, light);
            prop_assert!(v.is_closed(), "{:?}", v.stats);
        }
    }

    /// A far vertex at a finite distance: `K` times its extrusion direction past the vertex
    /// (the region the tests probe lies well inside, so the truncated volume counts the same).
    fn finite(adj: &Adjacency, v: VolumeVertex, light: Vec4) -> glam::DVec3 {
        const K: f64 = 1e4;
        let a = adj.positions[v.vertex as usize];
        let p = a.as_dvec3();
        if v.far {
            p + extrude(a, light).truncate().as_dvec3() * K
        } else {
            p
        }
    }

    /// Where the ray `o + t d` (t > 0) crosses triangle `[a, b, c]`: the sign of the crossing
    /// (+1 leaving through the front side, −1 entering), or 0 for no crossing. Double
    /// precision Möller–Trumbore.
    fn crossing(o: glam::DVec3, d: glam::DVec3, [a, b, c]: [glam::DVec3; 3], t_max: f64) -> i32 {
        let (e1, e2) = (b - a, c - a);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            return 0;
        }
        let tv = o - a;
        let u = tv.dot(pv) / det;
        let qv = tv.cross(e1);
        let v = d.dot(qv) / det;
        let t = e2.dot(qv) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || t <= 0.0 || t >= t_max {
            return 0;
        }
        if e1.cross(e2).dot(d) > 0.0 {
            1
        } else {
            -1
        }
    }

    /// The z-fail stencil count at `q` seen along `d`: back faces behind the surface add one,
    /// front faces subtract one (the GPU's ops, counted on the CPU).
    fn zfail_count(adj: &Adjacency, v: &Volume, light: Vec4, q: glam::DVec3, d: glam::DVec3) -> i32 {
        v.sides.iter().chain(&v.caps).map(|t| crossing(q, d, t.map(|x| finite(adj, x, light)), f64::INFINITY)).sum()
    }

    /// Triangles of `adj` the segment from `q` to the light crosses (light-facing ones only
    /// for closed meshes: those are the front cap the count is made of).
    fn occluders(adj: &Adjacency, light: Vec4, q: glam::DVec3) -> i32 {
        let lit = facing(adj, light);
        let (d, t_max) = if light.w == 0.0 {
            (light.truncate().as_dvec3(), f64::INFINITY)
        } else {
            (light.truncate().as_dvec3() - q, 1.0)
        };
        adj.triangles
            .iter()
            .zip(&lit)
            .filter(|(t, &f)| !degenerate(t) && (f == Facing::Towards || (!adj.report.closed && f != Facing::EdgeOn)))
            .map(|(t, _)| crossing(q, d, t.map(|i| adj.positions[i as usize].as_dvec3()), t_max).abs())
            .sum()
    }

    fn point_strategy() -> impl Strategy<Value = glam::DVec3> {
        (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0).prop_map(|(x, y, z)| glam::DVec3::new(x, y, z))
    }

    /// Lights outside the meshes' reach (radius 1.5), so no vertex sits on the light.
    fn outside_light() -> impl Strategy<Value = Vec4> {
        light_strategy().prop_filter("light clear of the mesh", |l| l.w == 0.0 || l.truncate().length() > 2.0)
    }

    proptest! {
        #[test]
        fn silhouette_edges_of_closed_meshes_form_closed_loops(mesh in closed_mesh(), light in light_strategy()) {
            let adj = Adjacency::build(&mesh);
            let edges = silhouette_edges(&adj, &facing(&adj, light));
            let mut degree: std::collections::HashMap<u32, i64> = Default::default();
            for [a, b] in &edges {
                *degree.entry(*a).or_default() += 1;
                *degree.entry(*b).or_default() -= 1;
            }
            // Every vertex is entered as often as it is left: the directed edges decompose
            // into closed loops.
            prop_assert!(degree.values().all(|&d| d == 0), "{} edges", edges.len());
        }

        #[test]
        fn the_zfail_count_is_the_number_of_casting_faces_towards_the_light(
            mesh in closed_mesh(),
            light in outside_light(),
            holes in prop::option::of(prop::collection::vec(prop::bool::weighted(0.7), 64)),
            q in point_strategy(),
            view in point_strategy(),
        ) {
            let mut mesh = mesh;
            if let Some(keep) = holes {
                mesh.indices = mesh.indices.chunks_exact(3).enumerate().filter(|(i, _)| keep[i % keep.len()]).flat_map(|(_, t)| t.to_vec()).collect();
            }
            let adj = Adjacency::build(&mesh);
            let v = Volume::build(&adj, light);
            let d = view.normalize_or(glam::DVec3::X);
            let count = zfail_count(&adj, &v, light, q, d);
            let expected = occluders(&adj, light, q);
            // The stencil count along any view ray is the winding number of the volume at the
            // visible point: one per casting face between it and the light, so it is
            // non-zero exactly where the point is in shadow.
            prop_assert_eq!(count, expected, "closed {}, {:?}", adj.report.closed, v.stats);
        }
    }

    #[test]
    fn a_box_lit_from_above_has_four_silhouette_edges() {
        let adj = Adjacency::build(&primitives::cuboid(Vec3::ONE));
        let v = Volume::build(&adj, Vec4::new(0.0, 5.0, 0.0, 1.0));
        assert_eq!(v.stats.silhouette_edges, 4);
        assert_eq!(v.stats.light_facing, 2);
        assert!(v.is_closed());
    }

    #[test]
    fn non_manifold_fins_close_with_multiplicity() {
        // Three quads sharing one edge (x = 0 axis), lit from +y: a non-manifold edge.
        let p = [
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, -1.0, 1.0),
        ];
        let idx = [0, 1, 3, 0, 3, 2, 0, 4, 5, 0, 5, 1, 0, 6, 7, 0, 7, 1];
        let mesh = crate::Mesh::with_flat_normals("fins", &p, &idx).unwrap();
        let adj = Adjacency::build(&mesh);
        assert_eq!(adj.report.non_manifold_edges, 1);
        for light in [Vec4::new(0.3, 2.0, 0.5, 1.0), Vec4::new(0.2, 1.0, 0.1, 0.0), Vec4::new(-2.0, -1.0, 0.5, 1.0)] {
            assert!(Volume::build(&adj, light).is_closed());
        }
    }

    #[test]
    fn an_open_triangle_edge_on_to_the_light_casts_nothing() {
        // Hard case 06's fin: its plane x = 0.5 holds the light. Closed on its own it would be
        // a flat sheet; it blocks no light ray, so it casts no volume at all.
        let p = [Vec3::new(0.5, 0.5, 1.0), Vec3::new(0.5, 1.5, 1.0), Vec3::new(0.5, 1.0, 2.0)];
        let adj = Adjacency::build(&crate::Mesh::with_flat_normals("fin", &p, &[0, 1, 2]).unwrap());
        let light = Vec4::new(0.5, 3.0, 0.25, 1.0);
        assert_eq!(facing(&adj, light), vec![Facing::EdgeOn]);
        let v = Volume::build(&adj, light);
        assert!(v.sides.is_empty() && v.caps.is_empty(), "{v:?}");
        // A hair off the plane, it casts its thin wedge again.
        let v = Volume::build(&adj, Vec4::new(0.5001, 3.0, 0.25, 1.0));
        assert_eq!((v.caps.len(), v.sides.len()), (2, 6));
        assert!(v.is_closed());
        // A closed box with a face in the light's plane keeps the paper's construction.
        let cube = Adjacency::build(&primitives::cuboid(Vec3::splat(0.5)));
        let v = Volume::build(&cube, Vec4::new(0.5, 3.0, 0.25, 1.0));
        assert_eq!(v.caps.len(), 12);
        assert!(v.is_closed());
    }

    #[test]
    fn far_vertices_point_away_from_the_light() {
        let l = Vec4::new(0.0, 4.0, 0.0, 1.0);
        assert_eq!(extrude(Vec3::ZERO, l), Vec4::new(0.0, -4.0, 0.0, 0.0));
        let d = Vec4::new(0.0, 1.0, 0.0, 0.0);
        assert_eq!(extrude(Vec3::new(5.0, 1.0, 2.0), d), Vec4::new(0.0, -1.0, 0.0, 0.0));
    }
}

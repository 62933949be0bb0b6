//! Edge adjacency for shadow volumes: vertices welded by position, every edge with the faces
//! that use it, and a topology report (closed? boundary and non-manifold edges).
//!
//! Everitt–Kilgard's robust volumes need closed 2-manifold casters; real meshes are not
//! (the repository's `assets/README.md`: the teapot and the bunny are open, suzanne is also
//! non-manifold). The report says what a mesh is, and the volume builder treats boundary and
//! non-manifold edges so that no crack or inverted shadow appears.

use crate::Mesh;
use glam::Vec3;
use serde::Serialize;
use std::collections::HashMap;

/// One face's use of an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeFace {
    /// Triangle index (into [`Adjacency::triangles`]).
    pub face: u32,
    /// Whether the face walks the edge as `v[0] → v[1]` (true) or `v[1] → v[0]`.
    pub forward: bool,
}

/// An undirected edge between two welded vertices and the faces that use it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Welded vertex indices, smaller first.
    pub v: [u32; 2],
    /// Faces using the edge (1: boundary, 2: manifold, 3+: non-manifold).
    pub faces: Vec<EdgeFace>,
}

/// What a mesh is, topologically.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct TopologyReport {
    /// Triangles (degenerate ones included).
    pub triangles: usize,
    /// Distinct positions after welding.
    pub vertices: usize,
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges used by exactly one face.
    pub boundary_edges: usize,
    /// Edges used by three or more faces.
    pub non_manifold_edges: usize,
    /// Triangles with two welded corners equal (no area, no edges of their own).
    pub degenerate_triangles: usize,
    /// No boundary and no non-manifold edge.
    pub closed: bool,
}

/// Welded connectivity of a mesh.
#[derive(Clone, Debug, Default)]
pub struct Adjacency {
    /// Welded positions.
    pub positions: Vec<Vec3>,
    /// Per welded position, the first of the mesh's vertices welded into it (where a copy of
    /// the mesh's vertices, deformed on the GPU, finds each welded position again).
    pub welded_from: Vec<u32>,
    /// Triangles over welded positions, in the mesh's order (winding kept).
    pub triangles: Vec<[u32; 3]>,
    /// Every undirected edge of the non-degenerate triangles.
    pub edges: Vec<Edge>,
    /// The topology summary.
    pub report: TopologyReport,
    /// Closed, and every vertex on or behind every triangle's plane (f64): a convex solid,
    /// whose shadow volume counts at most 1 anywhere, for any light. Only tested up to
    /// [`CONVEX_TEST_TRIANGLES`] triangles (the test is vertices × triangles); false beyond.
    pub convex: bool,
}

/// Meshes up to this many triangles are tested for [`Adjacency::convex`].
pub const CONVEX_TEST_TRIANGLES: usize = 8192;

impl Adjacency {
    /// Welds `mesh` by exact position and builds its edges.
    pub fn build(mesh: &Mesh) -> Self {
        let mut remap: HashMap<[u32; 3], u32> = HashMap::with_capacity(mesh.positions.len());
        let (mut positions, mut welded_from) = (Vec::new(), Vec::new());
        let welded: Vec<u32> = mesh
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                // -0.0 and 0.0 are the same point.
                let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
                *remap.entry(key).or_insert_with(|| {
                    positions.push(*p);
                    welded_from.push(i as u32);
                    positions.len() as u32 - 1
                })
            })
            .collect();
        let triangles: Vec<[u32; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| [welded[t[0] as usize], welded[t[1] as usize], welded[t[2] as usize]])
            .collect();
        let (edges, report) = edges_of(positions.len(), &triangles);
        let convex = report.closed && triangles.len() <= CONVEX_TEST_TRIANGLES && convex(&positions, &triangles);
        Self { positions, welded_from, triangles, edges, report, convex }
    }
}

/// Whether every position lies on or behind the plane of every non-degenerate triangle, the
/// plane's side taken with a tolerance of 4 f32 epsilons of the mesh's extent (the rounding of
/// the f32 positions of coplanar faces: a box's, a sphere's lat-long quads).
fn convex(positions: &[Vec3], triangles: &[[u32; 3]]) -> bool {
    let p: Vec<glam::DVec3> = positions.iter().map(|v| v.as_dvec3()).collect();
    let extent = p.iter().fold(0.0f64, |m, v| m.max(v.abs().max_element())).max(1e-30);
    triangles.iter().filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]).all(|t| {
        let [a, b, c] = t.map(|i| p[i as usize]);
        let n = (b - a).cross(c - a);
        let len = n.length();
        len == 0.0 || p.iter().all(|v| n.dot(*v - a) / len <= 4.0 * f64::from(f32::EPSILON) * extent)
    })
}

impl TopologyReport {
    /// The topology of an indexed triangle list as authored: an edge is one unordered
    /// vertex-index pair, with no welding (how the repository's `assets/README.md` counts).
    pub fn of_indices(vertex_count: usize, indices: &[u32]) -> Self {
        let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        edges_of(vertex_count, &triangles).1
    }
}

/// Every undirected edge of the non-degenerate `triangles`, with its faces, and the summary.
fn edges_of(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<Edge>, TopologyReport) {
    let mut index: HashMap<[u32; 2], usize> = HashMap::with_capacity(triangles.len() * 3 / 2);
    let mut edges: Vec<Edge> = Vec::with_capacity(triangles.len() * 3 / 2);
    let mut degenerate = 0;
    for (f, t) in triangles.iter().enumerate() {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            degenerate += 1;
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            let i = *index.entry(key).or_insert_with(|| {
                edges.push(Edge { v: key, faces: Vec::with_capacity(2) });
                edges.len() - 1
            });
            edges[i].faces.push(EdgeFace { face: f as u32, forward: a == key[0] });
        }
    }
    let boundary_edges = edges.iter().filter(|e| e.faces.len() == 1).count();
    let non_manifold_edges = edges.iter().filter(|e| e.faces.len() > 2).count();
    let report = TopologyReport {
        triangles: triangles.len(),
        vertices: vertex_count,
        edges: edges.len(),
        boundary_edges,
        non_manifold_edges,
        degenerate_triangles: degenerate,
        closed: boundary_edges == 0 && non_manifold_edges == 0,
    };
    (edges, report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    #[test]
    fn boxes_spheres_and_cylinders_are_convex_and_a_dented_sphere_or_a_plane_is_not() {
        for m in [
            primitives::cuboid(Vec3::new(1.0, 0.002, 1.0)),
            primitives::sphere(1.0, 16, 8),
            primitives::cylinder(1.0, 2.0, 12),
        ] {
            assert!(Adjacency::build(&m).convex, "{}", m.name);
        }
        let dented = primitives::displaced_sphere(1.0, 16, 8, |u, _| if u < 0.1 { 0.8 } else { 1.0 });
        assert!(!Adjacency::build(&dented).convex);
        assert!(!Adjacency::build(&primitives::plane(1.0)).convex, "open meshes are never convex solids");
    }

    #[test]
    fn closed_primitives_are_closed_and_a_plane_is_not() {
        for m in [primitives::cuboid(Vec3::ONE), primitives::sphere(1.0, 16, 8), primitives::cylinder(1.0, 2.0, 12)] {
            let r = Adjacency::build(&m).report;
            assert!(r.closed, "{}: {r:?}", m.name);
            // Euler characteristic of a sphere: V - E + F = 2.
            assert_eq!(
                r.vertices as i64 - r.edges as i64 + (r.triangles - r.degenerate_triangles) as i64,
                2,
                "{}",
                m.name
            );
        }
        let r = Adjacency::build(&primitives::plane(1.0)).report;
        assert_eq!((r.boundary_edges, r.closed), (4, false));
    }

    #[test]
    fn each_welded_position_names_the_first_vertex_welded_into_it() {
        // A cuboid's faces have vertices of their own: 24 vertices weld into 8 corners.
        let m = primitives::cuboid(Vec3::ONE);
        let adj = Adjacency::build(&m);
        assert_eq!((m.positions.len(), adj.positions.len(), adj.welded_from.len()), (24, 8, 8));
        for (w, &v) in adj.welded_from.iter().enumerate() {
            assert_eq!(m.positions[v as usize], adj.positions[w]);
            let first = m.positions.iter().position(|p| *p == adj.positions[w]);
            assert_eq!(first, Some(v as usize), "welded position {w}");
        }
    }
}

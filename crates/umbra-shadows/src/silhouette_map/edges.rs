//! Pass 2's input, on the CPU: every caster's silhouette edges for one light, in world space
//! (§3.1: "the silhouette edges of the geometry must first be identified using any of the
//! techniques for shadow volumes"). The facing and silhouette code is the shadow-volume
//! module's (`umbra_scene::{facing, silhouette_edges}`): one source of truth for both.

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use std::sync::Arc;
use umbra_scene::{facing, silhouette_edges, Adjacency, Light, Scene};

/// One silhouette edge, world-space endpoints: one instance of the edge-quad draw.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct EdgeInstance {
    pub a: [f32; 3],
    pub b: [f32; 3],
}

/// A light's edges, as a range of the frame's edge instances.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LightEdges {
    pub first: u32,
    pub count: u32,
    pub cpu_ms: f64,
}

/// Appends the silhouette edges of `casters` for `light` to `out`. `adjacency[i]` is mesh
/// `i`'s welded connectivity. An edge a non-manifold caster repeats is drawn once: it would
/// store the same points again.
pub(crate) fn extract(
    scene: &Scene,
    adjacency: &[Arc<Adjacency>],
    casters: &[usize],
    light: &Light,
    out: &mut Vec<EdgeInstance>,
) -> LightEdges {
    let started = std::time::Instant::now();
    let per_caster: Vec<Vec<EdgeInstance>> = casters
        .par_iter()
        .filter_map(|&i| {
            let o = scene.objects.get(i)?;
            let adj = adjacency.get(o.mesh)?;
            // Facing is decided in the caster's object space, as for its shadow volume.
            let lit = facing(adj, o.transform.inverse() * light.position);
            let mut edges = silhouette_edges(adj, &lit);
            edges.dedup();
            let world = |v: u32| o.transform.transform_point3(adj.positions[v as usize]).to_array();
            Some(edges.iter().map(|&[a, b]| EdgeInstance { a: world(a), b: world(b) }).collect())
        })
        .collect();
    let first = out.len() as u32;
    for edges in per_caster {
        out.extend(edges);
    }
    LightEdges { first, count: out.len() as u32 - first, cpu_ms: started.elapsed().as_secs_f64() * 1e3 }
}

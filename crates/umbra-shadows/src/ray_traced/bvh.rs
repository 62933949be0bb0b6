//! One binary BVH, built with obvhs and flattened for a GPU walk: the bottom level over a
//! mesh's triangles ([`MeshBvh`]) and the top level over instance boxes (`scene.rs`).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use obvhs::aabb::Aabb as ObvhsAabb;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::bvh2::Bvh2;
use obvhs::BvhBuildParams;
use std::time::{Duration, Instant};
use umbra_scene::{Aabb, Mesh};

use super::wide::{wide_build, wide_depth, BvhLayout, WideNode};

/// One BVH node as a traversal shader reads it: two `vec4`s in `std430`.
///
/// An inner node (`count == 0`) has its two children at `first` and `first + 1`; a leaf holds
/// `count` primitives from `first` on (triangles in leaf order for a mesh, instances for the
/// top level).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct BvhNode {
    /// Box minimum corner.
    pub min: [f32; 3],
    /// First child (inner node) or first primitive (leaf).
    pub first: u32,
    /// Box maximum corner.
    pub max: [f32; 3],
    /// Primitives in the leaf; 0 for an inner node.
    pub count: u32,
}

impl BvhNode {
    /// Whether it is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// Its box.
    pub fn bounds(&self) -> Aabb {
        Aabb { min: Vec3::from(self.min), max: Vec3::from(self.max) }
    }
}

/// One triangle as a traversal shader reads it: three `vec4`s in `std430` (`w` is 0), in the
/// mesh's winding and space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct BvhTriangle {
    /// The vertices, each padded to a `vec4`.
    pub vertices: [[f32; 4]; 3],
}

impl BvhTriangle {
    fn new(v: [Vec3; 3]) -> Self {
        Self { vertices: v.map(|p| p.extend(0.0).to_array()) }
    }

    /// Vertex `k` (0 to 2).
    pub fn vertex(&self, k: usize) -> Vec3 {
        let [x, y, z, _] = self.vertices[k];
        Vec3::new(x, y, z)
    }
}

/// A mesh's bottom-level BVH, in the mesh's own space.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    /// Binary nodes, the root first (none for a mesh without triangles, or in the
    /// compressed wide layout).
    pub nodes: Vec<BvhNode>,
    /// Compressed wide nodes, the root first (in that layout only).
    pub wide: Vec<WideNode>,
    /// The box of every triangle, in the mesh's space; `None` without triangles.
    pub bounds: Option<Aabb>,
    /// The mesh's triangles in leaf order.
    pub triangles: Vec<BvhTriangle>,
    /// Longest root-to-leaf path, in nodes.
    pub depth: u32,
    /// Wall time of the build and the flattening, in milliseconds.
    pub build_ms: f64,
}

impl MeshBvh {
    /// Builds `mesh`'s BVH in `layout` (obvhs, rayon threads).
    pub fn build(mesh: &Mesh, layout: BvhLayout) -> Self {
        let started = Instant::now();
        let triangles: Vec<BvhTriangle> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| BvhTriangle::new([0, 1, 2].map(|k| mesh.positions[t[k] as usize])))
            .collect();
        let boxes: Vec<ObvhsAabb> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| to_obvhs(t.vertex(k)));
                ObvhsAabb::new(a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let bounds = boxes
            .iter()
            .copied()
            .reduce(|a, b| a.union(&b))
            .map(|b| Aabb { min: Vec3::new(b.min.x, b.min.y, b.min.z), max: Vec3::new(b.max.x, b.max.y, b.max.z) });
        let (nodes, wide, order, depth) = match layout {
            BvhLayout::Binary => {
                let (nodes, order, depth) = flatten_build(&boxes);
                (nodes, Vec::new(), order, depth)
            }
            BvhLayout::CompressedWide => {
                let (wide, order) = wide_build(&boxes);
                let depth = wide_depth(&wide);
                (Vec::new(), wide, order, depth)
            }
        };
        let triangles = order.iter().map(|&i| triangles[i as usize]).collect();
        Self { nodes, wide, bounds, triangles, depth, build_ms: started.elapsed().as_secs_f64() * 1e3 }
    }

    /// Its nodes in its layout (binary or compressed wide).
    pub fn node_count(&self) -> usize {
        self.nodes.len() + self.wide.len()
    }

    /// Bytes of its nodes and triangles on the GPU.
    pub fn bytes(&self) -> u64 {
        (std::mem::size_of_val(&self.nodes[..])
            + std::mem::size_of_val(&self.wide[..])
            + std::mem::size_of_val(&self.triangles[..])) as u64
    }
}

/// A BVH over `boxes`, flattened: its nodes, the box index of each leaf slot (leaves' `first`
/// index into this order) and its depth. Empty without boxes.
pub(super) fn flatten_build(boxes: &[ObvhsAabb]) -> (Vec<BvhNode>, Vec<u32>, u32) {
    if boxes.is_empty() {
        return (Vec::new(), Vec::new(), 0);
    }
    let bvh = build_bvh2(boxes, BvhBuildParams::medium_build(), &mut Duration::default());
    let nodes: Vec<BvhNode> = bvh
        .nodes
        .iter()
        .map(|n| {
            let b = n.aabb();
            BvhNode { min: b.min.to_array(), first: n.first_index, max: b.max.to_array(), count: n.prim_count }
        })
        .collect();
    let depth = depth(&bvh);
    (nodes, bvh.primitive_indices, depth)
}

/// The longest root-to-leaf path of `bvh`, in nodes.
fn depth(bvh: &Bvh2) -> u32 {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1u32)];
    while let Some((i, d)) = stack.pop() {
        let n = &bvh.nodes[i];
        deepest = deepest.max(d);
        if !n.is_leaf() {
            let first = n.first_index as usize;
            stack.extend([(first, d + 1), (first + 1, d + 1)]);
        }
    }
    deepest
}

/// `b` transformed by `m` (the box of its eight transformed corners).
pub(super) fn transformed(b: Aabb, m: &Mat4) -> ObvhsAabb {
    let t = b.transformed(m);
    ObvhsAabb::new(to_obvhs(t.min), to_obvhs(t.max))
}

fn to_obvhs(v: Vec3) -> obvhs_glam::Vec3A {
    obvhs_glam::Vec3A::new(v.x, v.y, v.z)
}

//! The top level: one instance per shadow-casting object over its mesh's BVH, under a BVH of
//! their world boxes. A moving object rebuilds this level only; a mesh whose revision changed
//! rebuilds its own BVH.

use super::bvh::{flatten_build, transformed, BvhNode, MeshBvh};
use super::wide::{BvhLayout, WideNode};
use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use std::sync::Arc;
use std::time::Instant;
use umbra_scene::Scene;

/// One instance as a traversal shader reads it (`std430`): the world-to-object transform's
/// first three rows and where its mesh's nodes and triangles start in the scene's arrays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct BvhInstance {
    /// Rows 0 to 2 of the world-to-object matrix (row 3 is `0 0 0 1`).
    pub world_to_object: [[f32; 4]; 3],
    /// Index of its mesh's root in the scene's bottom-level nodes.
    pub node_offset: u32,
    /// Index of its mesh's first triangle in the scene's triangles.
    pub triangle_offset: u32,
    /// Index of the object in `scene.objects`.
    pub object: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}

/// What building and updating a [`RayScene`] cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RaySceneStats {
    /// Bottom-level (mesh) BVHs built so far.
    pub mesh_builds: u64,
    /// Top-level BVHs built so far.
    pub top_builds: u64,
    /// Wall time of the last update's mesh builds, in milliseconds.
    pub mesh_build_ms: f64,
    /// Wall time of the last update's top-level build, in milliseconds.
    pub top_build_ms: f64,
}

/// Per mesh, its BVH and the revision it was built from.
struct CachedMesh {
    revision: u64,
    triangles: usize,
    bvh: Arc<MeshBvh>,
}

/// The scene's casters as a two-level BVH ([module documentation](super)).
#[derive(Default)]
pub struct RayScene {
    /// How the meshes' BVHs are laid out.
    pub layout: BvhLayout,
    meshes: Vec<Option<CachedMesh>>,
    /// Top-level nodes over `instances` (leaves index `instances`).
    pub top: Vec<BvhNode>,
    /// The shadow-casting objects with a triangle, in top-level leaf order.
    pub instances: Vec<BvhInstance>,
    /// Every mesh's bottom-level nodes, one after the other (children index within their
    /// mesh), in the binary layout.
    pub nodes: Vec<BvhNode>,
    /// The same in the compressed wide layout.
    pub wide: Vec<WideNode>,
    /// Every mesh's triangles, one after the other, in leaf order.
    pub triangles: Vec<super::BvhTriangle>,
    /// The top level's depth plus the deepest instanced mesh's, in nodes.
    pub depth: u32,
    /// The top level's depth, in nodes.
    pub top_depth: u32,
    /// The deepest instanced mesh's depth, in nodes.
    pub mesh_depth: u32,
    /// What its builds cost.
    pub stats: RaySceneStats,
    /// Changes whenever its arrays change (what was uploaded of it is stale).
    pub revision: u64,
    /// Changes whenever its meshes' arrays (`nodes`, `triangles`) change.
    pub mesh_revision: u64,
    /// The instances the top level was last built over, in object order.
    built_over: Vec<BvhInstance>,
}

impl RayScene {
    /// The scene's casters, every BVH built, the meshes' binary.
    pub fn build(scene: &Scene) -> Self {
        Self::build_with(scene, BvhLayout::Binary)
    }

    /// The scene's casters, every BVH built, the meshes' in `layout`.
    pub fn build_with(scene: &Scene, layout: BvhLayout) -> Self {
        let mut rays = Self::empty(layout);
        rays.update(scene);
        rays
    }

    /// No caster yet; the meshes' BVHs will be laid out in `layout`.
    pub fn empty(layout: BvhLayout) -> Self {
        Self { layout, ..Self::default() }
    }

    /// Brings it up to `scene`: a mesh whose revision or triangle count changed gets a new
    /// BVH; the top level is rebuilt when a caster moved, came or went (or a mesh changed).
    pub fn update(&mut self, scene: &Scene) {
        let started = Instant::now();
        self.meshes.resize_with(scene.meshes.len(), || None);
        self.meshes.truncate(scene.meshes.len());
        let mut rebuilt = false;
        for (slot, mesh) in self.meshes.iter_mut().zip(&scene.meshes) {
            let triangles = mesh.indices.len() / 3;
            if slot.as_ref().is_some_and(|c| c.revision == mesh.revision() && c.triangles == triangles) {
                continue;
            }
            let bvh = Arc::new(MeshBvh::build(mesh, self.layout));
            *slot = Some(CachedMesh { revision: mesh.revision(), triangles, bvh });
            self.stats.mesh_builds += 1;
            rebuilt = true;
        }
        if rebuilt {
            self.stats.mesh_build_ms = started.elapsed().as_secs_f64() * 1e3;
            self.concatenate();
            self.mesh_revision += 1;
        } else {
            self.stats.mesh_build_ms = 0.0;
        }
        self.build_top(scene, rebuilt);
    }

    /// Every mesh's nodes and triangles into the scene's arrays.
    fn concatenate(&mut self) {
        self.nodes.clear();
        self.wide.clear();
        self.triangles.clear();
        for m in self.meshes.iter().flatten() {
            self.nodes.extend_from_slice(&m.bvh.nodes);
            self.wide.extend_from_slice(&m.bvh.wide);
            self.triangles.extend_from_slice(&m.bvh.triangles);
        }
    }

    /// The top level over every shadow-casting object whose mesh has a triangle, unless they
    /// are the ones it was built over and no mesh changed.
    fn build_top(&mut self, scene: &Scene, meshes_changed: bool) {
        let started = Instant::now();
        let mut offsets = Vec::with_capacity(self.meshes.len());
        let (mut nodes, mut triangles) = (0u32, 0u32);
        for m in &self.meshes {
            offsets.push((nodes, triangles));
            if let Some(m) = m {
                nodes += m.bvh.node_count() as u32;
                triangles += m.bvh.triangles.len() as u32;
            }
        }
        let mut candidates = Vec::new();
        let mut boxes = Vec::new();
        let mut depth = 0;
        for (i, o) in scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadows) {
            let Some(Some(m)) = self.meshes.get(o.mesh) else { continue };
            let Some(bounds) = m.bvh.bounds else { continue };
            let w = o.transform.inverse();
            let (node_offset, triangle_offset) = offsets[o.mesh];
            let rows = [w.row(0), w.row(1), w.row(2)].map(|r| r.to_array());
            candidates.push(BvhInstance {
                world_to_object: rows,
                node_offset,
                triangle_offset,
                object: i as u32,
                pad: 0,
            });
            boxes.push(transformed(bounds, &o.transform));
            depth = depth.max(m.bvh.depth);
        }
        if !meshes_changed && candidates == self.built_over && self.stats.top_builds > 0 {
            self.stats.top_build_ms = 0.0;
            return;
        }
        let (top, order, top_depth) = flatten_build(&boxes);
        self.instances = order.iter().map(|&i| candidates[i as usize]).collect();
        self.built_over = candidates;
        self.top = top;
        self.depth = depth + top_depth;
        (self.top_depth, self.mesh_depth) = (top_depth, depth);
        self.stats.top_builds += 1;
        self.stats.top_build_ms = started.elapsed().as_secs_f64() * 1e3;
        self.revision += 1;
    }

    /// Bytes of its nodes, instances and triangles on the GPU.
    pub fn bytes(&self) -> u64 {
        let size = |n: usize| n as u64;
        size(std::mem::size_of_val(&self.top[..]))
            + size(std::mem::size_of_val(&self.instances[..]))
            + size(std::mem::size_of_val(&self.nodes[..]))
            + size(std::mem::size_of_val(&self.wide[..]))
            + size(std::mem::size_of_val(&self.triangles[..]))
    }

    /// The meshes' nodes as the walk reads them: `uvec4`s, two a binary node, five a wide one.
    pub fn mesh_node_words(&self) -> &[u32] {
        match self.layout {
            BvhLayout::Binary => bytemuck::cast_slice(&self.nodes),
            BvhLayout::CompressedWide => bytemuck::cast_slice(&self.wide),
        }
    }

    /// The most entries the walk's stack can hold at once: one per level for the binary top
    /// level and, for the meshes, one per level (binary: both children pushed) or seven per
    /// level plus one (wide: a node's up to eight children replace it).
    pub fn stack_need(&self) -> u32 {
        match self.layout {
            BvhLayout::Binary => self.depth,
            BvhLayout::CompressedWide => self.top_depth.max(7 * self.mesh_depth + 1),
        }
    }

    /// The world-to-object matrix of `instance`.
    pub(super) fn world_to_object(instance: &BvhInstance) -> Mat4 {
        let [r0, r1, r2] = instance.world_to_object;
        // The rows as columns, transposed.
        Mat4::from_cols_array_2d(&[r0, r1, r2, [0.0, 0.0, 0.0, 1.0]]).transpose()
    }
}

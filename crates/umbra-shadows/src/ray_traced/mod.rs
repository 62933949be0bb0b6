//! Ray-traced shadows' acceleration structure: the scene's casters in a two-level BVH laid out
//! for a GPU walk (issue 25's first step; the compute traversal and the `ray_traced` and
//! `hybrid_rt` techniques build on it).
//!
//! - [`MeshBvh`] (bottom level, one per mesh): a binary BVH built on the host with obvhs
//!   (PLOC, reinsertion, leaves of up to 8 triangles), flattened into [`BvhNode`]s and the
//!   mesh's triangles in leaf order ([`BvhTriangle`]), in the mesh's own space; or, with
//!   [`BvhLayout::CompressedWide`], obvhs' compressed wide BVH (eight children a node, their
//!   boxes quantized to 8 bits, [`WideNode`]). Built once per mesh revision.
//! - [`RayScene`] (top level): one [`BvhInstance`] per shadow-casting object (its mesh's BVH,
//!   its world-to-object transform) under a binary BVH of their world boxes. Moving an object
//!   rebuilds only this level ([`RayScene::update`] counts both kinds of build).
//! - [`RayScene::occluded`]: the walk a traversal shader does over exactly these arrays — a
//!   stack per ray, a conservative slab test per node, the watertight triangle test of Woop,
//!   Benthin and Wald (2013) in `f32` (SwiftShader has no `shaderFloat64`), any hit ending the
//!   walk — with the nodes and triangles it visited, so the layout and its costs are tested and
//!   measured on the host.

mod bvh;
pub(crate) mod frame;
pub(crate) mod pass;
mod scene;
pub(crate) mod stats;
mod walk;
mod wide;

#[cfg(test)]
mod tests;

pub use bvh::{BvhNode, BvhTriangle, MeshBvh};
pub use scene::{BvhInstance, RayScene, RaySceneStats};
pub use stats::TraversalReport;
pub use walk::{WalkStats, MAX_STACK};
pub use wide::{BvhLayout, WideNode};

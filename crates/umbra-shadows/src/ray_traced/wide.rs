//! The compressed wide layout of a mesh's BVH (CWBVH, Ylitie, Karras and Laine 2017, as obvhs
//! builds it) beside the binary one ([`BvhLayout`]): its node as the walk reads it
//! ([`WideNode`]), its build and its depth. The walks are its `WalkNode` (walk.rs) on the host and
//! `occluded_in_wide` (`shaders-glsl/ray/bvh.glsl`) on the GPU.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use obvhs::aabb::Aabb as ObvhsAabb;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::BvhBuildParams;
use serde::Serialize;
use std::time::Duration;

/// How each mesh's BVH is laid out for the walk ([`crate::RendererDesc::bvh`]; the top level
/// over instances is always binary).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BvhLayout {
    /// Two children per inner node with full `f32` boxes ([`super::BvhNode`], 32 bytes a node).
    #[default]
    Binary,
    /// Compressed wide (CWBVH, Ylitie, Karras and Laine 2017, as obvhs builds it): up to eight
    /// children per node, their boxes quantized to 8 bits on the node's grid, up to three
    /// triangles per leaf ([`WideNode`], 80 bytes a node).
    CompressedWide,
}

impl BvhLayout {
    /// The specialization constant that picks the walk in `shaders-glsl/ray/bvh.glsl`
    /// (`WIDE_BVH`, `constant_id` 9), for every pipeline that walks the BVH.
    pub(crate) fn specialization(self) -> [(u32, u32); 1] {
        [(9, u32::from(self == BvhLayout::CompressedWide))]
    }

    /// Its name in reports and on the command line: `binary` or `cwbvh`.
    pub fn name(self) -> &'static str {
        match self {
            BvhLayout::Binary => "binary",
            BvhLayout::CompressedWide => "cwbvh",
        }
    }
}

impl std::str::FromStr for BvhLayout {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [BvhLayout::Binary, BvhLayout::CompressedWide]
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown BVH layout {s:?} (binary or cwbvh)"))
    }
}

/// One compressed wide node, obvhs' `CwBvhNode` as 20 words (five `uvec4`s in `std430`): the
/// grid origin `p` (words 0–2); the grid's power-of-two exponents and the inner-child mask
/// (word 3: bytes 0–2, byte 3); the first inner child and the first triangle (words 4, 5); a
/// meta byte per child slot (words 6, 7: 0 for an empty slot; `0b001` over `24 + slot` for an
/// inner child; a unary triangle count over the first triangle's offset for a leaf); then per
/// axis the eight children's quantized minima and maxima (words 8–19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct WideNode {
    /// The node's 80 bytes.
    pub words: [u32; 20],
}

impl WideNode {
    fn byte(&self, word: usize, k: usize) -> u32 {
        (self.words[word + k / 4] >> (8 * (k % 4))) & 0xff
    }

    /// Child slot `slot`'s meta byte (0: empty).
    pub fn meta(&self, slot: usize) -> u32 {
        self.byte(6, slot)
    }

    /// Whether child `slot` is an inner node.
    pub fn is_inner(&self, slot: usize) -> bool {
        (self.words[3] >> (24 + slot)) & 1 == 1
    }

    /// Index of inner child `slot` (relative to the mesh's first node): the inner children
    /// are stored in slot order from the first one.
    pub fn child(&self, slot: usize) -> u32 {
        let below = (self.words[3] >> 24) & ((1 << slot) - 1);
        self.words[4] + below.count_ones()
    }

    /// Leaf child `slot`'s first triangle (relative to the mesh's first) and count (1 to 3).
    pub fn triangles(&self, slot: usize) -> (u32, u32) {
        let meta = self.meta(slot);
        (self.words[5] + (meta & 31), (meta >> 5).count_ones())
    }

    /// Child `slot`'s box, one grid step wider on every side than its quantized one: the
    /// quantization rounds outward in exact arithmetic, and a step is far more than the
    /// rounding of the `f32` arithmetic that builds and decodes it, so the box never excludes
    /// a point of its child's.
    pub fn child_box(&self, slot: usize) -> (Vec3, Vec3) {
        let p = Vec3::new(f32::from_bits(self.words[0]), f32::from_bits(self.words[1]), f32::from_bits(self.words[2]));
        let e = self.words[3];
        let step = Vec3::new(
            f32::from_bits((e & 0xff) << 23),
            f32::from_bits(((e >> 8) & 0xff) << 23),
            f32::from_bits(((e >> 16) & 0xff) << 23),
        );
        let q = |word: usize| {
            Vec3::new(self.byte(word, slot) as f32, self.byte(word + 4, slot) as f32, self.byte(word + 8, slot) as f32)
        };
        (p + step * (q(8) - 1.0), p + step * (q(10) + 1.0))
    }
}

/// A compressed wide BVH over `boxes` (at most three per leaf): its nodes and the box index
/// of each leaf slot. Empty without boxes.
pub(super) fn wide_build(boxes: &[ObvhsAabb]) -> (Vec<WideNode>, Vec<u32>) {
    if boxes.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let params = BvhBuildParams { max_prims_per_leaf: 3, ..BvhBuildParams::medium_build() };
    let bvh = build_cwbvh(boxes, params, &mut Duration::default());
    let nodes = bvh.nodes.iter().map(|n| WideNode { words: bytemuck::cast(*n) }).collect();
    (nodes, bvh.primitive_indices)
}

/// The longest root-to-leaf path of a compressed wide BVH, in nodes.
pub(super) fn wide_depth(nodes: &[WideNode]) -> u32 {
    let mut deepest = 0;
    let mut stack = if nodes.is_empty() { vec![] } else { vec![(0u32, 1u32)] };
    while let Some((i, d)) = stack.pop() {
        deepest = deepest.max(d);
        let n = &nodes[i as usize];
        stack.extend((0..8).filter(|&s| n.meta(s) != 0 && n.is_inner(s)).map(|s| (n.child(s), d + 1)));
    }
    deepest
}

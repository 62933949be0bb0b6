//! A shadow ray's walk over a [`RayScene`]'s arrays, as a traversal shader does it: the top
//! level in world space, each instance's mesh in the mesh's space (the ray carried there by
//! its world-to-object matrix, `t` unchanged), any hit ending the walk.

use super::bvh::BvhNode;
use super::scene::{BvhInstance, RayScene};
use super::wide::{BvhLayout, WideNode};
use super::BvhTriangle;
use glam::Vec3;

/// The deepest BVH a traversal shader's stack walks (a push of both children per inner node
/// needs at most one entry per level).
pub const MAX_STACK: u32 = 64;

/// What one ray's walk visited.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkStats {
    /// Nodes whose box was tested (top and bottom level).
    pub nodes: u32,
    /// Triangles tested.
    pub triangles: u32,
    /// The most stack entries held at once.
    pub stack: u32,
}

impl RayScene {
    /// Whether a triangle of a shadow-casting object lies on `origin + t * dir` with `t` in
    /// `(0, t_max]`, and what the walk visited.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> (bool, WalkStats) {
        let mut stats = WalkStats::default();
        let slab = Slab::new(origin, dir);
        let hit = walk(&self.top, &slab, t_max, &mut stats, |s, first, count| {
            let instances = &self.instances[first as usize..(first + count) as usize];
            instances.iter().any(|i| self.occluded_in(i, origin, dir, t_max, s))
        });
        (hit, stats)
    }

    /// The ray against one instance's mesh, in the mesh's space.
    fn occluded_in(&self, instance: &BvhInstance, origin: Vec3, dir: Vec3, t_max: f32, stats: &mut WalkStats) -> bool {
        let m = RayScene::world_to_object(instance);
        let (o, d) = (m.transform_point3(origin), m.transform_vector3(dir));
        let (slab, ray) = (Slab::new(o, d), Watertight::new(o, d));
        let base = instance.node_offset as usize;
        let leaf = |s: &mut WalkStats, first: u32, count: u32| {
            let start = (instance.triangle_offset + first) as usize;
            self.triangles[start..start + count as usize].iter().any(|t| {
                s.triangles += 1;
                ray.hits(t, t_max)
            })
        };
        match self.layout {
            BvhLayout::Binary => walk(&self.nodes[base..], &slab, t_max, stats, leaf),
            BvhLayout::CompressedWide => walk(&self.wide[base..], &slab, t_max, stats, leaf),
        }
    }
}

/// What a node's test against the ray found, in the order the walk takes it.
enum Hit {
    /// An inner node to walk (index from the mesh's first node).
    Inner(u32),
    /// A leaf's primitives: first and count.
    Leaf(u32, u32),
}

/// A node of either layout, as the walk tests it.
trait WalkNode {
    /// Appends what of this node the ray may meet: a binary node's two children if its box is
    /// hit; a wide node's children whose boxes are hit, in slot order.
    fn hits(&self, slab: &Slab, t_max: f32, out: &mut Vec<Hit>);
}

impl WalkNode for BvhNode {
    fn hits(&self, slab: &Slab, t_max: f32, out: &mut Vec<Hit>) {
        if !slab.hits_box(Vec3::from(self.min), Vec3::from(self.max), t_max) {
            return;
        }
        match self.is_leaf() {
            true => out.push(Hit::Leaf(self.first, self.count)),
            false => out.extend([Hit::Inner(self.first), Hit::Inner(self.first + 1)]),
        }
    }
}

/// A wide node is one fetch of 80 bytes and up to eight box tests.
impl WalkNode for WideNode {
    fn hits(&self, slab: &Slab, t_max: f32, out: &mut Vec<Hit>) {
        for slot in (0..8).filter(|&s| self.meta(s) != 0) {
            let (lo, hi) = self.child_box(slot);
            if !slab.hits_box(lo, hi, t_max) {
                continue;
            }
            out.push(match self.is_inner(slot) {
                true => Hit::Inner(self.child(slot)),
                false => {
                    let (first, count) = self.triangles(slot);
                    Hit::Leaf(first, count)
                }
            });
        }
    }
}

/// A stack walk of the BVH whose root is `nodes[0]` (children index from `nodes`' start),
/// counting the nodes popped; `leaf(stats, first, count)` says whether a leaf's primitives
/// block the ray.
fn walk<N: WalkNode>(
    nodes: &[N],
    slab: &Slab,
    t_max: f32,
    stats: &mut WalkStats,
    mut leaf: impl FnMut(&mut WalkStats, u32, u32) -> bool,
) -> bool {
    if nodes.is_empty() {
        return false;
    }
    let (mut stack, mut hits) = (vec![0u32], Vec::with_capacity(8));
    while let Some(i) = stack.pop() {
        stats.nodes += 1;
        hits.clear();
        nodes[i as usize].hits(slab, t_max, &mut hits);
        for hit in &hits {
            match *hit {
                Hit::Inner(child) => {
                    stack.push(child);
                    stats.stack = stats.stack.max(stack.len() as u32);
                }
                Hit::Leaf(first, count) => {
                    if leaf(stats, first, count) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// A conservative ray-box test: the slab distances with the far one widened by `1 + 2γ₃`
/// (Ize 2013, as PBRT does), so rounding never drops a box the ray touches; a direction
/// component of 0 is replaced by a tiny one of the same sign, so no `0 × ∞` makes a NaN.
struct Slab {
    origin: Vec3,
    inverse: Vec3,
}

/// `1 + 2γ₃`, `γₙ = nε / (1 - nε)` with `ε = 2⁻²⁴`.
const WIDEN: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl Slab {
    fn new(origin: Vec3, dir: Vec3) -> Self {
        let safe = |d: f32| if d.abs() < 1e-20 { 1e-20f32.copysign(d) } else { d };
        Self { origin, inverse: Vec3::new(safe(dir.x), safe(dir.y), safe(dir.z)).recip() }
    }

    fn hits_box(&self, min: Vec3, max: Vec3, t_max: f32) -> bool {
        let t0 = (min - self.origin) * self.inverse;
        let t1 = (max - self.origin) * self.inverse;
        let near = t0.min(t1).max_element().max(0.0);
        let far = (t0.max(t1).min_element() * WIDEN).min(t_max);
        near <= far
    }
}

/// The watertight ray-triangle test (Woop, Benthin, Wald 2013) in `f32`: the dominant axis of
/// the direction becomes z and a shear maps the direction onto +z, so each edge is a 2D signed
/// area at the origin. An edge shared by two triangles gets the same area, negated, from both
/// (the same products in the same order), so no ray passes between them; a ray exactly on the
/// edge hits both.
struct Watertight {
    origin: Vec3,
    axes: [usize; 3],
    shear: Vec3,
}

impl Watertight {
    fn new(origin: Vec3, dir: Vec3) -> Self {
        let a = dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Keep the winding: x and y swap when the dominant component is negative.
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = Vec3::new(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
        Self { origin, axes: [kx, ky, kz], shear }
    }

    fn hits(&self, triangle: &BvhTriangle, t_max: f32) -> bool {
        let [kx, ky, kz] = self.axes;
        let s = self.shear;
        let sheared = |k: usize| {
            let p = triangle.vertex(k) - self.origin;
            Vec3::new(p[kx] - s.x * p[kz], p[ky] - s.y * p[kz], s.z * p[kz])
        };
        let (a, b, c) = (sheared(0), sheared(1), sheared(2));
        let u = c.x * b.y - c.y * b.x;
        let v = a.x * c.y - a.y * c.x;
        let w = b.x * a.y - b.y * a.x;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return false;
        }
        let det = u + v + w;
        if det == 0.0 {
            return false;
        }
        let t = (u * a.z + v * b.z + w * c.z) / det;
        t > 0.0 && t <= t_max
    }
}

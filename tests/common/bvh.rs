//! A small triangle BVH for the tests' exact shadow reference: nearest hit of a camera ray,
//! and whether a segment towards the light is blocked. Median split on the longest axis.
#![allow(dead_code)]

use glam::{Vec3, Vec4};
use umbra::scene::Scene;

/// A world-space triangle and the object it belongs to.
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    pub v: [Vec3; 3],
    pub object: usize,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// Leaf: first triangle and count; inner: left child index and 0.
    first: u32,
    count: u32,
}

/// The scene's triangles in a bounding-volume hierarchy.
pub struct Bvh {
    tris: Vec<Tri>,
    nodes: Vec<Node>,
}

/// A ray hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub tri: usize,
}

impl Bvh {
    /// Every triangle of every object (or only casters, with `casters_only`).
    pub fn of_scene(scene: &Scene, casters_only: bool) -> Self {
        let mut tris = Vec::new();
        for (i, o) in scene.objects.iter().enumerate() {
            if casters_only && !o.casts_shadows {
                continue;
            }
            let m = &scene.meshes[o.mesh];
            for t in m.indices.chunks_exact(3) {
                let v = [0, 1, 2].map(|k| o.transform.transform_point3(m.positions[t[k] as usize]));
                tris.push(Tri { v, object: i });
            }
        }
        let mut bvh = Bvh { tris, nodes: Vec::new() };
        let n = bvh.tris.len() as u32;
        bvh.nodes.push(Node { min: Vec3::ZERO, max: Vec3::ZERO, first: 0, count: n });
        bvh.split(0);
        bvh
    }

    pub fn tri(&self, i: usize) -> &Tri {
        &self.tris[i]
    }

    fn split(&mut self, node: usize) {
        let Node { first, count, .. } = self.nodes[node];
        let range = first as usize..(first + count) as usize;
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for t in &self.tris[range.clone()] {
            for v in t.v {
                min = min.min(v);
                max = max.max(v);
            }
        }
        self.nodes[node].min = min;
        self.nodes[node].max = max;
        if count <= 4 {
            return;
        }
        let ext = max - min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let centroid = |t: &Tri| (t.v[0] + t.v[1] + t.v[2])[axis];
        self.tris[range].sort_by(|a, b| centroid(a).total_cmp(&centroid(b)));
        let half = count / 2;
        let left = self.nodes.len();
        self.nodes.push(Node { min, max, first, count: half });
        self.nodes.push(Node { min, max, first: first + half, count: count - half });
        self.nodes[node].first = left as u32;
        self.nodes[node].count = 0;
        self.split(left);
        self.split(left + 1);
    }

    /// Nearest hit with `t` in `(t_min, t_max)`, skipping triangle `skip`.
    pub fn cast(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32, skip: Option<usize>) -> Option<Hit> {
        let inv = d.recip();
        let mut best: Option<Hit> = None;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            let limit = best.map_or(t_max, |h| h.t);
            let (a, b) = ((node.min - o) * inv, (node.max - o) * inv);
            let (t0, t1) = (a.min(b).max_element().max(t_min), a.max(b).min_element().min(limit));
            if t0 > t1 {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first as usize);
                stack.push(node.first as usize + 1);
                continue;
            }
            for i in node.first as usize..(node.first + node.count) as usize {
                if Some(i) == skip {
                    continue;
                }
                if let Some(t) = intersect(&self.tris[i], o, d) {
                    if t > t_min && t < best.map_or(t_max, |h| h.t) {
                        best = Some(Hit { t, tri: i });
                    }
                }
            }
        }
        best
    }

    /// Whether anything blocks the way from `p` to a homogeneous light (w = 0: direction).
    pub fn shadowed(&self, p: Vec3, light: Vec4, skip: Option<usize>) -> bool {
        let (d, t_max) = if light.w == 0.0 {
            (light.truncate().normalize(), f32::INFINITY)
        } else {
            let to = light.truncate() / light.w - p;
            (to.normalize(), to.length())
        };
        self.cast(p, d, 1e-4, t_max - 1e-4, skip).is_some()
    }
}

/// Möller–Trumbore, two-sided.
fn intersect(t: &Tri, o: Vec3, d: Vec3) -> Option<f32> {
    let (e1, e2) = (t.v[1] - t.v[0], t.v[2] - t.v[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - t.v[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
}

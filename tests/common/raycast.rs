//! Exact geometry for shadow tests: pixel rays, ray/box and ray/plane hits, segment/box
//! occlusion. Small and analytic on purpose: each test knows its scene's boxes and planes.
#![allow(dead_code)]

use glam::Vec3;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub struct Box3 {
    pub min: Vec3,
    pub max: Vec3,
}

impl Box3 {
    pub fn around(center: Vec3, half: Vec3) -> Self {
        Self { min: center - half, max: center + half }
    }

    /// Entry and exit parameters of `origin + t * dir` (slab test), if it meets the box.
    pub fn hit(&self, origin: Vec3, dir: Vec3) -> Option<(f32, f32)> {
        let inv = dir.recip();
        let (a, b) = ((self.min - origin) * inv, (self.max - origin) * inv);
        let (lo, hi) = (a.min(b), a.max(b));
        let (t0, t1) = (lo.max_element(), hi.min_element());
        (t0 <= t1 && t1 >= 0.0).then_some((t0, t1))
    }

    /// Whether the open segment from `a` to `b` passes through the box.
    pub fn blocks(&self, a: Vec3, b: Vec3) -> bool {
        self.hit(a, b - a).is_some_and(|(t0, t1)| t0 < 1.0 - 1e-4 && t1 > 1e-4)
    }
}

/// The ray through a pixel centre: the exact reference's own.
#[allow(unused_imports)]
pub use umbra_reference::pixel_ray;

/// Where a ray meets the plane `y = height`, if ahead of it.
pub fn hit_plane_y(origin: Vec3, dir: Vec3, height: f32) -> Option<Vec3> {
    let t = (height - origin.y) / dir.y;
    (t > 0.0).then(|| origin + dir * t)
}

/// Whether a 2D point (x, z) is inside a convex polygon given counter-clockwise or clockwise.
pub fn inside_convex(poly: &[glam::Vec2], p: glam::Vec2) -> bool {
    let sign = |i: usize| {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        (b - a).perp_dot(p - a)
    };
    let s: Vec<f32> = (0..poly.len()).map(sign).collect();
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

/// Distance from a 2D point to the boundary of a polygon.
pub fn distance_to_boundary(poly: &[glam::Vec2], p: glam::Vec2) -> f32 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + (b - a) * t).distance(p)
        })
        .fold(f32::INFINITY, f32::min)
}

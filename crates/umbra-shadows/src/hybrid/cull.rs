//! Blocker culling (Chan–Durand §6.3): after the shadow map, each caster's world bounding box is
//! drawn from the light against the map's depth under an occlusion query; a caster none of whose
//! box texels passes lies wholly behind other casters, so its volume sits inside theirs and
//! drawing it cannot change which pixels have a non-zero count. It is culled per caster, never
//! per edge, so the counts stay consistent.

use glam::{Vec3, Vec4};
use umbra_scene::{Aabb, Light};

/// Vertices of one box: 12 triangles, w = 1.
pub(crate) const BOX_VERTICES: u32 = 36;

/// The 36 vertices (12 triangles, any winding: drawn without culling) of `b`'s faces.
pub(crate) fn box_triangles(b: &Aabb, out: &mut Vec<Vec4>) {
    let corner = |i: usize| {
        let pick = |bit: usize, lo: f32, hi: f32| if i & bit != 0 { hi } else { lo };
        Vec4::new(pick(1, b.min.x, b.max.x), pick(2, b.min.y, b.max.y), pick(4, b.min.z, b.max.z), 1.0)
    };
    // Each face as a quad of corner indices (bit 0 = x, bit 1 = y, bit 2 = z).
    const FACES: [[usize; 4]; 6] = [[0, 2, 6, 4], [1, 3, 7, 5], [0, 1, 5, 4], [2, 3, 7, 6], [0, 1, 3, 2], [4, 5, 7, 6]];
    for [a, b_, c, d] in FACES {
        out.extend([a, b_, c, a, c, d].map(corner));
    }
}

/// Whether a caster with world bounds `b` may be culled by a query against `light`'s 2D map:
/// not when the light lies inside (or on) the box, where its faces would wrap around the
/// light and could miss the map's depth range.
pub(crate) fn queryable(light: &Light, b: &Aabb) -> bool {
    if light.position.w == 0.0 {
        return true;
    }
    let p: Vec3 = light.position.truncate() / light.position.w;
    !(p.cmpge(b.min).all() && p.cmple(b.max).all())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_triangles_cover_every_face() {
        let b = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let mut v = Vec::new();
        box_triangles(&b, &mut v);
        assert_eq!(v.len() as u32, BOX_VERTICES);
        // Every face plane (x, y, z at 0 and 1) holds exactly 2 triangles.
        for axis in 0..3 {
            for side in [0.0, 1.0] {
                let n = v.chunks_exact(3).filter(|t| t.iter().all(|p| p[axis] == side)).count();
                assert_eq!(n, 2, "axis {axis} side {side}");
            }
        }
    }

    #[test]
    fn lights_inside_a_box_keep_its_volume() {
        let b = Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(1.0) };
        assert!(!queryable(&Light::point(Vec3::ZERO, 1.0), &b));
        assert!(queryable(&Light::point(Vec3::new(0.0, 3.0, 0.0), 1.0), &b));
        assert!(queryable(&Light::directional(Vec3::Y, 1.0), &b));
    }
}

/// Blocker culling's queries in one frame: a box per (hybrid light, caster index), in the order
/// they are drawn and queried.
#[derive(Default)]
pub(crate) struct CullingPlan {
    pub boxes: Vec<(usize, usize)>,
    pub vertices: Vec<glam::Vec4>,
    /// Casters dropped per light, once the answers are in.
    culled: Vec<(usize, usize)>,
}

impl CullingPlan {
    /// The queries its boxes take (one per box; none without blocker culling).
    pub fn queries(&self) -> u32 {
        self.boxes.len() as u32
    }

    /// Takes in the queries' answers (`visible[i]`: samples of box `i`); returns the queried
    /// casters with no visible sample, as (light, caster index), highest index first so that
    /// removing them in order keeps the earlier indices valid.
    pub fn apply(&mut self, visible: &[u64]) -> Vec<(usize, usize)> {
        let mut dropped: Vec<(usize, usize)> =
            self.boxes.iter().zip(visible).filter(|(_, &n)| n == 0).map(|(&b, _)| b).collect();
        dropped.sort_by(|a, b| b.cmp(a));
        for &(light, _) in &self.boxes {
            if !self.culled.iter().any(|&(l, _)| l == light) {
                let n = dropped.iter().filter(|&&(l, _)| l == light).count();
                self.culled.push((light, n));
            }
        }
        dropped
    }

    /// Casters culled for `light`, when its boxes were queried.
    pub fn culled(&self, light: usize) -> Option<usize> {
        self.culled.iter().find(|&&(l, _)| l == light).map(|&(_, n)| n)
    }
}

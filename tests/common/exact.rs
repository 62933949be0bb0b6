//! The exact reference of hard shadows: the scene's triangles ray cast on the CPU (`obvhs`),
//! per pixel, for the first light.

use super::raycast::pixel_ray;
use glam::{Mat4, Vec3, Vec4};
use umbra::scene::Scene;
use umbra_reference::{towards, SceneBvh};

/// The exact state of a pixel: `Some(shadowed)` for a surface that faces the light, `None`
/// for background, surfaces facing away, and pixels whose centre lies within 0.5 px of a
/// shadow or silhouette edge (a corner of the pixel sees something else).
pub struct Reference {
    bvh: SceneBvh,
    light: Vec4,
}

impl Reference {
    /// The reference of `scene`'s first light.
    pub fn new(scene: &Scene) -> Self {
        Self { bvh: SceneBvh::build(scene), light: scene.lights[0].position }
    }

    /// (object seen, facing the light, shadowed) along one camera ray.
    fn sample(&self, o: Vec3, d: Vec3) -> Option<(usize, bool, bool)> {
        let hit = self.bvh.closest_hit(o, d, f32::INFINITY)?;
        let tri = self.bvh.triangles()[hit.triangle];
        let p = o + d * hit.t;
        let mut n = tri.normal();
        if n.dot(d) > 0.0 {
            n = -n; // two-sided lighting: the side the camera sees
        }
        let to_light = self.light.truncate() - p * self.light.w;
        let facing = n.dot(to_light) > 1e-6;
        let from = p + n * 1e-4;
        let (dir, distance) = towards(self.light, from);
        let shadowed = facing && self.bvh.occluded(from, dir, distance - 1e-4);
        Some((tri.object, facing, shadowed))
    }

    /// `Some(shadowed)` for pixel (x, y) of a `w` × `h` frame seen through `view_proj`, `None`
    /// where the pixel is not decided (see the type).
    pub fn pixel(&self, view_proj: Mat4, w: u32, h: u32, x: u32, y: u32) -> Option<bool> {
        let (o, d) = pixel_ray(view_proj, w, h, x, y);
        let centre = self.sample(o, d)?;
        if !centre.1 {
            return None;
        }
        let inv = view_proj.inverse();
        for (dx, dy) in [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)] {
            let ndc_x = (x as f32 + 0.5 + dx) / w as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - (y as f32 + 0.5 + dy) / h as f32 * 2.0;
            let near = inv.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
            let far = inv.project_point3(Vec3::new(ndc_x, ndc_y, 0.5));
            if self.sample(near, (far - near).normalize()) != Some(centre) {
                return None;
            }
        }
        Some(centre.2)
    }
}

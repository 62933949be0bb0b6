//! A light's fitted map views kept from the frame that fitted them.
//!
//! [`frustum::fit`] cuts every visible receiver's box to the view frustum (a point light's
//! cube) or every caster's box to the light's cone (a spot): with 64 instances that is the
//! hybrid's largest per-frame host cost after its grid samples (`samples.rs`), and it grows
//! with the scene (#26). Its answer depends only on the light's position and cone, the
//! camera's view-projection, and each object's bounds and caster/receiver flags. Those inputs
//! are kept as bits and compared exactly (`kept.rs`): a light none of them changed for is not
//! fitted again, any change fits it anew, so the views are always those a fit would give.

use super::frustum::{self, LightViews};
use super::kept::Kept;
use glam::Mat4;
use umbra_scene::{Aabb, Light, Scene};

/// Every light's last fit, by light index.
#[derive(Default)]
pub(crate) struct Fits {
    lights: Vec<Option<Kept<Option<LightViews>>>>,
    /// The key of the inputs being asked about (scratch, swapped with a kept one on a miss).
    current: Vec<u32>,
    /// How many times a light was fitted (tests count the misses).
    #[cfg(test)]
    fitted: usize,
}

/// Refills `key` with the bits of everything [`frustum::fit`] reads.
fn fill(key: &mut Vec<u32>, light: &Light, scene: &Scene, boxes: &[Option<Aabb>], view_proj: Mat4) {
    key.clear();
    let spot = light.spot.map(|s| [s.direction.x, s.direction.y, s.direction.z, s.inner_deg, s.outer_deg]);
    key.extend(light.position.to_array().map(f32::to_bits));
    key.push(u32::from(spot.is_some()));
    key.extend(spot.unwrap_or_default().map(f32::to_bits));
    key.extend(view_proj.to_cols_array().map(f32::to_bits));
    for (i, o) in scene.objects.iter().enumerate() {
        let b = boxes.get(i).copied().flatten();
        key.push(u32::from(o.casts_shadows) | u32::from(o.receives_shadows) << 1 | u32::from(b.is_some()) << 2);
        let corners = b.map_or([0.0; 6], |b| [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z]);
        key.extend(corners.map(f32::to_bits));
    }
    // The object count keeps two scenes apart even when their bits run on alike.
    key.push(scene.objects.len() as u32);
}

impl Fits {
    /// [`frustum::fit`] of light `index` (`light`), fitted only when its inputs changed.
    pub fn fit(
        &mut self,
        index: usize,
        light: &Light,
        scene: &Scene,
        boxes: &[Option<Aabb>],
        view_proj: Mat4,
    ) -> Option<LightViews> {
        fill(&mut self.current, light, scene, boxes, view_proj);
        if self.lights.len() <= index {
            self.lights.resize_with(index + 1, || None);
        }
        Kept::answer(&mut self.lights[index], &mut self.current, || {
            #[cfg(test)]
            {
                self.fitted += 1;
            }
            frustum::fit(light, scene, boxes, view_proj)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};

    /// The views' matrices and casters, to compare a kept fit with a fresh one.
    fn figures(v: &Option<LightViews>) -> Option<(Vec<[f32; 16]>, Vec<usize>, usize)> {
        v.as_ref().map(|v| (v.views.iter().map(Mat4::to_cols_array).collect(), v.casters.clone(), v.receivers.len()))
    }

    #[test]
    fn a_kept_fit_is_the_fresh_one_and_any_input_change_fits_again() {
        let mut scene = umbra_scene::procedural::build("cubes").expect("cubes");
        let light = 0;
        let mut fits = Fits::default();
        let check = |fits: &mut Fits, scene: &Scene, view_proj: Mat4, misses: usize| {
            let boxes = scene.object_bounds();
            let kept = fits.fit(light, &scene.lights[light], scene, &boxes, view_proj);
            let fresh = frustum::fit(&scene.lights[light], scene, &boxes, view_proj);
            assert_eq!(figures(&kept), figures(&fresh));
            assert!(fresh.is_some(), "the scene's light fits a map");
            assert_eq!(fits.fitted, misses);
        };
        let view_proj = crate::view::View::of_camera(&scene.camera, 4.0 / 3.0).view_proj;
        check(&mut fits, &scene, view_proj, 1);
        check(&mut fits, &scene, view_proj, 1); // the same bits: kept
        let moved = Mat4::from_translation(Vec3::X * 0.25) * view_proj;
        check(&mut fits, &scene, moved, 2); // the camera
        scene.lights[light].position += glam::Vec4::new(0.0, 0.5, 0.0, 0.0);
        check(&mut fits, &scene, moved, 3); // the light
        scene.objects[1].transform = Mat4::from_translation(Vec3::Y * 0.1) * scene.objects[1].transform;
        check(&mut fits, &scene, moved, 4); // an object's bounds
        scene.objects[1].casts_shadows = false;
        check(&mut fits, &scene, moved, 5); // a caster flag
        check(&mut fits, &scene, moved, 5);
    }
}

//! The receivers' grid samples of a light's map kept from the frame that took them.
//!
//! [`texels::texel_pixel_ratio`] (a map's default size) and [`texels::receiver_texel_size`]
//! (the report's texel size) sample 512 points per visible receiver box: about 2 ms a frame
//! for 64 instances on 2 cores, the last host cost that grew with the scene. Their answer
//! depends only on the light's views, the receivers' seen boxes, the camera and the frame's
//! height. Those inputs are kept as bits and compared exactly (`kept.rs`): a light none of them
//! moved for is not sampled again, any change samples it anew, so the answer is always the one
//! sampling would give.

use super::frustum::LightViews;
use super::kept::Kept;
use super::texels::{self, Seen};
use glam::Mat4;
use umbra_scene::Aabb;

/// The bits of everything one sampling reads, in reused storage (no allocation once warm).
#[derive(Default)]
struct Key(Vec<u32>);

impl Key {
    /// Refills the key with the bits of the inputs.
    fn fill(&mut self, views: &[Mat4], receivers: &[Aabb], seen: Seen<'_>, resolution: u32) {
        let camera = seen.view;
        let floats = views
            .iter()
            .flat_map(|m| m.to_cols_array())
            .chain(receivers.iter().flat_map(|b| b.min.to_array().into_iter().chain(b.max.to_array())))
            .chain(camera.view_proj.to_cols_array())
            .chain(camera.position.to_array())
            .chain(camera.forward.to_array())
            .chain([camera.near, camera.height_per_depth]);
        self.0.clear();
        self.0.extend(floats.map(f32::to_bits));
        // Lengths keep two view lists of different sizes apart even when their bits run on alike.
        self.0.extend([views.len() as u32, receivers.len() as u32, seen.height, resolution]);
    }
}

/// One light's two samplings.
#[derive(Default)]
struct LightSamples {
    ratio: Option<Kept<Option<f32>>>,
    texels: Option<Kept<Option<[f32; 2]>>>,
}

/// Every light's last samplings, by light index.
#[derive(Default)]
pub(crate) struct GridSamples {
    lights: Vec<LightSamples>,
    /// The key of the inputs being asked about (scratch, swapped with a kept one on a miss).
    current: Key,
    /// How many times a grid was sampled (tests count the misses).
    #[cfg(test)]
    sampled: usize,
}

impl GridSamples {
    fn light(&mut self, light: usize) -> &mut LightSamples {
        if self.lights.len() <= light {
            self.lights.resize_with(light + 1, LightSamples::default);
        }
        &mut self.lights[light]
    }

    /// Counts one sampling (tests only).
    fn count(&mut self) {
        #[cfg(test)]
        {
            self.sampled += 1;
        }
    }

    /// [`texels::resolution_from_frame`] of `light`'s `views`, sampled only when its inputs
    /// changed.
    pub fn resolution_from_frame(&mut self, light: usize, views: &LightViews, seen: Seen<'_>, width: u32) -> u32 {
        let reference = texels::REFERENCE_RESOLUTION;
        let mut current = std::mem::take(&mut self.current);
        current.fill(&views.views, &views.receivers, seen, reference);
        let mut missed = false;
        let ratio = Kept::answer(&mut self.light(light).ratio, &mut current.0, || {
            missed = true;
            texels::texel_pixel_ratio(views, reference, seen)
        });
        self.current = current;
        if missed {
            self.count();
        }
        crate::ShadowMapSettings::resolution_from_frame(ratio, reference, width, seen.height)
    }

    /// [`texels::receiver_texel_size`] of `light`'s `views` at `resolution`, sampled only
    /// when its inputs changed.
    pub fn receiver_texel_size(
        &mut self,
        light: usize,
        views: &LightViews,
        resolution: u32,
        seen: Seen<'_>,
    ) -> Option<[f32; 2]> {
        let mut current = std::mem::take(&mut self.current);
        current.fill(&views.views, &views.receivers, seen, resolution);
        let mut missed = false;
        let range = Kept::answer(&mut self.light(light).texels, &mut current.0, || {
            missed = true;
            texels::receiver_texel_size(&views.views, &views.receivers, resolution, seen)
        });
        self.current = current;
        if missed {
            self.count();
        }
        range
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::View;
    use glam::Vec3;

    fn camera(eye: Vec3) -> View {
        let view = Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y);
        View::of_matrices(view, Mat4::perspective_rh(0.9, 4.0 / 3.0, 0.1, 100.0))
    }

    fn light_views(sun: Vec3, receivers: Vec<Aabb>) -> LightViews {
        let view = Mat4::look_at_rh(sun, Vec3::ZERO, Vec3::Z);
        LightViews {
            kind: crate::shadow_map::frustum::MapKind::Single,
            views: vec![Mat4::orthographic_rh(-8.0, 8.0, -8.0, 8.0, 0.0, 40.0) * view],
            near: 0.0,
            far: 40.0,
            casters: Vec::new(),
            view_casters: None,
            receivers,
        }
    }

    /// Asks the cache and sampling afresh about one frame's inputs; both must agree bit for bit.
    fn agree(cache: &mut GridSamples, light: usize, views: &LightViews, eye: Vec3, height: u32) {
        let view = camera(eye);
        let seen = Seen { view: &view, height };
        let fresh_size = texels::resolution_from_frame(views, seen, height * 4 / 3);
        let fresh_texels = texels::receiver_texel_size(&views.views, &views.receivers, 512, seen);
        assert_eq!(cache.resolution_from_frame(light, views, seen, height * 4 / 3), fresh_size);
        let kept = cache.receiver_texel_size(light, views, 512, seen);
        assert_eq!(kept.map(|r| r.map(f32::to_bits)), fresh_texels.map(|r| r.map(f32::to_bits)));
        assert!(fresh_texels.is_some(), "the test's receivers must be seen");
    }

    #[test]
    fn kept_samples_equal_fresh_ones_after_any_change() {
        let floor = Aabb { min: Vec3::new(-6.0, -0.1, -6.0), max: Vec3::new(6.0, 0.0, 6.0) };
        let block = Aabb { min: Vec3::new(-1.0, 0.0, -1.0), max: Vec3::new(1.0, 2.0, 1.0) };
        let eye = Vec3::new(0.0, 6.0, 10.0);
        let sun = Vec3::new(4.0, 12.0, 3.0);
        let mut cache = GridSamples::default();
        let views = light_views(sun, vec![floor, block]);
        agree(&mut cache, 0, &views, eye, 192);
        assert_eq!(cache.sampled, 2, "the first frame samples both grids");
        agree(&mut cache, 0, &views, eye, 192);
        assert_eq!(cache.sampled, 2, "an unchanged frame samples nothing");
        // The camera moves, then the frame's height, then a receiver, then the light's view:
        // each samples both grids again and gives what fresh sampling gives.
        let moved = Vec3::new(1.0, 5.0, 9.0);
        agree(&mut cache, 0, &views, moved, 192);
        assert_eq!(cache.sampled, 4);
        agree(&mut cache, 0, &views, moved, 384);
        assert_eq!(cache.sampled, 6);
        let lifted = Aabb { min: block.min + Vec3::Y, max: block.max + Vec3::Y };
        let views = light_views(sun, vec![floor, lifted]);
        agree(&mut cache, 0, &views, moved, 384);
        assert_eq!(cache.sampled, 8);
        let views = light_views(Vec3::new(-3.0, 10.0, 2.0), vec![floor, lifted]);
        agree(&mut cache, 0, &views, moved, 384);
        assert_eq!(cache.sampled, 10);
        // One receiver fewer, and a second light, each sample for themselves.
        let views = light_views(Vec3::new(-3.0, 10.0, 2.0), vec![floor]);
        agree(&mut cache, 0, &views, moved, 384);
        assert_eq!(cache.sampled, 12);
        agree(&mut cache, 1, &views, moved, 384);
        assert_eq!(cache.sampled, 14);
        agree(&mut cache, 0, &views, moved, 384);
        assert_eq!(cache.sampled, 14, "light 0 still holds its answer");
    }

    #[test]
    fn a_negative_zero_is_a_change() {
        let mut a = Key::default();
        let mut b = Key::default();
        let view = camera(Vec3::new(0.0, 6.0, 10.0));
        let seen = Seen { view: &view, height: 192 };
        let zero = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let negative = Aabb { min: Vec3::new(-0.0, 0.0, 0.0), max: Vec3::ONE };
        a.fill(&[Mat4::IDENTITY], &[zero], seen, 512);
        b.fill(&[Mat4::IDENTITY], &[negative], seen, 512);
        assert_ne!(a.0, b.0);
    }
}

//! The view a frame is seen from, as every CPU step uses it: matrices (from umbra's own
//! [`Camera`] or as an engine built them, brought to umbra's depth convention) and the few
//! numbers planning and fitting read off them.

use glam::{Mat4, Vec3};
use serde::Serialize;
use umbra_scene::Camera;

/// A frame's view: world to view, view to clip (Vulkan's 0 ≤ z ≤ w, depth growing with
/// distance, umbra's y-up viewport), and what is derived from them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct View {
    /// World to view (right-handed, looking down -Z).
    pub view: Mat4,
    /// View to clip.
    pub proj: Mat4,
    /// `proj * view`.
    pub view_proj: Mat4,
    /// The eye in world space.
    pub position: Vec3,
    /// The unit view direction in world space.
    pub forward: Vec3,
    /// Distance of the near plane along the view direction.
    pub near: f32,
    /// The height of the view frustum per unit of depth along `forward` (`2 tan(fov_y / 2)`).
    pub height_per_depth: f32,
}

impl View {
    /// The view of `camera` on a target `aspect` (width / height) wide.
    pub fn of_camera(camera: &Camera, aspect: f32) -> Self {
        Self {
            view: camera.view(),
            proj: camera.projection(aspect),
            view_proj: camera.view_proj(aspect),
            position: camera.position,
            forward: (camera.target - camera.position).normalize_or_zero(),
            near: camera.near,
            height_per_depth: 2.0 * (camera.fov_y_deg.to_radians() * 0.5).tan(),
        }
    }

    /// The view of an engine's `view` and perspective `proj` matrices, already in umbra's
    /// convention (standard depth, `z = 0` at the near plane).
    pub fn of_matrices(view: Mat4, proj: Mat4) -> Self {
        let inverse = view.inverse();
        // The projection's depth row: z_clip = a·z + b with w = -z, zero at z = -near.
        let (a, b) = (proj.z_axis.z, proj.w_axis.z);
        Self {
            view,
            proj,
            view_proj: proj * view,
            position: inverse.w_axis.truncate(),
            forward: -inverse.z_axis.truncate().normalize_or_zero(),
            near: if a != 0.0 { b / a } else { 0.0 },
            height_per_depth: if proj.y_axis.y != 0.0 { 2.0 / proj.y_axis.y.abs() } else { 0.0 },
        }
    }

    /// The world distance between two adjacent depth values at `distance` from the eye along
    /// the view: depth `−a + b / d` (`z_clip = a·z + b`, `w = −z`) changes by `|b| / d²` per unit
    /// there, and its values just below 1 are [`Camera::DEPTH_STEP`] apart.
    pub fn depth_step_at(&self, distance: f32) -> f32 {
        let b = f64::from(self.proj.w_axis.z).abs();
        let d = f64::from(distance);
        if b == 0.0 {
            return f32::INFINITY;
        }
        (d * d / b * f64::from(Camera::DEPTH_STEP)) as f32
    }

    /// The camera's depth precision at `distance` (the scene's farthest point) where it is
    /// coarser than at [`umbra_scene::Camera::EXACT_NEAR_RATIO`], the ratio at which shadow
    /// volumes are measured exact; `None` where it is as fine.
    pub fn depth_precision(&self, distance: f32) -> Option<DepthPrecision> {
        let step = self.depth_step_at(distance);
        let exact = distance * DepthPrecision::EXACT_RELATIVE_STEP;
        (distance > 0.0 && step > exact).then_some(DepthPrecision { distance, step })
    }
}

/// How coarse the camera's depth is at the scene's farthest point
/// ([`crate::ShadowVolumeReport::depth_precision`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DepthPrecision {
    /// Distance from the eye to the farthest point of any object's bounds.
    pub distance: f32,
    /// World distance between two adjacent depth values there.
    pub step: f32,
}

impl DepthPrecision {
    /// The depth step, as a fraction of the distance, at which shadow volumes are measured
    /// exact: that of a near plane at [`umbra_scene::Camera::EXACT_NEAR_RATIO`] of the distance
    /// (about 0.06 %). Coarser steps are reported.
    pub const EXACT_RELATIVE_STEP: f32 = umbra_scene::Camera::DEPTH_STEP / umbra_scene::Camera::EXACT_NEAR_RATIO;

    /// A one-line warning for light `light`'s shadow volumes.
    pub fn warning(&self, light: usize) -> String {
        format!(
            "warning: light {light}: the camera's depth resolves {:.3e} world units ({:.2} % of the distance) at the scene's farthest point, {:.3e} away; shadow volumes are measured exact to {:.2} % (near plane {:e} of the distance): volume faces and surfaces nearer each other than that may count on the wrong side",
            self.step,
            100.0 * self.step / self.distance,
            self.distance,
            100.0 * Self::EXACT_RELATIVE_STEP,
            umbra_scene::Camera::EXACT_NEAR_RATIO,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_give_back_what_the_camera_holds() {
        let mut camera = Camera::look_at(Vec3::new(3.0, 2.0, 5.0), Vec3::new(0.0, 0.5, 0.0));
        for far in [Some(200.0), None] {
            camera.far = far;
            let own = View::of_camera(&camera, 4.0 / 3.0);
            let given = View::of_matrices(camera.view(), camera.projection(4.0 / 3.0));
            assert_eq!(own.view_proj, given.view_proj);
            assert!((own.position - given.position).length() < 1e-5, "{} {}", own.position, given.position);
            assert!((own.forward - given.forward).length() < 1e-6);
            assert!((own.near - given.near).abs() < 1e-6 * own.near.max(1.0), "{} {}", own.near, given.near);
            assert!((own.height_per_depth - given.height_per_depth).abs() < 1e-6);
        }
    }

    #[test]
    fn depth_precision_is_reported_below_the_exact_near_ratio() {
        let mut camera = Camera::look_at(Vec3::ZERO, -Vec3::Z);
        camera.far = None;
        camera.near = 0.1;
        let view = View::of_camera(&camera, 1.5);
        // P_inf: depth 1 − near/d, so the step at d is 2⁻²⁴ d² / near.
        let d = 44_000.0;
        let step = view.depth_step_at(d);
        assert!((step / (d * d / 0.1 * Camera::DEPTH_STEP) - 1.0).abs() < 1e-5, "{step}");
        // The step between two f32 depths just below 1, measured: d at 1 − 2⁻²⁴·k is near / (2⁻²⁴·k).
        let at = |k: f32| 0.1 / (k * Camera::DEPTH_STEP);
        assert!(((at(2.0) - at(3.0)) / view.depth_step_at(at(2.5)) - 1.0).abs() < 0.05);
        let p = view.depth_precision(d).expect("0.1 at 44 km is coarser than measured exact");
        assert_eq!((p.distance, p.step), (d, step));
        // Exactly at the measured-exact ratio and above it: nothing to report.
        let exact = 0.1 / umbra_scene::Camera::EXACT_NEAR_RATIO;
        assert!(view.depth_precision(exact * 0.999).is_none());
        assert!(view.depth_precision(exact * 1.01).is_some());
    }
}

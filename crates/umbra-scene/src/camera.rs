//! Perspective cameras, with an infinite-far variant (Everitt–Kilgard's P_inf).

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

/// A perspective camera looking from `position` at `target`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    #[serde(default = "up")]
    pub up: Vec3,
    /// Vertical field of view in degrees.
    #[serde(default = "fov")]
    pub fov_y_deg: f32,
    /// Near plane distance (> 0).
    #[serde(default = "near")]
    pub near: f32,
    /// Far plane distance, or `None` for a far plane at infinity.
    #[serde(default)]
    pub far: Option<f32>,
}

fn up() -> Vec3 {
    Vec3::Y
}
fn fov() -> f32 {
    50.0
}
fn near() -> f32 {
    0.05
}

impl Camera {
    /// A camera at `position` looking at `target` with umbra's defaults (50°, near 0.05,
    /// far 200).
    pub fn look_at(position: Vec3, target: Vec3) -> Self {
        Self { position, target, up: Vec3::Y, fov_y_deg: fov(), near: near(), far: Some(200.0) }
    }

    /// The smallest `near`, as a fraction of the distance from the eye to the scene's farthest
    /// point, that [`Camera::validate`] accepts: 2⁻²³ (about 1.2e-7). umbra's camera depth is
    /// standard (0 at the near plane, 1 at infinity): a point `d` away lies at depth
    /// `1 − near / d`, and the depth values just below 1 are 2⁻²⁴ apart in a 24-bit depth and
    /// in a 32-bit float one alike. At this ratio the farthest point still lies two steps in
    /// front of infinity, where depth is cleared and shadow volumes' back caps are drawn; below
    /// 2⁻²⁵ it would round onto them. Open worlds are accepted: a near plane of 0.1 with
    /// geometry 141 km away is 7e-7 (hard case 32). Between this bound and
    /// [`Camera::EXACT_NEAR_RATIO`] the frame report gives every shadow-volume light the depth
    /// step at the farthest point (`ShadowVolumeReport::depth_precision`).
    pub const MIN_NEAR_RATIO: f32 = 2.0 * Self::DEPTH_STEP;

    /// The step between adjacent depth values just below 1 (where distant points lie): 2⁻²⁴,
    /// in a 24-bit depth and in a 32-bit float one alike.
    pub const DEPTH_STEP: f32 = 1.0 / 16_777_216.0;

    /// The smallest `near`, as a fraction of the distance to the scene's farthest point, at
    /// which the conformance suite measured shadow volumes and the hybrid exact: hard case 07
    /// (geometry at 1e5–1e6 units, near = 100) sits at 1.05e-4 on both CPU drivers. Below it
    /// the depth step at the farthest point exceeds 2⁻²⁴ / 1e-4 ≈ 0.06 % of its distance, and
    /// the frame report says so per light. [`crate::Scene::fit_near_plane`] raises an
    /// interactive camera's near plane to it.
    pub const EXACT_NEAR_RATIO: f32 = 1e-4;

    /// Checks the camera for a scene whose farthest point is `reach` from the eye: finite
    /// vectors, `position ≠ target`, an `up` that is not zero or along the view direction,
    /// `0 < fov_y_deg < 180`, `near ≥ MIN_NEAR_RATIO × reach` (depth precision: below it the
    /// farthest point's depth cannot be told from infinity's) and `far > near`. The `Err` names
    /// the field.
    pub fn validate(&self, reach: f32) -> Result<(), String> {
        if !(self.position.is_finite() && self.target.is_finite() && self.up.is_finite()) {
            return Err("position, target and up must be finite".into());
        }
        let forward = self.target - self.position;
        if forward.length_squared() == 0.0 {
            return Err(format!("position and target are the same point {}", self.position));
        }
        if self.up.length_squared() == 0.0 || forward.normalize().cross(self.up.normalize()).length_squared() < 1e-8 {
            return Err(format!("up {} is zero or along the view direction", self.up));
        }
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(format!("fov_y_deg {} must be in (0, 180)", self.fov_y_deg));
        }
        let min_near = Self::MIN_NEAR_RATIO * reach;
        if !(self.near.is_finite() && self.near > 0.0 && self.near >= min_near) {
            return Err(format!(
                "near {:e} must be finite and ≥ {min_near:e} (2^-23 = {:e} of the distance {reach:e} to the scene's farthest point: depth precision)",
                self.near,
                Self::MIN_NEAR_RATIO
            ));
        }
        if let Some(far) = self.far.filter(|f| !(f.is_finite() && *f > self.near)) {
            return Err(format!("far {far} must be finite and > near {}", self.near));
        }
        Ok(())
    }

    /// World-to-view matrix (right-handed, looking down -Z).
    pub fn view(&self) -> Mat4 {
        let forward = (self.target - self.position).normalize_or_zero();
        // Avoid a degenerate basis when looking along `up`.
        let up =
            if forward.cross(self.up).length_squared() < 1e-8 { forward.any_orthonormal_vector() } else { self.up };
        Mat4::look_at_rh(self.position, self.target, up)
    }

    /// View-to-clip matrix for Vulkan's 0 ≤ z ≤ w depth range (used with umbra's y-up
    /// viewport). With `far == None` the far plane is at infinity: a point at infinity in front
    /// of the eye lands exactly on depth 1.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let fov = self.fov_y_deg.to_radians();
        match self.far {
            Some(far) => Mat4::perspective_rh(fov, aspect, self.near, far),
            None => Mat4::perspective_infinite_rh(fov, aspect, self.near),
        }
    }

    /// Projection times view.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn infinite_projection_puts_points_at_infinity_on_the_far_plane() {
        let mut c = Camera::look_at(Vec3::ZERO, -Vec3::Z);
        c.far = None;
        // Points at infinity (w = 0) in front of the eye, as shadow volumes extrude them.
        for dir in [Vec4::new(0.1, 0.2, -1.0, 0.0), Vec4::new(-3.0, 0.5, -0.2, 0.0), Vec4::new(0.0, 0.0, -1e-3, 0.0)] {
            let clip = c.view_proj(1.5) * dir;
            assert!(clip.w > 0.0);
            // Exactly the far depth, and inside 0 <= z <= w: never clipped.
            assert_eq!(clip.z, clip.w, "depth {} for {dir}", clip.z / clip.w);
        }
        let near = c.view_proj(1.5) * Vec4::new(0.0, 0.0, -c.near, 1.0);
        assert!((near.z / near.w).abs() < 1e-6);
    }
}

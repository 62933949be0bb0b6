//! How large a shadow-map texel is: in the world at a point ([`texel_at`]), against a screen
//! pixel over what the camera sees of the receivers (the Stamminger–Drettakis ratio behind a
//! map's default size and the report's texel size), along an orthographic map's axes, and as a
//! depth-bias clamp.

use super::frustum::LightViews;
use crate::view::View;
use glam::{Mat4, Vec3, Vec4Swizzles};
use umbra_scene::Aabb;

/// World size of one texel of the map view that holds `p` (across the light's rays, at `p`'s
/// depth in the map), or `None` when no view holds it.
pub(crate) fn texel_at(views: &[Mat4], p: Vec3, resolution: u32) -> Option<f32> {
    views.iter().find_map(|vp| {
        let clip = *vp * p.extend(1.0);
        let inside = clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w;
        if !inside {
            return None;
        }
        let ndc = clip.xyz() / clip.w;
        let inv = vp.inverse();
        let step = 2.0 / resolution as f32;
        let at = |dx: f32, dy: f32| inv.project_point3(ndc + Vec3::new(dx, dy, 0.0));
        let o = at(0.0, 0.0);
        Some(at(step, 0.0).distance(o).max(at(0.0, step).distance(o)))
    })
}

/// What a camera sees, for sampling receivers (`auto`'s choice, the hybrid's default map size,
/// the report's texel size): its view-projection and how large a pixel is at a given depth.
#[derive(Clone, Copy)]
pub(crate) struct Seen<'a> {
    pub view: &'a View,
    /// Pixel rows of the frame.
    pub height: u32,
}

impl Seen<'_> {
    /// Whether `p` lies inside the camera's side planes, beyond its near plane.
    fn holds(&self, p: Vec3) -> bool {
        let clip = self.view.view_proj * p.extend(1.0);
        clip.w > self.view.near && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w
    }

    /// World size of one pixel at `p` (its depth along the view axis times a pixel's angle).
    pub fn pixel_at(&self, p: Vec3) -> f32 {
        let v = self.view;
        let per_depth = v.height_per_depth / self.height.max(1) as f32;
        (p - v.position).dot(v.forward) * per_depth
    }

    /// Calls `f(i, p)` at the points `p` of a grid (`samples` per side) through each box `i`
    /// of `boxes` that the camera sees.
    pub fn for_grid(
        &self,
        boxes: impl IntoIterator<Item = (usize, Aabb)>,
        samples: usize,
        mut f: impl FnMut(usize, Vec3),
    ) {
        for (i, b) in boxes {
            let step = (b.max - b.min) / (samples - 1) as f32;
            for k in 0..samples * samples * samples {
                let (x, y, z) = (k % samples, k / samples % samples, k / (samples * samples));
                let p = b.min + step * Vec3::new(x as f32, y as f32, z as f32);
                if self.holds(p) {
                    f(i, p);
                }
            }
        }
    }
}

/// Grid points per side of a receiver box where the hybrid's default size and the report's
/// texel size are sampled.
const RECEIVER_SAMPLES: usize = 8;

/// The largest Stamminger–Drettakis ratio of `views` at `resolution` on what `seen` sees of the
/// receivers (`views.receivers`): a texel's world size over a pixel's at the same point.
/// `None` when no such point lies in a view.
pub(crate) fn texel_pixel_ratio(views: &LightViews, resolution: u32, seen: Seen<'_>) -> Option<f32> {
    let mut worst: Option<f32> = None;
    seen.for_grid(views.receivers.iter().copied().enumerate(), RECEIVER_SAMPLES, |_, p| {
        let pixel = seen.pixel_at(p);
        if let Some(t) = texel_at(&views.views, p, resolution).filter(|t| t.is_finite() && pixel > 0.0) {
            worst = Some(worst.map_or(t / pixel, |w| w.max(t / pixel)));
        }
    });
    worst
}

/// The map size of `views` in a `width` × `height` frame when nobody set one
/// ([`ShadowMapSettings::resolution_from_frame`](crate::ShadowMapSettings::resolution_from_frame)),
/// from the ratio at a reference size (texels shrink in proportion to the size).
pub(crate) fn resolution_from_frame(views: &LightViews, seen: Seen<'_>, width: u32) -> u32 {
    let ratio = texel_pixel_ratio(views, REFERENCE_RESOLUTION, seen);
    crate::ShadowMapSettings::resolution_from_frame(ratio, REFERENCE_RESOLUTION, width, seen.height)
}

/// The map size [`resolution_from_frame`] measures the texel-to-pixel ratio at.
pub(crate) const REFERENCE_RESOLUTION: u32 = 1024;

/// The least and the largest [`texel_at`] at the grid points of `receivers` that `seen` sees,
/// or `None` when no such point lies in a view.
pub(crate) fn receiver_texel_size(
    views: &[Mat4],
    receivers: &[Aabb],
    resolution: u32,
    seen: Seen<'_>,
) -> Option<[f32; 2]> {
    let mut range: Option<[f32; 2]> = None;
    seen.for_grid(receivers.iter().copied().enumerate(), RECEIVER_SAMPLES, |_, p| {
        if let Some(t) = texel_at(views, p, resolution).filter(|t| t.is_finite()) {
            range = Some(range.map_or([t, t], |[lo, hi]| [lo.min(t), hi.max(t)]));
        }
    });
    range
}

/// World units per texel along the map's x and y for an orthographic `view_proj` (clip x and
/// y span 2 over the box's width and height).
pub(crate) fn texel_size(view_proj: Mat4, resolution: u32) -> [f32; 2] {
    let m = view_proj.transpose(); // rows as columns
    [m.x_axis, m.y_axis].map(|row| 2.0 / (row.xyz().length() * resolution as f32))
}

/// The depth-bias clamp (in the map's depth units) equal to `texels` texel widths along the
/// light's rays, measured at the centre of the near plane of `view_proj` (exact everywhere for
/// orthographic maps; for perspective maps the largest value, nearer texels being smaller).
pub(crate) fn bias_clamp(view_proj: Mat4, resolution: u32, texels: f32) -> f32 {
    let inv = view_proj.inverse();
    let p0 = inv.project_point3(Vec3::ZERO);
    let texel = inv.project_point3(Vec3::new(2.0 / resolution as f32, 0.0, 0.0)).distance(p0);
    let along = (inv.project_point3(Vec3::new(0.0, 0.0, 0.5)) - p0).normalize_or_zero();
    let depth = view_proj.project_point3(p0 + along * texel * texels).z - view_proj.project_point3(p0).z;
    if depth.is_finite() {
        depth.max(0.0)
    } else {
        0.0
    }
}

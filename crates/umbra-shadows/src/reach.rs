//! Conservative geometry for the frame planner: where a light can add anything, which boxes a
//! view can see, where a caster's shadow volume can reach, and the screen rectangle and depth
//! range a bounded light covers. Every test answers "certainly not" or "maybe": culling on a
//! "certainly not" never changes the image.

use crate::view::View;
use glam::{Mat4, Vec3, Vec4, Vec4Swizzles};
use umbra_scene::{Aabb, Light};

/// Clip-space planes of a view-projection (Vulkan: 0 ≤ z ≤ w), each a `Vec4` (n, d) with
/// n·p + d ≥ 0 inside. Planes with a vanishing normal (the far plane of an infinite
/// projection) are left out.
#[derive(Clone, Debug)]
pub(crate) struct Planes(Vec<Vec4>);

/// Which planes of a frustum to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clip {
    /// Left, right, bottom, top: what clips even with depth clamp on.
    Sides,
    /// The sides, near and (when finite) far.
    All,
}

impl Planes {
    /// The planes of `view_proj` (Gribb–Hartmann).
    pub fn of(view_proj: Mat4, clip: Clip) -> Self {
        let m = view_proj.transpose(); // rows of view_proj as columns
        let (r0, r1, r2, r3) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
        let sides = [r3 + r0, r3 - r0, r3 + r1, r3 - r1];
        let depth = [r2, r3 - r2];
        let keep = |pl: &&Vec4| pl.xyz().length_squared() >= 1e-12;
        let planes = match clip {
            Clip::Sides => sides.iter().filter(keep).copied().collect(),
            Clip::All => sides.iter().chain(&depth).filter(keep).copied().collect(),
        };
        Self(planes)
    }

    /// Whether the box may be inside (false: certainly outside one plane).
    pub fn may_hold_box(&self, b: &Aabb) -> bool {
        self.0.iter().all(|pl| {
            // The box corner farthest along the plane normal.
            let corner = Vec3::select(pl.xyz().cmpge(Vec3::ZERO), b.max, b.min);
            pl.xyz().dot(corner) + pl.w >= 0.0
        })
    }

    /// These planes and `other`'s: the intersection of both regions.
    pub fn and(&self, other: &Planes) -> Planes {
        Planes(self.0.iter().chain(&other.0).copied().collect())
    }

    /// The corners of the part of box `b` inside every plane, or none when no part is. The
    /// part is convex, so its corners are the points where three of its bounding planes (the
    /// box's six faces and these planes) meet that lie inside all of them; every point of the
    /// part lies in their convex hull. A corner counts as inside within 10⁻⁵ of the box's
    /// size, so a flat box (a floor quad) keeps its corners.
    pub fn clip_box(&self, b: &Aabb) -> Vec<Vec3> {
        let faces =
            [Vec3::X, Vec3::Y, Vec3::Z].into_iter().flat_map(|n| [n.extend(-n.dot(b.min)), (-n).extend(n.dot(b.max))]);
        let planes: Vec<Vec4> =
            faces.chain(self.0.iter().map(|pl| *pl / pl.xyz().length())).filter(|pl| pl.is_finite()).collect();
        let scale = b.min.abs().max(b.max.abs()).max(b.max - b.min).max_element().max(1e-6);
        let tolerance = 1e-5 * scale;
        let inside = |p: Vec3| planes.iter().all(|pl| pl.xyz().dot(p) + pl.w >= -tolerance);
        let mut out = Vec::new();
        for i in 0..planes.len() {
            for j in i + 1..planes.len() {
                for k in j + 1..planes.len() {
                    let p = meet(planes[i], planes[j], planes[k]).filter(|&p| inside(p));
                    out.extend(p);
                }
            }
        }
        out
    }

    /// Whether the sphere may be inside.
    pub fn may_hold_sphere(&self, centre: Vec3, radius: f32) -> bool {
        self.0.iter().all(|pl| pl.xyz().dot(centre) + pl.w >= -radius * pl.xyz().length())
    }

    /// Whether the box swept away from `light` to infinity (where its shadow volume lies:
    /// Everitt–Kilgard's extrusion, caps included) may be inside. A plane separates the sweep
    /// when every corner is outside it and every extrusion direction points further out.
    pub fn may_hold_sweep(&self, b: &Aabb, light: Vec4) -> bool {
        let corners = corners(b);
        self.0.iter().all(|pl| {
            let n = pl.xyz();
            let separated = corners.iter().all(|&p| {
                let away = if light.w == 0.0 { -light.xyz() } else { p - light.xyz() / light.w };
                n.dot(p) + pl.w < 0.0 && n.dot(away) < 0.0
            });
            !separated
        })
    }
}

/// The point where three planes (unit normals) meet, or `None` when two are near parallel.
fn meet(a: Vec4, b: Vec4, c: Vec4) -> Option<Vec3> {
    let (na, nb, nc) = (a.xyz(), b.xyz(), c.xyz());
    let det = na.dot(nb.cross(nc));
    if det.abs() < 1e-6 {
        return None;
    }
    let p = (nb.cross(nc) * -a.w + nc.cross(na) * -b.w + na.cross(nb) * -c.w) / det;
    p.is_finite().then_some(p)
}

/// The eight corners of a box.
pub(crate) fn corners(b: &Aabb) -> [Vec3; 8] {
    let (lo, hi) = (b.min, b.max);
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// Why a light cannot add anything to a box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Unreached {
    /// Every point lies at or beyond the light's range.
    Range,
    /// Every point lies outside the spot's outer cone.
    Cone,
}

/// Whether `light` may add something inside `b` (`Err`: certainly not, and why). `margin`
/// widens the range and cone by that fraction (shadow maps: texels next to a lookup count).
pub(crate) fn light_reaches(light: &Light, b: &Aabb, margin: f32) -> Result<(), Unreached> {
    if light.position.w == 0.0 {
        return Ok(());
    }
    let p = light.position.xyz();
    if let Some(range) = light.bounded_range() {
        let nearest = p.clamp(b.min, b.max);
        if nearest.distance(p) >= range * (1.0 + margin) {
            return Err(Unreached::Range);
        }
    }
    if let Some(spot) = light.spot {
        // The box's bounding sphere against the cone: outside when the angle to its centre,
        // less the sphere's angular radius, exceeds the outer angle.
        let (centre, radius) = (b.center(), b.radius());
        let to = centre - p;
        let d = to.length();
        let axis = spot.direction.normalize_or_zero();
        if d > radius && axis != Vec3::ZERO {
            let angle = (to.dot(axis) / d).clamp(-1.0, 1.0).acos();
            let spread = (radius / d).clamp(0.0, 1.0).asin();
            if angle - spread > spot.outer_deg.to_radians() * (1.0 + margin) {
                return Err(Unreached::Cone);
            }
        }
    }
    Ok(())
}

/// Whether the sphere a bounded light reaches may be seen through `planes` (true for
/// unbounded lights).
pub(crate) fn light_may_be_seen(light: &Light, planes: &Planes) -> bool {
    match light.bounded_range() {
        Some(range) => planes.may_hold_sphere(light.position.xyz(), range),
        None => true,
    }
}

/// A bounded light's footprint on a `width` × `height` target: the scissor rectangle
/// (x, y, width, height in pixels, y down) and window-depth range of its range sphere, or
/// `None` when the sphere reaches the camera's near plane (then it may cover anything).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Footprint {
    pub scissor: [u32; 4],
    pub depth: [f32; 2],
}

/// The footprint of `light` seen from `view` on a `width` × `height` target (with a y-up
/// viewport, as the renderer sets it). The sphere's bounding cube in view space is projected:
/// depth grows with view distance, so its corners bound both the rectangle and the depth range.
pub(crate) fn footprint(light: &Light, view: &View, width: u32, height: u32) -> Option<Footprint> {
    let range = light.bounded_range()?;
    let centre = view.view.transform_point3(light.position.xyz());
    // View space looks down -z: the sphere must lie wholly beyond the near plane.
    if -centre.z - range <= view.near {
        return None;
    }
    let proj = view.proj;
    let cube = Aabb { min: centre - Vec3::splat(range), max: centre + Vec3::splat(range) };
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for c in corners(&cube) {
        let ndc = proj.project_point3(c);
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    let (w, h) = (width as f32, height as f32);
    // Viewport y = h, height = -h: NDC y = +1 is row 0.
    let x0 = ((lo.x + 1.0) * 0.5 * w).floor() - 1.0;
    let x1 = ((hi.x + 1.0) * 0.5 * w).ceil() + 1.0;
    let y0 = ((1.0 - hi.y) * 0.5 * h).floor() - 1.0;
    let y1 = ((1.0 - lo.y) * 0.5 * h).ceil() + 1.0;
    let clamp_x = |v: f32| v.clamp(0.0, w) as u32;
    let clamp_y = |v: f32| v.clamp(0.0, h) as u32;
    let (x0, x1, y0, y1) = (clamp_x(x0), clamp_x(x1), clamp_y(y0), clamp_y(y1));
    // A little slack in depth for the GPU's own rounding of the stored depth.
    const DEPTH_SLACK: f32 = 1e-5;
    Some(Footprint {
        scissor: [x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0)],
        depth: [(lo.z - DEPTH_SLACK).clamp(0.0, 1.0), (hi.z + DEPTH_SLACK).clamp(0.0, 1.0)],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use umbra_scene::Camera;

    fn unit_box(at: Vec3) -> Aabb {
        Aabb { min: at - Vec3::splat(0.5), max: at + Vec3::splat(0.5) }
    }

    fn camera() -> Mat4 {
        eye().view_proj(4.0 / 3.0)
    }

    fn eye() -> Camera {
        Camera {
            position: Vec3::new(0.0, 0.0, 10.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: None,
        }
    }

    #[test]
    fn a_clipped_box_keeps_only_what_the_view_holds() {
        let planes = Planes::of(camera(), Clip::All);
        // A 40 m floor quad (flat box): what the camera sees of it is far smaller, and every
        // corner of that part lies on the floor, inside the view.
        let floor = Aabb { min: Vec3::new(-20.0, 0.0, -20.0), max: Vec3::new(20.0, 0.0, 20.0) };
        let part = planes.clip_box(&floor);
        assert!(part.len() >= 3, "{part:?}");
        let seen = part.iter().fold(Aabb::EMPTY, |mut a, &p| {
            a.grow(p);
            a
        });
        assert!(seen.max.x - seen.min.x < 40.0 && seen.max.z - seen.min.z < 40.0, "{seen:?}");
        let loose = Planes(planes.0.iter().map(|pl| *pl + Vec4::W * 1e-3 * pl.xyz().length()).collect());
        for p in &part {
            assert!(p.y.abs() < 1e-4, "{p}");
            assert!(loose.may_hold_box(&Aabb { min: *p, max: *p }), "{p} outside the view");
        }
        // A box the camera cannot see has no part; one wholly inside keeps its eight corners.
        assert!(planes.clip_box(&unit_box(Vec3::new(0.0, 0.0, 20.0))).is_empty());
        let inside = unit_box(Vec3::new(0.0, 0.0, -10.0));
        let whole = planes.clip_box(&inside);
        assert_eq!(whole.len(), 8, "{whole:?}");
        assert!(corners(&inside).iter().all(|c| whole.iter().any(|p| p.distance(*c) < 1e-4)));
    }

    #[test]
    fn boxes_behind_the_camera_or_aside_are_out_of_view() {
        let planes = Planes::of(camera(), Clip::All);
        assert!(planes.may_hold_box(&unit_box(Vec3::ZERO)));
        assert!(!planes.may_hold_box(&unit_box(Vec3::new(0.0, 0.0, 20.0))));
        assert!(!planes.may_hold_box(&unit_box(Vec3::new(40.0, 0.0, 0.0))));
        // Infinite far plane: arbitrarily far along the view is still in.
        assert!(planes.may_hold_box(&unit_box(Vec3::new(0.0, 0.0, -1e6))));
    }

    #[test]
    fn a_sweep_reaches_the_view_only_when_its_shadow_can() {
        let planes = Planes::of(camera(), Clip::Sides);
        let aside = unit_box(Vec3::new(40.0, 0.0, 0.0));
        // Lit from further aside: the shadow falls towards the view.
        assert!(planes.may_hold_sweep(&aside, Vec4::new(80.0, 0.0, 0.0, 1.0)));
        // Lit from the view's side: the shadow falls away from it.
        assert!(!planes.may_hold_sweep(&aside, Vec4::new(0.0, 0.0, 0.0, 1.0)));
        assert!(!planes.may_hold_sweep(&aside, Vec4::new(-1.0, 0.0, 0.0, 0.0)));
        // A light inside the box: its volume goes everywhere.
        assert!(planes.may_hold_sweep(&aside, Vec4::new(40.0, 0.0, 0.0, 1.0)));
    }

    #[test]
    fn range_and_cone_bound_what_a_light_reaches() {
        let mut l = Light::point(Vec3::ZERO, 1.0).with_range(5.0);
        assert_eq!(light_reaches(&l, &unit_box(Vec3::new(5.4, 0.0, 0.0)), 0.0), Ok(()));
        assert_eq!(light_reaches(&l, &unit_box(Vec3::new(5.6, 0.0, 0.0)), 0.0), Err(Unreached::Range));
        l = Light::spot(Vec3::ZERO, -Vec3::Y, 20.0, 30.0, 1.0);
        assert_eq!(light_reaches(&l, &unit_box(Vec3::new(0.0, -4.0, 0.0)), 0.0), Ok(()));
        assert_eq!(light_reaches(&l, &unit_box(Vec3::new(0.0, 4.0, 0.0)), 0.0), Err(Unreached::Cone));
        assert_eq!(light_reaches(&l, &unit_box(Vec3::new(4.0, -1.0, 0.0)), 0.0), Err(Unreached::Cone));
        // Directional lights reach everything.
        let d = Light::directional(Vec3::Y, 1.0);
        assert_eq!(light_reaches(&d, &unit_box(Vec3::splat(1e6)), 0.0), Ok(()));
    }

    #[test]
    fn a_footprint_holds_the_projected_sphere() {
        let l = Light::point(Vec3::new(1.0, 0.5, 0.0), 1.0).with_range(1.0);
        let vp = camera();
        let f = footprint(&l, &View::of_camera(&eye(), 256.0 / 192.0), 256, 192).unwrap();
        let [x, y, w, h] = f.scissor;
        assert!(w > 0 && h > 0 && w < 256 && h < 192, "{f:?}");
        // Points on the sphere project inside the rectangle and depth range.
        for k in 0..200 {
            let t = k as f32 * 0.7;
            let dir = Vec3::new(t.cos() * (t * 0.3).sin(), (t * 0.3).cos(), t.sin() * (t * 0.3).sin());
            let clip = vp * (l.position.xyz() + dir).extend(1.0);
            let ndc = clip.xyz() / clip.w;
            let px = (ndc.x + 1.0) * 0.5 * 256.0;
            let py = (1.0 - ndc.y) * 0.5 * 192.0;
            assert!(px >= x as f32 && px <= (x + w) as f32 && py >= y as f32 && py <= (y + h) as f32);
            assert!(ndc.z >= f.depth[0] && ndc.z <= f.depth[1]);
        }
        // A sphere around the camera covers anything.
        let around = Light::point(Vec3::new(0.0, 0.0, 9.0), 1.0).with_range(2.0);
        assert!(footprint(&around, &View::of_camera(&eye(), 256.0 / 192.0), 256, 192).is_none());
    }
}

//! Light frusta: which view-projections a light's shadow map is rendered with.
//!
//! - directional: an orthographic box fitted to where casters can shadow what the camera sees
//!   of the receivers (their light-space xy overlap; depth from the nearest caster to the
//!   farthest of both);
//! - spot: a perspective frustum around the cone (2 × outer angle plus a margin, so the
//!   frustum's border lies outside the lit cone); cones wider than 80° use a cube map;
//! - point: six 90° faces of a cube map (Arneson §3), oriented as Vulkan samples cube maps.

use crate::reach::{Clip, Planes};
use glam::{Mat4, Vec3, Vec4, Vec4Swizzles};
use umbra_scene::{Aabb, Light, LightKind, Scene};

/// Spot cones wider than this (half-angle, degrees) get a cube map.
const MAX_SPOT_DEG: f32 = 80.0;
/// Extra degrees around a spot cone, so its edge never meets the frustum border.
const SPOT_MARGIN_DEG: f32 = 2.0;

/// Single map, cube map, or face atlas.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MapKind {
    /// One 2D map (spot, directional).
    Single,
    /// Six faces (point, wide spot).
    Cube,
    /// Six faces widened by a border, side by side in one 2D map (`atlas.rs`): a cube for the
    /// silhouette map.
    FaceAtlas,
}

impl MapKind {
    /// `GpuShadow::kind` (`gpu_scene.rs`) of a map of this kind, with or without a silhouette
    /// map: the shaders' `SHADOW_2D` (1), `SHADOW_CUBE` (2), `SHADOW_SILHOUETTE` (3) and
    /// `SHADOW_SILHOUETTE_CUBE` (4).
    pub(crate) fn shader_kind(self, silhouette: bool) -> u32 {
        match (self, silhouette) {
            (Self::Single, false) => 1,
            (Self::Cube, _) => 2,
            (Self::Single, true) => 3,
            (Self::FaceAtlas, _) => 4,
        }
    }

    /// Whether the map has six faces (a cube map or a face atlas).
    pub fn is_cube(self) -> bool {
        self != Self::Single
    }

    /// Views (faces) of a map of this kind.
    pub fn views(self) -> u32 {
        if self.is_cube() {
            super::atlas::FACES
        } else {
            1
        }
    }

    /// Texels per side of one view's clip square, for a map of `resolution`: a face atlas's
    /// faces carry their borders.
    pub fn view_side(self, resolution: u32) -> u32 {
        match self {
            Self::FaceAtlas => super::atlas::face_side(resolution),
            Self::Single | Self::Cube => resolution,
        }
    }

    /// Width and height of one 2D image (or of each layer of a cube map) of a map of
    /// `resolution`.
    pub fn extent(self, resolution: u32) -> (u32, u32) {
        match self {
            Self::FaceAtlas => super::atlas::extent(resolution),
            Self::Single | Self::Cube => (resolution, resolution),
        }
    }
}

/// The views a light's shadow map needs.
#[derive(Clone, Debug)]
pub(crate) struct LightViews {
    pub kind: MapKind,
    /// One view-projection per map layer.
    pub views: Vec<Mat4>,
    /// Near and far distances (perspective: from the light; orthographic: along its rays).
    pub near: f32,
    pub far: f32,
    /// Objects that cast into this map, nearest to the light first.
    pub casters: Vec<usize>,
    /// Per view, the casters that may touch it (`cull_per_view`); `None`: all of `casters`.
    pub view_casters: Option<Vec<Vec<usize>>>,
    /// The boxes of the visible receivers the fit used (those that may intersect the camera's
    /// frustum), in world space.
    pub receivers: Vec<Aabb>,
}

impl LightViews {
    /// Views of `kind` with their depth range; casters and receivers are filled in by `fit`.
    fn new(kind: MapKind, views: Vec<Mat4>, near: f32, far: f32) -> Self {
        Self { kind, views, near, far, casters: Vec::new(), view_casters: None, receivers: Vec::new() }
    }

    /// Turns cube views into a face atlas of `resolution` interior texels per face
    /// ([`super::atlas::widen`]); other views are left as they are. Call before
    /// [`Self::cull_per_view`], so each face keeps the casters its border sees.
    pub fn widen_to_face_atlas(&mut self, resolution: u32) {
        if self.kind == MapKind::Cube {
            super::atlas::widen(&mut self.views, resolution);
            self.kind = MapKind::FaceAtlas;
        }
    }

    /// The casters drawn into view `layer`.
    pub fn casters_of(&self, layer: usize) -> &[usize] {
        match &self.view_casters {
            Some(v) => v.get(layer).map_or(&[], Vec::as_slice),
            None => &self.casters,
        }
    }

    /// Keeps, per view, only the casters whose bounds may touch it (its side planes: the
    /// hardware would clip the rest, so the map is unchanged). Returns the (caster, view)
    /// pairs left out.
    pub fn cull_per_view(&mut self, boxes: &[Option<Aabb>]) -> usize {
        let mut culled = 0;
        let per_view = self
            .views
            .iter()
            .map(|&vp| {
                let planes = Planes::of(vp, Clip::Sides);
                let kept: Vec<usize> = self
                    .casters
                    .iter()
                    .copied()
                    .filter(|&c| boxes.get(c).copied().flatten().is_none_or(|b| planes.may_hold_box(&b)))
                    .collect();
                culled += self.casters.len() - kept.len();
                kept
            })
            .collect();
        self.view_casters = Some(per_view);
        culled
    }
}

/// Fits the views of `light`, or `None` when no caster can shadow a visible receiver. `boxes`
/// holds each object's world bounds (`Scene::object_bounds`).
///
/// Only what the camera sees sizes the map: each receiver's box is cut to the camera's
/// frustum (a 40 m floor becomes the few metres in view). A directional light keeps only the
/// casters that can shadow such a part (they overlap it as the light sees it and reach nearer
/// the light than its farthest point), and its map covers where they overlap, so every visible
/// receiver point a caster can shadow lies inside it and any other is lit whatever the map
/// holds. A spot light keeps the same casters (cut to its cone), its near plane in front of
/// them, but its map keeps the cone's extent; point lights keep every caster and their cube.
/// Far planes reach the farthest seen part.
pub(crate) fn fit(light: &Light, scene: &Scene, boxes: &[Option<Aabb>], camera_view_proj: Mat4) -> Option<LightViews> {
    let bounds = |i: usize| boxes.get(i).copied().flatten();
    let casters: Vec<(usize, Aabb)> = (0..scene.objects.len())
        .filter(|&i| scene.objects[i].casts_shadows)
        .filter_map(|i| Some((i, bounds(i)?)))
        .collect();
    let view = Planes::of(camera_view_proj, Clip::All);
    let receivers: Vec<Aabb> = (0..scene.objects.len())
        .filter(|&i| scene.objects[i].receives_shadows)
        .filter_map(bounds)
        .filter(|b| view.may_hold_box(b))
        .collect();
    if casters.is_empty() || receivers.is_empty() {
        return None;
    }
    let (mut fitted, kept) = match light.kind() {
        LightKind::Directional => directional(light.position.xyz(), &casters, &receivers, &view)?,
        LightKind::Spot if light.spot.is_some_and(|s| s.outer_deg <= MAX_SPOT_DEG) => {
            spot(light, &casters, &receivers, &view)?
        }
        LightKind::Spot | LightKind::Point => {
            let seen = seen_parts(&receivers, &view);
            if seen.is_empty() {
                return None;
            }
            let all: Vec<Aabb> = casters.iter().map(|c| c.1).collect();
            let mut cube = cube(light.position.xyz(), &all, &seen);
            cube.receivers = seen;
            (cube, casters.iter().map(|c| c.0).collect())
        }
    };
    // Front to back from the light: cheap, and it lets early depth reject hidden casters.
    let key = |i: &usize| {
        let c = bounds(*i).map(|b| b.center()).unwrap_or_default();
        if light.position.w == 0.0 {
            -c.dot(light.position.xyz())
        } else {
            c.distance_squared(light.position.xyz())
        }
    };
    let mut order = kept;
    order.sort_by(|a, b| key(a).total_cmp(&key(b)));
    fitted.casters = order;
    Some(fitted)
}

/// The world boxes of what `planes` hold of each of `receivers` (those with no part left out).
fn seen_parts(receivers: &[Aabb], planes: &Planes) -> Vec<Aabb> {
    world_boxes(&cut(receivers, planes))
}

/// The world box of each part.
fn world_boxes(parts: &[Vec<Vec3>]) -> Vec<Aabb> {
    parts.iter().filter_map(|part| bounds_of(part, &Mat4::IDENTITY)).collect()
}

/// The corners of what `planes` hold of each box (boxes with no part left out).
fn cut(boxes: &[Aabb], planes: &Planes) -> Vec<Vec<Vec3>> {
    boxes.iter().map(|b| planes.clip_box(b)).filter(|part| !part.is_empty()).collect()
}

/// The box of `points` transformed by `m` (`None` for no point).
fn bounds_of(points: &[Vec3], m: &Mat4) -> Option<Aabb> {
    let mut b = Aabb::EMPTY;
    points.iter().for_each(|p| b.grow(m.transform_point3(*p)));
    (!b.is_empty()).then_some(b)
}

/// Where casters can shadow seen receivers, as the light sees them: boxes in a space whose
/// x and y say which light ray a point lies on and whose z is its depth along the rays
/// (larger: farther from the light).
struct Overlap {
    /// The xy of every kept caster's box intersected with the receivers' it can shadow, and
    /// depth from the nearest kept caster to the farthest of those and their receivers.
    region: Aabb,
    /// Indices of the casters that can shadow some receiver.
    kept: Vec<usize>,
}

/// A caster can shadow a receiver when their boxes overlap in xy and the caster reaches
/// nearer the light than the receiver's farthest point.
fn overlap(casters: &[Aabb], receivers: &[Aabb]) -> Option<Overlap> {
    let mut out = Overlap { region: Aabb::EMPTY, kept: Vec::new() };
    for (i, c) in casters.iter().enumerate() {
        let mut any = false;
        for r in receivers {
            let (min, max) = (c.min.max(r.min), c.max.min(r.max));
            if min.x > max.x || min.y > max.y || c.min.z >= r.max.z {
                continue;
            }
            any = true;
            out.region.grow(min.truncate().extend(c.min.z));
            out.region.grow(max.truncate().extend(c.max.z.max(r.max.z)));
        }
        if any {
            out.kept.push(i);
        }
    }
    (!out.kept.is_empty()).then_some(out)
}

fn directional(
    towards_light: Vec3,
    casters: &[(usize, Aabb)],
    receivers: &[Aabb],
    view: &Planes,
) -> Option<(LightViews, Vec<usize>)> {
    let parts = cut(receivers, view);
    let seen = world_boxes(&parts);
    let all = casters.iter().map(|c| &c.1).chain(&seen).fold(Aabb::EMPTY, |a, b| a.union(*b));
    let dir = towards_light.normalize();
    let eye = all.center() + dir * (2.0 * all.radius() + 1.0);
    let light_view = Mat4::look_at_rh(eye, all.center(), any_up(dir));
    // Light space with depth along the rays (view space looks down -z).
    let flip = Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)) * light_view;
    let cs: Vec<Aabb> = casters.iter().map(|c| c.1.transformed(&flip)).collect();
    let rs: Vec<Aabb> = parts.iter().filter_map(|part| bounds_of(part, &flip)).collect();
    let Overlap { region, kept } = overlap(&cs, &rs)?;
    let (min, max) = (region.min, region.max);
    let pad = (max - min) * 0.01 + Vec3::splat(1e-4);
    let depth_pad = (max.z - min.z) * 0.01 + 1e-3;
    let (near, far) = (min.z - depth_pad, max.z + depth_pad);
    let proj = Mat4::orthographic_rh(min.x - pad.x, max.x + pad.x, min.y - pad.y, max.y + pad.y, near, far);
    let mut views = LightViews::new(MapKind::Single, vec![proj * light_view], near, far);
    views.receivers = seen;
    Some((views, kept.into_iter().map(|k| casters[k].0).collect()))
}

/// The far distance from `p` that holds every caster and receiver (a view's depth never
/// exceeds the Euclidean distance).
fn far_from(p: Vec3, casters: &[Aabb], receivers: &[Aabb]) -> f32 {
    let far_corner = |b: &Aabb| (p - b.min).abs().max((p - b.max).abs()).length();
    casters.iter().chain(receivers).map(far_corner).fold(0.0f32, f32::max) * 1.01 + 1e-3
}

/// A near plane in front of every caster's nearest `depth`, but not so close that depth
/// precision collapses: 90% of the nearest caster, at least far / 10^4.
fn near_plane(nearest_caster: f32, far: f32) -> (f32, f32) {
    let near = (nearest_caster * 0.9).max(far * 1e-4);
    (near, far.max(near * 2.0))
}

/// Spot lights: a perspective frustum around the cone (2 × outer angle plus a margin, so the
/// cone's edge never meets the map's border) over the casters that can shadow what the camera
/// sees of a receiver inside the cone: as the light sees them (directions x/depth, y/depth and
/// depth along the axis, every part first cut to the cone) they overlap such a part and reach
/// nearer the light than its farthest point. The near plane sits in front of the nearest kept
/// caster part, the far plane beyond the farthest seen part. Cutting the frustum off-axis to
/// that overlap as well waits for a bias that holds at hard case 07's coordinates
/// (docs/techniques/shadow-maps.md: the narrower window's smaller texels shrink the
/// slope-scaled bias below the depth error of its huge, clipped floor triangles).
fn spot(
    light: &Light,
    casters: &[(usize, Aabb)],
    receivers: &[Aabb],
    view: &Planes,
) -> Option<(LightViews, Vec<usize>)> {
    let p = light.position.xyz();
    let s = light.spot.unwrap_or(umbra_scene::Spot { direction: -Vec3::Y, inner_deg: 30.0, outer_deg: 30.0 });
    let axis = s.direction.normalize();
    let fov = (2.0 * (s.outer_deg + SPOT_MARGIN_DEG)).to_radians();
    let light_view = Mat4::look_at_rh(p, p + axis, any_up(axis));
    let cone = Planes::of(Mat4::perspective_rh(fov, 1.0, 1.0, 2.0) * light_view, Clip::Sides);
    let t = (fov * 0.5).tan();
    // A part reaching the light itself spans every direction of the cone.
    let directions = |points: &[Vec3]| {
        let mut b = Aabb::EMPTY;
        for q in points {
            let v = light_view.transform_point3(*q);
            let depth = -v.z;
            if depth > 1e-6 * t {
                b.grow((v.truncate() / depth).extend(depth));
            } else {
                b.grow(Vec3::new(-t, -t, 0.0));
                b.grow(Vec3::new(t, t, 0.0));
            }
        }
        (!b.is_empty()).then_some(b)
    };
    let cs: Vec<Aabb> = casters.iter().map(|c| directions(&cone.clip_box(&c.1)).unwrap_or(Aabb::EMPTY)).collect();
    let parts = cut(receivers, &view.and(&cone));
    let rs: Vec<Aabb> = parts.iter().filter_map(|part| directions(part)).collect();
    let Overlap { region, kept } = overlap(&cs, &rs)?;
    let seen = world_boxes(&parts);
    let kept_boxes: Vec<Aabb> = kept.iter().map(|&k| casters[k].1).collect();
    let (near, far) = near_plane(region.min.z, far_from(p, &kept_boxes, &seen));
    let proj = Mat4::perspective_rh(fov, 1.0, near, far);
    let mut views = LightViews::new(MapKind::Single, vec![proj * light_view], near, far);
    views.receivers = seen;
    Some((views, kept.into_iter().map(|k| casters[k].0).collect()))
}

/// Right, up and forward of the six cube faces in Vulkan's layer order (+X, -X, +Y, -Y, +Z,
/// -Z), such that rendering with umbra's y-up viewport stores texel (s, t) where
/// `texture(samplerCube, v)` reads it (Vulkan spec, "Cube Map Face Selection").
pub(crate) const CUBE_FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    (Vec3::Z, Vec3::Y, Vec3::NEG_X),
    (Vec3::X, Vec3::NEG_Z, Vec3::Y),
    (Vec3::X, Vec3::Z, Vec3::NEG_Y),
    (Vec3::X, Vec3::Y, Vec3::Z),
    (Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z),
];

fn cube(p: Vec3, casters: &[Aabb], receivers: &[Aabb]) -> LightViews {
    // A point's depth in the face it falls in is its major-axis distance |v|_inf, so the near
    // plane must lie inside the L-infinity distance to every caster, not the Euclidean one (a
    // caster corner on a face seam is sqrt(2) nearer along the axis than in distance).
    let linf = |b: &Aabb| (b.min - p).max(p - b.max).max(Vec3::ZERO).max_element();
    let nearest = casters.iter().map(linf).fold(f32::INFINITY, f32::min);
    let (near, far) = near_plane(nearest, far_from(p, casters, receivers));
    let proj = Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, near, far);
    let views = CUBE_FACES
        .iter()
        .map(|&(r, u, f)| {
            // Rows r, u, -f: a mirrored basis, as cube faces are; the shadow pass culls nothing.
            let view = Mat4::from_cols(
                Vec4::new(r.x, u.x, -f.x, 0.0),
                Vec4::new(r.y, u.y, -f.y, 0.0),
                Vec4::new(r.z, u.z, -f.z, 0.0),
                Vec4::new(-r.dot(p), -u.dot(p), f.dot(p), 1.0),
            );
            proj * view
        })
        .collect();
    LightViews::new(MapKind::Cube, views, near, far)
}

fn any_up(dir: Vec3) -> Vec3 {
    if dir.normalize().y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reach::corners;
    use crate::shadow_map::texels::texel_size;
    use umbra_scene::Camera;

    /// Vulkan's cube face selection: (face, sc, tc, ma) for a direction.
    fn select_face(v: Vec3) -> (usize, f32, f32, f32) {
        let a = v.abs();
        if a.x >= a.y && a.x >= a.z {
            if v.x > 0.0 {
                (0, -v.z, -v.y, a.x)
            } else {
                (1, v.z, -v.y, a.x)
            }
        } else if a.y >= a.z {
            if v.y > 0.0 {
                (2, v.x, v.z, a.y)
            } else {
                (3, v.x, -v.z, a.y)
            }
        } else if v.z > 0.0 {
            (4, v.x, -v.y, a.z)
        } else {
            (5, -v.x, -v.y, a.z)
        }
    }

    #[test]
    fn cube_faces_store_each_direction_where_the_sampler_reads_it() {
        let p = Vec3::new(1.0, 2.0, -3.0);
        let boxes = [Aabb { min: Vec3::splat(-10.0), max: Vec3::splat(10.0) }];
        let views = cube(p, &boxes, &boxes);
        let mut seed = 12345u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        // Every caster must lie beyond the near plane in the face that holds it.
        let seam_box = Aabb { min: Vec3::new(1.9, 1.9, -3.0), max: Vec3::new(2.4, 2.4, -2.5) };
        let near_test = cube(p, &[seam_box], &boxes);
        let nearest_corner = Vec3::new(1.9, 1.9, -3.0) - p;
        assert!(near_test.near < nearest_corner.abs().max_element(), "near {} clips the seam box", near_test.near);
        for _ in 0..500 {
            let v = Vec3::new(rnd(), rnd(), rnd()) * 3.0;
            if v.length() < 0.2 {
                continue;
            }
            let (face, sc, tc, ma) = select_face(v);
            let clip = views.views[face] * (p + v).extend(1.0);
            let ndc = clip.xyz() / clip.w;
            // The shadow pass's y-up viewport stores NDC (x, y) at s = (x+1)/2, t = (1-y)/2;
            // the sampler reads s = (sc/ma+1)/2, t = (tc/ma+1)/2.
            assert!((ndc.x - sc / ma).abs() < 1e-4, "face {face} x: {} vs {}", ndc.x, sc / ma);
            assert!((-ndc.y - tc / ma).abs() < 1e-4, "face {face} y: {} vs {}", -ndc.y, tc / ma);
            // The lookup shader's depth formula (lookup.glsl, lookup_cube).
            let (n, f) = (views.near, views.far);
            let expected = f / (f - n) * (1.0 - n / ma);
            assert!((ndc.z - expected).abs() < 1e-4, "depth {} vs {expected}", ndc.z);
        }
    }

    /// A camera 3 m above a 40 m floor looking at the origin: it sees a few metres of it.
    fn camera() -> Planes {
        let eye = Camera {
            position: Vec3::new(0.0, 3.0, 4.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: None,
        };
        Planes::of(eye.view_proj(4.0 / 3.0), Clip::All)
    }

    const FLOOR: Aabb = Aabb { min: Vec3::new(-20.0, -0.1, -20.0), max: Vec3::new(20.0, 0.0, 20.0) };

    /// Whether the segment from `a` to `b` meets box `c` (slab test).
    fn segment_meets(a: Vec3, b: Vec3, c: &Aabb) -> bool {
        let d = b - a;
        let (t0, t1) = (((c.min - a) / d), ((c.max - a) / d));
        let (lo, hi) = (t0.min(t1).max_element(), t0.max(t1).min_element());
        lo <= hi && hi >= 0.0 && lo <= 1.0
    }

    /// Every floor point the camera sees that a caster box can shadow lies inside the map.
    fn shadowed_floor_lies_in_the_map(light: Vec4, views: &LightViews, casters: &[Aabb]) {
        let seen = camera();
        let mut inside = 0;
        for i in 0..=200 {
            for j in 0..=200 {
                let q = Vec3::new(-20.0 + 0.2 * i as f32, 0.0, -20.0 + 0.2 * j as f32);
                let towards = if light.w == 0.0 { q + light.xyz() * 100.0 } else { light.xyz() };
                if !seen.may_hold_box(&Aabb { min: q, max: q }) || !casters.iter().any(|c| segment_meets(q, towards, c))
                {
                    continue;
                }
                let clip = views.views[0] * q.extend(1.0);
                let ndc = clip.xyz() / clip.w;
                assert!(clip.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0, "{q} -> {ndc} outside the map");
                inside += 1;
            }
        }
        assert!(inside > 10, "the test saw only {inside} shadowed points");
    }

    #[test]
    fn directional_fit_covers_what_the_camera_sees_of_the_floor_only() {
        let caster = Aabb { min: Vec3::new(-0.5, 0.5, -0.5), max: Vec3::new(0.5, 1.0, 0.5) };
        let far_away = Aabb { min: Vec3::new(15.0, 1.0, 15.0), max: Vec3::new(16.0, 2.0, 16.0) };
        let towards = Vec3::new(0.3, 1.0, 0.2);
        let (v, kept) = directional(towards, &[(0, caster), (1, far_away)], &[FLOOR], &camera()).unwrap();
        // The caster far out of view shadows nothing the camera sees: not drawn, not fitted.
        assert_eq!(kept, vec![0]);
        let [w, h] = texel_size(v.views[0], 1);
        assert!(w < 3.0 && h < 3.0, "map spans {w} x {h}: the whole floor sized it");
        for c in corners(&caster) {
            let ndc = v.views[0].project_point3(c);
            assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z), "{c} -> {ndc}");
        }
        shadowed_floor_lies_in_the_map(towards.extend(0.0), &v, &[caster]);
        // With only the far caster nothing visible can be shadowed.
        assert!(directional(towards, &[(1, far_away)], &[FLOOR], &camera()).is_none());
    }

    #[test]
    fn spot_fit_keeps_the_casters_that_can_shadow_what_the_camera_sees() {
        let caster = Aabb { min: Vec3::new(-0.3, 1.0, -0.3), max: Vec3::new(0.3, 1.2, 0.3) };
        // Inside the cone, but its shadow falls on the floor far out of view.
        let aside = Aabb { min: Vec3::new(5.0, 1.0, -5.5), max: Vec3::new(5.5, 1.5, -5.0) };
        let light = Light::spot(Vec3::new(0.5, 4.0, 0.5), -Vec3::Y, 60.0, 70.0, 1.0);
        let (v, kept) = spot(&light, &[(0, caster), (1, aside)], &[FLOOR], &camera()).unwrap();
        assert_eq!(kept, vec![0]);
        shadowed_floor_lies_in_the_map(light.position, &v, &[caster]);
        // The near plane sits in front of the kept caster's top (2.8 below the light), not at
        // a ten-thousandth of the far plane.
        assert!(v.near > 2.0 && v.near < 2.8, "near {}", v.near);
        assert!(spot(&light, &[(1, aside)], &[FLOOR], &camera()).is_none());
    }
}

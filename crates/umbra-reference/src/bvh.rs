//! Every triangle of a scene in world space, in an obvhs compressed wide BVH (CWBVH, built in
//! parallel), with exact ray queries: the nearest hit of a camera ray and whether a shadow ray
//! is blocked. Triangles are tested in double precision with a watertight test (Woop, Benthin
//! and Wald 2013), so a ray through an edge shared by two triangles of a closed mesh always
//! hits one of them: the reference never leaks light between triangles.

use glam::{DVec3, Vec3};
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use std::time::{Duration, Instant};
use umbra_scene::Scene;

/// One world-space triangle and the object it came from.
#[derive(Clone, Copy, Debug)]
pub struct SceneTriangle {
    /// Vertices in world space, in the mesh's winding.
    pub vertices: [Vec3; 3],
    /// Index of the object in `scene.objects`.
    pub object: usize,
    /// Whether the object casts shadows (shadow rays ignore the others).
    pub casts_shadows: bool,
}

impl SceneTriangle {
    /// The unit geometric normal (by winding), or zero for a degenerate triangle.
    pub fn normal(&self) -> Vec3 {
        let [a, b, c] = self.vertices;
        (b - a).cross(c - a).normalize_or_zero()
    }
}

/// A ray's nearest hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f32,
    /// Index into [`SceneBvh::triangles`].
    pub triangle: usize,
}

/// The scene's triangles and their BVH.
pub struct SceneBvh {
    triangles: Vec<SceneTriangle>,
    bvh: Option<CwBvh>,
    build_ms: f64,
}

impl SceneBvh {
    /// Builds the BVH over every triangle of every object (rayon threads).
    pub fn build(scene: &Scene) -> Self {
        let started = Instant::now();
        let mut triangles = Vec::with_capacity(scene.triangle_count());
        for (object, o) in scene.objects.iter().enumerate() {
            let Some(mesh) = scene.meshes.get(o.mesh) else { continue };
            for t in mesh.indices.chunks_exact(3) {
                let vertex = |k: usize| o.transform.transform_point3(mesh.positions[t[k] as usize]);
                triangles.push(SceneTriangle {
                    vertices: [vertex(0), vertex(1), vertex(2)],
                    object,
                    casts_shadows: o.casts_shadows,
                });
            }
        }
        let bvh = (!triangles.is_empty()).then(|| {
            let boxes: Vec<Triangle> = triangles
                .iter()
                .map(|t| {
                    let [v0, v1, v2] = t.vertices.map(to_obvhs);
                    Triangle { v0, v1, v2 }
                })
                .collect();
            // No spatial splits: each leaf entry is one input triangle.
            build_cwbvh_from_tris(&boxes, BvhBuildParams::medium_build(), &mut Duration::default())
        });
        Self { triangles, bvh, build_ms: started.elapsed().as_secs_f64() * 1e3 }
    }

    /// The scene's triangles, in object order.
    pub fn triangles(&self) -> &[SceneTriangle] {
        &self.triangles
    }

    /// Wall time of [`SceneBvh::build`], in milliseconds.
    pub fn build_ms(&self) -> f64 {
        self.build_ms
    }

    /// The nearest triangle hit by `origin + t * dir` with `t` in `(0, t_max)`; `dir` must be
    /// a unit vector.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = WatertightRay::new(origin, dir);
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(obvhs_ray(origin, dir, t_max), &mut hit, |r, id| {
            let triangle = &self.triangles[bvh.primitive_indices[id] as usize];
            ray.intersect(triangle, f64::from(r.tmax))
        });
        found.then(|| Hit { t: hit.t, triangle: bvh.primitive_indices[hit.primitive_id as usize] as usize })
    }

    /// Whether a triangle of a shadow-casting object lies on `origin + t * dir` with `t` in
    /// `(0, t_max)`; `dir` must be a unit vector.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let Some(bvh) = self.bvh.as_ref() else { return false };
        let ray = WatertightRay::new(origin, dir);
        !bvh.ray_traverse_miss(obvhs_ray(origin, dir, t_max), |r, id| {
            let triangle = &self.triangles[bvh.primitive_indices[id] as usize];
            if !triangle.casts_shadows {
                return f32::INFINITY;
            }
            ray.intersect(triangle, f64::from(r.tmax))
        })
    }

    /// Every triangle of a shadow-casting object on `origin + t * dir` with `t` in
    /// `(0, t_max)`, in no particular order; `dir` must be a unit vector.
    pub fn blockers(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Vec<usize> {
        let mut out = Vec::new();
        let Some(bvh) = self.bvh.as_ref() else { return out };
        let ray = WatertightRay::new(origin, dir);
        bvh.ray_traverse_miss(obvhs_ray(origin, dir, t_max), |r, id| {
            let index = bvh.primitive_indices[id] as usize;
            let triangle = &self.triangles[index];
            if triangle.casts_shadows && ray.intersect(triangle, f64::from(r.tmax)).is_finite() {
                out.push(index);
            }
            // Never report a hit, so the walk visits every triangle on the ray.
            f32::INFINITY
        });
        out
    }
}

fn to_obvhs(v: Vec3) -> obvhs_glam::Vec3A {
    obvhs_glam::Vec3A::new(v.x, v.y, v.z)
}

fn obvhs_ray(origin: Vec3, dir: Vec3, t_max: f32) -> Ray {
    // `+ 0.0` turns -0.0 into +0.0: obvhs 0.4 picks the traversal octant from the sign bits
    // but inverts -0.0 to a positive infinity stand-in, and then misses every box (seen with
    // a ray straight down, `-Vec3::Y`).
    Ray::new(to_obvhs(origin), to_obvhs(dir + Vec3::ZERO), 0.0, t_max)
}

/// A ray set up for the watertight test: the axis where the direction is largest becomes z,
/// and a shear maps the direction onto +z, so each edge test is a 2D signed area at the origin.
struct WatertightRay {
    origin: DVec3,
    /// Permutation of the axes: x, y, then z (the dominant one).
    axes: [usize; 3],
    shear: DVec3,
}

impl WatertightRay {
    fn new(origin: Vec3, dir: Vec3) -> Self {
        let d = dir.as_dvec3();
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Keep the winding: swapping x and y when the dominant component is negative.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = DVec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        Self { origin: origin.as_dvec3(), axes: [kx, ky, kz], shear }
    }

    /// The hit distance in `(0, t_max]`, or infinity.
    fn intersect(&self, triangle: &SceneTriangle, t_max: f64) -> f32 {
        let [kx, ky, kz] = self.axes;
        let s = self.shear;
        let sheared = |v: Vec3| {
            let p = v.as_dvec3() - self.origin;
            DVec3::new(p[kx] - s.x * p[kz], p[ky] - s.y * p[kz], s.z * p[kz])
        };
        let [a, b, c] = triangle.vertices.map(sheared);
        // Signed areas of the edges seen from the ray (exact enough in f64 for f32 inputs).
        let u = c.x * b.y - c.y * b.x;
        let v = a.x * c.y - a.y * c.x;
        let w = b.x * a.y - b.y * a.x;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return f32::INFINITY;
        }
        let det = u + v + w;
        if det == 0.0 {
            return f32::INFINITY;
        }
        let t = (u * a.z + v * b.z + w * c.z) / det;
        if t > 0.0 && t <= t_max {
            t as f32
        } else {
            f32::INFINITY
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use umbra_scene::{primitives, Mesh};

    fn quad_scene() -> Scene {
        let mut scene = Scene::new("quad");
        // Two triangles sharing the diagonal from (-1, 0, -1) to (1, 0, 1).
        let positions = [
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 1.0),
        ];
        let mesh = Mesh::with_flat_normals("quad", &positions, &[0, 2, 1, 0, 3, 2]).expect("valid quad");
        let m = scene.add_mesh(mesh);
        scene.add_object(m, Mat4::IDENTITY, Vec3::ONE);
        scene
    }

    #[test]
    fn rays_through_a_shared_edge_always_hit() {
        let bvh = SceneBvh::build(&quad_scene());
        // The diagonal, corners excepted (an axis-parallel ray on a box face is a tie).
        for i in 1..200 {
            let s = -1.0 + 2.0 * i as f32 / 200.0;
            let origin = Vec3::new(s, 3.0, s);
            assert!(bvh.occluded(origin, -Vec3::Y, 10.0), "ray at {s} leaked through the diagonal");
            let hit = bvh.closest_hit(origin, -Vec3::Y, f32::INFINITY).expect("hit");
            assert!((hit.t - 3.0).abs() < 1e-5);
        }
        assert!(!bvh.occluded(Vec3::new(1.01, 3.0, 0.0), -Vec3::Y, 10.0));
        assert!(!bvh.occluded(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y, 2.9), "t_max must stop the ray");
    }

    #[test]
    fn nearest_of_stacked_boxes_and_non_casters() {
        let mut scene = Scene::new("stack");
        let cube = scene.add_mesh(primitives::cuboid(Vec3::splat(0.5)));
        scene.add_object(cube, Mat4::from_translation(Vec3::new(0.0, 0.0, 0.0)), Vec3::ONE);
        scene.add_object(cube, Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0)), Vec3::ONE).casts_shadows = false;
        let bvh = SceneBvh::build(&scene);
        let hit = bvh.closest_hit(Vec3::new(0.1, 10.0, 0.1), -Vec3::Y, f32::INFINITY).expect("hit");
        assert!((hit.t - 6.5).abs() < 1e-5, "{hit:?}");
        assert_eq!(bvh.triangles()[hit.triangle].object, 1);
        // The upper cube casts no shadow: only the lower one blocks.
        assert!(bvh.occluded(Vec3::new(0.1, 10.0, 0.1), -Vec3::Y, 20.0));
        assert!(!bvh.occluded(Vec3::new(0.1, 10.0, 0.1), -Vec3::Y, 8.0));
        // Every casting triangle on the ray: the lower cube's top and bottom, not the upper's;
        // on a face's diagonal, both its triangles (the test is watertight).
        let off_diagonal = Vec3::new(0.1, 10.0, 0.2);
        let all = bvh.blockers(off_diagonal, -Vec3::Y, 20.0);
        assert_eq!(all.len(), 2, "{all:?}");
        assert!(all.iter().all(|&t| bvh.triangles()[t].object == 0));
        assert_eq!(bvh.blockers(off_diagonal, -Vec3::Y, 10.0).len(), 1, "t_max stops the walk");
        assert!(bvh.blockers(off_diagonal, -Vec3::Y, 8.0).is_empty());
        assert_eq!(bvh.blockers(Vec3::new(0.1, 10.0, 0.1), -Vec3::Y, 10.0).len(), 2, "the top's two halves");
    }
}

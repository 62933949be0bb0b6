//! A scene: meshes, placed objects, lights, a camera.

use crate::{Aabb, Camera, Light, Mesh};
use glam::{Mat4, Vec3};

/// One placed instance of a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Object-to-world transform.
    pub transform: Mat4,
    /// Linear RGB diffuse reflectance.
    pub albedo: Vec3,
    /// Whether it occludes lights (is a shadow caster).
    pub casts_shadows: bool,
    /// Whether shadows fall on it.
    pub receives_shadows: bool,
}

/// Everything a frame renders.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Name (procedural name or file stem).
    pub name: String,
    /// Mesh library; objects refer to it by index.
    pub meshes: Vec<Mesh>,
    /// Placed objects.
    pub objects: Vec<Object>,
    /// Lights.
    pub lights: Vec<Light>,
    /// The camera.
    pub camera: Camera,
    /// Linear RGB ambient light (added once, unshadowed).
    pub ambient: Vec3,
    /// Linear RGB clear colour.
    pub background: Vec3,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            name: "scene".into(),
            meshes: Vec::new(),
            objects: Vec::new(),
            lights: Vec::new(),
            camera: Camera::look_at(Vec3::new(0.0, 2.0, 6.0), Vec3::ZERO),
            ambient: Vec3::splat(0.08),
            background: Vec3::new(0.02, 0.02, 0.03),
        }
    }
}

impl Scene {
    /// An empty scene with defaults (camera, ambient, background).
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Default::default() }
    }

    /// Adds a mesh to the library and returns its index.
    pub fn add_mesh(&mut self, mesh: Mesh) -> usize {
        self.meshes.push(mesh);
        self.meshes.len() - 1
    }

    /// Places mesh `mesh` with `transform` and `albedo`, casting and receiving shadows.
    pub fn add_object(&mut self, mesh: usize, transform: Mat4, albedo: Vec3) -> &mut Object {
        let name = self.meshes.get(mesh).map(|m| m.name.clone()).unwrap_or_default();
        self.objects.push(Object { name, mesh, transform, albedo, casts_shadows: true, receives_shadows: true });
        let last = self.objects.len() - 1;
        &mut self.objects[last]
    }

    /// Triangles drawn per pass (instances counted).
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().filter_map(|o| self.meshes.get(o.mesh)).map(Mesh::triangle_count).sum()
    }

    /// World-space bounds of each object (`None` where its mesh index is out of range), in
    /// object order. Walks every mesh's positions: compute once per frame and share.
    pub fn object_bounds(&self) -> Vec<Option<Aabb>> {
        self.objects.iter().map(|o| self.meshes.get(o.mesh).map(|m| m.bounds().transformed(&o.transform))).collect()
    }

    /// World-space bounds of every object.
    pub fn bounds(&self) -> Aabb {
        self.object_bounds().into_iter().flatten().fold(Aabb::EMPTY, Aabb::union)
    }

    /// An upper bound on the distance from the camera to the farthest point of the scene (its
    /// bounding sphere's far side); 0 for an empty scene. [`Camera::validate`] bounds `near`
    /// by it.
    pub fn camera_reach(&self) -> f32 {
        self.reach_of(self.bounds())
    }

    /// [`Scene::camera_reach`] for the scene bounds `b`, already computed.
    fn reach_of(&self, b: Aabb) -> f32 {
        if b.is_empty() {
            0.0
        } else {
            (b.center() - self.camera.position).length() + b.radius()
        }
    }

    /// Raises the camera's `near` to the smallest at which shadow volumes are measured exact
    /// for this scene ([`Camera::EXACT_NEAR_RATIO`] of its reach; never lowers it): for
    /// interactive cameras that zoom out past their near plane's precision.
    pub fn fit_near_plane(&mut self) {
        let least = Camera::EXACT_NEAR_RATIO * self.camera_reach();
        if self.camera.near < least {
            self.camera.near = least * 1.001;
            if let Some(far) = self.camera.far.as_mut() {
                *far = far.max(self.camera.near * 2.0);
            }
        }
    }

    /// Points the camera at the scene from the front-right-above, far enough to see it all.
    pub fn frame_camera(&mut self) {
        let b = self.bounds();
        if b.is_empty() {
            return;
        }
        let (c, r) = (b.center(), b.radius().max(1e-3));
        let dir = Vec3::new(0.55, 0.45, 1.0).normalize();
        let distance = r / (self.camera.fov_y_deg.to_radians() * 0.5).sin() * 1.05;
        self.camera.position = c + dir * distance;
        self.camera.target = c;
        self.camera.near = (distance - r).max(distance * 1e-3);
        self.camera.far = Some(distance + r * 2.0);
    }

    /// Turns every point light into a spot aimed at the scene's centre, its cone just around
    /// the scene's bounds (at most `max_cone_deg` half-angle; 1° of soft edge): one 2D map per
    /// light instead of a cube (`umbra-bench --spot-lights`). Returns the indices of the
    /// lights it changed.
    pub fn point_lights_to_spots(&mut self, max_cone_deg: f32) -> Vec<usize> {
        let bounds = self.bounds();
        let mut changed = Vec::new();
        for (i, light) in self.lights.iter_mut().enumerate() {
            if light.kind() != crate::LightKind::Point || bounds.is_empty() {
                continue;
            }
            let to_centre = bounds.center() - light.position.truncate();
            let distance = to_centre.length().max(1e-3);
            let half = (bounds.radius() / distance).clamp(0.0, 1.0).asin().to_degrees() + 2.0;
            let outer = half.min(max_cone_deg).max(2.0);
            light.spot = Some(crate::Spot { direction: to_centre, inner_deg: outer - 1.0, outer_deg: outer });
            changed.push(i);
        }
        changed
    }

    /// Adds a key directional light from above, on the camera's side, when the scene has no
    /// light at all, so a bare mesh file still shows its shape.
    pub fn ensure_light(&mut self) {
        if self.lights.is_empty() {
            let view = (self.camera.position - self.camera.target).normalize_or_zero();
            let mut l = Light::directional(view + Vec3::new(-0.6, 1.2, 0.0), 1.0);
            l.name = "default key light".into();
            self.lights.push(l);
        }
    }

    /// Checks everything a frame relies on, before any GPU work: every mesh is valid (finite,
    /// within [`crate::MAX_COORDINATE`], indices in range), every object refers to a mesh and
    /// has a finite transform that keeps it within `MAX_COORDINATE`, at most
    /// [`crate::limits::MAX_OBJECTS`] objects and [`crate::limits::MAX_LIGHTS`] lights, every
    /// light passes [`Light::validate`], ambient and background are finite and ≥ 0, and the
    /// camera passes [`Camera::validate`] for this scene's bounds.
    pub fn validate(&self) -> crate::SceneResult<()> {
        for m in &self.meshes {
            m.validate()?;
        }
        let bounds = self.validate_placement()?;
        self.validate_camera(bounds)
    }

    /// The camera against the scene's world `bounds` ([`Camera::validate`]).
    pub(crate) fn validate_camera(&self, bounds: Aabb) -> crate::SceneResult<()> {
        self.camera
            .validate(self.reach_of(bounds))
            .map_err(|why| crate::SceneError::InvalidScene { what: "camera".into(), why })
    }

    /// What [`Scene::validate`] checks but the meshes' contents and the camera (for an engine
    /// that registered checked meshes and brings its own view): objects, lights, ambient and
    /// background. Returns the world bounds of every object.
    pub fn validate_placement(&self) -> crate::SceneResult<Aabb> {
        self.placement_with(|i| self.meshes.get(i).map(Mesh::bounds))
    }

    /// [`Scene::validate_placement`] with mesh `i`'s bounds from `mesh_bounds(i)` (`None`: no
    /// such mesh).
    pub(crate) fn placement_with(&self, mesh_bounds: impl Fn(usize) -> Option<Aabb>) -> crate::SceneResult<Aabb> {
        fn invalid<T>(what: String, why: String) -> crate::SceneResult<T> {
            Err(crate::SceneError::InvalidScene { what, why })
        }
        if self.objects.len() > crate::limits::MAX_OBJECTS {
            let (value, limit) = (self.objects.len() as u64, crate::limits::MAX_OBJECTS as u64);
            return Err(crate::SceneError::Limit { what: "objects".into(), value, limit });
        }
        // The scene's bounds, gathered on the way (the camera check needs them).
        let mut bounds = Aabb::EMPTY;
        for (i, o) in self.objects.iter().enumerate() {
            let what = || format!("object {i} ({:?})", o.name);
            let Some(mesh_bounds) = mesh_bounds(o.mesh) else {
                return invalid(what(), format!("refers to mesh {} of {}", o.mesh, self.meshes.len()));
            };
            if !o.transform.is_finite() || !o.albedo.is_finite() {
                return invalid(what(), "transform or albedo is not finite".into());
            }
            let b = mesh_bounds.transformed(&o.transform);
            let reach = b.min.abs().max(b.max.abs()).max_element();
            let within = reach.is_finite() && reach <= crate::MAX_COORDINATE;
            if !b.is_empty() && !within {
                return invalid(
                    what(),
                    format!("reaches {reach:e} in world space, beyond ±{:e}", crate::MAX_COORDINATE),
                );
            }
            bounds = bounds.union(b);
        }
        if self.lights.len() > crate::limits::MAX_LIGHTS {
            let (value, limit) = (self.lights.len() as u64, crate::limits::MAX_LIGHTS as u64);
            return Err(crate::SceneError::Limit { what: "lights".into(), value, limit });
        }
        for (i, l) in self.lights.iter().enumerate() {
            let what = if l.name.is_empty() { format!("light {i}") } else { format!("light {i} ({:?})", l.name) };
            l.validate().or_else(|why| invalid(what, why))?;
        }
        for (what, c) in [("ambient", self.ambient), ("background", self.background)] {
            if !(c.is_finite() && c.min_element() >= 0.0) {
                return invalid(what.into(), format!("{c} must be finite and ≥ 0"));
            }
        }
        Ok(bounds)
    }
}

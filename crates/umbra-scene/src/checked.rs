//! What [`Scene::validate`] and [`Scene::object_bounds`] learn of each mesh, kept by the mesh's
//! [revision](Mesh::revision) ([`CheckedMeshes`]): a renderer that checks a scene every frame
//! reads a mesh's vertices once per revision, not once per frame and instance.

use crate::{Aabb, Mesh, Scene, SceneResult};

/// Per mesh of a scene, the revision that passed [`Mesh::validate`] and its bounds then.
///
/// Relies on the contract of [`Mesh::revision`]: a mesh changed in place must be
/// [touched](Mesh::touch), or it is neither checked nor measured again.
#[derive(Clone, Debug, Default)]
pub struct CheckedMeshes {
    meshes: Vec<Option<(u64, Aabb)>>,
}

impl CheckedMeshes {
    /// Validates every mesh of `meshes` whose revision it has not seen pass, and keeps the
    /// bounds of each; the first invalid mesh's error otherwise (and it stays unchecked).
    fn check(&mut self, meshes: &[Mesh]) -> SceneResult<()> {
        self.meshes.resize(meshes.len(), None);
        for (slot, mesh) in self.meshes.iter_mut().zip(meshes) {
            if slot.is_some_and(|(revision, _)| revision == mesh.revision()) {
                continue;
            }
            *slot = None;
            mesh.validate()?;
            *slot = Some((mesh.revision(), mesh.bounds()));
        }
        Ok(())
    }

    /// The bounds of mesh `index` of `meshes`: kept when its revision is the one checked,
    /// measured otherwise.
    fn bounds(&self, meshes: &[Mesh], index: usize) -> Option<Aabb> {
        let mesh = meshes.get(index)?;
        match self.meshes.get(index).copied().flatten() {
            Some((revision, bounds)) if revision == mesh.revision() => Some(bounds),
            _ => Some(mesh.bounds()),
        }
    }
}

impl Scene {
    /// [`Scene::validate`], each mesh's contents checked and measured only when `checked` has
    /// not seen its revision pass: the same answer, the same errors.
    pub fn validate_with(&self, checked: &mut CheckedMeshes) -> SceneResult<()> {
        let bounds = self.validate_placement_with(checked)?;
        self.validate_camera(bounds)
    }

    /// [`Scene::validate_placement`] after each mesh's contents are checked and measured (only
    /// when `checked` has not seen its revision pass): the world bounds of every object.
    pub fn validate_placement_with(&self, checked: &mut CheckedMeshes) -> SceneResult<Aabb> {
        checked.check(&self.meshes)?;
        self.placement_with(|i| checked.bounds(&self.meshes, i))
    }

    /// [`Scene::object_bounds`] with each mesh's bounds from `checked` where it holds the
    /// mesh's revision: the same boxes.
    pub fn object_bounds_with(&self, checked: &CheckedMeshes) -> Vec<Option<Aabb>> {
        self.objects.iter().map(|o| checked.bounds(&self.meshes, o.mesh).map(|b| b.transformed(&o.transform))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural;
    use glam::Vec3;

    #[test]
    fn the_same_answers_as_the_unkept_checks() {
        for name in procedural::NAMES {
            let scene = procedural::build(name).expect("scene");
            let mut checked = CheckedMeshes::default();
            scene.validate_with(&mut checked).expect("valid");
            assert_eq!(scene.object_bounds_with(&checked), scene.object_bounds(), "{name}");
            assert_eq!(scene.validate_placement_with(&mut checked).ok(), scene.validate_placement().ok(), "{name}");
        }
    }

    #[test]
    fn a_mesh_is_checked_again_once_touched() {
        let mut scene = procedural::build("cubes").expect("cubes");
        let mut checked = CheckedMeshes::default();
        scene.validate_with(&mut checked).expect("valid");
        // Changed in place without a touch: the contract says renderers may not notice.
        scene.meshes[0].positions[0] = Vec3::NAN;
        assert!(scene.validate_with(&mut checked).is_ok());
        scene.meshes[0].touch();
        let (kept, fresh) = (scene.validate_with(&mut checked), scene.validate());
        assert_eq!(kept.map_err(|e| e.to_string()), fresh.map_err(|e| e.to_string()));
        assert!(scene.validate_with(&mut checked).is_err(), "an invalid mesh stays unchecked");
        // Moved objects need no mesh read: their boxes follow the transform.
        scene.meshes[0].positions[0] = Vec3::ZERO;
        scene.meshes[0].touch();
        scene.objects[1].transform = glam::Mat4::from_translation(Vec3::X) * scene.objects[1].transform;
        scene.validate_with(&mut checked).expect("valid again");
        assert_eq!(scene.object_bounds_with(&checked), scene.object_bounds());
    }
}

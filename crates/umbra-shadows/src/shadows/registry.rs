//! The engine's scene as umbra keeps it: meshes (CPU copies, from which volumes and silhouettes
//! are built) and instances, each named by a stable id while others come and go. Lights come
//! with each frame. A transform update touches only that instance: meshes are uploaded again
//! only when one is added or removed.

use crate::{RenderError, RenderResult};
use glam::{Mat4, Vec3};
use umbra_scene::{Mesh, Object, Scene};

/// A mesh registered with [`crate::Shadows::add_mesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeshId(pub(crate) u32);

/// An instance registered with [`crate::Shadows::add_instance`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InstanceId(pub(crate) u32);

/// One placed mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// The mesh drawn.
    pub mesh: MeshId,
    /// Object-to-world transform (finite).
    pub transform: Mat4,
    /// Whether it occludes lights.
    pub casts_shadows: bool,
    /// Whether shadows fall on it (elsewhere its visibility is 1).
    pub receives_shadows: bool,
}

impl Instance {
    /// `mesh` at `transform`, casting and receiving shadows.
    pub fn new(mesh: MeshId, transform: Mat4) -> Self {
        Self { mesh, transform, casts_shadows: true, receives_shadows: true }
    }

    /// A scene object's placement and flags, drawing `mesh` (its mesh as registered).
    pub fn of_object(object: &Object, mesh: MeshId) -> Self {
        Self {
            mesh,
            transform: object.transform,
            casts_shadows: object.casts_shadows,
            receives_shadows: object.receives_shadows,
        }
    }
}

/// The scene umbra records from, and the ids that name its parts.
#[derive(Default)]
pub(crate) struct Registry {
    pub scene: Scene,
    /// Per mesh id, whether it is registered (a removed mesh's slot holds an empty mesh).
    meshes: Vec<bool>,
    /// Per instance id, its index in `scene.objects` while registered.
    instances: Vec<Option<usize>>,
    /// Per object, its instance id.
    ids: Vec<u32>,
}

impl Registry {
    pub fn add_mesh(&mut self, mesh: Mesh) -> RenderResult<MeshId> {
        mesh.validate()?;
        self.scene.meshes.push(mesh);
        self.meshes.push(true);
        Ok(MeshId(self.meshes.len() as u32 - 1))
    }

    /// Removes `id`; an error while an instance draws it.
    pub fn remove_mesh(&mut self, id: MeshId) -> RenderResult<()> {
        self.mesh_index(id)?;
        if let Some(i) = self.scene.objects.iter().position(|o| o.mesh == id.0 as usize) {
            return Err(invalid(format!("{id:?}"), format!("instance {:?} still draws it", InstanceId(self.ids[i]))));
        }
        self.scene.meshes[id.0 as usize] = Mesh::default();
        self.meshes[id.0 as usize] = false;
        Ok(())
    }

    pub fn add_instance(&mut self, instance: Instance) -> RenderResult<InstanceId> {
        let mesh = self.mesh_index(instance.mesh)?;
        finite(instance.transform, || format!("{:?}'s transform", InstanceId(self.instances.len() as u32)))?;
        let id = self.instances.len() as u32;
        self.instances.push(Some(self.scene.objects.len()));
        self.ids.push(id);
        self.scene.objects.push(Object {
            name: format!("instance {id}"),
            mesh,
            transform: instance.transform,
            albedo: Vec3::ONE,
            casts_shadows: instance.casts_shadows,
            receives_shadows: instance.receives_shadows,
        });
        Ok(InstanceId(id))
    }

    pub fn set_transform(&mut self, id: InstanceId, transform: Mat4) -> RenderResult<()> {
        let i = self.instance_index(id)?;
        finite(transform, || format!("{id:?}'s transform"))?;
        self.scene.objects[i].transform = transform;
        Ok(())
    }

    pub fn remove_instance(&mut self, id: InstanceId) -> RenderResult<()> {
        let i = self.instance_index(id)?;
        self.scene.objects.swap_remove(i);
        self.ids.swap_remove(i);
        self.instances[id.0 as usize] = None;
        if let Some(&moved) = self.ids.get(i) {
            self.instances[moved as usize] = Some(i);
        }
        Ok(())
    }

    fn mesh_index(&self, id: MeshId) -> RenderResult<usize> {
        match self.meshes.get(id.0 as usize) {
            Some(true) => Ok(id.0 as usize),
            _ => Err(invalid(format!("{id:?}"), "names no registered mesh".into())),
        }
    }

    fn instance_index(&self, id: InstanceId) -> RenderResult<usize> {
        self.instances
            .get(id.0 as usize)
            .copied()
            .flatten()
            .ok_or_else(|| invalid(format!("{id:?}"), "names no registered instance".into()))
    }
}

fn finite(m: Mat4, what: impl FnOnce() -> String) -> RenderResult<()> {
    match m.is_finite() {
        true => Ok(()),
        false => Err(invalid(what(), "must be finite".into())),
    }
}

pub(crate) fn invalid(field: String, why: String) -> RenderError {
    RenderError::InvalidInput { field, why }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> Mesh {
        Mesh::with_smooth_normals("tri", vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![0, 1, 2]).unwrap()
    }

    #[test]
    fn ids_stay_put_while_others_are_removed() {
        let mut r = Registry::default();
        let m = r.add_mesh(triangle()).unwrap();
        let ids: Vec<InstanceId> = (0..4)
            .map(|k| r.add_instance(Instance::new(m, Mat4::from_translation(Vec3::X * k as f32))).unwrap())
            .collect();
        r.remove_instance(ids[1]).unwrap();
        r.set_transform(ids[3], Mat4::from_translation(Vec3::Z)).unwrap();
        assert_eq!(r.scene.objects.len(), 3);
        let at = |id: InstanceId| r.scene.objects[r.instance_index(id).unwrap()].transform;
        assert_eq!(at(ids[3]), Mat4::from_translation(Vec3::Z));
        assert_eq!(at(ids[2]), Mat4::from_translation(Vec3::X * 2.0));
        let gone = r.set_transform(ids[1], Mat4::IDENTITY).unwrap_err().to_string();
        assert_eq!(gone, "InstanceId(1): names no registered instance");
        let busy = r.remove_mesh(m).unwrap_err().to_string();
        assert!(busy.contains("still draws it"), "{busy}");
        let bad = r.set_transform(ids[0], Mat4::from_scale(Vec3::NAN)).unwrap_err().to_string();
        assert_eq!(bad, "InstanceId(0)'s transform: must be finite");
        for id in [ids[0], ids[2], ids[3]] {
            r.remove_instance(id).unwrap();
        }
        r.remove_mesh(m).unwrap();
        assert!(r.add_instance(Instance::new(m, Mat4::IDENTITY)).is_err());
    }
}

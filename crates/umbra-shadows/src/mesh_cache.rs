//! What the renderer derives from each mesh, kept while the mesh keeps its revision
//! ([`umbra_scene::Mesh::revision`]): today its welded adjacency.

use crate::{RenderError, RenderResult};
use std::sync::Arc;
use umbra_scene::{Adjacency, Mesh, Scene};

/// The sizes and end points of a mesh's geometry: cheap to compare every frame, and a change
/// under an unchanged revision means the mesh was edited without [`Mesh::touch`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Shape {
    vertices: usize,
    indices: usize,
    first: [u32; 3],
    last: [u32; 3],
}

impl Shape {
    fn of(m: &Mesh) -> Self {
        let bits = |p: Option<&glam::Vec3>| p.map_or([0; 3], |p| p.to_array().map(f32::to_bits));
        Self {
            vertices: m.positions.len(),
            indices: m.indices.len(),
            first: bits(m.positions.first()),
            last: bits(m.positions.last()),
        }
    }
}

struct Entry {
    revision: u64,
    shape: Shape,
    adjacency: Arc<Adjacency>,
}

/// Welded connectivity per mesh index, rebuilt when a mesh's revision changes.
#[derive(Default)]
pub(crate) struct MeshCache {
    entries: Vec<Entry>,
}

impl MeshCache {
    /// The adjacency of every mesh of `scene`, in mesh order, rebuilding only meshes whose
    /// revision changed. A mesh whose sizes or end points changed under the same revision is a
    /// [`RenderError::StaleMesh`] (it was edited in place without [`Mesh::touch`]).
    pub fn adjacency(&mut self, scene: &Scene) -> RenderResult<Vec<Arc<Adjacency>>> {
        self.entries.truncate(scene.meshes.len());
        for (i, mesh) in scene.meshes.iter().enumerate() {
            let shape = Shape::of(mesh);
            match self.entries.get(i) {
                Some(e) if e.revision == mesh.revision() && e.shape == shape => continue,
                Some(e) if e.revision == mesh.revision() => {
                    return Err(RenderError::StaleMesh { mesh: i, name: mesh.name.clone() })
                }
                _ => {}
            }
            let entry = Entry { revision: mesh.revision(), shape, adjacency: Arc::new(Adjacency::build(mesh)) };
            match self.entries.get_mut(i) {
                Some(e) => *e = entry,
                None => self.entries.push(entry),
            }
        }
        Ok(self.entries.iter().map(|e| Arc::clone(&e.adjacency)).collect())
    }
}

//! Triangle meshes: positions, normals and `u32` indices.

use crate::error::{SceneError, SceneResult};
use glam::{Mat3, Mat4, Vec3};

/// The largest coordinate magnitude a scene may hold, in world and object space: ±1e6.
///
/// This is the bound where the techniques are measured exact: hard case 07 (geometry at
/// 1e5–1e6 units, 5e5 from the origin) passes shadow volumes and the hybrid against the
/// reference on both CPU drivers. Past it f32 keeps less than 0.06 units of a coordinate and
/// the drivers' rounding of the same vertex diverges (geometry at 1e11 rendered differently on
/// lavapipe and SwiftShader), so a scene beyond it is rejected with a typed error before any
/// GPU work. (It also keeps Everitt–Kilgard's facing test — products of three coordinates —
/// far inside f32's range.)
pub const MAX_COORDINATE: f32 = 1e6;

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf); growing it by a point gives that point.
    pub const EMPTY: Self = Self { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// Grows the box to contain `p`.
    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The union of two boxes.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// Whether nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Half the diagonal (a bounding-sphere radius around the centre).
    pub fn radius(&self) -> f32 {
        (self.max - self.min).length() * 0.5
    }

    /// The box of the eight corners transformed by `m`.
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            out.grow(m.transform_point3(c));
        }
        out
    }
}

/// An indexed triangle mesh. Front faces wind counter-clockwise.
///
/// Every mesh carries a [`revision`](Mesh::revision): a process-unique number naming its
/// contents, assigned afresh by every constructor and by [`Mesh::touch`]. Renderers key what
/// they derive from a mesh (welded adjacency, uploaded buffers) by it, so **call
/// [`Mesh::touch`] after changing `positions`, `normals` or `indices` in place** (the in-place
/// methods here, [`Mesh::transform`] and [`Mesh::append`], do it themselves). A clone keeps the
/// revision of the mesh it copies: same revision, same contents. Equality compares contents,
/// never revisions.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Name (from glTF, the scene file or the generator).
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Triangle list indices into `positions`.
    pub indices: Vec<u32>,
    /// The topology as authored in the source file (index pairs, before any unwelding for
    /// flat normals), when the mesh was imported; see [`crate::Adjacency`] for the welded one.
    pub authored_topology: Option<crate::TopologyReport>,
    /// See [`Mesh::revision`].
    pub(crate) revision: u64,
}

/// The next fresh revision (never 0, never reused in this process).
fn fresh_revision() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl Default for Mesh {
    fn default() -> Self {
        Self::from_parts(String::new(), Vec::new(), Vec::new(), Vec::new())
    }
}

impl PartialEq for Mesh {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
            && self.positions == other.positions
            && self.normals == other.normals
            && self.indices == other.indices
            && self.authored_topology == other.authored_topology
    }
}

impl Mesh {
    /// The parts as they are, unchecked, with a fresh revision.
    pub(crate) fn from_parts(name: String, positions: Vec<Vec3>, normals: Vec<Vec3>, indices: Vec<u32>) -> Self {
        Self { name, positions, normals, indices, authored_topology: None, revision: fresh_revision() }
    }

    /// The process-unique number naming this mesh's contents (see [`Mesh`]).
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Gives the mesh a fresh revision: call it after changing its `positions`, `normals` or
    /// `indices` in place, so renderers rebuild and re-upload what they derived from it.
    pub fn touch(&mut self) {
        self.revision = fresh_revision();
    }

    /// A mesh from parts, checked: as many normals as positions, indices in range and a
    /// multiple of three, finite positions within [`MAX_COORDINATE`], at most
    /// [`crate::limits::MAX_VERTICES`] vertices and [`crate::limits::MAX_INDICES`] indices.
    pub fn new(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        indices: Vec<u32>,
    ) -> SceneResult<Self> {
        let mesh = Self::from_parts(name.into(), positions, normals, indices);
        mesh.validate()?;
        Ok(mesh)
    }

    /// A mesh without normals: every triangle gets its own three vertices carrying the face
    /// normal (flat shading, as glTF requires when `NORMAL` is absent).
    pub fn with_flat_normals(name: impl Into<String>, positions: &[Vec3], indices: &[u32]) -> SceneResult<Self> {
        let name = name.into();
        check_indices(&name, positions.len(), indices)?;
        // Every index becomes a vertex of its own.
        check_count(&name, "vertices (one per index, for flat normals)", indices.len(), crate::limits::MAX_VERTICES)?;
        let mut out = Self { name, ..Default::default() };
        for tri in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let base = out.positions.len() as u32;
            out.positions.extend([a, b, c]);
            out.normals.extend([n, n, n]);
            out.indices.extend([base, base + 1, base + 2]);
        }
        out.validate()?;
        Ok(out)
    }

    /// A mesh with smooth normals: area-weighted averages of the faces around each vertex.
    pub fn with_smooth_normals(name: impl Into<String>, positions: Vec<Vec3>, indices: Vec<u32>) -> SceneResult<Self> {
        let name = name.into();
        check_indices(&name, positions.len(), &indices)?;
        let mut normals = vec![Vec3::ZERO; positions.len()];
        for tri in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
            let n = (b - a).cross(c - a);
            for &i in tri {
                normals[i as usize] += n;
            }
        }
        let normals = normals.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::Y)).collect();
        Self::new(name, positions, normals, indices)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Bounding box of the positions.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for &p in &self.positions {
            b.grow(p);
        }
        b
    }

    /// Transforms positions by `m` and normals by its inverse transpose (in place).
    pub fn transform(&mut self, m: Mat4) {
        let normal_matrix = Mat3::from_mat4(m).inverse().transpose();
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (normal_matrix * *n).normalize_or_zero();
        }
        if m.determinant() < 0.0 {
            for tri in self.indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
        self.touch();
    }

    /// This mesh transformed by `m` (see [`Mesh::transform`]).
    pub fn transformed(mut self, m: Mat4) -> Self {
        self.transform(m);
        self
    }

    /// Appends another mesh's triangles.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
        self.touch();
    }

    /// Checks the invariants listed on [`Mesh::new`].
    pub fn validate(&self) -> SceneResult<()> {
        check_count(&self.name, "vertices", self.positions.len(), crate::limits::MAX_VERTICES)?;
        let bad = |why: String| Err(SceneError::InvalidMesh { mesh: self.name.clone(), why });
        if self.normals.len() != self.positions.len() {
            return bad(format!("{} normals for {} positions", self.normals.len(), self.positions.len()));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return bad(format!("position {i} is not finite"));
        }
        if let Some(i) = self.positions.iter().position(|p| p.abs().max_element() > MAX_COORDINATE) {
            return bad(format!("position {i} is beyond ±{MAX_COORDINATE:e} (umbra_scene::MAX_COORDINATE)"));
        }
        check_indices(&self.name, self.positions.len(), &self.indices)
    }
}

/// A [`SceneError::Limit`] when mesh `name` has more than `limit` `what`.
fn check_count(name: &str, what: &str, count: usize, limit: usize) -> SceneResult<()> {
    if count > limit {
        return Err(SceneError::Limit {
            what: format!("mesh {name:?}: {what}"),
            value: count as u64,
            limit: limit as u64,
        });
    }
    Ok(())
}

fn check_indices(name: &str, vertices: usize, indices: &[u32]) -> SceneResult<()> {
    check_count(name, "indices", indices.len(), crate::limits::MAX_INDICES)?;
    let bad = |why: String| Err(SceneError::InvalidMesh { mesh: name.to_owned(), why });
    if indices.len() % 3 != 0 {
        return bad(format!("{} indices is not a multiple of 3", indices.len()));
    }
    if let Some(&i) = indices.iter().find(|&&i| i as usize >= vertices) {
        return bad(format!("index {i} out of range for {vertices} vertices"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_normals_follow_counter_clockwise_winding() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Z];
        let m = Mesh::with_flat_normals("t", &p, &[0, 2, 1]).unwrap();
        assert_eq!(m.normals, vec![Vec3::Y; 3]);
        assert_eq!(m.triangle_count(), 1);
    }

    #[test]
    fn revisions_are_fresh_per_mesh_shared_by_clones_and_renewed_by_edits() {
        let a = crate::primitives::cuboid(Vec3::ONE);
        let b = crate::primitives::cuboid(Vec3::ONE);
        assert_eq!(a, b, "equal contents compare equal");
        assert_ne!(a.revision(), b.revision(), "every mesh gets its own revision");
        let mut c = a.clone();
        assert_eq!(c.revision(), a.revision(), "a clone has the same contents");
        c.positions[7].x += 0.5;
        c.touch();
        assert_ne!(c.revision(), a.revision());
        let before = c.revision();
        c.transform(Mat4::from_translation(Vec3::X));
        assert_ne!(c.revision(), before, "in-place methods touch");
        let before = c.revision();
        c.append(&b);
        assert_ne!(c.revision(), before);
        assert_ne!(Mesh::default().revision(), Mesh::default().revision());
    }

    #[test]
    fn out_of_range_index_is_an_error() {
        let e = Mesh::new("bad", vec![Vec3::ZERO], vec![Vec3::Y], vec![0, 0, 1]).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
    }

    #[test]
    fn mirroring_keeps_faces_outward() {
        let p = [Vec3::ZERO, Vec3::Z, Vec3::X];
        let m = Mesh::with_flat_normals("t", &p, &[0, 1, 2])
            .unwrap()
            .transformed(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        let [a, b, c] = [0, 1, 2].map(|k| m.positions[m.indices[k] as usize]);
        let face = (b - a).cross(c - a).normalize();
        assert!(face.dot(m.normals[0]) > 0.99, "winding and normal agree after a mirror");
    }
}

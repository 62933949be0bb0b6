//! # umbra-scene — what umbra renders, on the CPU only
//!
//! Meshes ([`Mesh`]: positions, normals, `u32` indices), placed [`Object`]s flagged
//! `casts_shadows` / `receives_shadows`, [`Light`]s as homogeneous positions (directional
//! w = 0, point and spot w = 1) with the [`Technique`] wanted per light, and a perspective
//! [`Camera`] with an infinite-far variant. Scenes come from glTF ([`import_gltf`]), from TOML
//! scene files ([`load_scene_file`]) or from the papers' procedural generators
//! ([`procedural::build`]); [`load`] takes any of the three by name or path.
//!
//! This crate never touches Vulkan.

#![warn(missing_docs)]

mod adjacency;
mod camera;
mod checked;
mod error;
mod files;
mod gltf;
mod light;
pub mod limits;
mod mesh;
pub mod primitives;
pub mod procedural;
mod scene;
mod scene_file;
mod volume;

pub use adjacency::{Adjacency, Edge, EdgeFace, TopologyReport, CONVEX_TEST_TRIANGLES};
pub use camera::Camera;
pub use checked::CheckedMeshes;
pub use error::{SceneError, SceneResult};
pub use gltf::{import_gltf, import_gltf_slice};
pub use light::{Light, LightKind, Spot, Technique};
pub use mesh::{Aabb, Mesh, MAX_COORDINATE};
pub use scene::{Object, Scene};
pub use scene_file::{load_scene_file, parse_scene};
pub use volume::{extrude, facing, silhouette_edges, Facing, Volume, VolumeStats, VolumeVertex};

use std::path::Path;

/// Loads a scene from a procedural name (see [`procedural::NAMES`]), a `.toml` scene file or a
/// `.glb`/`.gltf` file. A glTF file without lights gets a default key light, and one without a
/// camera a camera framing it.
pub fn load(spec: &str) -> SceneResult<Scene> {
    if procedural::NAMES.contains(&spec) {
        return procedural::build(spec);
    }
    let path = Path::new(spec);
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    match ext.as_str() {
        "toml" => load_scene_file(path),
        "glb" | "gltf" => {
            let mut scene = import_gltf(path)?;
            scene.ensure_light();
            Ok(scene)
        }
        _ => Err(SceneError::UnknownScene(spec.to_owned())),
    }
}

//! The one error type of `umbra-scene`.

use std::path::PathBuf;

/// Everything that can go wrong building or loading a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A glTF file is malformed or uses something umbra cannot import.
    #[error("glTF {path}: {source}")]
    Gltf {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// The parser's error.
        source: gltf::Error,
    },
    /// A scene file is not valid TOML for umbra's format.
    #[error("scene file {path}: {message}")]
    SceneFile {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Geometry is inconsistent (index out of range, non-finite position, …).
    #[error("mesh {mesh:?}: {why}")]
    InvalidMesh {
        /// The mesh's name.
        mesh: String,
        /// What is wrong.
        why: String,
    },
    /// Something other than a mesh is unusable: an object's transform, a light, the camera.
    #[error("{what}: {why}")]
    InvalidScene {
        /// What is wrong (`object "floor"`, `light 2`, `camera`).
        what: String,
        /// Why.
        why: String,
    },
    /// A procedural scene name that does not exist.
    #[error("unknown scene {0:?}: expected one of {procedural}, a .toml scene file or a .glb/.gltf path", procedural = crate::procedural::NAMES.join(", "))]
    UnknownScene(String),
}

/// `Result` with [`SceneError`].
pub type SceneResult<T> = Result<T, SceneError>;

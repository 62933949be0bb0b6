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
    /// A path names something other than a regular file (a FIFO, a device, a directory);
    /// refused before it is opened.
    #[error("{path}: {kind}, not a regular file")]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is instead (`a FIFO`, `a character device`, …).
        kind: &'static str,
    },
    /// An input exceeds one of umbra's documented bounds ([`crate::limits`]).
    #[error("{what} is {value}, beyond umbra's limit of {limit}")]
    Limit {
        /// What is too large (a file, a field, a count), named as in the input.
        what: String,
        /// Its value.
        value: u64,
        /// The bound.
        limit: u64,
    },
    /// A glTF file is malformed or uses something umbra cannot import.
    #[error("glTF {path}: {at}: {why}")]
    Gltf {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// Where in the document, as a glTF JSON path (`accessors[3]`, `meshes[0].primitives[1]`).
        at: String,
        /// What is wrong.
        why: String,
    },
    /// A glTF buffer URI that umbra does not follow: anything but a `data:` URI or a relative
    /// reference to a regular file inside the glTF file's folder.
    #[error("glTF {path}: {at}: uri {uri:?} refused: {why}")]
    GltfUri {
        /// The glTF file (or `<memory>`).
        path: PathBuf,
        /// Which buffer (`buffers[1]`).
        at: String,
        /// The URI as written (shortened when long).
        uri: String,
        /// Why it is refused.
        why: String,
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

//! Where a glTF document came from, for error messages and for resolving its URIs.

use crate::error::SceneError;
use std::path::{Path, PathBuf};

/// The file a document was read from (or `<memory>`) and the folder its relative URIs resolve
/// in (`None` for documents read from memory: they may only use embedded data).
pub(crate) struct Source {
    /// The file, for messages.
    pub path: PathBuf,
    /// The folder relative buffer URIs must stay inside.
    pub folder: Option<PathBuf>,
}

impl Source {
    /// A file on disk.
    pub fn file(path: &Path) -> Self {
        let folder = path.parent().map(|p| if p.as_os_str().is_empty() { Path::new(".") } else { p });
        Self { path: path.to_owned(), folder: folder.map(Path::to_owned) }
    }

    /// Bytes from memory.
    pub fn memory() -> Self {
        Self { path: PathBuf::from("<memory>"), folder: None }
    }

    /// A [`SceneError::Gltf`] at `at` (a glTF JSON path).
    pub fn error(&self, at: impl Into<String>, why: impl Into<String>) -> SceneError {
        SceneError::Gltf { path: self.path.clone(), at: at.into(), why: why.into() }
    }
}

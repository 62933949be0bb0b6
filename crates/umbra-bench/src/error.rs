//! The bench's one error type.

use std::path::PathBuf;

/// What can stop a sweep.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// Vulkan set-up failed.
    #[error(transparent)]
    Vulkan(#[from] umbra_vk::VkError),
    /// Rendering failed (other than a configuration the device cannot run, which is skipped).
    #[error(transparent)]
    Render(#[from] umbra_shadows::RenderError),
    /// A scene could not be loaded.
    #[error("scene {name:?}: {source}")]
    Scene {
        /// The `--scenes` entry.
        name: String,
        /// Why.
        source: umbra_scene::SceneError,
    },
    /// The reference or a comparison failed.
    #[error(transparent)]
    Reference(#[from] umbra_reference::ReferenceError),
    /// The conformance suite could not run a case.
    #[error(transparent)]
    Conformance(#[from] umbra_conformance::ConformanceError),
    /// A flag's value makes no sense.
    #[error("{0}")]
    Usage(String),
    /// A file could not be read or parsed.
    #[error("reading {path}: {message}")]
    Input {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A file could not be written.
    #[error("writing {path}: {message}")]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl BenchError {
    /// An output error for `path`.
    pub fn output(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        Self::Output { path: path.to_owned(), message: e.to_string() }
    }

    /// An input error for `path`.
    pub fn input(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        Self::Input { path: path.to_owned(), message: e.to_string() }
    }
}

/// Result alias of the bench.
pub type BenchResult<T> = Result<T, BenchError>;

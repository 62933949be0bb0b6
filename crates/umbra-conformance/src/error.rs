//! The one error type of `umbra-conformance`.

use std::path::PathBuf;

/// What stops a conformance run (a failed case is a [`crate::Verdict`], not an error).
#[derive(Debug, thiserror::Error)]
pub enum ConformanceError {
    /// A case's scene file could not be loaded (other than the typed error a case expects).
    #[error("case {case}: {source}")]
    Scene {
        /// The case's file stem.
        case: String,
        /// The loader's error.
        source: umbra_scene::SceneError,
    },
    /// Rendering failed for a reason other than an unsupported feature.
    #[error(transparent)]
    Render(#[from] umbra_shadows::RenderError),
    /// The exact reference rejected its input.
    #[error(transparent)]
    Reference(#[from] umbra_reference::ReferenceError),
    /// A frame lacks what judging needs.
    #[error("{0}")]
    Incomplete(String),
    /// Writing an image or report failed.
    #[error("writing {path}: {message}")]
    Output {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// `Result` with [`ConformanceError`].
pub type ConformanceResult<T> = Result<T, ConformanceError>;

//! The reference's one error type.

use std::path::PathBuf;

/// What can go wrong building or comparing references.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// Two images that must be the same size are not.
    #[error("size mismatch: {what} is {got:?}, expected {expected:?}")]
    SizeMismatch {
        /// Which image.
        what: &'static str,
        /// Its width and height (or pixel count as `(n, 1)`).
        got: (usize, usize),
        /// The size it should have.
        expected: (usize, usize),
    },
    /// A light index past the scene's lights.
    #[error("light {light} does not exist (the scene has {lights})")]
    NoSuchLight {
        /// The index asked for.
        light: usize,
        /// How many lights the scene has.
        lights: usize,
    },
    /// An output file could not be written.
    #[error("writing {path}: {message}")]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// Result alias of this crate.
pub type ReferenceResult<T> = Result<T, ReferenceError>;

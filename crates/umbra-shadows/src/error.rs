//! The one error type of `umbra-shadows`.

use umbra_scene::Technique;

/// Everything that can go wrong rendering a frame.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A Vulkan-level failure (device, memory, unsupported feature, invalid description).
    #[error(transparent)]
    Vk(#[from] umbra_vk::VkError),
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] umbra_scene::SceneError),
    /// A light's kind cannot use the technique it asks for.
    #[error("light {light} asks for {technique:?}: {why}")]
    UnsupportedLight {
        /// Index of the light.
        light: usize,
        /// The technique it asked for.
        technique: Technique,
        /// Why, and what to use instead.
        why: String,
    },
    /// A shadow map's resolution is outside 64..=the device limit.
    #[error("shadow map of light {light}: resolution {resolution}: {why}")]
    InvalidShadowMap {
        /// Index of the light.
        light: usize,
        /// Resolution asked for.
        resolution: u32,
        /// The accepted range and the limit it comes from.
        why: String,
    },
    /// The target size is unusable.
    #[error("invalid target size {width}x{height}: {why}")]
    InvalidSize {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
        /// Why it is invalid.
        why: String,
    },
    /// Writing an output file failed.
    #[error("writing {path}: {message}")]
    Output {
        /// The file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// `Result` with [`RenderError`].
pub type RenderResult<T> = Result<T, RenderError>;

//! The one error type of `umbra-shadows`.

use serde::Serialize;
use umbra_scene::Technique;
use umbra_vk::Limit;

/// Everything that can go wrong rendering a frame.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A Vulkan-level failure (device, memory, unsupported feature, invalid description).
    #[error(transparent)]
    Vk(#[from] umbra_vk::VkError),
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] umbra_scene::SceneError),
    /// A light cannot use the technique it asks for on this device (ray-traced shadows without
    /// ray queries).
    #[error("light {light} asks for {technique:?}: {why}")]
    UnsupportedLight {
        /// Index of the light.
        light: usize,
        /// The technique it asked for.
        technique: Technique,
        /// Why, and what to use instead.
        why: String,
    },
    /// A shadow map's resolution is outside 64..=the device limits.
    #[error("shadow map of light {light}: resolution {resolution}: {why}")]
    InvalidShadowMap {
        /// Index of the light.
        light: usize,
        /// Resolution asked for.
        resolution: u32,
        /// The accepted range and the limit it comes from.
        why: String,
        /// The device limit it breaks (`None`: below the minimum, or an internal misuse).
        limit: Option<Limit>,
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
        /// The device limit it breaks (`None`: a zero side).
        limit: Option<Limit>,
    },
    /// A buffer the frame binds would be larger than a device limit allows
    /// (`maxStorageBufferRange` for the object, light and shadow-view buffers,
    /// `maxUniformBufferRange` for the frame uniforms, `maxBufferSize` or
    /// `maxMemoryAllocationSize` for the vertex and index buffers). Checked before any GPU work.
    #[error("{what}, but {limit} on {device}")]
    DeviceLimit {
        /// What needs how much (`1000000 objects need 137.3 MiB of object buffer (144 bytes each)`).
        what: String,
        /// The limit it breaks, with its value.
        limit: Limit,
        /// The device name.
        device: String,
    },
    /// The frame's shadow maps need more memory than `RendererDesc::shadow_map_budget_bytes`;
    /// checked before any of them is allocated.
    #[error(
        "the frame's shadow maps need {} ({}), over RendererDesc::shadow_map_budget_bytes = {}: lower the \
         maps' resolution (shadow_map.resolution, the lights' shadow_map_size), shadow fewer lights, or raise the budget",
        umbra_vk::human_bytes(*bytes),
        lights.iter().map(ToString::to_string).collect::<Vec<_>>().join(", "),
        umbra_vk::human_bytes(*budget)
    )]
    ShadowBudget {
        /// Every light with shadow storage this frame, with what it needs.
        lights: Vec<ShadowStorage>,
        /// Their sum in bytes.
        bytes: u64,
        /// The budget in bytes.
        budget: u64,
    },
    /// A renderer setting is not finite or outside its accepted range.
    #[error("{field} = {value} is not accepted: {accepted}")]
    InvalidSetting {
        /// The field (`shadow_map.bias.constant`, …).
        field: &'static str,
        /// The value given.
        value: String,
        /// The accepted range.
        accepted: String,
    },
    /// A mesh changed (its vertex or index count, or its first or last position) but kept its
    /// revision: it was edited in place without [`umbra_scene::Mesh::touch`], and what the
    /// renderer derived from it would be stale.
    #[error("mesh {mesh} ({name:?}) changed but kept its revision: call Mesh::touch() after editing a mesh in place")]
    StaleMesh {
        /// Index of the mesh in `Scene::meshes`.
        mesh: usize,
        /// Its name.
        name: String,
    },
    /// An argument is wrong (an id that names nothing, a frame slot out of range, a depth
    /// buffer umbra cannot use) or a call came out of order; `field` names what.
    #[error("{field}: {why}")]
    InvalidInput {
        /// The argument or field (`FrameInputs::depth.format`, `InstanceId(7)`, …).
        field: String,
        /// What is wrong with it, and what would be accepted.
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

/// What one light's shadow storage takes in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ShadowStorage {
    /// Index of the light.
    pub light: usize,
    /// Texels per side of its maps.
    pub resolution: u32,
    /// Texels per side of one face as allocated: `resolution`, plus the borders around each face
    /// of a cube silhouette map's atlas.
    pub face_side: u32,
    /// Whether its depth map is a cube (six faces).
    pub cube: bool,
    /// Whether it has a depth map (a hybrid light without blocker culling has only its depth
    /// bounds, of the same size).
    pub depth: bool,
    /// Whether it also has a silhouette map (and, with diagnostics, its readback).
    pub silhouette: bool,
    /// Whether it also has the hybrid's depth bounds (two depth layers per map face).
    pub bounds: bool,
    /// Bytes of its depth map, silhouette map and silhouette-map readback, and depth bounds.
    pub bytes: u64,
}

impl std::fmt::Display for ShadowStorage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let faces = if self.cube { "6 x " } else { "" };
        // A silhouette map's cube is a face atlas: its faces carry borders.
        let borders = if self.face_side != self.resolution { " (faces with their borders)" } else { "" };
        let side = self.face_side;
        let silhouette = if self.silhouette { " + silhouette map" } else { "" };
        let bounds = match (self.bounds, self.depth) {
            (false, _) => "",
            (true, true) => " + depth bounds",
            (true, false) => " depth bounds",
        };
        let bytes = umbra_vk::human_bytes(self.bytes);
        write!(f, "light {}: {faces}{side}²{borders}{silhouette}{bounds} = {bytes}", self.light)
    }
}

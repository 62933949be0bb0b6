//! # umbra-shaders — umbra's GLSL compiled to SPIR-V at build time
//!
//! `build.rs` compiles every `.vert`/`.frag`/`.comp`/`.geom` file under `shaders-glsl/` with
//! glslang (the `shaderc` crate, built from source) for Vulkan 1.3 / SPIR-V 1.6, and embeds the
//! words here: one module per folder (`forward::MESH_VERT` is `shaders-glsl/forward/mesh.vert`),
//! plus [`ALL`] for tools and tests. `shaders-glsl/common/` holds include-only `*.glsl` files.

#![warn(missing_docs)]

/// A pipeline stage a shader runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Vertex shader.
    Vertex,
    /// Fragment shader.
    Fragment,
    /// Compute shader.
    Compute,
    /// Geometry shader (used only when the device has them).
    Geometry,
}

/// One embedded shader module.
#[derive(Clone, Copy, Debug)]
pub struct Shader {
    /// Path under `shaders-glsl/`, e.g. `forward/mesh.vert`.
    pub path: &'static str,
    /// Its stage.
    pub stage: Stage,
    /// SPIR-V words.
    pub spirv: &'static [u32],
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// Looks a shader up by its path under `shaders-glsl/`.
pub fn get(path: &str) -> Option<&'static Shader> {
    ALL.iter().find(|s| s.path == path)
}

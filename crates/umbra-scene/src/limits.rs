//! The documented bounds on everything `umbra-scene` reads or builds from input.
//!
//! Every count that decides an allocation is checked against one of these *before* the
//! allocation, and a value past it is a [`crate::SceneError::Limit`] naming the field. They are
//! generous for real scenes (the repository's largest asset has 69 451 triangles) and small
//! enough that a hostile file cannot take the machine's memory. `docs/input.md` lists them with
//! every bad input and what umbra does with it.

/// Largest `.glb`, `.gltf` or external buffer file read (1 GiB).
pub const MAX_FILE_BYTES: u64 = 1 << 30;
/// Largest TOML scene file read (16 MiB).
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;
/// Most vertices in one mesh (and elements in one glTF accessor): 2²⁴.
pub const MAX_VERTICES: usize = 1 << 24;
/// Most indices in one mesh: 3 × 2²⁴.
pub const MAX_INDICES: usize = 3 << 24;
/// Most placed objects in one scene (glTF node instances, scene-file `repeat`s): 2²⁰.
pub const MAX_OBJECTS: usize = 1 << 20;
/// Most lights in one scene.
pub const MAX_LIGHTS: usize = 1024;
/// Most segments (and rings) of a procedural sphere or cylinder.
pub const MAX_SEGMENTS: u32 = 1024;
/// Deepest procedural tree (3⁹ twigs: about 240 000 triangles).
pub const MAX_TREE_DEPTH: u32 = 9;

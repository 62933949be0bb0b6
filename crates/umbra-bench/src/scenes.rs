//! Scenes by name for the bench: procedural names, scene files, glTF paths, and bare asset
//! file names found in the repository's `assets/` folder.

use crate::{BenchError, BenchResult};
use std::path::{Path, PathBuf};

/// Where a bare `.glb`/`.gltf` file name is looked up: `$UMBRA_ASSETS` when set, else the
/// `assets/` folder of the repository this bench was built from.
pub fn assets_dir() -> PathBuf {
    std::env::var_os("UMBRA_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets"))
}

/// The bench's own scene files (`crates/umbra-bench/scenes/`: `sixteen-bunnies.toml`).
pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// Loads `name` (a bare file name that does not exist here is looked up in [`assets_dir`],
/// then in [`scenes_dir`]);
/// with `spot_lights` every point light becomes a spot around the scene (cone at most 80°),
/// and with `light_range` every point and spot light is bounded to that range.
pub fn load(name: &str, spot_lights: bool, light_range: Option<f32>) -> BenchResult<umbra_scene::Scene> {
    let mut spec = name.to_owned();
    if !Path::new(name).exists() && !umbra_scene::procedural::NAMES.contains(&name) {
        let candidates = [assets_dir().join(name), scenes_dir().join(name)];
        if let Some(candidate) = candidates.iter().find(|c| c.exists()) {
            spec = candidate.to_string_lossy().into_owned();
        }
    }
    let scene_error = |source| BenchError::Scene { name: name.to_owned(), source };
    let mut scene = umbra_scene::load(&spec).map_err(scene_error)?;
    if spot_lights {
        scene.point_lights_to_spots(80.0);
    }
    if let Some(range) = light_range {
        for light in &mut scene.lights {
            light.range = Some(range);
        }
        scene.validate().map_err(scene_error)?;
    }
    Ok(scene)
}

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

/// The bench's own scene files (`crates/umbra-bench/scenes/`: `one-bunny.toml`,
/// `four-bunnies.toml` and `sixteen-bunnies.toml`, one bunny mesh instanced).
pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// What the bench does to a scene's lights before rendering it (`--spot-lights`,
/// `--light-range`); by default nothing: every technique takes the scene's own lights.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub struct LightArgs {
    /// Turn every point light into a spot around the scene (cone at most 80°), for every
    /// technique alike (one 2D map per light instead of a cube).
    #[arg(long)]
    pub spot_lights: bool,
    /// Bound every point and spot light to this range (world units): the light adds exactly
    /// nothing beyond it, so planning can cull by it (scissor, depth bounds, casters).
    #[arg(long, value_parser = crate::parse_light_range)]
    pub light_range: Option<f32>,
}

/// Loads `name` (a bare file name that does not exist here is looked up in [`assets_dir`],
/// then in [`scenes_dir`]) and changes its lights as `lights` says.
pub fn load(name: &str, lights: LightArgs) -> BenchResult<umbra_scene::Scene> {
    let mut spec = name.to_owned();
    if !Path::new(name).exists() && !umbra_scene::procedural::NAMES.contains(&name) {
        let candidates = [assets_dir().join(name), scenes_dir().join(name)];
        if let Some(candidate) = candidates.iter().find(|c| c.exists()) {
            spec = candidate.to_string_lossy().into_owned();
        }
    }
    let scene_error = |source| BenchError::Scene { name: name.to_owned(), source };
    let mut scene = umbra_scene::load(&spec).map_err(scene_error)?;
    if lights.spot_lights {
        scene.point_lights_to_spots(80.0);
    }
    if let Some(range) = lights.light_range {
        for light in &mut scene.lights {
            light.range = Some(range);
        }
        scene.validate().map_err(scene_error)?;
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scaling scenes load by bare name and hold 1, 4 and 16 instances of one bunny mesh
    /// (69,451 triangles) on a 12-triangle floor.
    #[test]
    fn the_bunny_scenes_instance_one_mesh() {
        for (name, bunnies) in [("one-bunny.toml", 1), ("four-bunnies.toml", 4), ("sixteen-bunnies.toml", 16)] {
            let scene = load(name, LightArgs::default()).expect(name);
            assert_eq!(scene.meshes.len(), 2, "{name}: the floor and one bunny mesh");
            assert_eq!(scene.objects.len(), 1 + bunnies, "{name}");
            assert_eq!(scene.triangle_count(), 12 + 69_451 * bunnies, "{name}");
        }
    }
}

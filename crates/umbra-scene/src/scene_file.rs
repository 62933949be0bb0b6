//! umbra's TOML scene files. Unknown keys are errors in every table; counts and sizes are
//! bounded by [`crate::limits`] (`docs/input.md` lists every rule).
//!
//! ```toml
//! name = "demo"
//! ambient = [0.08, 0.08, 0.08]
//!
//! [camera]
//! position = [4.0, 3.0, 6.0]
//! target = [0.0, 0.5, 0.0]
//! fov_y_deg = 50.0
//! far = 100.0            # omit for a far plane at infinity
//!
//! [[mesh]]
//! name = "floor"
//! kind = "box"           # plane | box | sphere | cylinder | file | triangles | tree
//! half = [5.0, 0.05, 5.0]
//!
//! [[mesh]]
//! name = "fin"
//! kind = "triangles"     # inline geometry, flat-shaded, counter-clockwise fronts
//! positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
//! indices = [0, 1, 2]
//!
//! [[mesh]]
//! name = "tree"
//! kind = "tree"          # the procedural branching tree: depth (default 7, 0..=9), seed
//! depth = 6
//!
//! [[mesh]]
//! name = "bunny"
//! kind = "file"
//! path = "../assets/stanford-bunny.glb"   # relative to the scene file
//!
//! [[object]]
//! mesh = "bunny"
//! translation = [0.0, -0.2, 0.0]
//! rotation_deg = [0.0, 30.0, 0.0]
//! scale = 10.0           # or [x, y, z]
//! albedo = [0.8, 0.7, 0.6]
//! repeat = 1             # optional: that many copies, the i-th moved by i * step
//! step = [0.0, 0.0, 0.0]
//!
//! [[light]]
//! kind = "point"         # directional | point | spot
//! position = [2.0, 6.0, 1.0]
//! intensity = 40.0
//! technique = "shadow_map"   # unshadowed | shadow_map | shadow_volume | silhouette_map | hybrid | auto
//! range = 12.0            # optional (point, spot): adds exactly nothing beyond this distance
//! shadow_map_size = 2048      # optional, overrides the renderer's default
//! ```

use crate::error::{SceneError, SceneResult};
use crate::limits::{MAX_INDICES, MAX_OBJECTS, MAX_SCENE_FILE_BYTES, MAX_SEGMENTS, MAX_TREE_DEPTH, MAX_VERTICES};
use crate::primitives;
use crate::{Camera, Light, Mesh, Scene, Spot, Technique};
use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    name: Option<String>,
    ambient: Option<Vec3>,
    background: Option<Vec3>,
    camera: Option<Camera>,
    #[serde(default)]
    mesh: Vec<MeshEntry>,
    #[serde(default)]
    object: Vec<ObjectEntry>,
    #[serde(default)]
    light: Vec<LightEntry>,
}

/// A `[[mesh]]` table: its `name`, then the fields of its `kind`, unknown keys refused.
struct MeshEntry {
    name: String,
    source: MeshSource,
}

impl<'de> Deserialize<'de> for MeshEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let mut table = toml::Table::deserialize(d)?;
        let name = match table.remove("name") {
            Some(toml::Value::String(name)) => name,
            Some(other) => {
                return Err(D::Error::custom(format!("mesh `name` must be a string, not {}", other.type_str())))
            }
            None => return Err(D::Error::missing_field("name")),
        };
        let source = MeshSource::deserialize(toml::Value::Table(table))
            .map_err(|e| D::Error::custom(format!("mesh {name:?}: {}", e.message())))?;
        Ok(Self { name, source })
    }
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum MeshSource {
    Plane { size: f32 },
    Box { half: Vec3 },
    Sphere { radius: f32, segments: Option<u32>, rings: Option<u32> },
    Cylinder { radius: f32, height: f32, segments: Option<u32> },
    File { path: String },
    Triangles { positions: Vec<Vec3>, indices: Vec<u32> },
    Tree { depth: Option<u32>, seed: Option<u64> },
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Scale {
    Uniform(f32),
    Axes(Vec3),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectEntry {
    mesh: String,
    name: Option<String>,
    translation: Option<Vec3>,
    rotation_deg: Option<Vec3>,
    scale: Option<Scale>,
    albedo: Option<Vec3>,
    casts_shadows: Option<bool>,
    receives_shadows: Option<bool>,
    repeat: Option<u32>,
    step: Option<Vec3>,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum Kind {
    Directional,
    Point,
    Spot,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightEntry {
    kind: Kind,
    name: Option<String>,
    position: Option<Vec3>,
    direction: Option<Vec3>,
    inner_deg: Option<f32>,
    outer_deg: Option<f32>,
    color: Option<Vec3>,
    intensity: Option<f32>,
    technique: Option<Technique>,
    shadow_map_size: Option<u32>,
    range: Option<f32>,
}

/// Loads a TOML scene file; mesh `path`s are relative to the file's folder.
pub fn load_scene_file(path: &Path) -> SceneResult<Scene> {
    let bytes = crate::files::read_regular(path, MAX_SCENE_FILE_BYTES)?;
    let text = String::from_utf8(bytes)
        .map_err(|e| SceneError::SceneFile { path: path.to_owned(), message: format!("not UTF-8 text: {e}") })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    parse_scene(&text, dir, &stem).map_err(|message| SceneError::SceneFile { path: path.to_owned(), message })
}

/// Parses scene-file text; `dir` resolves mesh paths.
pub fn parse_scene(text: &str, dir: &Path, default_name: &str) -> Result<Scene, String> {
    let file: File = toml::from_str(text).map_err(|e| e.to_string())?;
    let mut scene = Scene::new(file.name.unwrap_or_else(|| default_name.to_owned()));
    scene.ambient = file.ambient.unwrap_or(scene.ambient);
    scene.background = file.background.unwrap_or(scene.background);
    let mut names = Vec::new();
    for entry in file.mesh {
        if names.contains(&entry.name) {
            return Err(format!("two meshes are named {:?}: an object's `mesh` would be ambiguous", entry.name));
        }
        let mut mesh = build_mesh(&entry.source, dir).map_err(|e| format!("mesh {:?}: {e}", entry.name))?;
        mesh.name = entry.name.clone();
        names.push(entry.name);
        scene.add_mesh(mesh);
    }
    for o in file.object {
        let id = names
            .iter()
            .position(|n| *n == o.mesh)
            .ok_or_else(|| format!("object refers to unknown mesh {:?}", o.mesh))?;
        let r = o.rotation_deg.unwrap_or(Vec3::ZERO);
        let rotation = Quat::from_euler(EulerRot::XYZ, r.x.to_radians(), r.y.to_radians(), r.z.to_radians());
        let scale = match o.scale {
            None => Vec3::ONE,
            Some(Scale::Uniform(s)) => Vec3::splat(s),
            Some(Scale::Axes(v)) => v,
        };
        let name = o.name.unwrap_or(o.mesh);
        let repeat = o.repeat.unwrap_or(1) as usize;
        if repeat == 0 {
            return Err(format!("object {name:?}: repeat = 0 places nothing (omit the object, or repeat ≥ 1)"));
        }
        if scene.objects.len() + repeat > MAX_OBJECTS {
            let total = scene.objects.len() + repeat;
            return Err(format!(
                "object {name:?}: repeat = {repeat} makes {total} objects, beyond umbra's limit of {MAX_OBJECTS}"
            ));
        }
        for i in 0..repeat {
            let at = o.translation.unwrap_or(Vec3::ZERO) + o.step.unwrap_or(Vec3::ZERO) * i as f32;
            let transform = Mat4::from_scale_rotation_translation(scale, rotation, at);
            let obj = scene.add_object(id, transform, o.albedo.unwrap_or(Vec3::splat(0.8)));
            obj.name = if repeat > 1 { format!("{name} {i}") } else { name.clone() };
            obj.casts_shadows = o.casts_shadows.unwrap_or(true);
            obj.receives_shadows = o.receives_shadows.unwrap_or(true);
        }
    }
    for l in file.light {
        scene.lights.push(build_light(l)?);
    }
    match file.camera {
        Some(c) => scene.camera = c,
        None => scene.frame_camera(),
    }
    scene.validate().map_err(|e| e.to_string())?;
    Ok(scene)
}

/// `value` if it is finite and > 0, else an error naming `field`.
fn positive(field: &str, value: f32) -> Result<f32, String> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("`{field}` = {value} must be finite and > 0"))
    }
}

/// `value` (or `default`) if it lies in `min..=max`, else an error naming `field`.
fn count(field: &str, value: Option<u32>, default: u32, min: u32, max: u32) -> Result<u32, String> {
    match value.unwrap_or(default) {
        v if (min..=max).contains(&v) => Ok(v),
        v => Err(format!("`{field}` = {v} must be in {min}..={max}")),
    }
}

fn build_mesh(source: &MeshSource, dir: &Path) -> Result<Mesh, String> {
    Ok(match *source {
        MeshSource::Plane { size } => primitives::plane(positive("size", size)?),
        MeshSource::Box { half } => {
            for (axis, h) in ["x", "y", "z"].iter().zip(half.to_array()) {
                positive(&format!("half.{axis}"), h)?;
            }
            primitives::cuboid(half)
        }
        MeshSource::Sphere { radius, segments, rings } => primitives::sphere(
            positive("radius", radius)?,
            count("segments", segments, 48, 3, MAX_SEGMENTS)?,
            count("rings", rings, 24, 2, MAX_SEGMENTS)?,
        ),
        MeshSource::Cylinder { radius, height, segments } => primitives::cylinder(
            positive("radius", radius)?,
            positive("height", height)?,
            count("segments", segments, 48, 3, MAX_SEGMENTS)?,
        ),
        MeshSource::File { ref path } => merged_file(&dir.join(path))?,
        MeshSource::Tree { depth, seed } => crate::procedural::tree(
            seed.unwrap_or(crate::procedural::TREE_SEED),
            count("depth", depth, 7, 0, MAX_TREE_DEPTH)?,
        ),
        MeshSource::Triangles { ref positions, ref indices } => {
            Mesh::with_flat_normals("triangles", positions, indices).map_err(|e| match e {
                SceneError::InvalidMesh { why, .. } => why,
                e => e.to_string(),
            })?
        }
    })
}

/// A whole glTF file as one mesh, its node transforms baked in (at most
/// [`MAX_VERTICES`] vertices and [`MAX_INDICES`] indices once instances are copied).
fn merged_file(path: &Path) -> Result<Mesh, String> {
    let sub = crate::import_gltf(path).map_err(|e| e.to_string())?;
    let (mut vertices, mut indices) = (0usize, 0usize);
    for o in &sub.objects {
        vertices = vertices.saturating_add(sub.meshes[o.mesh].positions.len());
        indices = indices.saturating_add(sub.meshes[o.mesh].indices.len());
    }
    if vertices > MAX_VERTICES || indices > MAX_INDICES {
        return Err(format!(
            "{}: its {} instances make {vertices} vertices and {indices} indices, beyond umbra's limits of {MAX_VERTICES} and {MAX_INDICES}",
            path.display(),
            sub.objects.len()
        ));
    }
    let mut merged = Mesh::default();
    for o in &sub.objects {
        merged.append(&sub.meshes[o.mesh].clone().transformed(o.transform));
    }
    Ok(merged)
}

fn build_light(l: LightEntry) -> Result<Light, String> {
    let need = |v: Option<Vec3>, what: &str| v.ok_or_else(|| format!("light needs `{what}`"));
    let intensity = l.intensity.unwrap_or(1.0);
    let mut light = match l.kind {
        Kind::Directional => Light::directional(need(l.direction, "direction")?, intensity),
        Kind::Point => Light::point(need(l.position, "position")?, intensity),
        Kind::Spot => {
            let mut s = Light::point(need(l.position, "position")?, intensity);
            let outer = l.outer_deg.unwrap_or(30.0);
            s.spot = Some(Spot {
                direction: need(l.direction, "direction")?,
                inner_deg: l.inner_deg.unwrap_or(outer * 0.8),
                outer_deg: outer,
            });
            s
        }
    };
    light.color = l.color.unwrap_or(Vec3::ONE);
    light.technique = l.technique.unwrap_or_default();
    light.shadow_map_size = l.shadow_map_size;
    light.range = l.range;
    light.name = l.name.unwrap_or_default();
    Ok(light)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_file_builds_meshes_objects_lights_and_camera() {
        let text = r#"
            name = "t"
            [camera]
            position = [0, 2, 5]
            target = [0, 0, 0]
            [[mesh]]
            name = "floor"
            kind = "box"
            half = [5, 0.05, 5]
            [[object]]
            mesh = "floor"
            translation = [0, -0.05, 0]
            scale = 2
            [[light]]
            kind = "spot"
            position = [0, 4, 0]
            direction = [0, -1, 0]
            outer_deg = 25
            technique = "shadow_map"
        "#;
        let s = parse_scene(text, Path::new("."), "x").unwrap();
        assert_eq!(s.name, "t");
        assert_eq!(s.objects.len(), 1);
        assert_eq!(s.lights[0].kind(), crate::LightKind::Spot);
        assert_eq!(s.lights[0].technique, Technique::ShadowMap);
        assert_eq!(s.camera.far, None, "no far given: infinite");
        assert!((s.bounds().max.x - 10.0).abs() < 1e-5);
    }

    #[test]
    fn errors_name_the_problem() {
        let e = parse_scene("[[object]]\nmesh = \"nope\"\n", Path::new("."), "x").unwrap_err();
        assert!(e.contains("unknown mesh"), "{e}");
        let e = parse_scene("[[light]]\nkind = \"point\"\n", Path::new("."), "x").unwrap_err();
        assert!(e.contains("position"), "{e}");
        assert!(parse_scene("bogus = 1", Path::new("."), "x").is_err());
    }

    #[test]
    fn inline_triangles_and_repeated_objects() {
        let text = r#"
            [[mesh]]
            name = "fin"
            kind = "triangles"
            positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
            indices = [0, 1, 2]
            [[object]]
            mesh = "fin"
            translation = [0, 1, 0]
            repeat = 3
            step = [0, 0.5, 0]
        "#;
        let s = parse_scene(text, Path::new("."), "x").unwrap();
        assert_eq!(s.objects.len(), 3);
        assert_eq!(s.objects[2].transform.w_axis.y, 2.0);
        assert_eq!(s.objects[1].name, "fin 1");
        assert_eq!(s.meshes[0].triangle_count(), 1);
    }

    #[test]
    fn non_finite_and_huge_coordinates_are_typed_errors() {
        let mesh = |p: &str| {
            format!("[[mesh]]\nname = \"m\"\nkind = \"triangles\"\npositions = [[0, 0, 0], [1, 0, 0], {p}]\nindices = [0, 1, 2]\n")
        };
        for (p, why) in [("[nan, 1, 0]", "not finite"), ("[0, inf, 0]", "not finite"), ("[0, 1e30, 0]", "beyond")] {
            let e = parse_scene(&mesh(p), Path::new("."), "x").unwrap_err();
            assert!(e.contains(why), "{p}: {e}");
        }
        let light = "[[light]]\nkind = \"point\"\nposition = [0, nan, 0]\n";
        assert!(parse_scene(light, Path::new("."), "x").unwrap_err().contains("not finite"));
        let far = "[[object]]\nmesh = \"m\"\ntranslation = [2e12, 0, 0]\n";
        let e = parse_scene(&(mesh("[0, 1, 0]") + far), Path::new("."), "x").unwrap_err();
        assert!(e.contains("world space"), "{e}");
    }
}

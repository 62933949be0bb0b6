//! glTF 2.0 import: node hierarchy, triangle meshes, perspective cameras, `KHR_lights_punctual`.

use crate::error::{SceneError, SceneResult};
use crate::{Camera, Light, Mesh, Scene, Spot};
use glam::{Mat4, Vec3, Vec4};
use std::collections::HashMap;
use std::path::Path;

/// Imports a `.glb` or `.gltf` file (external buffers resolved next to it).
pub fn import_gltf(path: &Path) -> SceneResult<Scene> {
    let (doc, buffers, _images) =
        gltf::import(path).map_err(|source| SceneError::Gltf { path: path.to_owned(), source })?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    build(&doc, &buffers, &name, path)
}

/// Imports a glTF document from memory (`.glb` bytes or `.gltf` JSON with embedded buffers).
pub fn import_gltf_slice(bytes: &[u8], name: &str) -> SceneResult<Scene> {
    let memory = Path::new("<memory>");
    let (doc, buffers, _images) =
        gltf::import_slice(bytes).map_err(|source| SceneError::Gltf { path: memory.to_owned(), source })?;
    build(&doc, &buffers, name, memory)
}

fn build(doc: &gltf::Document, buffers: &[gltf::buffer::Data], name: &str, path: &Path) -> SceneResult<Scene> {
    let mut scene = Scene::new(name);
    let mut camera = None;
    let mut cache: HashMap<(usize, usize), usize> = HashMap::new();
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => doc.nodes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
    let mut visited = 0usize;
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > doc.nodes().len() * 4 + 16 {
            return Err(SceneError::SceneFile { path: path.to_owned(), message: "node hierarchy has a cycle".into() });
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    log::warn!(
                        "{}: mesh {:?} primitive {} is {:?}, not triangles: skipped",
                        path.display(),
                        mesh.name(),
                        prim.index(),
                        prim.mode()
                    );
                    continue;
                }
                let key = (mesh.index(), prim.index());
                let id = match cache.get(&key) {
                    Some(&id) => id,
                    None => {
                        let m = read_primitive(&prim, buffers, mesh.name().unwrap_or("mesh"), path)?;
                        let id = scene.add_mesh(m);
                        cache.insert(key, id);
                        id
                    }
                };
                let albedo = Vec4::from(prim.material().pbr_metallic_roughness().base_color_factor()).truncate();
                let o = scene.add_object(id, world, albedo);
                o.name = node.name().or(mesh.name()).unwrap_or("node").to_owned();
            }
        }
        if let (None, Some(cam)) = (&camera, node.camera()) {
            camera = read_camera(&cam, world);
        }
        if let Some(light) = node.light() {
            scene.lights.push(read_light(&light, world));
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    match camera {
        Some(c) => scene.camera = c,
        None => scene.frame_camera(),
    }
    Ok(scene)
}

fn read_primitive(
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    name: &str,
    path: &Path,
) -> SceneResult<Mesh> {
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| d.0.as_slice()));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| SceneError::InvalidMesh {
            mesh: name.to_owned(),
            why: format!("{}: no POSITION", path.display()),
        })?
        .map(Vec3::from)
        .collect();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let authored = crate::TopologyReport::of_indices(positions.len(), &indices);
    let mut mesh = match reader.read_normals() {
        Some(n) => Mesh::new(name, positions, n.map(|n| Vec3::from(n).normalize_or_zero()).collect(), indices),
        // glTF 2.0 §3.7.2.1: "When normals are not specified, client implementations MUST
        // calculate flat normals."
        None => Mesh::with_flat_normals(name, &positions, &indices),
    }?;
    mesh.authored_topology = Some(authored);
    Ok(mesh)
}

fn read_camera(cam: &gltf::Camera, world: Mat4) -> Option<Camera> {
    let gltf::camera::Projection::Perspective(p) = cam.projection() else {
        log::warn!("orthographic glTF camera {:?} ignored: umbra cameras are perspective", cam.name());
        return None;
    };
    let position = world.transform_point3(Vec3::ZERO);
    Some(Camera {
        position,
        target: position + world.transform_vector3(-Vec3::Z),
        up: world.transform_vector3(Vec3::Y),
        fov_y_deg: p.yfov().to_degrees(),
        near: p.znear(),
        far: p.zfar(),
    })
}

fn read_light(light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    use gltf::khr_lights_punctual::Kind;
    // Punctual lights shine along the node's local -Z.
    let shine = world.transform_vector3(-Vec3::Z);
    let position = world.transform_point3(Vec3::ZERO);
    let mut l = match light.kind() {
        Kind::Directional => Light::directional(-shine, light.intensity()),
        Kind::Point => Light::point(position, light.intensity()),
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let mut l = Light::point(position, light.intensity());
            l.spot = Some(Spot {
                direction: shine,
                inner_deg: inner_cone_angle.to_degrees(),
                outer_deg: outer_cone_angle.to_degrees(),
            });
            l
        }
    };
    l.color = Vec3::from(light.color());
    l.range = light.range();
    l.name = light.name().unwrap_or("light").to_owned();
    l
}

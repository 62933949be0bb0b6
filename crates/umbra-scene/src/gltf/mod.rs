//! glTF 2.0 import: node hierarchy, triangle meshes, perspective cameras, `KHR_lights_punctual`.
//!
//! umbra reads the JSON with `gltf-json`'s types and then checks everything it uses itself,
//! before reading a byte of buffer data: every index, every accessor's type, componentType and
//! extent, every bufferView against its buffer, the node hierarchy. Buffers come from the GLB
//! binary chunk, `data:` URIs, or regular files inside the glTF file's folder — never an
//! absolute path, a `..`, a symbolic link out of the folder, a URI scheme or a device. Images
//! are never read or decoded: umbra draws geometry only. Every failure is a
//! [`crate::SceneError`] naming the JSON path; none panics.

mod accessor;
mod buffers;
mod container;
mod nodes;
mod source;
mod uri;

use crate::error::{SceneError, SceneResult};
use crate::limits::{MAX_FILE_BYTES, MAX_OBJECTS};
use crate::{Camera, Light, Mesh, Scene, Spot};
use accessor::Reader;
use buffers::Buffers;
use container::Document;
use glam::{Mat4, Vec3};
use gltf::json::mesh::{Mode, Primitive, Semantic};
use gltf::json::validation::Checked;
use gltf::json::Root;
use source::Source;
use std::collections::HashMap;
use std::path::Path;

/// Imports a `.glb` or `.gltf` file (external buffers resolved inside its folder).
pub fn import_gltf(path: &Path) -> SceneResult<Scene> {
    let bytes = crate::files::read_regular(path, MAX_FILE_BYTES)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    import(&bytes, &Source::file(path), &name)
}

/// Imports a glTF document from memory (`.glb` bytes or `.gltf` JSON with embedded buffers;
/// a URI naming a file is refused: there is no folder to resolve it in).
pub fn import_gltf_slice(bytes: &[u8], name: &str) -> SceneResult<Scene> {
    import(bytes, &Source::memory(), name)
}

fn import(bytes: &[u8], src: &Source, name: &str) -> SceneResult<Scene> {
    let doc = container::parse(bytes, src)?;
    let order = nodes::walk(&doc.root, src)?;
    let buffers = Buffers::load(&doc, &needed_buffers(&doc), src)?;
    let scene = build(&doc, &Reader { root: &doc.root, buffers: &buffers, src }, &order, name)?;
    scene.validate()?;
    Ok(scene)
}

/// The triangle primitives umbra draws.
fn drawn(p: &Primitive) -> bool {
    p.mode == Checked::Valid(Mode::Triangles)
}

/// Which buffers the drawn primitives' accessors read (images' buffers are never opened).
fn needed_buffers(doc: &Document) -> Vec<bool> {
    let root = &doc.root;
    let mut needed = vec![false; root.buffers.len()];
    let mut mark = |view: usize| {
        if let Some(b) = root.buffer_views.get(view).and_then(|v| needed.get_mut(v.buffer.value())) {
            *b = true;
        }
    };
    let prims = root.meshes.iter().flat_map(|m| &m.primitives).filter(|p| drawn(p));
    for p in prims {
        for a in p.attributes.values().chain(&p.indices).filter_map(|a| root.accessors.get(a.value())) {
            a.buffer_view.iter().for_each(|v| mark(v.value()));
            if let Some(s) = &a.sparse {
                mark(s.indices.buffer_view.value());
                mark(s.values.buffer_view.value());
            }
        }
    }
    needed
}

fn build(doc: &Document, reader: &Reader, order: &[(usize, Mat4)], name: &str) -> SceneResult<Scene> {
    let (root, src) = (&doc.root, reader.src);
    let mut scene = Scene::new(name);
    let mut camera = None;
    let mut meshes: HashMap<(usize, usize), usize> = HashMap::new();
    for &(i, world) in order {
        let node = &root.nodes[i];
        let at = |field: &str| format!("nodes[{i}].{field}");
        if let Some(m) = node.mesh {
            let mesh = root
                .meshes
                .get(m.value())
                .ok_or_else(|| missing(src, at("mesh"), "mesh", m.value(), root.meshes.len()))?;
            for (p, prim) in mesh.primitives.iter().enumerate() {
                if prim.mode == Checked::Invalid {
                    return Err(
                        src.error(format!("meshes[{}].primitives[{p}].mode", m.value()), "not a glTF primitive mode")
                    );
                }
                if !drawn(prim) {
                    log::warn!(
                        "{}: meshes[{}].primitives[{p}] is not triangles: skipped",
                        src.path.display(),
                        m.value()
                    );
                    continue;
                }
                let id = match meshes.get(&(m.value(), p)) {
                    Some(&id) => id,
                    None => {
                        let label = mesh.name.clone().unwrap_or_else(|| format!("mesh {}", m.value()));
                        let id = scene.add_mesh(primitive(reader, prim, &label, m.value(), p)?);
                        meshes.insert((m.value(), p), id);
                        id
                    }
                };
                if scene.objects.len() >= MAX_OBJECTS {
                    let what = format!("glTF {}: placed mesh primitives", src.path.display());
                    return Err(SceneError::Limit {
                        what,
                        value: scene.objects.len() as u64 + 1,
                        limit: MAX_OBJECTS as u64,
                    });
                }
                let albedo = albedo(root, prim, src)?;
                let o = scene.add_object(id, world, albedo);
                o.name = node.name.clone().or_else(|| mesh.name.clone()).unwrap_or_else(|| format!("node {i}"));
            }
        }
        if let Some(c) = node.camera {
            let cam = root
                .cameras
                .get(c.value())
                .ok_or_else(|| missing(src, at("camera"), "camera", c.value(), root.cameras.len()))?;
            if camera.is_none() {
                camera = read_camera(cam, world);
            }
        }
        if let Some(l) = node.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()) {
            let lights =
                root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map_or(&[][..], |k| &k.lights);
            let light = lights.get(l.light.value()).ok_or_else(|| {
                missing(src, at("extensions.KHR_lights_punctual.light"), "light", l.light.value(), lights.len())
            })?;
            scene.lights.push(read_light(light, world, l.light.value(), src)?);
        }
    }
    match camera {
        Some(c) => scene.camera = c,
        None => scene.frame_camera(),
    }
    Ok(scene)
}

fn missing(src: &Source, at: String, what: &str, index: usize, len: usize) -> SceneError {
    src.error(at, format!("{what} {index} does not exist (the file has {len})"))
}

fn albedo(root: &Root, prim: &Primitive, src: &Source) -> SceneResult<Vec3> {
    let Some(m) = prim.material else { return Ok(Vec3::ONE) };
    let material = root
        .materials
        .get(m.value())
        .ok_or_else(|| missing(src, "primitive.material".into(), "material", m.value(), root.materials.len()))?;
    Ok(Vec3::from_slice(&material.pbr_metallic_roughness.base_color_factor.0[..3]))
}

fn primitive(reader: &Reader, prim: &Primitive, name: &str, m: usize, p: usize) -> SceneResult<Mesh> {
    let at = format!("meshes[{m}].primitives[{p}]");
    let attribute = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|a| a.value());
    let position = attribute(Semantic::Positions).ok_or_else(|| reader.src.error(&at, "has no POSITION attribute"))?;
    let positions = reader.vec3(position, &format!("{at}.attributes.POSITION"))?;
    let indices = match prim.indices {
        Some(i) => reader.indices(i.value(), &format!("{at}.indices"))?,
        None => (0..positions.len() as u32).collect(),
    };
    let authored = crate::TopologyReport::of_indices(positions.len(), &indices);
    let mut mesh = match attribute(Semantic::Normals) {
        Some(n) => {
            let normals = reader.vec3(n, &format!("{at}.attributes.NORMAL"))?;
            if normals.len() != positions.len() {
                let why = format!("NORMAL has {} elements, POSITION {}", normals.len(), positions.len());
                return Err(reader.src.error(&at, why));
            }
            Mesh::new(name, positions, normals.into_iter().map(Vec3::normalize_or_zero).collect(), indices)
        }
        // glTF 2.0 §3.7.2.1: "When normals are not specified, client implementations MUST
        // calculate flat normals."
        None => Mesh::with_flat_normals(name, &positions, &indices),
    }?;
    mesh.authored_topology = Some(authored);
    Ok(mesh)
}

fn read_camera(cam: &gltf::json::Camera, world: Mat4) -> Option<Camera> {
    let Some(p) =
        cam.perspective.as_ref().filter(|_| cam.type_ == Checked::Valid(gltf::json::camera::Type::Perspective))
    else {
        log::warn!("glTF camera {:?} is not perspective: ignored (umbra cameras are perspective)", cam.name);
        return None;
    };
    let position = world.transform_point3(Vec3::ZERO);
    Some(Camera {
        position,
        target: position + world.transform_vector3(-Vec3::Z),
        up: world.transform_vector3(Vec3::Y),
        fov_y_deg: p.yfov.to_degrees(),
        near: p.znear,
        far: p.zfar,
    })
}

fn read_light(
    light: &gltf::json::extensions::scene::khr_lights_punctual::Light,
    world: Mat4,
    index: usize,
    src: &Source,
) -> SceneResult<Light> {
    use gltf::json::extensions::scene::khr_lights_punctual::Type;
    // Punctual lights shine along the node's local -Z.
    let shine = world.transform_vector3(-Vec3::Z);
    let position = world.transform_point3(Vec3::ZERO);
    let at = format!("extensions.KHR_lights_punctual.lights[{index}]");
    let mut l = match light.type_ {
        Checked::Valid(Type::Directional) => Light::directional(-shine, light.intensity),
        Checked::Valid(Type::Point) => Light::point(position, light.intensity),
        Checked::Valid(Type::Spot) => {
            let cone = light.spot.as_ref().ok_or_else(|| src.error(&at, "a spot light needs `spot`"))?;
            let mut l = Light::point(position, light.intensity);
            l.spot = Some(Spot {
                direction: shine,
                inner_deg: cone.inner_cone_angle.to_degrees(),
                outer_deg: cone.outer_cone_angle.to_degrees(),
            });
            l
        }
        Checked::Invalid => return Err(src.error(&at, "type is not directional, point or spot")),
    };
    l.color = Vec3::from(light.color);
    l.range = light.range;
    l.name = light.name.clone().unwrap_or_else(|| format!("light {index}"));
    Ok(l)
}

//! glTF import: flat normals, node transforms, cameras and lights, malformed input, real assets.

use glam::{Vec3, Vec4};
use std::path::PathBuf;
use umbra_scene::{import_gltf, import_gltf_slice, LightKind, SceneError};

fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// A glTF JSON document with one triangle (positions + u32 indices, no normals) and `nodes`.
fn document(indices: [u32; 3], nodes: &str, extra: &str) -> String {
    let positions = [[1.0f32, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let mut bin: Vec<u8> = positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{b64}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,-1], "max": [1,1,0]}},
    {{"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}}
  ],
  "meshes": [{{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "nodes": [{nodes}],
  "scenes": [{{"nodes": [0]}}],
  "scene": 0{extra}
}}"#,
        len = bin.len(),
        b64 = base64(&bin)
    )
}

#[test]
fn a_mesh_without_normals_gets_flat_normals() {
    let doc = document([0, 1, 2], r#"{"mesh": 0}"#, "");
    let scene = import_gltf_slice(doc.as_bytes(), "tri").unwrap();
    let mesh = &scene.meshes[0];
    // a=(1,0,0), b=(0,0,-1), c=(0,1,0): (b - a) x (c - a) = (-1,0,-1) x (-1,1,0) = (1,1,-1).
    let expected = Vec3::new(1.0, 1.0, -1.0).normalize();
    assert_eq!(mesh.normals.len(), 3);
    for n in &mesh.normals {
        assert!(n.abs_diff_eq(expected, 1e-6), "normal {n}");
    }
}

#[test]
fn node_transforms_compose_parent_times_child() {
    // Parent: translate (1,2,3), scale 2. Child: rotate 90 degrees about +Y, translate (1,0,0).
    // Vertex (1,0,0): rotation -> (0,0,-1); + (1,0,0) -> (1,0,-1); scale -> (2,0,-2);
    // + (1,2,3) -> (3,2,1), computed by hand.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let nodes = format!(
        r#"{{"children": [1], "translation": [1,2,3], "scale": [2,2,2]}},
           {{"mesh": 0, "rotation": [0,{h},0,{h}], "translation": [1,0,0]}}"#
    );
    let scene = import_gltf_slice(document([0, 1, 2], &nodes, "").as_bytes(), "tree").unwrap();
    assert_eq!(scene.objects.len(), 1);
    let p = scene.objects[0].transform * Vec4::new(1.0, 0.0, 0.0, 1.0);
    assert!(p.truncate().abs_diff_eq(Vec3::new(3.0, 2.0, 1.0), 1e-5), "landed at {p}");
}

#[test]
fn cameras_and_punctual_lights_are_imported_in_world_space() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    // Node 1: camera at (0,1,5) looking down -Z. Node 2: directional light rotated -90 degrees
    // about X, so it shines along -Y (straight down): towards-light is +Y.
    let nodes = format!(
        r#"{{"mesh": 0, "children": [1, 2]}},
           {{"camera": 0, "translation": [0,1,5]}},
           {{"rotation": [-{h},0,0,{h}], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}"#
    );
    let extra = r#",
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 50}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1,0.5,0.25], "intensity": 3}]}}"#;
    let scene = import_gltf_slice(document([0, 1, 2], &nodes, extra).as_bytes(), "cam").unwrap();
    assert!(scene.camera.position.abs_diff_eq(Vec3::new(0.0, 1.0, 5.0), 1e-6));
    assert!((scene.camera.target - scene.camera.position).normalize().abs_diff_eq(-Vec3::Z, 1e-6));
    assert_eq!(scene.camera.far, Some(50.0));
    let light = &scene.lights[0];
    assert_eq!(light.kind(), LightKind::Directional);
    assert!(light.position.truncate().abs_diff_eq(Vec3::Y, 1e-5), "towards light {}", light.position);
    assert_eq!(light.radiance(), Vec3::new(3.0, 1.5, 0.75));
}

#[test]
fn malformed_files_give_errors_not_panics() {
    assert!(matches!(import_gltf_slice(b"not a gltf file", "junk"), Err(SceneError::Gltf { .. })));
    let doc = document([0, 1, 2], r#"{"mesh": 0}"#, "");
    let truncated = &doc.as_bytes()[..doc.len() / 2];
    assert!(import_gltf_slice(truncated, "cut").is_err());
    let bad_ref = doc.replace(r#""nodes": [{"mesh": 0}]"#, r#""nodes": [{"mesh": 7}]"#);
    assert!(import_gltf_slice(bad_ref.as_bytes(), "bad ref").is_err());
    let e = import_gltf_slice(document([0, 1, 9], r#"{"mesh": 0}"#, "").as_bytes(), "bad index").unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
    let mut glb = b"glTF".to_vec();
    glb.extend([2, 0, 0, 0, 255, 255, 0, 0]);
    assert!(import_gltf_slice(&glb, "bad glb").is_err());
    assert!(matches!(import_gltf(std::path::Path::new("/nonexistent/x.glb")), Err(SceneError::Io { .. })));
}

/// The repository's `assets/` folder, or `UMBRA_ASSETS`.
fn assets() -> PathBuf {
    std::env::var_os("UMBRA_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets"))
}

#[test]
fn the_topology_report_reproduces_the_assets_readme_table() {
    // assets/README.md: triangles, boundary edges, non-manifold edges, closed.
    let table = [
        ("spot.glb", 5_856, 0, 0, true),
        ("fandisk.glb", 12_946, 0, 0, true),
        ("teapot.glb", 6_320, 1_036, 0, false),
        ("stanford-bunny.glb", 69_451, 223, 0, false),
        ("suzanne.glb", 968, 42, 1, false),
    ];
    for (file, tris, boundary, non_manifold, closed) in table {
        let scene = import_gltf(&assets().join(file)).unwrap();
        let r = scene.meshes[0].authored_topology.expect("imported meshes record their topology");
        let welded = umbra_scene::Adjacency::build(&scene.meshes[0]).report;
        println!("{file}: authored {r:?}\n{file}: welded by position {welded:?}");
        assert_eq!(
            (r.triangles, r.boundary_edges, r.non_manifold_edges, r.closed),
            (tris, boundary, non_manifold, closed),
            "{file}"
        );
        // Welding by position can only merge vertices: never more boundary edges, and closed
        // meshes stay closed.
        assert!(welded.boundary_edges <= r.boundary_edges && (!closed || welded.closed), "{file}");
    }
}

#[test]
fn every_asset_loads_with_its_documented_triangle_count() {
    let expected = [
        ("spot.glb", 5_856),
        ("fandisk.glb", 12_946),
        ("teapot.glb", 6_320),
        ("stanford-bunny.glb", 69_451),
        ("suzanne.glb", 968),
    ];
    let dir = assets();
    assert!(dir.is_dir(), "assets folder {} missing (set UMBRA_ASSETS)", dir.display());
    for (file, tris) in expected {
        let scene = import_gltf(&dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(scene.triangle_count(), tris, "{file}");
        // The assets carry no NORMAL: flat normals, three vertices per triangle.
        let mesh = &scene.meshes[0];
        assert_eq!(mesh.normals.len(), 3 * mesh.triangle_count(), "{file} flat normals");
        assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3 || *n == Vec3::ZERO));
    }
}

#[test]
fn sparse_accessors_substitute_their_values() {
    // Vertex 2 of the triangle replaced by (0, 5, 0) through a sparse substitution read from
    // a second buffer.
    let mut sparse: Vec<u8> = 2u32.to_le_bytes().to_vec();
    sparse.extend([0.0f32, 5.0, 0.0].iter().flat_map(|f| f.to_le_bytes()));
    let second = format!(r#"{{"byteLength": 16, "uri": "data:application/octet-stream;base64,{}"}}"#, base64(&sparse));
    let doc = document([0, 1, 2], r#"{"mesh": 0}"#, "")
        .replace("\"}],\n  \"bufferViews\"", &format!("\"}}, {second}],\n  \"bufferViews\""))
        .replace(
            r#""byteOffset": 36, "byteLength": 12}]"#,
            r#""byteOffset": 36, "byteLength": 12}, {"buffer": 1, "byteLength": 4}, {"buffer": 1, "byteOffset": 4, "byteLength": 12}]"#,
        )
        .replace(
            r#""count": 3, "type": "VEC3""#,
            r#""count": 3, "type": "VEC3", "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5125}, "values": {"bufferView": 3}}"#,
        );
    let scene = import_gltf_slice(doc.as_bytes(), "sparse").unwrap_or_else(|e| panic!("{e}\n{doc}"));
    let p = &scene.meshes[0].positions;
    assert!(p.contains(&Vec3::new(0.0, 5.0, 0.0)) && !p.contains(&Vec3::new(0.0, 1.0, 0.0)), "{p:?}");
}

//! Every embedded module passes `spirv-val` (Debian package `spirv-tools`).

use std::io::Write;
use std::process::{Command, Stdio};

#[test]
fn every_embedded_module_passes_spirv_val() {
    assert!(!umbra_shaders::ALL.is_empty(), "no shaders were embedded");
    for shader in umbra_shaders::ALL {
        let bytes: Vec<u8> = shader.spirv.iter().flat_map(|w| w.to_le_bytes()).collect();
        let mut child = Command::new("spirv-val")
            .args(["--target-env", "vulkan1.3", "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spirv-val not found: install spirv-tools (ci/setup.sh does)");
        child.stdin.take().expect("stdin").write_all(&bytes).expect("write SPIR-V");
        let out = child.wait_with_output().expect("spirv-val runs");
        assert!(
            out.status.success(),
            "spirv-val rejected {}:\n{}{}",
            shader.path,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    println!("spirv-val: {} modules valid", umbra_shaders::ALL.len());
}

#[test]
fn lookup_by_path_finds_the_forward_shaders() {
    let vs = umbra_shaders::get("forward/mesh.vert").expect("forward/mesh.vert embedded");
    assert_eq!(vs.stage, umbra_shaders::Stage::Vertex);
    assert_eq!(vs.spirv[0], 0x0723_0203, "SPIR-V magic number");
    assert!(umbra_shaders::get("common/scene.glsl").is_none(), "include files are not modules");
}

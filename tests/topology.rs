//! Every frame report lists each mesh's topology (triangles, closed, boundary and non-manifold
//! edges, as authored and after welding, and what shadow volumes do about them), and the
//! shadow-volume and hybrid examples print a one-line warning for open or non-manifold casters.

mod common;

use umbra::scene::Technique;
use umbra::shadows::{Renderer, RendererDesc, TopologySource, VolumeConstruction};

fn suzanne() -> std::path::PathBuf {
    common::assets().join("suzanne.glb")
}

#[test]
fn the_frame_report_lists_every_meshes_topology() {
    common::with_context(|ctx| {
        let mut renderer = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        let mut scene = umbra::scene::load(suzanne().to_str().unwrap()).unwrap();
        for light in &mut scene.lights {
            light.technique = Technique::ShadowVolume;
        }
        let report = renderer.render(&scene).unwrap().report;
        let t = &report.scene.topology;
        assert_eq!(t.len(), scene.meshes.len());
        let monkey = &t[0];
        println!("{}", serde_json::to_string(monkey).unwrap());
        assert_eq!((monkey.triangles, monkey.boundary_edges, monkey.non_manifold_edges), (968, 42, 1));
        assert!(!monkey.closed);
        assert_eq!(monkey.counted, TopologySource::AsAuthored);
        assert_eq!(monkey.shadow_volumes, VolumeConstruction::PerTriangle);
        assert!(monkey.welded.boundary_edges <= monkey.boundary_edges);
        let warning = monkey.warning().expect("an open caster is warned about");
        assert!(warning.contains("42 boundary edges") && warning.contains("1 non-manifold edge"), "{warning}");

        // Procedural closed meshes: counted welded, closed, silhouettes extruded, no warning.
        let cubes = umbra::scene::load("cubes").unwrap();
        let report = renderer.render(&cubes).unwrap().report;
        let closed: Vec<_> = report.scene.topology.iter().filter(|m| m.casters > 0).collect();
        assert!(!closed.is_empty());
        for m in closed {
            assert_eq!(
                (m.closed, m.counted, m.shadow_volumes),
                (true, TopologySource::Welded, VolumeConstruction::SilhouetteExtrusion),
                "{m:?}"
            );
            assert_eq!(m.warning(), None);
        }
    });
}

/// Runs `example` on `scene` headless at the test size; its stdout and its report JSON.
fn run_example(example: &str, scene: &str) -> (String, serde_json::Value) {
    let out = common::output_dir(&format!("topology-{example}"));
    let size = format!("{}x{}", common::SIZE.0, common::SIZE.1);
    let run = std::process::Command::new(common::example(example))
        .args(["--scene", scene, "--size", &size, "--warmup", "0", "--out"])
        .arg(&out)
        .output()
        .expect("example runs");
    let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
    assert!(run.status.success(), "{example} failed: {}\n{stdout}", String::from_utf8_lossy(&run.stderr));
    let json = std::fs::read_to_string(out.join(format!("{example}.json"))).expect("report JSON");
    (stdout, serde_json::from_str(&json).expect("JSON"))
}

#[test]
fn the_volume_examples_warn_about_open_and_non_manifold_casters() {
    for example in ["shadow_volume", "hybrid"] {
        let (stdout, report) = run_example(example, suzanne().to_str().unwrap());
        let warnings: Vec<&str> = stdout.lines().filter(|l| l.starts_with("warning: caster mesh")).collect();
        println!("{example}: {warnings:?}");
        assert_eq!(warnings.len(), 1, "{stdout}");
        assert!(warnings[0].contains("open (42 boundary edges) and non-manifold (1 non-manifold edge)"), "{stdout}");
        let m = &report["scene"]["topology"][0];
        assert_eq!((m["boundary_edges"].as_u64(), m["non_manifold_edges"].as_u64()), (Some(42), Some(1)), "{m}");
        assert_eq!(m["counted"], "as_authored");
        assert_eq!(m["shadow_volumes"], "per_triangle");

        let (stdout, _) = run_example(example, "cubes");
        assert!(!stdout.contains("warning: caster mesh"), "cubes are closed:\n{stdout}");
    }
}

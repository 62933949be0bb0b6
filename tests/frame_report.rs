//! The frame report: every pass timed on the GPU, the device that `UMBRA_DEVICE` selected.

mod common;

use umbra::shadows::{Renderer, RendererDesc};

#[test]
fn every_pass_has_a_positive_gpu_time_and_the_selected_device() {
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        let scene = umbra::scene::load("cubes").unwrap();
        let first = r.render(&scene).unwrap();
        let names = |f: &umbra::shadows::Frame| f.report.passes.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        // The first frame uploads the meshes in its own first pass; later ones reuse them.
        assert_eq!(names(&first), ["mesh upload", "ambient", "light 0 (point)", "readback"]);
        let frame = r.render(&scene).unwrap();
        let report = &frame.report;
        assert!(report.capabilities.timestamps, "{} has no timestamps", report.device);
        assert_eq!(names(&frame), ["ambient", "light 0 (point)", "readback"]);
        for p in &report.passes {
            let t = p.gpu_ms.expect("timed");
            println!("{:<18} {t:.4} ms", p.name);
            assert!(t > 0.0, "pass {} has GPU time {t}", p.name);
        }
        let total = report.total_gpu_ms.unwrap();
        let sum: f64 = report.passes.iter().filter_map(|p| p.gpu_ms).sum();
        assert!((total - sum).abs() < 1e-9);
        assert_eq!(report.passes[0].triangles as usize, scene.triangle_count());

        match std::env::var("UMBRA_DEVICE") {
            Ok(wanted) if !wanted.is_empty() => {
                let wanted = wanted.to_lowercase();
                assert!(
                    report.device.to_lowercase().contains(&wanted),
                    "device {:?} != UMBRA_DEVICE {wanted:?}",
                    report.device
                );
                let driver = report.driver.to_lowercase();
                let expected_driver = match wanted.as_str() {
                    "llvmpipe" => Some("llvmpipe"),
                    "swiftshader" => Some("swiftshader"),
                    _ => None,
                };
                if let Some(d) = expected_driver {
                    assert!(driver.contains(d), "driver {driver:?} is not {d}");
                }
            }
            _ => println!("UMBRA_DEVICE unset: rendered on {} ({})", report.device, report.driver),
        }

        let json: serde_json::Value = serde_json::from_str(&report.to_json()).unwrap();
        for key in ["device", "driver", "capabilities", "scene", "width", "height", "lights", "passes", "total_gpu_ms"]
        {
            assert!(json.get(key).is_some(), "JSON report lacks {key}");
        }
        assert_eq!(json["passes"][0]["name"], "ambient");
        assert_eq!(json["scene"]["name"], "cubes");
    });
}

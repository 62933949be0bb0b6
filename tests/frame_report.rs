//! The frame report: every pass timed on the GPU, the device that `UMBRA_DEVICE` selected.

mod common;

use umbra::shadows::{Renderer, RendererDesc};
use umbra::vk::selection::fits;

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
                // The report names the device and driver that UMBRA_DEVICE picked.
                let (device, driver) = (&report.device, &report.driver);
                assert!(
                    fits(&wanted, device, driver),
                    "device {device:?}, driver {driver:?} != UMBRA_DEVICE {wanted:?}"
                );
                assert_eq!(report.driver, ctx.capabilities().driver());
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

#[test]
fn a_frame_kept_on_the_gpu_is_the_frame_read_back() {
    common::with_context(|ctx| {
        let scene = umbra::scene::load("cubes").unwrap();
        let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
        let read = Renderer::new(ctx, desc).unwrap().render(&scene).unwrap();
        desc.read_color = false;
        let mut kept = Renderer::new(ctx, desc).unwrap();
        let frame = kept.render(&scene).unwrap();
        assert!(frame.rgba.is_empty(), "read_color off: nothing read back");
        let names = |f: &umbra::shadows::Frame| f.report.passes.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        assert_eq!(names(&frame), names(&read), "the same passes");
        // The engine's own copy of the colour target, left in TRANSFER_SRC_OPTIMAL.
        let image = kept.color_image().unwrap();
        let size = u64::from(4 * common::SIZE.0 * common::SIZE.1);
        let out = umbra::vk::Buffer::new(ctx, "test readback", umbra::vk::BufferDesc::readback(size)).unwrap();
        let mut rec = ctx.begin_commands("copy the kept frame").unwrap();
        rec.copy_image_to_buffer(image, 0, &out);
        rec.transfer_to_host(&[&out]);
        ctx.submit_and_wait(rec).unwrap();
        assert!(out.read().unwrap() == read.rgba, "the kept image differs from the read-back frame");
        println!("read_color off: the colour target on the GPU equals the read-back frame ({} bytes)", read.rgba.len());
    });
}

//! Every procedural scene and every asset in `assets/` renders, validation-clean, and shows something.

mod common;

use umbra::shadows::{Frame, Renderer, RendererDesc};

/// Fraction of pixels that differ from the background colour.
fn coverage(frame: &Frame, background: [u8; 3]) -> f64 {
    let covered = frame.rgba.chunks_exact(4).filter(|p| p[..3] != background).count();
    covered as f64 / (frame.width * frame.height) as f64
}

fn render_and_check(renderer: &mut Renderer, spec: &str, stem: &str) {
    let scene = umbra::scene::load(spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    let frame = renderer.render(&scene).unwrap_or_else(|e| panic!("{spec}: {e}"));
    let bg = (scene.background * 255.0).to_array().map(|v| v as u8);
    let covered = coverage(&frame, bg);
    println!("{stem}: {} triangles, {:.0}% of pixels covered", frame.report.scene.triangles, covered * 100.0);
    frame.save_png(&common::output_dir("scenes").join(format!("{stem}.png"))).unwrap();
    assert!(covered > 0.05, "{spec}: only {:.1}% of pixels differ from the background", covered * 100.0);
    assert!(!frame.rgba.chunks_exact(4).any(|p| p == [0xCD; 4]), "{spec}: poisoned readback bytes survived");
    // Every pass belongs to a light, which has a lighting pass, or is one of the frame's own:
    // ambient, readback, the mesh upload of a frame that uploaded them, and the once-a-frame
    // passes of shadow volumes built on the GPU.
    let own = ["ambient", "readback", "mesh upload", "volume draws reset", "volume counts readback"];
    let frame_passes: Vec<&str> =
        frame.report.passes.iter().filter(|p| p.light.is_none()).map(|p| p.name.as_str()).collect();
    assert!(frame_passes.iter().all(|p| own.contains(p)), "{spec}: frame passes {frame_passes:?}");
    assert!(frame_passes.contains(&"ambient") && frame_passes.contains(&"readback"), "{spec}: {frame_passes:?}");
    let upload = frame.report.geometry_uploaded_bytes > 0;
    assert_eq!(frame_passes.contains(&"mesh upload"), upload, "{spec}: {frame_passes:?}");
    let per_light: usize = frame.report.lights.iter().map(|l| l.passes.len()).sum();
    assert_eq!(frame.report.passes.len(), frame_passes.len() + per_light, "{spec}: frame passes + each light's");
    for l in frame.report.lights.iter().filter(|l| l.recorded) {
        assert!(l.passes.iter().any(|p| p.starts_with("light ")), "{spec}: light {} has no lighting pass", l.light);
    }
}

#[test]
fn every_procedural_scene_renders_validation_clean() {
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        for name in umbra::scene::procedural::NAMES {
            render_and_check(&mut r, name, name);
        }
    });
}

#[test]
fn every_asset_renders_validation_clean() {
    let dir = common::assets();
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        for file in ["spot.glb", "fandisk.glb", "teapot.glb", "stanford-bunny.glb", "suzanne.glb"] {
            let path = dir.join(file);
            render_and_check(&mut r, path.to_str().unwrap(), file.trim_end_matches(".glb"));
        }
    });
}

#[test]
fn a_scene_file_renders() {
    let dir = std::env::temp_dir().join(format!("umbra-scene-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let assets = common::assets();
    let file = dir.join("bunny.toml");
    std::fs::write(
        &file,
        format!(
            r#"
name = "bunny on a box"
[camera]
position = [0.6, 0.5, 1.2]
target = [0.0, 0.1, 0.0]
[[mesh]]
name = "floor"
kind = "box"
half = [1.0, 0.02, 1.0]
[[mesh]]
name = "bunny"
kind = "file"
path = {:?}
[[object]]
mesh = "floor"
translation = [0.0, -0.02, 0.0]
[[object]]
mesh = "bunny"
scale = 2.0
translation = [0.0, -0.066, 0.0]
albedo = [0.9, 0.8, 0.7]
[[light]]
kind = "spot"
position = [0.5, 1.5, 0.5]
direction = [-0.5, -1.5, -0.5]
outer_deg = 35
intensity = 3.0
"#,
            assets.join("stanford-bunny.glb")
        ),
    )
    .unwrap();
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        render_and_check(&mut r, file.to_str().unwrap(), "scene-file");
    });
}

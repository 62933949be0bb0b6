//! After warm-up a frame allocates no device memory: the meshes stay on the GPU while their
//! revisions hold, the per-frame buffers and vertex streams are rewritten in place, the maps
//! and targets are kept. Every technique, on a scene of boxes and on the plaza (bounded lights,
//! blocker culling), counted by `FrameReport::memory_allocations`.

mod common;

use umbra::scene::Technique;
use umbra::shadows::{Renderer, RendererDesc};

#[test]
fn warm_frames_allocate_no_device_memory() {
    common::with_context(|ctx| {
        let mut failures = Vec::new();
        for scene_name in ["cubes", "plaza"] {
            for technique in Technique::ALL {
                let mut desc = RendererDesc::new(128, 96);
                desc.shadow_map.resolution = 512;
                let mut renderer = Renderer::new(ctx, desc).expect("renderer");
                let mut scene = umbra::scene::load(scene_name).expect("scene");
                if technique == Technique::SilhouetteMap {
                    scene.point_lights_to_spots(80.0);
                }
                for light in &mut scene.lights {
                    light.technique = technique;
                }
                let frames: Vec<u64> =
                    (0..3).map(|_| renderer.render(&scene).expect("frame").report.memory_allocations).collect();
                println!("{scene_name} {}: allocations per frame {frames:?}", technique.name());
                if frames[1..].iter().any(|&n| n != 0) {
                    failures.push(format!("{scene_name} {}: {frames:?}", technique.name()));
                }
            }
        }
        assert!(failures.is_empty(), "warm frames allocated device memory: {failures:?}");
    });
}

//! The per-light visibility image, the one product of every technique: each shadowed light's
//! technique writes it, its lighting reads it, and the accuracy measurements compare it with
//! the exact reference. Here, on both drivers, for every shadowing technique: every shadowed
//! light gets exactly one image; its shadow mask is the one the light's classification (a
//! separate diagnostic pass) gives; reading it back changes no pixel of the frame; it holds
//! fractions only where a filtered map means them; and a frame without shadows has none.

mod common;

use umbra::scene::Technique;
use umbra::shadows::{Frame, PassId, Renderer, RendererDesc, ShadowFilter};

fn render(ctx: &umbra::vk::Context, desc: RendererDesc, scene: &str, technique: Technique) -> Frame {
    let mut scene = umbra::scene::load(scene).expect("scene");
    for light in &mut scene.lights {
        light.technique = technique;
    }
    let mut renderer = Renderer::new(ctx, desc).expect("renderer");
    renderer.render(&scene).expect("frame")
}

fn views(desc: RendererDesc) -> RendererDesc {
    RendererDesc { diagnostics: true, read_visibility: true, ..desc }
}

#[test]
fn every_shadowed_light_writes_one_image_with_its_classification_mask() {
    common::with_context(|ctx| {
        let plain = RendererDesc::new(common::SIZE.0, common::SIZE.1);
        for scene in ["cubes", "plaza", "tree"] {
            for technique in Technique::SHADOWING {
                let frame = render(ctx, views(plain), scene, technique);
                let shadowed: Vec<usize> =
                    frame.report.lights.iter().filter(|l| l.recorded && l.shadowed).map(|l| l.light).collect();
                let imaged: Vec<usize> = frame.visibility.iter().map(|v| v.light).collect();
                println!("{scene} {}: shadowed lights {shadowed:?}, visibility images {imaged:?}", technique.name());
                assert!(!imaged.is_empty(), "{scene} {}: no visibility image", technique.name());
                assert!(imaged.iter().all(|l| shadowed.contains(l)), "{scene}: {imaged:?} vs {shadowed:?}");
                for v in &frame.visibility {
                    assert_eq!((v.width, v.height), (plain.width, plain.height));
                    assert_eq!(v.texels.len(), (plain.width * plain.height) as usize);
                    let decided = v.shadow_mask().iter().filter(|m| m.is_some()).count();
                    assert!(decided > 0, "light {} decides nothing", v.light);
                    // Shadow rays have no separate classification pass: tests/ray_traced.rs and
                    // the hard cases judge them against the exact reference instead.
                    let d = frame.diagnostics.iter().find(|d| d.light == v.light);
                    assert_eq!(
                        d.is_none(),
                        matches!(technique, Technique::RayTraced | Technique::HybridRt),
                        "{scene} {}",
                        technique.name()
                    );
                    if let Some(d) = d {
                        let differ = v.disagreements_with(&d.shadow_mask());
                        println!("  light {}: {decided} pixels decided, {differ} disagree with the classes", v.light);
                        assert_eq!(differ, 0, "{scene} {} light {}", technique.name(), v.light);
                    }
                    // Only a filtered map (2x2 PCF by default) leaves fractions; the others decide 0 or 1.
                    let binary = v.texels.iter().all(|t| t[0] == 0.0 || t[0] == 1.0);
                    let in_range = v.texels.iter().all(|t| (0.0..=1.0).contains(&t[0]) && (t[1] == 0.0 || t[1] == 1.0));
                    assert!(in_range, "{scene} {}", technique.name());
                    assert!(binary || technique == Technique::ShadowMap, "{scene} {}", technique.name());
                    let writers = frame.report.passes.iter().filter(|p| p.light == Some(v.light)).count();
                    assert!(writers >= 2, "light {}: {writers} passes", v.light);
                }
                // Reading the images back is a diagnostic: the frame is the same without it.
                let without = render(ctx, plain, scene, technique);
                assert!(without.visibility.is_empty());
                assert!(without.rgba == frame.rgba, "{scene} {}: the readback changed the image", technique.name());
            }
        }
    });
}

#[test]
fn filtered_maps_store_their_fractions_and_unshadowed_lights_none() {
    common::with_context(|ctx| {
        let mut desc = views(RendererDesc::new(common::SIZE.0, common::SIZE.1));
        desc.shadow_map.filter = ShadowFilter::Pcf3x3;
        let frame = render(ctx, desc, "cubes", Technique::ShadowMap);
        let v = frame.visibility.first().expect("a visibility image");
        let ninths: Vec<f32> = v.texels.iter().map(|t| t[0]).filter(|&x| x > 0.0 && x < 1.0).collect();
        println!("pcf3x3 on cubes: {} fractional pixels", ninths.len());
        assert!(!ninths.is_empty(), "a 3x3 kernel gives fractions on the shadow's edge");
        // k/9 exactly as the lookup summed them: (sum of k ones) / 9.
        assert!(ninths.iter().all(|&x| (1..9).any(|k| x == k as f32 / 9.0)), "{:?}", &ninths[..ninths.len().min(8)]);
        let pass = frame.report.pass(PassId::MapVisibility(v.light)).expect("visibility pass");
        assert!(pass.triangles > 0);

        let unshadowed = render(ctx, desc, "cubes", Technique::Unshadowed);
        assert!(unshadowed.visibility.is_empty(), "an unshadowed light has no visibility image");
    });
}

//! Ray-traced shadows (`Technique::RayTraced`, `umbra_shadows::ray_traced`): one shadow ray per
//! receiver pixel through the scene's two-level BVH, in a fragment shader over the frame's
//! surfaces; and the ray-traced hybrid (`Technique::HybridRt`): the hybrid's classification,
//! then rays only at the pixels it leaves uncertain, listed and dispatched indirectly. Here, on
//! both drivers with validation: both exact against the reference on the sweep scenes (the
//! judge's rule for an exact technique: nothing wrong beyond a true edge's seam), compared pixel
//! for pixel with shadow volumes, and a moving caster that rebuilds only the BVH's top level
//! while every frame stays exact and allocates nothing.

mod common;

use glam::{Mat4, Vec3};
use umbra::scene::{Scene, Technique};
use umbra::shadows::ray_traced::BvhLayout;
use umbra::shadows::{AutoAccuracy, AutoPolicy, Frame, Renderer, RendererDesc};
use umbra_conformance::judge::judge;
use umbra_conformance::Judgement;
use umbra_reference::SceneBvh;

fn desc() -> RendererDesc {
    RendererDesc { gbuffer: true, read_visibility: true, ..RendererDesc::new(common::SIZE.0, common::SIZE.1) }
}

fn with_technique(scene: &Scene, technique: Technique) -> Scene {
    let mut scene = scene.clone();
    scene.lights.iter_mut().for_each(|l| l.technique = technique);
    scene
}

/// `frame` of `scene` (every light `technique`) judged against the exact reference.
fn judged(ctx: &umbra::vk::Context, scene: &Scene, frame: &Frame, technique: Technique) -> Judgement {
    let bvh = SceneBvh::build(scene);
    let bits = ctx.capabilities().sub_pixel_precision_bits;
    let (j, _) = judge(scene, &bvh, frame, technique, bits).expect("judged");
    if j.unexplained() > 0 {
        println!("    unexplained at (light, x, y): {:?}", j.unexplained_at);
    }
    j
}

/// The two techniques that cast shadow rays.
const RAY_TECHNIQUES: [Technique; 2] = [Technique::RayTraced, Technique::HybridRt];

#[test]
fn exact_on_the_sweep_scenes_and_next_to_shadow_volumes() {
    common::with_context(|ctx| {
        for name in ["cubes", "cage", "tree", "pins", "plaza"] {
            let scene = umbra::scene::load(name).expect("scene");
            let volumes = with_technique(&scene, Technique::ShadowVolume);
            let sv = Renderer::new(ctx, desc()).and_then(|mut r| r.render(&volumes)).expect("shadow-volume frame");
            let jv = judged(ctx, &volumes, &sv, Technique::ShadowVolume);
            for technique in RAY_TECHNIQUES {
                exact_next_to_volumes(ctx, name, &scene, technique, &sv, &jv);
            }
        }
    });
}

/// `scene` rendered with `technique` is exact and never more wrong than shadow volumes' `sv`
/// (judged `jv`); prints how they differ.
fn exact_next_to_volumes(
    ctx: &umbra::vk::Context,
    name: &str,
    scene: &Scene,
    technique: Technique,
    sv: &Frame,
    jv: &Judgement,
) {
    let rays = with_technique(scene, technique);
    let frame = Renderer::new(ctx, desc()).and_then(|mut r| r.render(&rays)).expect("frame");
    let j = judged(ctx, &rays, &frame, technique);
    let mut differ = 0;
    for v in &frame.visibility {
        let other = sv.visibility.iter().find(|o| o.light == v.light).expect("the same lights shadowed");
        differ += v.shadow_mask().iter().zip(other.shadow_mask()).filter(|(a, b)| **a != *b).count();
    }
    let report = frame.report.lights.iter().find_map(|l| l.ray_traced).expect("a ray-traced report");
    let t = technique.name();
    println!(
        "{name} {t}: wrong {} of {} (seam {}, edge-on {}, unexplained {}); shadow volumes wrong {} (seam {}, snapped {}); {differ} pixels differ between them; BVH {} instances, {} triangles, {} KiB, depth {}",
        j.wrong,
        j.compared,
        j.seam,
        j.edge_on,
        j.unexplained(),
        jv.wrong,
        jv.seam,
        jv.snapping,
        report.instances,
        report.triangles,
        report.bvh_bytes / 1024,
        report.depth
    );
    assert!(j.compared > 1000, "{name} {t}: too few pixels judged");
    assert_eq!(j.unexplained(), 0, "{name} {t}");
    // The reference's own rays: never more wrong than shadow volumes.
    assert!(j.wrong <= jv.wrong, "{name} {t}: {} wrong against shadow volumes' {}", j.wrong, jv.wrong);
    let passes = &frame.report.passes;
    match technique {
        Technique::HybridRt => {
            let pixels = u64::from(frame.width) * u64::from(frame.height);
            for l in frame.report.lights.iter().filter(|l| l.shadowed) {
                let h = l.hybrid_rt.expect("a ray-traced hybrid report");
                let rays = h.rays.expect("rays counted in umbra's own frame");
                println!(
                    "    light {}: {rays} rays ({:.2}% of the image)",
                    l.light,
                    100.0 * rays as f64 / pixels as f64
                );
                // Rays only where the map is unsure: never one per pixel.
                assert!(rays > 0 && rays < pixels / 2, "{name} light {}: {rays} rays", l.light);
                assert_eq!(h.rays_dropped, Some(0), "{name} light {}", l.light);
            }
            assert!(passes.iter().any(|p| p.name.starts_with("hybrid rays")), "{name}: no ray dispatch");
        }
        _ => assert!(passes.iter().any(|p| p.name.ends_with("(rays)")), "{name}: no ray pass"),
    }
}

#[test]
fn a_moving_caster_rebuilds_only_the_top_level_and_stays_exact() {
    common::with_context(|ctx| {
        for technique in RAY_TECHNIQUES {
            moving_caster(ctx, technique);
        }
    });
}

/// Ten frames of `technique` with a caster moved before each.
fn moving_caster(ctx: &umbra::vk::Context, technique: Technique) {
    {
        let mut scene = with_technique(&umbra::scene::load("cubes").expect("cubes"), technique);
        let mut renderer = Renderer::new(ctx, desc()).expect("renderer");
        let caster = scene.objects.iter().position(|o| o.casts_shadows && o.name != "floor").expect("a caster");
        let mut builds = Vec::new();
        for frame_index in 0..10 {
            let o = &mut scene.objects[caster];
            o.transform = Mat4::from_translation(Vec3::new(0.04, 0.0, 0.02)) * o.transform;
            let frame = renderer.render(&scene).expect("frame");
            let r = frame.report.lights[0].ray_traced.expect("ray-traced report");
            let j = judged(ctx, &scene, &frame, technique);
            let (unexplained, compared) = (j.unexplained(), j.compared);
            println!(
                "{} frame {frame_index}: mesh builds {}, top builds {} ({:.3} ms), {unexplained} of {compared} unexplained, {} bytes uploaded, {} allocations",
                technique.name(),
                r.mesh_builds,
                r.top_builds,
                r.top_build_ms,
                frame.report.geometry_uploaded_bytes,
                frame.report.memory_allocations
            );
            assert_eq!(unexplained, 0, "frame {frame_index}");
            if frame_index > 0 {
                assert_eq!(frame.report.memory_allocations, 0, "frame {frame_index} allocated");
            }
            builds.push((r.mesh_builds, r.top_builds));
        }
        assert!(builds.iter().all(|&(m, _)| m == builds[0].0), "a mesh BVH was built again: {builds:?}");
        assert!(builds.windows(2).all(|w| w[1].1 == w[0].1 + 1), "one top level per move: {builds:?}");
    }
}

#[test]
fn diagnostics_count_the_rays_and_how_far_they_walk() {
    common::with_context(|ctx| {
        let scene = umbra::scene::load("cubes").expect("cubes");
        for technique in RAY_TECHNIQUES {
            traversal_counted(ctx, &with_technique(&scene, technique));
        }
    });
}

/// With diagnostics, each ray-casting light reports its rays and their walk through the BVH,
/// and the frame's visibility is the one it has without them.
fn traversal_counted(ctx: &umbra::vk::Context, scene: &Scene) {
    let plain = Renderer::new(ctx, desc()).and_then(|mut r| r.render(scene)).expect("frame");
    let counted = RendererDesc { diagnostics: true, ..desc() };
    let frame = Renderer::new(ctx, counted).and_then(|mut r| r.render(scene)).expect("frame with diagnostics");
    let technique = scene.lights[0].technique.name();
    for (a, b) in plain.visibility.iter().zip(&frame.visibility) {
        assert!(a.shadow_mask() == b.shadow_mask(), "{technique}: diagnostics changed light {}'s visibility", a.light);
    }
    let pixels = u64::from(frame.width) * u64::from(frame.height);
    for l in frame.report.lights.iter().filter(|l| l.shadowed) {
        let t = l.ray_traced.and_then(|r| r.traversal).expect("traversal counted with diagnostics");
        println!(
            "{technique} light {}: {} rays, nodes per ray {:.1} (p95 {}), triangles per ray {:.2} (p95 {})",
            l.light, t.rays, t.nodes_mean, t.nodes_p95, t.triangles_mean, t.triangles_p95
        );
        match l.hybrid_rt {
            // The counted twin casts the list the technique cast: its entries less those of a
            // pixel a later fragment appended again (a handful along silhouettes).
            Some(h) => {
                let listed = h.rays.expect("rays listed");
                assert!(t.rays <= listed && t.rays * 100 >= listed * 95, "light {}: {} of {listed}", l.light, t.rays);
            }
            // One ray per receiver fragment: a good part of the image is floor and cubes.
            None => assert!(t.rays > pixels / 4 && t.rays <= pixels, "light {}: {} rays", l.light, t.rays),
        }
        // Every ray tests at least the top level's root; p95 is a count some ray reached.
        assert!(t.nodes_mean >= 1.0 && t.nodes_p95 >= 1, "light {}: {t:?}", l.light);
        assert!(t.triangles_mean >= 0.0 && (t.nodes_p95 as f64) < 1e6, "light {}: {t:?}", l.light);
    }
    // Without diagnostics nothing is counted.
    assert!(plain.report.lights.iter().all(|l| l.ray_traced.is_none_or(|r| r.traversal.is_none())));
}

#[test]
fn auto_asked_for_exact_shadows_is_exact_and_picks_by_the_casters_triangles() {
    common::with_context(|ctx| {
        // Both CI drivers are CPU rasterizers: volumes or rays, no classification first.
        let mut policy = AutoPolicy::for_device(ctx.capabilities());
        assert!(!policy.classify_first, "{}", ctx.capabilities().device_type);
        policy.accuracy = AutoAccuracy::Exact;
        let desc = RendererDesc { auto: Some(policy), ..desc() };
        for (name, expected) in [("cubes", Technique::ShadowVolume), ("tree", Technique::RayTraced)] {
            let scene = with_technique(&umbra::scene::load(name).expect("scene"), Technique::Auto);
            let frame = Renderer::new(ctx, desc).and_then(|mut r| r.render(&scene)).expect("frame");
            for l in frame.report.lights.iter().filter(|l| l.recorded) {
                println!("{name} light {}: {:?}", l.light, l.auto_choice);
                assert_eq!(l.technique, expected, "{name} light {}: {:?}", l.light, l.auto_choice);
            }
            let j = judged(ctx, &scene, &frame, expected);
            println!("{name}: wrong {} of {} (seam {}), unexplained {}", j.wrong, j.compared, j.seam, j.unexplained());
            assert!(j.compared > 1000 && j.unexplained() == 0, "{name}");
        }
    });
}

#[test]
fn the_compressed_wide_bvh_gives_the_binary_bvhs_images() {
    common::with_context(|ctx| {
        for name in ["cubes", "cage", "tree", "pins", "plaza"] {
            let scene = umbra::scene::load(name).expect("scene");
            for technique in RAY_TECHNIQUES {
                let scene = with_technique(&scene, technique);
                let frames = [BvhLayout::Binary, BvhLayout::CompressedWide].map(|bvh| {
                    let desc = RendererDesc { bvh, diagnostics: true, ..desc() };
                    Renderer::new(ctx, desc).and_then(|mut r| r.render(&scene)).expect("frame")
                });
                let walks: Vec<_> = frames
                    .iter()
                    .map(|f| f.report.lights.iter().find_map(|l| l.ray_traced.and_then(|r| r.traversal)))
                    .collect();
                let t = technique.name();
                println!("{name} {t}: binary {:?}\n    cwbvh {:?}", walks[0], walks[1]);
                let [binary, wide] = &frames;
                assert!(wide.rgba == binary.rgba, "{name} {t}: the images differ");
                for (a, b) in binary.visibility.iter().zip(&wide.visibility) {
                    assert!(a.shadow_mask() == b.shadow_mask(), "{name} {t}: light {}'s visibility differs", a.light);
                }
                let (Some(a), Some(b)) = (walks[0], walks[1]) else { panic!("{name} {t}: no traversal counted") };
                assert_eq!(a.rays, b.rays, "{name} {t}");
                // Fewer, wider nodes: each one fetched is eight boxes.
                assert!(b.nodes_mean < a.nodes_mean, "{name} {t}: {b:?} against {a:?}");
            }
        }
    });
}

#[test]
fn the_compressed_wide_bvh_gives_the_binary_bvhs_images_on_every_hard_case() {
    common::with_context(|ctx| {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hard-cases");
        let mut cases: Vec<_> =
            std::fs::read_dir(&dir).expect("hard cases").map(|e| e.expect("entry").path()).collect();
        cases.sort();
        let mut compared = 0;
        for path in cases.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            let Ok(scene) = umbra::scene::load(path.to_str().expect("path")) else {
                println!("{name}: refused by the loader (its own test covers it)");
                continue;
            };
            let scene = with_technique(&scene, Technique::RayTraced);
            let [binary, wide] = [BvhLayout::Binary, BvhLayout::CompressedWide]
                .map(|bvh| Renderer::new(ctx, RendererDesc { bvh, ..desc() }).and_then(|mut r| r.render(&scene)));
            match (binary, wide) {
                (Ok(a), Ok(b)) => {
                    assert!(a.rgba == b.rgba, "{name}: the images differ");
                    compared += 1;
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name}"),
                (a, b) => panic!("{name}: binary {:?}, wide {:?}", a.err(), b.err()),
            }
        }
        println!("{compared} hard cases: the same image with either layout");
        assert!(compared >= 25, "{compared}");
    });
}

#[test]
fn the_rays_walk_umbras_bvh_in_its_shaders_and_the_report_says_whether_ray_queries_are_offered() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        println!("{} ({}): ray queries offered: {}", caps.device_name, caps.driver(), caps.ray_query);
        // Which CI driver offers VK_KHR_ray_query is tests/capabilities.rs's to check (Mesa 25's
        // lavapipe does); here the report must say what the device offers.
        let scene = with_technique(&umbra::scene::load("cubes").expect("cubes"), Technique::RayTraced);
        let frame = Renderer::new(ctx, desc()).and_then(|mut r| r.render(&scene)).expect("frame");
        let report = frame.report.lights[0].ray_traced.expect("a ray-traced report");
        assert!(report.ray_query_offered == caps.ray_query && report.layout == BvhLayout::Binary, "{report:?}");
        assert!(frame.report.passes.iter().any(|p| p.name.ends_with("(rays)")), "the shader walk's pass");
        let j = judged(ctx, &scene, &frame, Technique::RayTraced);
        assert_eq!(j.unexplained(), 0);
    });
}

//! The hybrid (Chan–Durand 2004) against full z-fail shadow volumes: equal images except where
//! the coarse shadow map misses features, a computation mask that keeps every stencil update to
//! silhouette pixels, the two real masks giving the same image, under-biased maps repaired by
//! the volumes (§5.1), and blocker culling that changes nothing. Every test prints the mask its
//! driver runs: `depth-bounds` on SwiftShader (and GPUs), `stencil` on lavapipe (no
//! `depthBounds`).

mod common;

use glam::{Mat4, Vec3};
use umbra::scene::{primitives, Camera, Light, Scene, Technique};
use umbra::shadows::{
    DepthBias, Frame, HybridSettings, MaskKind, PixelClass, RenderError, Renderer, RendererDesc, ShadowMapSettings,
    VolumeMode,
};
use umbra::vk::Context;

const W: u32 = 256;
const H: u32 = 192;

fn renderer(ctx: &Context, mask: Option<MaskKind>, configure: impl FnOnce(&mut RendererDesc)) -> Renderer {
    let mut desc = RendererDesc::new(W, H);
    desc.hybrid.mask = mask;
    desc.shadow_volume.mode = VolumeMode::ZFail;
    configure(&mut desc);
    Renderer::new(ctx, desc).expect("renderer")
}

fn with_technique(scene: &Scene, t: Technique) -> Scene {
    let mut s = scene.clone();
    for l in &mut s.lights {
        l.technique = t;
    }
    s
}

/// Whether the device has `depthBounds`; without it, says what is skipped (`what`).
fn has_depth_bounds(ctx: &Context, what: &str) -> bool {
    let has = ctx.capabilities().depth_bounds;
    if !has {
        println!("SKIPPED on {}: {what}", ctx.capabilities().device_name);
    }
    has
}

fn is_swiftshader(ctx: &Context) -> bool {
    ctx.capabilities().device_name.to_lowercase().contains("swiftshader")
}

/// Pixels whose colour differs by more than 2/255 in some channel, as a mask.
fn differing(a: &Frame, b: &Frame) -> Vec<bool> {
    a.rgba.chunks_exact(4).zip(b.rgba.chunks_exact(4)).map(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 2)).collect()
}

/// The frame with differing pixels in magenta, for people to look at.
fn save_diff(name: &str, frame: &Frame, diff: &[bool]) {
    let rgba: Vec<u8> = frame
        .rgba
        .chunks_exact(4)
        .zip(diff)
        .flat_map(|(p, &d)| if d { [255, 0, 255, 255] } else { [p[0], p[1], p[2], 255] })
        .collect();
    let path = common::output_dir("hybrid").join(format!("{name}-diff.png"));
    image::save_buffer(&path, &rgba, W, H, image::ColorType::Rgba8).expect("write diff");
}

fn load(name: &str) -> Scene {
    if name.ends_with(".glb") {
        umbra::scene::load(common::assets().join(name).to_str().expect("utf-8 path")).expect("asset")
    } else {
        umbra::scene::load(name).expect("procedural scene")
    }
}

/// Differing pixels allowed against full z-fail volumes, as a fraction of the image: the
/// conservative classification leaves the map nothing it could get wrong (0 pixels measured on
/// every scene here, both drivers, at 256×192); 0.01% of the image, the sweep's acceptance
/// margin. Measured figures are in docs/techniques/hybrid.md.
const EQUIVALENCE_BOUND: f64 = 1e-4;

#[test]
fn matches_full_zfail_shadow_volumes_even_for_features_below_a_texel() {
    common::with_context(|ctx| {
        let mut failures = Vec::new();
        for name in ["cubes", "cage", "tree", "spot.glb"] {
            let scene = load(name);
            let mut r = renderer(ctx, None, |_| {});
            let hybrid = r.render(&with_technique(&scene, Technique::Hybrid)).expect("hybrid frame");
            let volumes = r.render(&with_technique(&scene, Technique::ShadowVolume)).expect("volume frame");
            let diff = differing(&hybrid, &volumes);
            let n = diff.iter().filter(|&&d| d).count();
            let fraction = n as f64 / (W * H) as f64;
            let report = hybrid.report.lights[0].hybrid.as_ref().expect("hybrid report");
            let bound = EQUIVALENCE_BOUND;
            println!(
                "{name}: mask {}, P = {:.2}%, {n} pixels differ from full z-fail ({:.3}%, bound {:.2}%)",
                report.mask.name(),
                100.0 * report.silhouette_fraction,
                100.0 * fraction,
                100.0 * bound
            );
            save_diff(name, &hybrid, &diff);
            if fraction > bound {
                failures.push(format!("{name}: {n} pixels differ"));
            }
        }
        assert!(failures.is_empty(), "{failures:?}");
    });
}

#[test]
fn the_mask_keeps_stencil_updates_to_silhouette_pixels() {
    common::with_context(|ctx| {
        let scene = with_technique(&load("cubes"), Technique::Hybrid);
        let mut r = renderer(ctx, None, |d| {
            d.diagnostics = true;
            d.shadow_volume.overdraw = true;
        });
        let frame = r.render(&scene).expect("frame");
        let report = frame.report.lights[0].hybrid.as_ref().expect("hybrid report");
        let d = &frame.diagnostics[0];
        let stencil = d.stencil.as_ref().expect("stencil read back");
        let count_bits = if report.mask == MaskKind::Stencil { 0x7f } else { 0xff };
        let classes: Vec<PixelClass> =
            d.classification.chunks_exact(4).map(|p| PixelClass::decode([p[0], p[1], p[2], p[3]])).collect();
        let silhouette = classes.iter().filter(|c| c.is_silhouette()).count();
        let stray: Vec<usize> =
            (0..stencil.len()).filter(|&i| stencil[i] & count_bits != 0 && !classes[i].is_silhouette()).collect();
        let (o, masked) = (report.volume_fragments.expect("O"), report.masked_volume_fragments.expect("masked"));
        println!(
            "mask {}: {silhouette} silhouette pixels (query: {}), {} non-zero counts outside them, volume fragments {masked} masked / {o} unmasked ({:.1}%)",
            report.mask.name(),
            report.silhouette_pixels,
            stray.len(),
            100.0 * masked as f64 / o as f64
        );
        assert_eq!(silhouette as u64, report.silhouette_pixels, "the mask pass's query counts the silhouette pixels");
        // SwiftShader's depth-bounds test lets a volume fragment through at a handful of masked
        // pixels (the stencil mask on the same driver lets none); those pixels read their
        // colour from the map, so the image does not change (`both_real_masks_give_one_image`).
        let allowed = if is_swiftshader(ctx) && report.mask == MaskKind::DepthBounds {
            println!("KNOWN SWIFTSHADER ISSUE: depth-bounds test passes {} masked pixels", stray.len());
            (W * H) as usize / 10_000
        } else {
            0
        };
        assert!(
            stray.len() <= allowed,
            "non-zero stencil outside the silhouette set at {:?}",
            &stray[..stray.len().min(8)]
        );
        // The conservative classification marks more pixels than the 2×2 PCF test did (P 19.8%
        // on cubes at 256×192 with the default 256² map, 13.8% before with 128²): 31.3% of the
        // fragments pass the mask there (54% at 128²).
        assert!(masked * 3 < o * 2, "masked volume fragments {masked} are not < 2/3 of {o}");
    });
}

#[test]
fn both_real_masks_give_one_image() {
    common::with_context(|ctx| {
        if !has_depth_bounds(ctx, "no depthBounds, so only the stencil mask runs here; SwiftShader compares both masks")
        {
            return;
        }
        for name in ["cubes", "cage"] {
            let scene = with_technique(&load(name), Technique::Hybrid);
            let frames: Vec<Frame> =
                MaskKind::ALL.iter().map(|&m| renderer(ctx, Some(m), |_| {}).render(&scene).expect("frame")).collect();
            for (m, f) in MaskKind::ALL.iter().zip(&frames).skip(1) {
                let n = differing(&frames[0], f).iter().filter(|&&d| d).count();
                println!("{name}: depth-bounds vs {}: {n} pixels differ", m.name());
                assert_eq!(n, 0, "{name}: depth-bounds and {} masks differ", m.name());
                assert_eq!(frames[0].rgba, f.rgba, "{name}: images are not bit-identical");
            }
        }
    });
}

#[test]
fn depth_bounds_without_the_feature_is_a_typed_error() {
    common::with_context(|ctx| {
        let mut desc = RendererDesc::new(W, H);
        desc.hybrid.mask = Some(MaskKind::DepthBounds);
        match (ctx.capabilities().depth_bounds, Renderer::new(ctx, desc)) {
            (false, Err(RenderError::Vk(e))) => println!("{}: {e}", ctx.capabilities().device_name),
            (false, Ok(_)) => panic!("depth-bounds mask accepted without depthBounds"),
            (true, r) => {
                r.expect("depth-bounds mask where depthBounds exists");
                println!("{} has depthBounds: the mask is accepted", ctx.capabilities().device_name);
            }
            (false, Err(e)) => panic!("wrong error: {e}"),
        }
    });
}

/// A floor tilted 25° under a directional light at 45°, a box casting on it, no ambient.
fn tilted_floor() -> Scene {
    let mut s = Scene::new("tilted floor");
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(6.0, 0.05, 6.0)));
    s.add_object(floor, Mat4::from_rotation_x(25f32.to_radians()), Vec3::splat(0.8));
    let cube = s.add_mesh(primitives::cuboid(Vec3::splat(0.5)));
    s.add_object(cube, Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0)), Vec3::splat(0.6));
    s.lights.push(Light::directional(Vec3::new(0.4, 1.0, 0.6), 1.0));
    s.camera = Camera::look_at(Vec3::new(0.0, 5.0, 7.0), Vec3::ZERO);
    s
}

#[test]
fn under_biased_maps_are_repaired_by_the_volumes() {
    common::with_context(|ctx| {
        let scene = tilted_floor();
        let no_bias = |d: &mut RendererDesc| {
            d.shadow_map = ShadowMapSettings {
                resolution: Some(128),
                bias: DepthBias { constant: 0.0, slope: 0.0, clamp_texels: None },
                normal_offset: 0.0,
                ..ShadowMapSettings::DEFAULT
            };
            d.hybrid.resolution = Some(128);
        };
        let mut r = renderer(ctx, None, no_bias);
        let exact = r.render(&with_technique(&scene, Technique::ShadowVolume)).expect("volumes");
        let map = r.render(&with_technique(&scene, Technique::ShadowMap)).expect("shadow map");
        let hybrid = r.render(&with_technique(&scene, Technique::Hybrid)).expect("hybrid");
        let acne = |f: &Frame| differing(f, &exact);
        let (map_wrong, hybrid_wrong) = (acne(&map), acne(&hybrid));
        let count = |d: &[bool]| d.iter().filter(|&&x| x).count();
        let report = hybrid.report.lights[0].hybrid.as_ref().expect("hybrid report");
        println!(
            "zero bias, mask {}: shadow map {} pixels wrong, hybrid {} (P = {:.1}%)",
            report.mask.name(),
            count(&map_wrong),
            count(&hybrid_wrong),
            100.0 * report.silhouette_fraction
        );
        save_diff("acne-shadow-map", &map, &map_wrong);
        save_diff("acne-hybrid", &hybrid, &hybrid_wrong);
        assert!(count(&map_wrong) > 1000, "the zero-bias shadow map should show acne");
        assert!(count(&hybrid_wrong) * 100 < count(&map_wrong), "the hybrid keeps acne");
    });
}

/// A wide plate above a small box, both over a floor: from the light the plate hides the box.
fn hidden_blocker() -> Scene {
    let mut s = Scene::new("hidden blocker");
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(6.0, 0.05, 6.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let plate = s.add_mesh(primitives::cuboid(Vec3::new(1.5, 0.05, 1.5)));
    s.add_object(plate, Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)), Vec3::splat(0.6));
    let small = s.add_mesh(primitives::cuboid(Vec3::splat(0.3)));
    s.add_object(small, Mat4::from_translation(Vec3::new(0.2, 1.0, 0.1)), Vec3::splat(0.5));
    s.lights.push(Light::directional(Vec3::new(0.1, 1.0, 0.05), 1.0));
    s.camera = Camera::look_at(Vec3::new(4.0, 4.0, 5.0), Vec3::ZERO);
    s
}

#[test]
fn blocker_culling_drops_hidden_casters_without_changing_the_image() {
    common::with_context(|ctx| {
        for (name, scene) in [("hidden blocker", hidden_blocker()), ("cubes", load("cubes"))] {
            let scene = with_technique(&scene, Technique::Hybrid);
            let plain = renderer(ctx, None, |_| {}).render(&scene).expect("frame");
            let culled = renderer(ctx, None, |d| d.hybrid = HybridSettings { cull_blockers: true, ..d.hybrid })
                .render(&scene)
                .expect("culled frame");
            let report = culled.report.lights[0].hybrid.as_ref().expect("hybrid report");
            match report.culled_casters {
                Some(n) => {
                    println!("{name}: mask {}, {n} of {} casters culled", report.mask.name(), n + report.volume_casters)
                }
                None => println!("{name}: its point light uses a cube map, whose casters are not queried"),
            }
            assert_eq!(plain.rgba, culled.rgba, "{name}: culling changed the image");
            if name == "hidden blocker" {
                assert_eq!(report.culled_casters, Some(1), "the box under the plate is culled, nothing else");
            }
        }
    });
}

/// `n` thin slabs stacked under a directional light from straight above, over a floor: every
/// shadowed floor pixel lies in all `n` volumes.
fn stacked_slabs(n: usize) -> Scene {
    let mut s = Scene::new(format!("{n} slabs"));
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(6.0, 0.05, 6.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let slab = s.add_mesh(primitives::cuboid(Vec3::new(1.0, 0.001, 1.0)));
    for i in 0..n {
        let y = 1.0 + i as f32 * 1.5 / n as f32;
        s.add_object(slab, Mat4::from_translation(Vec3::new(0.0, y, 0.0)), Vec3::splat(0.5));
    }
    s.lights.push(Light { technique: Technique::Hybrid, ..Light::directional(Vec3::Y, 1.0) });
    s.camera = Camera::look_at(Vec3::new(-2.5, 0.6, 3.5), Vec3::new(0.3, 0.0, 0.0));
    s
}

#[test]
fn counts_never_alias_under_any_mask() {
    // 128 and 256 volumes on one pixel: multiples of the stencil mask's 7-bit count and of
    // the full 8 bits. Under every mask the device has, the hybrid's visibility must equal the
    // shadow volumes' (which count in batches too), and the report must say it batched.
    common::with_context(|ctx| {
        has_depth_bounds(ctx, "the depth-bounds mask (no depthBounds feature); SwiftShader covers it");
        for n in [128, 256] {
            let scene = stacked_slabs(n);
            let mut desc = RendererDesc::new(W, H);
            desc.read_visibility = true;
            let exact = Renderer::new(ctx, desc)
                .expect("renderer")
                .render(&with_technique(&scene, Technique::ShadowVolume))
                .expect("frame");
            let truth = exact.shadow_mask(0).expect("a shadow-volume mask");
            assert!(
                truth.iter().filter(|s| **s == Some(true)).count() > 1_000,
                "{n}: the slabs' shadow is on the floor"
            );
            for mask in
                MaskKind::ALL.into_iter().filter(|m| *m != MaskKind::DepthBounds || ctx.capabilities().depth_bounds)
            {
                let frame = renderer(ctx, Some(mask), |d| d.read_visibility = true).render(&scene).expect("frame");
                let batches = frame.report.lights[0].shadow_volume.as_ref().map_or(0, |v| v.count_batches);
                let wrong =
                    frame.shadow_mask(0).expect("a hybrid mask").iter().zip(&truth).filter(|(a, b)| a != b).count();
                println!(
                    "{n} slabs, {} mask: {batches} count batches, {wrong} pixels differ from shadow volumes",
                    mask.name()
                );
                assert_eq!(wrong, 0, "{n} slabs, {} mask", mask.name());
                let all_bits = if mask == MaskKind::Stencil { 127 } else { 255 };
                assert_eq!(batches > 1, n + 1 > all_bits, "{n} slabs, {} mask: batching", mask.name());
            }
        }
    });
}

/// The bounds need no conservative rasterization (`VK_EXT_conservative_rasterization`): every
/// triangle is tested against every texel's square in the fragment stage. The capability is
/// probed all the same, and neither CPU driver offers it: the hybrid's exactness above was
/// measured without it.
#[test]
fn the_bounds_need_no_conservative_rasterization() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        println!("{}: VK_EXT_conservative_rasterization {}", caps.device_name, caps.conservative_rasterization);
        if is_swiftshader(ctx) || caps.device_name.contains("llvmpipe") {
            assert!(
                !caps.conservative_rasterization,
                "{}: the CPU drivers have no conservative rasterization",
                caps.device_name
            );
        }
        let scene = with_technique(&load("cubes"), Technique::Hybrid);
        let frame = renderer(ctx, None, |_| {}).render(&scene).expect("hybrid frame");
        let passes: Vec<&str> = frame.report.passes.iter().map(|p| p.name.as_str()).collect();
        assert!(passes.contains(&"hybrid bounds 0"), "{passes:?}");
    });
}

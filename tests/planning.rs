//! The frame planner (issue #9): shadow work only where it can change the image, the same image
//! as without planning, and `casts_shadows` / `receives_shadows` honoured by every technique.
//!
//! `UMBRA_DEVICE=… cargo test --test planning -- --nocapture` prints each plan.

mod common;

use common::raycast::Box3;
use glam::{Mat4, Vec3};
use umbra::scene::{primitives::cuboid, Light, Scene, Technique};
use umbra::shadows::{CullReason, Frame, FrameReport, Renderer, RendererDesc};
use umbra::vk::Context;

/// Passes that do shadow work (anything but the lighting, ambient, readback and diagnostics).
fn shadow_passes(report: &FrameReport) -> Vec<&str> {
    report
        .passes
        .iter()
        .filter(|p| !p.diagnostic)
        .map(|p| p.name.as_str())
        .filter(|n| !n.starts_with("light ") && !["ambient", "readback", "mesh upload"].contains(n))
        .collect()
}

fn renderer(ctx: &Context, cull: bool, overdraw: bool) -> Renderer {
    let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
    desc.cull = cull;
    desc.shadow_volume.overdraw = overdraw;
    desc.hybrid.cull_blockers = cull;
    Renderer::new(ctx, desc).unwrap()
}

fn print_plan(label: &str, report: &FrameReport) {
    println!(
        "{label}: {} recorded, {} skipped, culled {:?}",
        report.plan.lights_recorded, report.plan.lights_skipped, report.plan.culled
    );
    for l in &report.lights {
        let why = l.skipped_because.as_deref().or(l.unshadowed_because.as_deref()).unwrap_or("");
        println!("  light {} {:<14} passes {:?} {why}", l.light, l.technique.name(), l.passes);
    }
}

#[test]
fn a_scene_without_casters_records_no_shadow_pass() {
    common::with_context(|ctx| {
        let (mut planned, mut unplanned) = (renderer(ctx, true, true), renderer(ctx, false, true));
        for technique in [Technique::ShadowMap, Technique::ShadowVolume, Technique::SilhouetteMap, Technique::Hybrid] {
            let mut scene = umbra::scene::load("ball").unwrap();
            scene.lights[0].technique = technique;
            for o in &mut scene.objects {
                o.casts_shadows = false;
            }
            let frame = planned.render(&scene).unwrap();
            let r = &frame.report;
            print_plan(technique.name(), r);
            assert_eq!(shadow_passes(r), Vec::<&str>::new(), "{}", technique.name());
            let l = &r.lights[0];
            assert!(l.recorded && !l.shadowed, "{}", technique.name());
            assert_eq!(l.unshadowed_because.as_deref(), Some("no caster can shadow a visible receiver"));
            assert!(l.shadow_volume.is_none() && frame.overdraw.is_none(), "no volume fragment was spent");
            assert_eq!(l.culled.iter().find(|c| c.reason == CullReason::NotACaster).map(|c| c.count), Some(2));
            // Without planning, volumes are counted over nothing (map techniques find no caster
            // to fit a map to either way), to the same image.
            let reference = unplanned.render(&scene).unwrap();
            print_plan("  --no-cull", &reference.report);
            if technique == Technique::ShadowVolume {
                let v = reference.report.lights[0].shadow_volume.as_ref().unwrap();
                assert_eq!((v.casters, v.volume_fragments), (0, Some(0)));
            }
            assert!(frame.rgba == reference.rgba, "{}: planning changed the image", technique.name());
        }
    });
}

#[test]
fn eight_lights_two_in_view_do_shadow_work_for_two() {
    common::with_context(|ctx| {
        let scene = umbra::scene::load("plaza").unwrap();
        assert_eq!(scene.lights.len(), 8);
        let planned = renderer(ctx, true, true).render(&scene).unwrap();
        let unplanned = renderer(ctx, false, true).render(&scene).unwrap();
        print_plan("planned", &planned.report);
        print_plan("--no-cull", &unplanned.report);
        let r = &planned.report;
        assert_eq!((r.plan.lights_recorded, r.plan.lights_skipped, r.plan.lights_shadowed), (2, 6, 2));
        let working: Vec<usize> = r.passes.iter().filter_map(|p| p.light).collect();
        assert!(working.iter().all(|&l| l == 1 || l == 2), "passes for other lights: {working:?}");
        for l in [1, 2] {
            let names = &r.lights[l].passes;
            assert!(names.len() >= 2, "light {l}: {names:?}");
        }
        for l in r.lights.iter().filter(|l| !l.recorded) {
            assert!(l.passes.is_empty());
            assert_eq!(l.skipped_because.as_deref(), Some("its range misses the view frustum"));
        }
        // The query results: volume fragments only for the lights in view.
        let fragments = |f: &Frame| -> Vec<(usize, u64)> {
            f.report
                .lights
                .iter()
                .filter_map(|l| l.shadow_volume.as_ref().and_then(|v| v.volume_fragments).map(|n| (l.light, n)))
                .collect()
        };
        let (with, without) = (fragments(&planned), fragments(&unplanned));
        println!("volume fragments: planned {with:?}, --no-cull {without:?}");
        assert!(with.iter().all(|&(l, n)| (l == 1 || l == 2) && n > 0), "{with:?}");
        assert!(!with.is_empty());
        let sum = |v: &[(usize, u64)]| v.iter().map(|&(_, n)| n).sum::<u64>();
        assert!(sum(&with) < sum(&without), "culling saved no volume fragments");
        assert!(unplanned.report.passes.iter().filter_map(|p| p.light).any(|l| l != 1 && l != 2));
        assert!(planned.rgba == unplanned.rgba, "planning changed the image");
        planned.save_png(&common::output_dir("planning").join("plaza.png")).unwrap();
    });
}

/// Every procedural scene with every technique (and bounded lights, and `auto`): the planned
/// image is the unplanned one, byte for byte.
#[test]
fn planned_images_are_bit_identical_to_no_cull() {
    common::with_context(|ctx| {
        let (mut planned, mut unplanned) = (renderer(ctx, true, false), renderer(ctx, false, false));
        let techniques = [
            Technique::ShadowMap,
            Technique::ShadowVolume,
            Technique::SilhouetteMap,
            Technique::Hybrid,
            Technique::Auto,
        ];
        let mut compared = 0;
        for name in umbra::scene::procedural::NAMES {
            let base = umbra::scene::load(name).unwrap();
            let centre = base.bounds().center();
            for bounded in [false, true] {
                for technique in techniques {
                    let mut scene = base.clone();
                    for l in &mut scene.lights {
                        l.technique = technique;
                        if bounded && l.range.is_none() {
                            l.range = Some(l.position.truncate().distance(centre));
                        }
                    }
                    let a = planned.render(&scene).unwrap();
                    let b = unplanned.render(&scene).unwrap();
                    let differing = a.rgba.chunks_exact(4).zip(b.rgba.chunks_exact(4)).filter(|(x, y)| x != y).count();
                    let label =
                        format!("{name} {} {}", technique.name(), if bounded { "bounded" } else { "unbounded" });
                    let shadow_passes = |f: &Frame| shadow_passes(&f.report).len();
                    println!(
                        "{label:<34} culled {:?}, shadow passes {} vs {}",
                        a.report.plan.culled,
                        shadow_passes(&a),
                        shadow_passes(&b)
                    );
                    assert_eq!(differing, 0, "{label}: planning changed {differing} pixels");
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, umbra::scene::procedural::NAMES.len() * 10);
    });
}

/// A floor, caster A at x = −1.2 and caster B at x = +1.2, lit from −x so A's shadow also
/// falls on B.
fn two_boxes() -> (Scene, Box3, Box3, Vec3) {
    let mut s = Scene::new("two boxes");
    let floor = s.add_mesh(cuboid(Vec3::new(6.0, 0.05, 6.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8)).name = "floor".into();
    let cube = s.add_mesh(cuboid(Vec3::splat(0.5)));
    let (a, b) = (Vec3::new(-1.2, 0.5, 0.0), Vec3::new(1.2, 0.8, 0.2));
    s.add_object(cube, Mat4::from_translation(a), Vec3::new(0.8, 0.4, 0.3)).name = "A".into();
    s.add_object(
        cube,
        Mat4::from_scale_rotation_translation(Vec3::new(1.0, 1.6, 1.0), glam::Quat::IDENTITY, b),
        Vec3::new(0.3, 0.5, 0.8),
    )
    .name = "B".into();
    let light = Vec3::new(-4.5, 2.0, 0.4);
    s.lights.push(Light::point(light, light.length_squared()));
    s.camera = umbra::scene::Camera::look_at(Vec3::new(-2.5, 4.0, 6.5), Vec3::new(0.3, 0.3, 0.0));
    let box_a = Box3::around(a, Vec3::splat(0.5));
    let box_b = Box3::around(b, Vec3::new(0.5, 0.8, 0.5));
    (s, box_a, box_b, light)
}

/// Per pixel of a G-buffer: object index and whether each box blocks its light, decided the
/// same way for the pixel and every neighbour within `radius` (else `None`: an edge).
struct Truth {
    object: Vec<Option<usize>>,
    blocked: Vec<Option<(bool, bool)>>,
}

fn truth(frame: &Frame, a: &Box3, b: &Box3, light: Vec3, radius: i32) -> Truth {
    let g = frame.gbuffer.as_ref().expect("g-buffer");
    let (w, h) = (frame.width as i32, frame.height as i32);
    let object: Vec<Option<usize>> = g.position.iter().map(|p| (p[3] > 0.0).then(|| p[3] as usize - 1)).collect();
    let state = |i: usize| {
        let p = Vec3::from_slice(&g.position[i][..3]);
        let n = Vec3::from_slice(&g.normal[i][..3]);
        // Surfaces turned away from the light are dark either way.
        (n.dot(light - p) > 1e-3).then(|| (a.blocks(p, light), b.blocks(p, light)))
    };
    let blocked = (0..(w * h) as usize)
        .map(|i| {
            let here = state(i).filter(|_| object[i].is_some())?;
            let (x, y) = (i as i32 % w, i as i32 / w);
            for dy in -radius..=radius {
                for dx in -radius..=radius {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w || ny >= h {
                        return None;
                    }
                    let j = (ny * w + nx) as usize;
                    if object[j] != object[i] || state(j) != Some(here) {
                        return None;
                    }
                }
            }
            Some(here)
        })
        .collect();
    Truth { object, blocked }
}

fn changed(x: &Frame, y: &Frame) -> Vec<bool> {
    x.rgba.chunks_exact(4).zip(y.rgba.chunks_exact(4)).map(|(p, q)| p != q).collect()
}

/// (technique, pixels around an edge left undecided: exact volumes 1, filtered maps 3, and
/// whether it is exact: a shadow map also darkens some lit pixels, acne at grazing light)
const FLAG_TECHNIQUES: [(Technique, i32, bool); 3] =
    [(Technique::ShadowVolume, 1, true), (Technique::ShadowMap, 3, false), (Technique::Hybrid, 1, true)];

fn flag_renderer(ctx: &Context) -> Renderer {
    let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
    desc.gbuffer = true;
    desc.shadow_map.resolution = Some(2048);
    Renderer::new(ctx, desc).unwrap()
}

#[test]
fn casts_shadows_false_removes_exactly_that_objects_shadow() {
    common::with_context(|ctx| {
        let mut r = flag_renderer(ctx);
        for (technique, radius, _) in FLAG_TECHNIQUES {
            let (mut scene, a, b, light) = two_boxes();
            scene.lights[0].technique = technique;
            let all = r.render(&scene).unwrap();
            scene.objects[1].casts_shadows = false;
            let without_a = r.render(&scene).unwrap();
            let t = truth(&all, &a, &b, light, radius);
            let d = changed(&all, &without_a);
            let (mut removed, mut kept_b) = (0, 0);
            for (i, (&changed, &blocked)) in d.iter().zip(&t.blocked).enumerate() {
                match blocked {
                    // A's shadow, and only A's: gone.
                    Some((true, false)) => {
                        assert!(changed, "{}: pixel {i} still in A's shadow", technique.name());
                        removed += 1;
                    }
                    // B's shadow, and light where no box blocks: unchanged.
                    Some((_, true)) | Some((false, false)) => {
                        assert!(!changed, "{}: pixel {i} changed outside A's shadow", technique.name());
                        kept_b += usize::from(blocked == Some((false, true)));
                    }
                    None => {}
                }
            }
            // No changed pixel may be far from A's shadow.
            let stray = (0..d.len()).filter(|&i| d[i] && t.blocked[i].is_some_and(|s| !s.0)).count();
            println!(
                "{}: {removed} pixels of A's shadow removed, {kept_b} of B's kept, {stray} stray",
                technique.name()
            );
            assert_eq!(stray, 0);
            assert!(removed > 200 && kept_b > 200, "the scene must show both shadows");
        }
    });
}

#[test]
fn receives_shadows_false_removes_shadows_on_exactly_that_object() {
    common::with_context(|ctx| {
        let mut r = flag_renderer(ctx);
        for (technique, radius, exact) in FLAG_TECHNIQUES {
            let (mut scene, a, b, light) = two_boxes();
            scene.lights[0].technique = technique;
            let all = r.render(&scene).unwrap();
            scene.objects[0].receives_shadows = false; // the floor
            let bare_floor = r.render(&scene).unwrap();
            let t = truth(&all, &a, &b, light, radius);
            let d = changed(&all, &bare_floor);
            let (mut floor_lit, mut b_kept) = (0, 0);
            for (i, &changed) in d.iter().enumerate() {
                if changed {
                    assert_eq!(t.object[i], Some(0), "{}: pixel {i} changed off the floor", technique.name());
                }
                let Some(blocked) = t.blocked[i] else { continue };
                let shadowed = blocked.0 || blocked.1;
                match t.object[i] {
                    Some(0) => {
                        if shadowed || exact {
                            assert_eq!(
                                changed,
                                shadowed,
                                "{}: floor pixel {i} (shadowed: {shadowed})",
                                technique.name()
                            );
                        }
                        floor_lit += usize::from(shadowed);
                    }
                    Some(2) if blocked.0 => b_kept += 1, // B in A's shadow: still shadowed (unchanged)
                    _ => {}
                }
            }
            println!(
                "{}: {floor_lit} floor pixels unshadowed, {b_kept} pixels of B still in A's shadow",
                technique.name()
            );
            assert!(floor_lit > 500 && b_kept > 10, "the scene must shadow the floor and B");
        }
    });
}

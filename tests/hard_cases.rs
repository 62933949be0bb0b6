//! The hard-case conformance suite (`tests/hard-cases/*.toml`, judged by
//! `umbra-conformance`): one test per case, every technique, on the device `UMBRA_DEVICE`
//! names, with the validation layer on. `ci/test.sh` runs it on lavapipe and SwiftShader;
//! `bash ci/hard-cases.sh` writes the table of both to `docs/hard-cases.md`.

mod common;

use std::path::PathBuf;
use umbra::scene::{Light, Scene};
use umbra::shadows::{RenderError, Renderer, RendererDesc};
use umbra_conformance::{run_case, CaseRun, Verdict};

fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/hard-cases")
}

/// Runs case `file` on the suite's device, prints every verdict, saves its picture, and fails
/// on any non-conformant verdict.
fn conformant(file: &str) -> CaseRun {
    let case = umbra_conformance::case(file).unwrap_or_else(|| panic!("no case {file}"));
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        let run = run_case(ctx, &cases_dir(), case, common::SIZE).expect("case runs");
        println!("{} on {}: {}", run.case, run.device, run.why);
        if let Some(e) = &run.typed_error {
            println!("  typed error: {e}");
        }
        for t in &run.techniques {
            let j = t.judgement.as_ref();
            println!(
                "  {:<15} {:?}  compared {} shadowed {} wrong {} (seam {}, texel band {}, unexplained {}) {}",
                t.technique.name(),
                t.verdict,
                j.map_or(0, |j| j.compared),
                j.map_or(0, |j| j.shadowed),
                j.map_or(0, |j| j.wrong),
                j.map_or(0, |j| j.seam),
                j.map_or(0, |j| j.texel_band),
                j.map_or(0, |j| j.unexplained()),
                t.notes.join("; ")
            );
            if let Some(j) = j.filter(|j| !j.unexplained_at.is_empty()) {
                println!("    unexplained (light, x, y): {:?}", j.unexplained_at);
            }
        }
        if !caps.depth_bounds && run.techniques.iter().any(|t| t.technique == umbra::scene::Technique::Hybrid) {
            println!(
                "  SKIPPED on {}: the hybrid's depth-bounds mask (no depthBounds feature; the stencil mask ran instead). SwiftShader covers it.",
                caps.device_name
            );
        }
        if !run.techniques.is_empty() {
            let picture = common::output_dir("hard_cases").join(format!("{}.png", run.case));
            umbra_conformance::report::save_picture(&run, &picture).expect("picture");
        }
        let failures: Vec<String> = std::iter::once((&run.verdict, "case"))
            .chain(run.techniques.iter().map(|t| (&t.verdict, t.technique.name())))
            .filter(|(v, _)| matches!(v, Verdict::Fail(_)))
            .map(|(v, what)| format!("{what}: {v:?}"))
            .collect();
        assert!(failures.is_empty(), "{file}: {failures:#?}");
        run
    })
}

macro_rules! hard_case {
    ($($name:ident => $file:literal,)*) => {
        $(
            #[test]
            fn $name() {
                conformant($file);
            }
        )*
        /// Every case in the table has a test here.
        #[test]
        fn every_case_has_a_test() {
            let tested = [$($file),*];
            for c in umbra_conformance::CASES {
                assert!(tested.contains(&c.file), "{} has no test", c.file);
            }
            assert_eq!(tested.len(), umbra_conformance::CASES.len());
        }
    };
}

hard_case! {
    case_01_eye_inside_volume => "01-eye-inside-volume",
    case_02_near_plane_slices_volume => "02-near-plane-slices-volume",
    case_03_light_inside_open_container => "03-light-inside-open-container",
    case_04_grazing_directional_light => "04-grazing-directional-light",
    case_05_light_touching_occluder => "05-light-touching-occluder",
    case_06_light_in_caster_plane => "06-light-in-caster-plane",
    case_07_huge_coordinates => "07-huge-coordinates",
    case_08_300_overlapping_volumes => "08-300-overlapping-volumes",
    case_09_zero_area_and_needles => "09-zero-area-and-needles",
    case_10_duplicated_vertices_t_junctions => "10-duplicated-vertices-t-junctions",
    case_11_open_meshes => "11-open-meshes",
    case_12_non_manifold_edges => "12-non-manifold-edges",
    case_13_coplanar_faces => "13-coplanar-faces",
    case_14_grazing_light_on_receiver => "14-grazing-light-on-receiver",
    case_15_caster_smaller_than_a_texel => "15-caster-smaller-than-a-texel",
    case_16_thin_geometry_tree => "16-thin-geometry-tree",
    case_17_silhouette_through_texel_corners => "17-silhouette-through-texel-corners",
    case_18_two_silhouettes_in_one_texel => "18-two-silhouettes-in-one-texel",
    case_19_dueling_frusta => "19-dueling-frusta",
    case_20_eight_mixed_lights => "20-eight-mixed-lights",
    case_21_non_finite_mesh => "21-non-finite-mesh",
    case_22_light_a_hair_above_small_occluders => "22-light-a-hair-above-small-occluders",
    case_23_scanned_open_mesh_under_a_low_sun => "23-scanned-open-mesh-under-a-low-sun",
    case_24_256_overlapping_volumes => "24-256-overlapping-volumes",
    case_25_512_overlapping_volumes => "25-512-overlapping-volumes",
    case_26_128_overlapping_volumes => "26-128-overlapping-volumes",
    case_27_384_overlapping_volumes => "27-384-overlapping-volumes",
    case_28_thin_parts_on_a_large_floor => "28-thin-parts-on-a-large-floor",
    case_29_near_plane_slices_an_occluder_under_a_low_sun => "29-near-plane-slices-an-occluder-under-a-low-sun",
    case_30_point_light_in_a_room_of_occluders => "30-point-light-in-a-room-of-occluders",
    case_31_near_plane_cuts_a_sun_volume_at_the_frame_border => "31-near-plane-cuts-a-sun-volume-at-the-frame-border",
    case_32_open_world_near_0_1_far_44_km => "32-open-world-near-0-1-far-44-km",
}

/// Adds a spot light to `s` with its cone changed by `f`.
fn spot(s: &mut Scene, f: fn(&mut umbra::scene::Spot)) {
    let mut l = Light::spot(glam::Vec3::new(0.0, 4.0, 0.0), -glam::Vec3::Y, 20.0, 30.0, 1.0);
    f(l.spot.as_mut().expect("a spot"));
    s.lights.push(l);
}

/// Case 21 through the API: a scene built in code with a NaN or infinite vertex, a vertex at
/// 1e30, geometry beyond `MAX_COORDINATE`, an infinite transform, a NaN, negative or
/// degenerate light, a degenerate camera (issue #20's list) or too many lights is a typed
/// `RenderError::Scene` before any GPU work (the renderer submits nothing), and the same
/// renderer then renders a valid scene.
#[test]
fn non_finite_and_huge_input_is_a_typed_error_before_any_gpu_work() {
    let valid = umbra::scene::load("cubes").expect("cubes");
    type Break = fn(&mut Scene);
    let cases: [(&str, Break); 18] = [
        ("NaN vertex", |s| s.meshes[0].positions[0].y = f32::NAN),
        ("infinite vertex", |s| s.meshes[0].positions[1].x = f32::INFINITY),
        ("vertex at 1e30", |s| s.meshes[0].positions[2].z = 1e30),
        ("infinite transform", |s| s.objects[0].transform.w_axis.x = f32::INFINITY),
        ("geometry at 1e11", |s| s.objects[0].transform.w_axis.x = 1e11),
        ("NaN light", |s| s.lights.push(Light::point(glam::Vec3::new(0.0, f32::NAN, 0.0), 1.0))),
        ("negative intensity", |s| s.lights.push(Light::point(glam::Vec3::Y * 4.0, -1.0))),
        ("spot direction zero", |s| spot(s, |c| c.direction = glam::Vec3::ZERO)),
        ("spot outer NaN", |s| spot(s, |c| c.outer_deg = f32::NAN)),
        ("spot inner above outer", |s| spot(s, |c| c.inner_deg = 45.0)),
        ("camera fov 0", |s| s.camera.fov_y_deg = 0.0),
        ("camera fov 180", |s| s.camera.fov_y_deg = 180.0),
        ("camera up zero", |s| s.camera.up = glam::Vec3::ZERO),
        ("camera at its target", |s| s.camera.target = s.camera.position),
        ("near 1e-30", |s| s.camera.near = 1e-30),
        ("NaN ambient", |s| s.ambient.x = f32::NAN),
        ("infinite background", |s| s.background.y = f32::INFINITY),
        ("1025 lights", |s| s.lights.resize(1025, Light::point(glam::Vec3::Y * 4.0, 1.0))),
    ];
    common::with_context(|ctx| {
        let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
        desc.diagnostics = true;
        let mut renderer = Renderer::new(ctx, desc).expect("renderer");
        for (what, break_it) in cases {
            let mut scene = valid.clone();
            break_it(&mut scene);
            match renderer.render(&scene) {
                Err(e @ RenderError::Scene(_)) => println!("{what}: {e}"),
                other => panic!("{what}: expected a typed scene error, got {:?}", other.map(|_| "a frame")),
            }
            assert_eq!(renderer.submissions(), 0, "{what}: GPU work was submitted");
        }
        renderer.render(&valid).expect("a valid scene still renders");
        assert!(renderer.submissions() > 0);
    });
}

/// Runs case `file`'s shadow map with every light's map at each of `sizes`, and fails on any
/// verdict that is not conformant.
fn shadow_map_conformant_at(file: &str, sizes: &[u32]) {
    let case = umbra_conformance::case(file).unwrap_or_else(|| panic!("no case {file}"));
    let scene = umbra::scene::load_scene_file(&umbra_conformance::case_path(&cases_dir(), case)).expect("scene");
    let bvh = umbra_reference::SceneBvh::build(&scene);
    common::with_context(|ctx| {
        for &size in sizes {
            let mut sized = scene.clone();
            sized.lights.iter_mut().for_each(|l| l.shadow_map_size = Some(size));
            let run = umbra_conformance::run::run_technique(
                ctx,
                &sized,
                &bvh,
                umbra::scene::Technique::ShadowMap,
                umbra_conformance::Expect::Strict,
                common::SIZE,
            )
            .expect("case runs");
            let j = run.judgement.as_ref().expect("judged");
            println!("{file} at {size}²: {:?}, wrong {} (texel band {})", run.verdict, j.wrong, j.texel_band);
            assert!(run.verdict.ok(), "{file} at {size}²: {:?} at {:?}", run.verdict, j.unexplained_at);
        }
    });
}

/// Case 28's shadow map at map sizes whose texel grid falls differently on the 2 cm arm: the
/// false shadow a texel centre that hits the arm casts lies within the texel band of the arm's
/// true shadow, so every size is conformant. Judged with the band's eight points alone (no
/// texel centres), 1536² leaves 22 pixels unexplained on lavapipe, one row along the arm's
/// shadow, and case 28 itself fails at 2048².
#[test]
fn case_28_shadow_map_is_conformant_at_every_map_size() {
    shadow_map_conformant_at("28-thin-parts-on-a-large-floor", &[1536, 2048, 2400, 2730, 3000]);
}

/// Case 09's shadow map at the 256² a 256×192 frame picks by default: the needles' shadows,
/// thinner than a texel, pass within 0.1–0.4 texel of wrongly shadowed pixels but between the
/// map's texel centres; the band's 1/8-texel grid finds them (without it, 1 pixel on lavapipe
/// and 3 on SwiftShader were unexplained).
#[test]
fn case_09_shadow_map_is_conformant_at_a_frame_sized_map() {
    shadow_map_conformant_at("09-zero-area-and-needles", &[256]);
}

/// Why case 32 submits its ground in 3 × 3 cells, as engines submit terrain: one quad 200 km
/// across, seen through a near plane of 0.1, reaches far past the view where the near plane
/// cuts it, and SwiftShader's rasterizer then loses it (the bottom-centre pixel holds no
/// surface, 3.7 m from where the eye ray meets the ground; a 2 km quad is drawn 7 % too far,
/// a 60 km box shows its underside), while lavapipe places it within a millimetre. Cells of 200 m under the eye keep both
/// drivers exact (case 32 is strict on both). Measured by the G-buffer, not by shadows: every
/// technique shades the points the G-buffer holds.
#[test]
fn one_ground_quad_200_km_across_is_rasterized_exactly_by_lavapipe_only() {
    let case = umbra_conformance::case("32-open-world-near-0-1-far-44-km").expect("case 32");
    let mut scene = umbra::scene::load_scene_file(&umbra_conformance::case_path(&cases_dir(), case)).expect("scene");
    let ground = scene.meshes.iter().position(|m| m.name == "ground").expect("a ground");
    scene.meshes[ground] = umbra::scene::primitives::plane(200_000.0);
    // The point the eye ray through the bottom-centre pixel meets on the ground (y = 0).
    let (w, h) = common::SIZE;
    let (x, y) = (w / 2, h - 2);
    let inverse = scene.camera.view_proj(w as f32 / h as f32).inverse();
    let ndc = glam::Vec2::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / h as f32 * 2.0);
    let far = inverse.project_point3(ndc.extend(0.5));
    let eye = scene.camera.position;
    let truth = eye + (far - eye) * (eye.y / (eye.y - far.y));
    common::with_context(|ctx| {
        let swiftshader = ctx.capabilities().device_name.contains("SwiftShader");
        let mut desc = RendererDesc::new(w, h);
        desc.gbuffer = true;
        let frame = Renderer::new(ctx, desc).and_then(|mut r| r.render(&scene)).expect("renders");
        let p = frame.gbuffer.as_ref().expect("G-buffer").position[(y * w + x) as usize];
        let error = (glam::Vec3::new(p[0], p[1], p[2]) - truth).length();
        println!(
            "one 200 km ground quad, near 0.1, pixel ({x}, {y}) on {}: G-buffer point {:?} ({}), the eye ray meets the ground at {truth}: {error:.4} apart",
            ctx.capabilities().device_name,
            &p[..3],
            if p[3] == 0.0 { "no surface drawn" } else { "a surface drawn" }
        );
        if swiftshader {
            assert!(error > 0.1, "SwiftShader placed the point within {error}: case 32 could use one quad");
        } else {
            assert!(error < 1e-3, "lavapipe placed the point {error} away");
        }
    });
}

/// The frame report says where the camera's depth is coarser than where shadow volumes are
/// measured exact: in case 32 (near 0.1, the ground's far corner 141 km away) every
/// shadow-volume and hybrid light carries `depth_precision`, its step 2⁻²⁴ d² / near, with a
/// warning naming the light; case 07, just above `Camera::EXACT_NEAR_RATIO`, carries none.
#[test]
fn the_report_gives_the_depth_step_where_it_is_coarser_than_measured_exact() {
    let load = |file: &str| {
        let case = umbra_conformance::case(file).expect("a case");
        umbra::scene::load_scene_file(&umbra_conformance::case_path(&cases_dir(), case)).expect("scene")
    };
    common::with_context(|ctx| {
        for (file, warned) in [("32-open-world-near-0-1-far-44-km", true), ("07-huge-coordinates", false)] {
            let mut scene = load(file);
            for technique in [umbra::scene::Technique::ShadowVolume, umbra::scene::Technique::Hybrid] {
                scene.lights.iter_mut().for_each(|l| l.technique = technique);
                let desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
                let frame = Renderer::new(ctx, desc).and_then(|mut r| r.render(&scene)).expect("renders");
                for l in &frame.report.lights {
                    let volumes = l.shadow_volume.as_ref().expect("a volume report");
                    match (volumes.depth_precision, warned) {
                        (Some(p), true) => {
                            let expected =
                                p.distance * p.distance / scene.camera.near * umbra::scene::Camera::DEPTH_STEP;
                            assert!((p.step / expected - 1.0).abs() < 1e-3, "{p:?}");
                            assert!(p.distance > 1.4e5 && p.step > 1e4, "{p:?}");
                            let warning = p.warning(l.light);
                            assert!(warning.contains(&format!("light {}", l.light)), "{warning}");
                            println!("{file}, {}: {warning}", technique.name());
                        }
                        (None, false) => println!("{file}, {}: no depth-precision warning", technique.name()),
                        (p, _) => panic!("{file}, {}: depth precision {p:?}", technique.name()),
                    }
                }
            }
        }
    });
}

/// Case 31 from the eyes around it, at the suite's size and at 320×240: the floor's cut cap
/// drifts from the floor by a different fraction of a pixel's depth change at each. With the
/// quarter-pixel bias the cut caps had before, SwiftShader drew the false-shadow wedge from 8
/// of these 18 (276 to 5 398 unexplained pixels; the issue's own eye, (0.3, 0.6) at 320×240,
/// 621). Now no eye leaves more than two unexplained pixels: on SwiftShader at 320×240, eyes
/// (0.2, 0.7) and (0.3, 0.6) leave 1 and 2 lone pixels along the shadow's edge near the frame's
/// bottom-left corner, whatever the cut caps' bias (1, 2 or 4 pixels' slope) and with the
/// volumes clipped by the driver as on the host (3 pixels at (0.3, 0.6) then): the driver's
/// rasterization of the volume's side there, not the cut caps; lavapipe has them right.
#[test]
fn case_31_has_no_wedge_from_the_eyes_around_it() {
    let case = umbra_conformance::case("31-near-plane-cuts-a-sun-volume-at-the-frame-border").expect("case 31");
    let scene = umbra::scene::load_scene_file(&umbra_conformance::case_path(&cases_dir(), case)).expect("scene");
    common::with_context(|ctx| {
        for size in [common::SIZE, (320, 240)] {
            for (x, y) in [0.2, 0.3, 0.4].into_iter().flat_map(|x| [0.5, 0.6, 0.7].map(|y| (x, y))) {
                let mut moved = scene.clone();
                moved.camera.position = glam::Vec3::new(x, y, 4.0);
                let bvh = umbra_reference::SceneBvh::build(&moved);
                for technique in [umbra::scene::Technique::ShadowVolume, umbra::scene::Technique::Hybrid] {
                    let run = umbra_conformance::run::run_technique(
                        ctx,
                        &moved,
                        &bvh,
                        technique,
                        umbra_conformance::Expect::Strict,
                        size,
                    )
                    .expect("case runs");
                    let j = run.judgement.as_ref().expect("judged");
                    println!(
                        "{}x{}, eye ({x}, {y}, 4), {}: wrong {} (seam {}), unexplained {}",
                        size.0,
                        size.1,
                        technique.name(),
                        j.wrong,
                        j.seam,
                        j.unexplained()
                    );
                    let eye = format!("eye ({x}, {y}) at {size:?}, {}", technique.name());
                    assert!(
                        run.deterministic && run.nan_free && j.class_disagreements == 0,
                        "{eye}: {:?}",
                        run.verdict
                    );
                    assert!(j.unexplained() <= 2, "{eye}: {:?} at {:?}", run.verdict, j.unexplained_at);
                }
            }
        }
    });
}
